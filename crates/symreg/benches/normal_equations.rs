//! The normal equations of Levenberg-Marquardt (`J^T J`, `J^T r`, with the forward and
//! adjoint sweeps they need), where a search spends most of its time: 100 seeded random
//! programs with affine inputs (the search's default), all parameters free, 1,000 rows (a
//! search fits on at most 2,000). `avx2` is the run-time path on a CPU with AVX2 (four dot
//! products at a time), `portable` the reference without AVX2 (scalar dot products, as the
//! AVX2 path also had before, and SSE2 sweeps); both give the same bits
//! (`tests/it/properties.rs`).
#![allow(missing_docs, clippy::unwrap_used)]
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use hxai_symreg::bench_programs::{affine_programs, column};
use hxai_symreg::eval::Evaluator;

fn bench(c: &mut Criterion) {
    let rows = 1_000;
    let progs = affine_programs(100, 7);
    let cols: Vec<Vec<f64>> = (0..3).map(|j| column(j, rows)).collect();
    let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
    let y: Vec<f64> = cols[0].iter().zip(&cols[1]).map(|(a, b)| a * b).collect();
    let mut g = c.benchmark_group("normal_equations");
    g.throughput(Throughput::Elements(progs.len() as u64));
    for path in ["avx2", "portable"] {
        let mut evs: Vec<Evaluator> = progs
            .iter()
            .map(|(p, _)| {
                let ev = Evaluator::new(p);
                if path == "portable" {
                    ev.portable()
                } else {
                    ev
                }
            })
            .collect();
        g.bench_with_input(BenchmarkId::new(path, rows), &rows, |b, _| {
            b.iter(|| {
                let mut s = 0.0;
                for ((p, params), ev) in progs.iter().zip(evs.iter_mut()) {
                    let free: Vec<usize> = (0..params.len()).collect();
                    let m = free.len();
                    let (mut jtj, mut jtr) = (vec![0.0; m * m], vec![0.0; m]);
                    s += ev.normal_equations(
                        hxai_symreg::eval::Inputs {
                            prog: p,
                            params,
                            cols: &refs,
                        },
                        &free,
                        &y,
                        &mut jtj,
                        &mut jtr,
                    );
                    s += jtj[m * m - 1];
                }
                s
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
