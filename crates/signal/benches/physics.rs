//! Physics chain on a 20,000-sample record: 4th-order band-pass filtfilt, two integrations
//! with linear drift removal. Compare with `scripts/bench_signal.py` (same computation in scipy).
#![allow(missing_docs, clippy::unwrap_used)]

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use hxai_signal::{Band, PhysicsConfig, butter};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::SeedableRng;

fn record(n: usize, fs: f64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let w = 2.0 * std::f64::consts::PI * 20.0;
    (0..n)
        .map(|i| -w * w * 5e-6 * (w * i as f64 / fs).sin() + 0.01 * (rng.r#gen::<f64>() - 0.5))
        .collect()
}

fn bench(c: &mut Criterion) {
    let fs = 10_000.0;
    let mut g = c.benchmark_group("physics");
    for n in [2_000usize, 20_000] {
        let x = record(n, fs);
        g.throughput(Throughput::Elements(n as u64));
        let cfg = PhysicsConfig::default();
        g.bench_with_input(BenchmarkId::new("displacement", n), &x, |b, x| {
            b.iter(|| hxai_signal::displacement(x, fs, &cfg).unwrap())
        });
        let valid = cfg.check(fs).unwrap();
        g.bench_with_input(
            BenchmarkId::new("displacement_prechecked", n),
            &x,
            |b, x| b.iter(|| valid.displacement(x).unwrap()),
        );
        let sos = butter(4, Band::Bandpass(5.0, 200.0), fs).unwrap();
        g.bench_with_input(BenchmarkId::new("filtfilt_bp4", n), &x, |b, x| {
            b.iter(|| sos.filtfilt(x).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
