//! The error model of the criterion (`SearchConfig::error_model`, issue 47): a positive
//! target whose scatter grows with its value is judged on every row.
#![allow(clippy::unwrap_used)]
use hxai_symreg::{ErrorModel, Node, Op, SearchConfig, SrError, Table, search};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `hxai sr`'s defaults that matter here (strict nesting, the power primitive, the
/// description-length criterion), with `error_model`.
fn sr_config(error_model: ErrorModel) -> SearchConfig {
    SearchConfig {
        error_model,
        ..crate::common::sr_defaults()
    }
}

/// 60 rows of an allometric law `10 m^0.7` with 30 % multiplicative scatter, `m` spread
/// log-uniformly over six decades (a body mass from grams to tonnes).
fn allometric() -> (Table, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let m: Vec<f64> = (0..60)
        .map(|_| 10f64.powf(rng.gen_range(-2.0..4.0)))
        .collect();
    let y: Vec<f64> = m
        .iter()
        .map(|&v| {
            let e: f64 = (0..12).map(|_| rng.gen_range(-0.5..0.5)).sum::<f64>();
            10.0 * v.powf(0.7) * (0.3 * e).exp()
        })
        .collect();
    (Table::new(vec!["m".into()], vec![m]).unwrap(), y)
}

#[test]
fn a_power_law_over_decades_is_picked_under_the_multiplicative_error() {
    let (data, y) = allometric();
    let r = search(&data, &y, &sr_config(ErrorModel::Auto), &mut |_| {}).unwrap();
    let best = &r.best;
    assert!(
        best.program.nodes.contains(&Node::Op(Op::Pow)),
        "not a power law: {}",
        best.equation()
    );
    // its slope on the log-log scale over the rows' range is the law's, within the scatter
    let probe = Table::new(vec!["m".into()], vec![vec![0.1, 1000.0]]).unwrap();
    let p = best.predict(&probe).unwrap();
    let slope = (p[1] / p[0]).ln() / (1e4f64).ln();
    assert!(
        (slope - 0.7).abs() < 0.1,
        "slope {slope}: {}",
        best.equation()
    );
}

#[test]
fn an_exact_law_is_picked_alike_under_auto_and_additive() {
    // on a noise-free law both losses sit at the floor: the tie stays additive
    let x: Vec<f64> = (0..40).map(|i| 1.0 + 0.1 * i as f64).collect();
    let y: Vec<f64> = x.iter().map(|v| 2.0 + 3.0 * v * v).collect();
    let data = Table::new(vec!["x".into()], vec![x]).unwrap();
    let auto = search(&data, &y, &sr_config(ErrorModel::Auto), &mut |_| {}).unwrap();
    let add = search(&data, &y, &sr_config(ErrorModel::Additive), &mut |_| {}).unwrap();
    assert_eq!(auto.best.equation(), add.best.equation());
    assert_eq!(auto.best.score, add.best.score);
}

#[test]
fn the_multiplicative_error_refuses_a_target_that_is_not_positive() {
    let x: Vec<f64> = (0..20).map(f64::from).collect();
    let y: Vec<f64> = x.iter().map(|v| v - 3.0).collect();
    let data = Table::new(vec!["x".into()], vec![x]).unwrap();
    let err = search(
        &data,
        &y,
        &sr_config(ErrorModel::Multiplicative),
        &mut |_| {},
    )
    .unwrap_err();
    match err {
        SrError::InvalidConfig(m) => assert!(m.contains("positive") && m.contains("row 0"), "{m}"),
        e => panic!("unexpected error {e}"),
    }
    // auto falls back to the additive error on such a target
    assert!(search(&data, &y, &sr_config(ErrorModel::Auto), &mut |_| {}).is_ok());
}
