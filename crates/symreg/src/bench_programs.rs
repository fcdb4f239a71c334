//! The fixed set of random programs and data used to measure evaluation throughput, shared
//! by the criterion bench and the pyoperon comparison script (via
//! `testdata/symreg/eval_programs.json`). Internal: public (and hidden from the docs) only
//! for the benches, the example and the tests.
use crate::Op;
use crate::program::{ComplexityMeasure, Program};
use crate::search::generate::Tables;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Operators both engines have: arithmetic plus transcendental functions.
pub const BENCH_OPS: [Op; 11] = [
    Op::Add,
    Op::Sub,
    Op::Mul,
    Op::Div,
    Op::Exp,
    Op::Log,
    Op::Sin,
    Op::Cos,
    Op::Sqrt,
    Op::Square,
    Op::Tanh,
];

/// `count` seeded random programs over 3 inputs (no affine scaling, constants as leaves) of
/// 5 to 25 nodes, with their parameters.
pub fn programs(count: usize, seed: u64) -> Vec<(Program, Vec<f64>)> {
    generate(count, seed, false)
}

/// The same draw with affine inputs (each input leaf has a fitted scale and offset, as in a
/// search): the programs of the normal-equations bench.
pub fn affine_programs(count: usize, seed: u64) -> Vec<(Program, Vec<f64>)> {
    generate(count, seed, true)
}

/// `count` seeded random programs of 5 to 25 nodes over 3 inputs; the output map is the
/// identity, every other parameter is drawn from [0.5, 2).
fn generate(count: usize, seed: u64, affine: bool) -> Vec<(Program, Vec<f64>)> {
    let t = Tables {
        ops: BENCH_OPS.to_vec(),
        op_w: vec![1.0; BENCH_OPS.len()],
        in_w: vec![1.0; 3],
        affine,
        measure: ComplexityMeasure::Edges,
        max_complexity: 25,
        op_costs: crate::ops::OpCosts::default(),
    };
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::new();
    while out.len() < count {
        let mut nodes = Vec::new();
        t.grow(&mut rng, 25, &mut nodes);
        if nodes.len() < 5 {
            continue;
        }
        let p = Program { nodes, affine };
        let mut params: Vec<f64> = (0..p.n_params()).map(|_| rng.gen_range(0.5..2.0)).collect();
        params[0] = 1.0;
        params[1] = 0.0;
        out.push((p, params));
    }
    out
}

/// Column `j` of the benchmark data: `x[r] = 0.5 + 2 ((7919 r + 104729 j) mod 10007) / 10007`,
/// computed exactly in both languages.
pub fn column(j: usize, rows: usize) -> Vec<f64> {
    (0..rows)
        .map(|r| 0.5 + 2.0 * ((7919 * r + 104_729 * j) % 10007) as f64 / 10007.0)
        .collect()
}
