//! Per-operator evaluation cost: a chain of eight applications of one operator on 10,000
//! rows, in node evaluations per second (tells which kernel the throughput bench spends its
//! time in).
#![allow(missing_docs)]
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use hxai_symreg::Op;
use hxai_symreg::bench_programs::{BENCH_OPS, column};
use hxai_symreg::eval::Evaluator;
use hxai_symreg::program::{Node, Program};

fn chain(op: Op) -> Program {
    let mut nodes = vec![Node::Var(0)];
    for _ in 0..8 {
        if op.arity() == 2 {
            nodes.push(Node::Var(1));
        }
        nodes.push(Node::Op(op));
    }
    Program {
        nodes,
        affine: false,
    }
}

fn bench(c: &mut Criterion) {
    let rows = 10_000;
    let cols: Vec<Vec<f64>> = (0..3).map(|j| column(j, rows)).collect();
    let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
    let mut g = c.benchmark_group("eval_op");
    // sub costs what add does
    for op in BENCH_OPS.into_iter().filter(|&op| op != Op::Sub) {
        let p = chain(op);
        let params = vec![1.0, 0.0];
        let mut ev = Evaluator::new(&p);
        let mut out = Vec::with_capacity(rows);
        g.throughput(Throughput::Elements((p.nodes.len() * rows) as u64));
        g.bench_with_input(BenchmarkId::new(op.name(), rows), &rows, |b, &rows| {
            b.iter(|| {
                ev.predict(&p, &params, &refs, rows, &mut out);
                out[rows / 2]
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
