//! `--monotone` (issue 68) through the table hybrid: the correction's effect of a declared
//! column never moves the wrong way on a grid of its training range, `auto` then never picks
//! the free form, and bad settings are refused before any work.
#![allow(clippy::unwrap_used)]

use hxai_hybrid::HybridError;
use hxai_hybrid::tables::{CorrectionForm, Form, TableConfig, fit};
use hxai_symreg::Table;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `n` rows of `y = 2 x (1 + 0.05 (z - 5)^2) (1 + noise)`: a physics `k*x` and a correction
/// that falls, then rises, in `z` over [0, 10].
fn table(n: usize) -> Table {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut x, mut z, mut y) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        let u: f64 = rng.gen_range(1.0..10.0);
        let v: f64 = rng.gen_range(0.0..10.0);
        let e: f64 = rng.gen_range(-0.01..0.01);
        x.push(u);
        z.push(v);
        y.push(2.0 * u * (1.0 + 0.05 * (v - 5.0).powi(2)) * (1.0 + e));
    }
    Table::new(vec!["x".into(), "z".into(), "y".into()], vec![x, z, y]).unwrap()
}

fn config(form: Form) -> TableConfig {
    let mut cfg = TableConfig::new("y", "k*x");
    cfg.calibrate = vec!["k".into()];
    cfg.correction = CorrectionForm::Multiplicative;
    cfg.form = form;
    cfg.conformal_folds = 0;
    // a harmonic in `z`, which can follow the dip (every other one-column shape is
    // monotone, and a pair of `x` and `z` that reads `z` alone is no longer taken)
    cfg.periodic = vec!["z".into()];
    cfg
}

/// The correction's values along `z` over [lo, hi] at `x` = 5: whether they never fall.
fn rises_in_z(m: &hxai_hybrid::tables::TableModel, lo: f64, hi: f64) -> bool {
    let z: Vec<f64> = (0..201)
        .map(|i| lo + (hi - lo) * f64::from(i) / 200.0)
        .collect();
    let n = z.len();
    let g = Table::new(
        vec!["x".into(), "z".into(), "y".into()],
        vec![vec![5.0; n], z, vec![0.0; n]],
    )
    .unwrap();
    let c = m.predict(&g).unwrap().correction;
    c.windows(2)
        .all(|w| w[1] >= w[0] - 1e-9 * (1.0 + w[0].abs()))
}

#[test]
fn the_correction_respects_a_monotone_constraint_and_auto_never_picks_free() {
    let t = table(300);
    let z = t.column("z").unwrap();
    let (lo, hi) = z.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, &v| {
        (a.0.min(v), a.1.max(v))
    });
    let free = fit(&t, &config(Form::Factors), &mut |_| {}).unwrap();
    assert!(
        !rises_in_z(&free, lo, hi),
        "without the constraint the correction should follow the dip: {}",
        free.correction.forms.equation
    );
    for form in [Form::Factors, Form::Auto] {
        let mut cfg = config(form);
        cfg.increasing = vec!["z".into()];
        let m = fit(&t, &cfg, &mut |_| {}).unwrap();
        assert!(
            rises_in_z(&m, lo, hi),
            "{form:?}: {}",
            m.correction.forms.equation
        );
        assert_ne!(m.correction.form, Some(Form::Free));
    }
}

#[test]
fn bad_monotone_settings_are_refused() {
    let t = table(60);
    let refused = |cfg: TableConfig, says: &str| match fit(&t, &cfg, &mut |_| {}) {
        Err(HybridError::InvalidConfig(m)) => assert!(m.contains(says), "{m}"),
        other => panic!("expected a refusal saying {says:?}, got {:?}", other.err()),
    };
    let mut cfg = config(Form::Free);
    cfg.increasing = vec!["z".into()];
    refused(cfg, "--form free");
    let mut cfg = config(Form::Factors);
    cfg.increasing = vec!["z".into()];
    cfg.decreasing = vec!["z".into()];
    refused(cfg, "both increasing");
    let mut cfg = config(Form::Factors);
    cfg.decreasing = vec!["w".into()];
    refused(cfg, "not a feature");
}

/// `--consensus N` binds the factor form too (issue 68): the model file's selection says
/// what share of the N resamples gave its factor set back.
#[test]
fn the_factor_form_takes_the_consensus_and_reports_its_share() {
    // `y = 2 x (1 + 0.1 z) (1 + noise)`: one clear effect of `z`
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let (mut x, mut z, mut y) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..200 {
        let (u, v): (f64, f64) = (rng.gen_range(1.0..10.0), rng.gen_range(0.0..10.0));
        x.push(u);
        z.push(v);
        y.push(2.0 * u * (1.0 + 0.1 * v) * (1.0 + rng.gen_range(-0.01..0.01)));
    }
    let t = Table::new(vec!["x".into(), "z".into(), "y".into()], vec![x, z, y]).unwrap();
    let mut cfg = config(Form::Factors);
    cfg.periodic.clear();
    let plain = fit(&t, &cfg, &mut |_| {}).unwrap();
    assert_eq!(plain.correction.selection.as_ref().unwrap().runs, None);
    cfg.search.consensus_runs = 6;
    let m = fit(&t, &cfg, &mut |_| {}).unwrap();
    let sel = m.correction.selection.as_ref().unwrap();
    assert_eq!(sel.method, "factors");
    assert_eq!(sel.runs, Some(6));
    let share = sel.share.unwrap();
    assert!((0.0..=1.0).contains(&share), "share {share}");
    // the z effect is strong: most selections agree on it
    assert!(share > 0.5, "share {share}");
    assert!(
        m.correction
            .factors
            .as_ref()
            .unwrap()
            .iter()
            .any(|f| f.column.as_deref() == Some("z"))
    );
}
