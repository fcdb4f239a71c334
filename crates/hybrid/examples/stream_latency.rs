//! The distribution of the cost of one `push` of one sample into the streaming estimator
//! (`hxai_hybrid::records::stream`), which criterion's means do not show: 2,000,000 pushes at 10 kHz
//! and 25 Hz (200 s of stream) after a warm-up, each timed on its own, then the median, the
//! 99th and 99.9th percentiles and the maximum, and the throughput of the whole loop.
//!
//! `cargo run --release -p hxai-hybrid --example stream_latency` (docs/benchmarks.md).
#![allow(missing_docs, clippy::unwrap_used, clippy::print_stdout)]

use hxai_hybrid::records::RecordModel;
use hxai_hybrid::records::stream::Estimator;
use std::time::Instant;

fn main() {
    let model =
        RecordModel::from_json(include_str!("../../../testdata/bad/good/model.json")).unwrap();
    let (fs, f) = (10_000.0, 25.0);
    let w = 2.0 * std::f64::consts::PI * f;
    let n = 2_000_000usize;
    let x: Vec<f64> = (0..n + 10_000)
        .map(|i| -6e-6 * w * w * (w * i as f64 / fs).sin() + 1e-3 * ((i * 7919) % 101) as f64)
        .collect();
    let mut est = Estimator::new(&model, f, fs).unwrap();
    est.push(&x[..10_000]).unwrap();
    let mut rows = Vec::with_capacity(1);
    let mut ns = Vec::with_capacity(n);
    let start = Instant::now();
    for v in &x[10_000..] {
        let t = Instant::now();
        rows.clear();
        est.push_into(std::slice::from_ref(v), &mut rows).unwrap();
        ns.push(t.elapsed().as_nanos() as u64);
    }
    let total = start.elapsed().as_secs_f64();
    ns.sort_unstable();
    let q = |p: f64| ns[((ns.len() - 1) as f64 * p).round() as usize];
    println!(
        "one push of one sample, {n} pushes: median {} ns, p99 {} ns, p99.9 {} ns, max {} ns",
        q(0.5),
        q(0.99),
        q(0.999),
        ns[ns.len() - 1]
    );
    // The loop's rate includes the two clock reads per push.
    println!(
        "timed loop: {:.2} million samples/s",
        n as f64 / total / 1e6
    );
    let mut est = Estimator::new(&model, f, fs).unwrap();
    let mut rows = Vec::with_capacity(x.len());
    let start = Instant::now();
    est.push_into(&x, &mut rows).unwrap();
    let batch = start.elapsed().as_secs_f64();
    println!(
        "one batch of {} samples: {:.2} million samples/s ({:.0} times real time at 10 kHz)",
        x.len(),
        x.len() as f64 / batch / 1e6,
        x.len() as f64 / batch / fs
    );
}
