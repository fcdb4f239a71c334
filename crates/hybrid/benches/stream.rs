//! The streaming estimator (`hxai_hybrid::records::stream`) against the offline prediction
//! (`RecordModel::predict`, what `hxai predict` runs) on the same samples, in the same run:
//! - `push_one`: one sample per call (the per-sample cost of a live stream; the estimator is
//!   warmed up first, so every call does the full work);
//! - `push_batch/10000`: a batch of 10,000 samples (1 s at 10 kHz) per call;
//! - `offline_predict/10000`: the offline pipeline on a whole record of those 10,000 samples
//!   (the reference: the ratio of the two is what docs/benchmarks.md quotes).
//!
//! Both use the model of `testdata/bad/good/model.json` at 10 kHz and 25 Hz. The 99th
//! percentile of one push is measured by `cargo run --release -p hxai-hybrid --example
//! stream_latency` (criterion reports means).
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use hxai_hybrid::records::stream::Estimator;
use hxai_hybrid::records::{RecordInput, RecordModel};
use std::hint::black_box;

fn accel(n: usize, fs: f64, f: f64) -> Vec<f64> {
    let w = 2.0 * std::f64::consts::PI * f;
    use rand::Rng;
    use rand_chacha::rand_core::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    (0..n)
        .map(|i| {
            let noise = rng.r#gen::<f64>() - 0.5;
            -6e-6 * w * w * (w * i as f64 / fs).sin() + 0.02 * noise
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let model =
        RecordModel::from_json(include_str!("../../../testdata/bad/good/model.json")).unwrap();
    let (fs, f) = (10_000.0, 25.0);
    let x = accel(10_000, fs, f);
    let mut g = c.benchmark_group("stream");

    let mut est = Estimator::new(&model, f, fs).unwrap();
    est.push(&x).unwrap();
    let mut rows = Vec::with_capacity(1);
    let mut k = 0usize;
    g.throughput(Throughput::Elements(1));
    g.bench_function("push_one", |b| {
        b.iter(|| {
            rows.clear();
            est.push_into(black_box(&x[k..=k]), &mut rows).unwrap();
            k = (k + 1) % x.len();
            black_box(&rows);
        })
    });

    let n = x.len();
    g.throughput(Throughput::Elements(n as u64));
    let mut est = Estimator::new(&model, f, fs).unwrap();
    est.push(&x).unwrap();
    let mut rows = Vec::with_capacity(n);
    g.bench_with_input(BenchmarkId::new("push_batch", n), &x, |b, x| {
        b.iter(|| {
            rows.clear();
            est.push_into(x, &mut rows).unwrap();
            black_box(&rows);
        })
    });
    g.bench_with_input(BenchmarkId::new("offline_predict", n), &x, |b, x| {
        b.iter(|| {
            let input = RecordInput {
                id: "bench",
                fs_hz: fs,
                frequency_hz: f,
                signal: x,
                truth: None,
            };
            black_box(model.predict(&input).unwrap())
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
