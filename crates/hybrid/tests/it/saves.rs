//! Every fit saves (issue 63): a table hybrid fitted on a random small table writes a model
//! file that reads back as it was written and predicts identically.
//!
//! The failure this guards against: the model was read back through a `serde_json::Value`,
//! whose objects sort their keys, so `hybrid.uncertainty.params` (template order, `k` before
//! `c`) came back as `c, k` while its `slots` and covariance kept template order, and the
//! check refused to write the file on most tables with two calibrated parameters.
#![allow(clippy::unwrap_used)]

use hxai_hybrid::IntervalMethod;
use hxai_hybrid::tables::{TableConfig, TableModel, fit};
use hxai_symreg::Table;
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `n` rows of `x1 ~ U(45, 90)`, `x2 ~ U(160, 241)`, `y = a + b1 x1 + b2 x2 + N(0, sd)`
/// (uniform noise of the same sd, enough for the fit's purposes).
fn linear_table(n: usize, a: f64, b1: f64, b2: f64, sd: f64, seed: u64) -> Table {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut x1, mut x2, mut y) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        let u: f64 = rng.gen_range(45.0..90.0);
        let v: f64 = rng.gen_range(160.0..241.0);
        let e: f64 = rng.gen_range(-1.0..1.0) * sd * 3f64.sqrt();
        x1.push(u);
        x2.push(v);
        y.push(a + b1 * u + b2 * v + e);
    }
    Table::new(vec!["x1".into(), "x2".into(), "y".into()], vec![x1, x2, y]).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(8))]

    // Invariant: whatever the table, a fit's model file is written (the checked JSON is
    // accepted), reads back equal to the model, and predicts bit for bit what the fitted
    // model predicts, intervals included.
    #[test]
    fn every_fit_writes_a_model_that_reads_back(
        n in 20usize..120, a in 100.0f64..1000.0, b1 in -10.0f64..10.0, b2 in -3.0f64..3.0,
        sd in 1.0f64..50.0, seed in 0u64..1000,
        physics in prop::sample::select(vec!["k*x1 + c", "k*x1 + c + b*x2", "z*x1 + a"]),
    ) {
        let t = linear_table(n, a, b1, b2, sd, seed);
        let mut cfg = TableConfig::new("y", physics);
        cfg.calibrate = ["k", "c", "b", "z", "a"]
            .iter()
            .filter(|p| physics.contains(*p))
            .map(|p| p.to_string())
            .collect();
        cfg.seed = seed;
        cfg.search.epochs = 2;
        cfg.search.candidates_per_epoch = 200;
        let m = fit(&t, &cfg, &mut |_| {}).unwrap();
        let json = m.to_checked_json();
        prop_assert!(json.is_ok(), "{physics} on {n} rows: {:?}", json.err());
        let back = TableModel::from_json(&json.unwrap()).unwrap();
        prop_assert_eq!(&back, &m);
        prop_assert_eq!(back.predict(&t).unwrap(), m.predict(&t).unwrap());
        prop_assert_eq!(back.intervals(&t, 0.95).unwrap(), m.intervals(&t, 0.95).unwrap());
        // an interval always holds its point, beside the data too
        let far = Table::new(
            vec!["x1".into(), "x2".into()],
            vec![vec![45.0, 90.0, 0.0, 200.0, 60.0], vec![160.0, 241.0, 200.0, 100.0, 400.0]],
        )
        .unwrap();
        // far rows may lie outside the correction's domain (no value there): the rule is
        // for the rows that have a prediction
        let Ok(p) = m.predict(&far).map(|p| p.hybrid) else {
            return Ok(());
        };
        let methods = [m.default_interval_method(0.95), Some(IntervalMethod::Delta)];
        for method in methods.into_iter().flatten() {
            for ((lo, hi), p) in m.intervals_with(&far, 0.95, method).unwrap().iter().zip(&p) {
                prop_assert!(
                    !p.is_finite() || lo.is_nan() || (lo <= p && p <= hi),
                    "{method:?}: {p} outside [{lo}, {hi}]"
                );
            }
        }
        // x1 = 0 and 200 lie beside x1's range (x2 counts only where the hybrid reads it)
        prop_assert_eq!(&m.outside_training(&far)[2..4], &[true, true]);
    }
}

/// Rows beside the data are flagged (a column outside its training range by more than 10 %
/// of its width) and a prediction of a sign the training target never had is warned about
/// by its row.
#[test]
fn rows_beside_the_data_and_predictions_of_a_new_sign_are_named() {
    let t = linear_table(60, 1200.0, -6.57, -1.37, 5.0, 3);
    let mut cfg = TableConfig::new("y", "k*x1 + c");
    cfg.calibrate = vec!["k".into(), "c".into()];
    cfg.search.epochs = 2;
    cfg.search.candidates_per_epoch = 200;
    let m = fit(&t, &cfg, &mut |_| {}).unwrap();
    let tr = m.training.as_ref().unwrap();
    assert!(tr.target[0] > 0.0, "{:?}", tr.target);
    // just inside and just outside 10 % of the width beyond each end of x1's range
    let [lo, hi] = tr.columns["x1"];
    let w = hi - lo;
    let rows = Table::new(
        vec!["x1".into(), "x2".into()],
        vec![
            vec![
                lo - 0.09 * w,
                hi + 0.09 * w,
                hi + 0.11 * w,
                lo - 0.11 * w,
                300.0,
            ],
            vec![200.0; 5],
        ],
    )
    .unwrap();
    assert_eq!(
        m.outside_training(&rows),
        vec![false, false, true, true, true]
    );
    let p = m.predict(&rows).unwrap().hybrid;
    assert!(p[4] < 0.0, "{p:?}");
    let w = m.prediction_warnings(&rows, &p);
    assert!(
        w.iter()
            .any(|w| w.starts_with("3 of 5 rows lie beside the data")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|w| w.contains("negative") && w.contains("row(s) 5")),
        "{w:?}"
    );
    // a file written before the ranges were stored reads and flags nothing
    let mut old = m.clone();
    old.training = None;
    old.conformal = None;
    assert_eq!(old.outside_training(&rows), vec![false; 5]);
}

/// The reproducer at each size it names: `k*x1 + c` calibrated, the model written.
#[test]
fn the_reproducer_writes_its_model_at_every_size() {
    for n in [30, 60, 100, 200] {
        let t = linear_table(n, 885.0, -6.57, -1.37, 35.0, n as u64);
        let mut cfg = TableConfig::new("y", "k*x1 + c");
        cfg.calibrate = vec!["k".into(), "c".into()];
        cfg.init = [("k".to_string(), 1.0), ("c".to_string(), 0.0)].into();
        cfg.search.epochs = 2;
        cfg.search.candidates_per_epoch = 200;
        let m = fit(&t, &cfg, &mut |_| {}).unwrap();
        let json = m.to_checked_json().unwrap();
        assert_eq!(TableModel::from_json(&json).unwrap(), m, "{n} rows");
    }
}
