//! All twelve features on a 20,000-sample record (default settings: biased sigma, Welch PSD).
//! Compare with `scripts/bench_signal.py` (same computation in numpy/scipy).
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::SeedableRng;

fn bench(c: &mut Criterion) {
    let fs = 10_000.0;
    let mut g = c.benchmark_group("features");
    for n in [2_000usize, 20_000] {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let w = 2.0 * std::f64::consts::PI * 20.0;
        let x: Vec<f64> = (0..n)
            .map(|i| (w * i as f64 / fs).sin() + 0.1 * (rng.r#gen::<f64>() - 0.5))
            .collect();
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::new("extract", n), &x, |b, x| {
            b.iter(|| hxai_features::extract(x, fs, 20.0).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
