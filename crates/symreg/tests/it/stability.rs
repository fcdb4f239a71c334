//! `stability`: bootstrap reruns of the search, identical for any thread count.
use hxai_symreg::{SearchConfig, Table, stability};

fn data() -> (Table, Vec<f64>) {
    // y = 3 x1^2 + 1 with a deterministic wiggle as noise; x2 is unused
    let n = 120;
    let x1: Vec<f64> = (0..n).map(|i| 0.5 + 0.02 * i as f64).collect();
    let x2: Vec<f64> = (0..n).map(|i| ((i * 37) % 17) as f64).collect();
    let y: Vec<f64> = x1
        .iter()
        .enumerate()
        .map(|(i, v)| 3.0 * v * v + 1.0 + 0.01 * ((i * 7919) % 13) as f64)
        .collect();
    (
        Table::new(vec!["x1".into(), "x2".into()], vec![x1, x2]).expect("table"),
        y,
    )
}

fn cfg() -> SearchConfig {
    SearchConfig {
        epochs: 2,
        candidates_per_epoch: 150,
        ..SearchConfig::default()
    }
}

/// Results depend on the seed and the data, not on the thread count; every run is reported
/// through the progress callback; shares are fractions of the runs.
#[test]
fn stability_is_independent_of_threads_and_finds_the_feature() {
    let (t, y) = data();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let mut calls = 0usize;
        let s = pool
            .install(|| stability(&t, &y, &cfg(), 4, &mut |_, _| calls += 1))
            .expect("stability");
        (s, calls)
    };
    let (one, calls) = run(1);
    let (two, _) = run(2);
    assert_eq!(one, two);
    assert_eq!(calls, 4);
    assert_eq!(one.runs, 4);
    // x1 carries the whole signal: every run uses it (share 1, exactly 4 of 4)
    assert_eq!(one.features["x1"], 1.0);
    let total: f64 = one.structures.iter().map(|s| s.share).sum();
    assert!((total - 1.0).abs() < 1e-12, "shares sum to {total}");
    let r2 = one.r2.expect("out-of-bag R^2");
    assert!(r2.mean > 0.99, "{r2:?}");
    assert!(stability(&t, &y, &cfg(), 0, &mut |_, _| {}).is_err());
}

/// A feature used in every one of 10 runs has share 1 exactly (ten additions of 0.1 would
/// give 0.9999999999999999).
#[test]
fn shares_are_whole_runs_over_runs() {
    let (t, y) = data();
    let s = stability(&t, &y, &cfg(), 10, &mut |_, _| {}).expect("stability");
    assert_eq!(s.features["x1"], 1.0);
    for share in s.features.values() {
        assert_eq!((share * 10.0).round() / 10.0, *share, "{share}");
    }
}

/// Constants are ignored and `+`, `*` operands ordered: one structure for `c*x1 + c` and
/// its reorderings, whatever the values.
#[test]
fn structures_ignore_constants() {
    use hxai_symreg::{Model, Node, Op, Program};
    let a = Model::new(
        vec!["x1".into(), "x2".into()],
        Program {
            nodes: vec![Node::Var(0), Node::Var(1), Node::Op(Op::Mul)],
            affine: true,
        },
        vec![1.5, 0.2, 0.3, 0.0, 2.0, 1.0],
    )
    .expect("model");
    let b = Model::new(
        vec!["x1".into(), "x2".into()],
        Program {
            nodes: vec![Node::Var(1), Node::Var(0), Node::Op(Op::Mul)],
            affine: true,
        },
        vec![-4.0, 7.0, 1.1, 0.5, 0.9, -3.0],
    )
    .expect("model");
    assert_eq!(
        hxai_symreg::stability::structure_of(&a),
        hxai_symreg::stability::structure_of(&b)
    );
}

/// Structures equal up to their algebra are one too (issue 23): a constant factor inside is
/// absorbed by the output scale, and with affine inputs a difference is a sum.
#[test]
fn structures_are_compared_by_their_canonical_form() {
    use hxai_symreg::stability::structure_of;
    use hxai_symreg::{Model, Node, Op, Program};
    let names = || vec!["x1".to_string(), "x2".to_string()];
    let model = |nodes: Vec<Node>, affine: bool| {
        let program = Program { nodes, affine };
        let params = vec![0.7; program.n_params()];
        Model::new(names(), program, params).expect("model")
    };
    let (x1, x2, c) = (Node::Var(0), Node::Var(1), Node::Const);
    let op = Node::Op;
    // x1*(c*x2) and x1*x2, no affine inputs
    let a = model(vec![x1, c, x2, op(Op::Mul), op(Op::Mul)], false);
    let b = model(vec![x1, x2, op(Op::Mul)], false);
    assert_eq!(structure_of(&a), structure_of(&b));
    assert_eq!(structure_of(&b), "c*x1*x2 + c");
    // sub(x1, x2) and add(x2, x1) with affine inputs
    let a = model(vec![x1, x2, op(Op::Sub)], true);
    let b = model(vec![x2, x1, op(Op::Add)], true);
    assert_eq!(structure_of(&a), structure_of(&b));
    // exp(x1 + c) and exp(x1)
    let a = model(vec![x1, c, op(Op::Add), op(Op::Exp)], false);
    let b = model(vec![x1, op(Op::Exp)], false);
    assert_eq!(structure_of(&a), structure_of(&b));
    assert_eq!(structure_of(&b), "c*exp(x1) + c");
    // different structures stay apart
    let a = model(vec![x1, op(Op::Exp)], false);
    let b = model(vec![x1, op(Op::Square), op(Op::Exp)], false);
    assert_ne!(structure_of(&a), structure_of(&b));
}
