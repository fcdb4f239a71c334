//! Quick evaluation-throughput probe (same programs and data as the criterion bench and
//! `scripts/bench_sr_eval_pyoperon.py`): prints node evaluations per second, best of 5.
#![allow(clippy::print_stdout, missing_docs)]
use hxai_symreg::bench_programs::{column, programs};
use hxai_symreg::eval::Evaluator;
use std::time::Instant;

fn main() {
    let progs = programs(100, 7);
    for rows in [1_000usize, 10_000] {
        let cols: Vec<Vec<f64>> = (0..3).map(|j| column(j, rows)).collect();
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let nodes: usize = progs.iter().map(|(p, _)| p.nodes.len()).sum();
        let mut evs: Vec<Evaluator> = progs.iter().map(|(p, _)| Evaluator::new(p)).collect();
        let mut out = Vec::with_capacity(rows);
        let mut best = f64::INFINITY;
        let mut sink = 0.0;
        for _ in 0..5 {
            let t = Instant::now();
            for ((p, params), ev) in progs.iter().zip(evs.iter_mut()) {
                ev.predict(p, params, &refs, rows, &mut out);
                sink += out[rows / 2];
            }
            best = best.min(t.elapsed().as_secs_f64());
        }
        println!(
            "{{\"rows\": {rows}, \"programs\": 100, \"nodes\": {nodes}, \"seconds\": {best}, \"node_evals_per_s\": {}, \"sink\": {}}}",
            (nodes * rows) as f64 / best,
            sink.is_finite()
        );
    }
}
