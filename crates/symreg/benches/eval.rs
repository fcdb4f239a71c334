//! Evaluation throughput: node evaluations per second per thread on random programs with
//! transcendental operators, 10,000 rows (the same programs as
//! `scripts/bench_sr_eval_pyoperon.py`).
#![allow(missing_docs)]
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use hxai_symreg::bench_programs::{column, programs};
use hxai_symreg::eval::Evaluator;

fn bench(c: &mut Criterion) {
    let progs = programs(100, 7);
    let mut g = c.benchmark_group("eval");
    for rows in [1_000usize, 10_000] {
        let cols: Vec<Vec<f64>> = (0..3).map(|j| column(j, rows)).collect();
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let nodes: usize = progs.iter().map(|(p, _)| p.nodes.len()).sum();
        g.throughput(Throughput::Elements((nodes * rows) as u64));
        let mut evs: Vec<Evaluator> = progs.iter().map(|(p, _)| Evaluator::new(p)).collect();
        let mut out = Vec::with_capacity(rows);
        g.bench_with_input(BenchmarkId::new("100_programs", rows), &rows, |b, &rows| {
            b.iter(|| {
                let mut s = 0.0;
                for ((p, params), ev) in progs.iter().zip(evs.iter_mut()) {
                    ev.predict(p, params, &refs, rows, &mut out);
                    s += out[rows / 2];
                }
                s
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
