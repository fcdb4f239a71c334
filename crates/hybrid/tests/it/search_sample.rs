//! A table past `search_rows` (issue 67): the structure is searched on a stratified sample,
//! the constants fitted on every training row, the conformal calibration on the sample; the
//! model says so, saves, reads back and gives intervals.
#![allow(clippy::unwrap_used)]

use hxai_hybrid::IntervalMethod;
use hxai_hybrid::tables::{CorrectionForm, Form, TableConfig, TableModel, fit};
use hxai_symreg::Table;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `n` rows of `y = k x (1 + 0.3 z) (1 + noise)`: a physics `k*x` and a factor in `z`.
fn table(n: usize) -> Table {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let (mut x, mut z, mut y) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        let u: f64 = rng.gen_range(1.0..10.0);
        let v: f64 = rng.gen_range(0.0..2.0);
        let e: f64 = rng.gen_range(-0.02..0.02);
        x.push(u);
        z.push(v);
        y.push(2.0 * u * (1.0 + 0.3 * v) * (1.0 + e));
    }
    Table::new(vec!["x".into(), "z".into(), "y".into()], vec![x, z, y]).unwrap()
}

fn config(search_rows: usize) -> TableConfig {
    let mut cfg = TableConfig::new("y", "k*x");
    cfg.calibrate = vec!["k".into()];
    cfg.correction = CorrectionForm::Multiplicative;
    cfg.form = Form::Factors;
    cfg.search_rows = search_rows;
    cfg
}

#[test]
fn a_table_past_search_rows_is_searched_on_a_sample_and_fitted_on_every_row() {
    let t = table(1000);
    let m = fit(&t, &config(200), &mut |_| {}).unwrap();
    let s = m.search_sample.as_ref().unwrap();
    // 200 stratified rows and the rows of the 2 columns' extremes
    assert!(
        (200..=204).contains(&s.rows) && s.training_rows == 800,
        "{s:?}"
    );
    assert!(s.method.contains("strata of the target"), "{}", s.method);
    // the factor in z is found
    assert_eq!(m.correction.forms.features, vec!["z".to_string()]);
    let c = m.conformal.as_ref().unwrap();
    assert_eq!(c.scores.len(), s.rows);
    let text = m.to_checked_json().unwrap();
    let back = TableModel::from_json(&text).unwrap();
    assert_eq!(back, m);
    let iv = back
        .intervals_with(&t, 0.9, IntervalMethod::Conformal)
        .unwrap();
    let y = t.require("y").unwrap();
    let covered = iv
        .iter()
        .zip(y)
        .filter(|((lo, hi), v)| lo <= *v && *v <= hi)
        .count();
    assert!(covered as f64 / y.len() as f64 > 0.85, "{covered} of 1000");
    // the same fit with every row searched: the same structure, a test RMSE within 5 %
    let all = fit(&t, &config(usize::MAX), &mut |_| {}).unwrap();
    assert!(all.search_sample.is_none());
    assert_eq!(all.correction.forms.features, m.correction.forms.features);
    let (a, b) = (
        m.scores.test.as_ref().unwrap().hybrid.rmse,
        all.scores.test.as_ref().unwrap().hybrid.rmse,
    );
    assert!(
        (a - b).abs() <= 0.05 * b,
        "test RMSE {a} on the sample, {b} on every row"
    );
}

#[test]
fn a_search_sample_below_the_floor_is_refused() {
    let err = fit(&table(50), &config(10), &mut |_| {}).unwrap_err();
    assert!(err.to_string().contains("--search-rows 10"), "{err}");
}
