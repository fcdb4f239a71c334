//! The factor form's pictures (issue 46 item 4): the partial residuals `hxai explain` draws
//! beside each factor's band follow the factor the data was made with.
#![allow(clippy::unwrap_used)]
use hxai_hybrid::tables::{CorrectionForm, Form, TableConfig, fit};
use hxai_symreg::Table;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `y = 3 a * sqrt(b) * (1 + e)`, `e` 1 % normal-ish noise, physics `k*a`: the
/// multiplicative correction is the factor `sqrt(b)`; `c` is a distractor. Returns the
/// table and each row's noise `e`.
fn table(n: usize, seed: u64) -> (Table, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut cols = vec![Vec::new(), Vec::new(), Vec::new(), Vec::new()];
    let mut noise = Vec::new();
    for _ in 0..n {
        let a: f64 = rng.gen_range(1.0..5.0);
        let b: f64 = rng.gen_range(0.5..8.0);
        let c: f64 = rng.gen_range(0.0..1.0);
        let e: f64 = (0..4).map(|_| rng.gen_range(-0.0173..0.0173)).sum();
        cols[0].push(a);
        cols[1].push(b);
        cols[2].push(c);
        cols[3].push(3.0 * a * b.sqrt() * (1.0 + e));
        noise.push(e);
    }
    let t = Table::new(vec!["a".into(), "b".into(), "c".into(), "y".into()], cols).unwrap();
    (t, noise)
}

/// Each training row's partial residual of the factor of `b` is the true factor there,
/// normalised by its mean over the training rows, times the row's own noise: its relative
/// deviation from the true factor is the noise `e` of the row (median |deviation - e|
/// below 0.3 %, against noise of sd 1 %), so the points show the scatter and not just the
/// fitted curve. The product form and the log form alike; `explain` carries the same
/// points.
#[test]
fn partial_residuals_follow_the_true_factor() {
    let (t, noise) = table(300, 4);
    for form in [CorrectionForm::Multiplicative, CorrectionForm::Log] {
        let mut cfg = TableConfig::new("y", "k*a");
        cfg.calibrate = vec!["k".into()];
        cfg.correction = form;
        cfg.form = Form::Factors;
        cfg.search.epochs = 2;
        let m = fit(&t, &cfg, &mut |_| {}).unwrap();
        let pr = m.partial_residuals(&t).unwrap();
        let (_, points) = pr.iter().find(|(c, _)| c == "b").unwrap_or_else(|| {
            panic!(
                "{form:?}: no factor of b in {}",
                m.correction.forms.equation
            )
        });
        assert_eq!(points.len(), m.split.train.len());
        let b = t.column("b").unwrap();
        let mean =
            m.split.train.iter().map(|&i| b[i].sqrt()).sum::<f64>() / m.split.train.len() as f64;
        let mut off: Vec<f64> = points
            .iter()
            .zip(&m.split.train)
            .map(|(&(x, r), &i)| {
                assert_eq!(x, b[i]);
                (r / (x.sqrt() / mean) - 1.0 - noise[i]).abs()
            })
            .collect();
        off.sort_by(f64::total_cmp);
        let median = off[off.len() / 2];
        assert!(
            median < 0.003,
            "{form:?}: median |deviation - noise| {median}"
        );
        let e = m.explain(Some(&t), 0.95, None).unwrap();
        assert_eq!(e.partial_residuals, pr);
    }
}

/// A free-form correction has no factors, so no partial residuals.
#[test]
fn a_free_correction_has_no_partial_residuals() {
    let (t, _) = table(120, 5);
    let mut cfg = TableConfig::new("y", "k*a");
    cfg.calibrate = vec!["k".into()];
    cfg.correction = CorrectionForm::Multiplicative;
    cfg.search.epochs = 2;
    let m = fit(&t, &cfg, &mut |_| {}).unwrap();
    assert!(m.partial_residuals(&t).unwrap().is_empty());
}
