//! The process hybrid (`hxai_hybrid::tables`) on synthetic tables with known laws:
//! calibration and its standard errors, the one-equation hybrid against `predict`, splits,
//! the comparison, and every bad-input error naming what is wrong.
#![allow(clippy::unwrap_used)]
use hxai_hybrid::HybridError;
use hxai_hybrid::tables::{
    CorrectionForm, Form, TableConfig, TableModel, compare, fit, fit_split, split_rows,
};
use hxai_symreg::Table;
use hxai_symreg::infix::compile_text;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;

use crate::common::COMPARE_MODELS;

/// Turning-like table: feed f, nose radius r, speed v, a distractor d;
/// Ra = 1.3 f^2/(32 r) + 2e-4 v + noise (sd `noise`).
fn roughness(n: usize, noise: f64, seed: u64) -> Table {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut cols = vec![Vec::new(); 5];
    for _ in 0..n {
        let f: f64 = rng.gen_range(0.05..0.3);
        let r: f64 = rng.gen_range(0.4..1.6);
        let v: f64 = rng.gen_range(50.0..300.0);
        let d: f64 = rng.gen_range(0.0..1.0);
        let e: f64 = rng.gen_range(-1.0..1.0) * noise;
        let ra = 1.3 * f * f / (32.0 * r) + 2e-4 * v + e;
        for (c, x) in cols.iter_mut().zip([f, r, v, d, ra]) {
            c.push(x);
        }
    }
    Table::new(
        ["f", "r", "v", "d", "Ra"]
            .iter()
            .map(|s| s.to_string())
            .collect(),
        cols,
    )
    .unwrap()
}

fn quick(mut cfg: TableConfig) -> TableConfig {
    cfg.search.epochs = 3;
    cfg.search.candidates_per_epoch = 300;
    cfg
}

fn cfg_roughness() -> TableConfig {
    let mut c = quick(TableConfig::new("Ra", "k*f^2/(32*r)"));
    c.calibrate = vec!["k".into()];
    c
}

/// A table of the named columns.
fn table_of<const N: usize>(columns: [(&str, Vec<f64>); N]) -> Table {
    let (names, cols) = columns.into_iter().map(|(n, c)| (n.to_string(), c)).unzip();
    Table::new(names, cols).unwrap()
}

/// The quick fit of `physics` for the target `y` on a table of the named `columns`, the
/// parameters `calibrate` calibrated.
fn fit_calibrated<const N: usize>(
    columns: [(&str, Vec<f64>); N],
    physics: &str,
    calibrate: &[&str],
) -> TableModel {
    let t = table_of(columns);
    let mut cfg = quick(TableConfig::new("y", physics));
    cfg.calibrate = calibrate.iter().map(|p| p.to_string()).collect();
    fit(&t, &cfg, &mut |_| {}).unwrap()
}

/// Evaluates `text` (infix, e.g. the model's sympy form) on every row of `table`.
fn eval_text(text: &str, table: &Table) -> Vec<f64> {
    let c = compile_text(text, &BTreeMap::new()).unwrap();
    let cols: Vec<&[f64]> = c.inputs.iter().map(|n| table.column(n).unwrap()).collect();
    c.eval_columns(&cols, table.n_rows())
}

fn assert_rel(a: &[f64], b: &[f64], tol: f64, what: &str) {
    assert_eq!(a.len(), b.len());
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= tol * x.abs().max(y.abs()).max(1e-300),
            "{what} row {i}: {x} vs {y}"
        );
    }
}

/// Calibrating `a*x + b` is ordinary least squares: the estimates and their standard
/// errors `s^2 (X^T X)^-1` must match the closed form (1e-7 relative; LM stops at a
/// relative improvement of 1e-15 in the MSE).
#[test]
fn calibration_matches_least_squares_with_standard_errors() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let n = 200;
    let x: Vec<f64> = (0..n).map(|_| rng.gen_range(0.0..10.0)).collect();
    let z: Vec<f64> = (0..n).map(|_| rng.gen_range(0.0..1.0)).collect();
    let y: Vec<f64> = x
        .iter()
        .zip(&z)
        .map(|(x, z)| 3.0 * x - 2.0 + 0.5 * z + rng.gen_range(-0.3..0.3))
        .collect();
    let m = fit_calibrated(
        [("x", x.clone()), ("z", z), ("y", y.clone())],
        "a*x + b",
        &["a", "b"],
    );
    // closed form on the training rows
    let rows = &m.split.train;
    let (xs, ys): (Vec<f64>, Vec<f64>) = rows.iter().map(|&i| (x[i], y[i])).unzip();
    let k = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / k, ys.iter().sum::<f64>() / k);
    let sxx: f64 = xs.iter().map(|v| (v - mx).powi(2)).sum();
    let sxy: f64 = xs.iter().zip(&ys).map(|(a, b)| (a - mx) * (b - my)).sum();
    let a = sxy / sxx;
    let b = my - a * mx;
    let sse: f64 = xs
        .iter()
        .zip(&ys)
        .map(|(u, v)| (v - a * u - b).powi(2))
        .sum();
    let s2 = sse / (k - 2.0);
    let se_a = (s2 / sxx).sqrt();
    let se_b = (s2 * (1.0 / k + mx * mx / sxx)).sqrt();
    let p = &m.physics.parameters;
    let se = &m.physics.standard_errors;
    assert!((p["a"] - a).abs() < 1e-7 * a.abs(), "{} vs {a}", p["a"]);
    assert!((p["b"] - b).abs() < 1e-7 * b.abs(), "{} vs {b}", p["b"]);
    assert!((se["a"].unwrap() - se_a).abs() < 1e-6 * se_a);
    assert!((se["b"].unwrap() - se_b).abs() < 1e-6 * se_b);
    assert_eq!(m.physics.initial["a"], 1.0);
}

/// A parameter used twice moves as one unknown: `C*x + C` is least squares of y on
/// (x + 1), so C = sum((x+1) y) / sum((x+1)^2) over the training rows (1e-9 relative).
#[test]
fn a_parameter_used_twice_is_one_unknown() {
    let x: Vec<f64> = (0..80).map(|i| 0.1 * i as f64).collect();
    let w: Vec<f64> = (0..80).map(|i| ((i * 37) % 17) as f64).collect();
    let y: Vec<f64> = x
        .iter()
        .zip(&w)
        .map(|(x, w)| 2.5 * (x + 1.0) + 0.1 * w)
        .collect();
    let m = fit_calibrated(
        [("x", x.clone()), ("w", w), ("y", y.clone())],
        "C*x + C",
        &["C"],
    );
    let rows = &m.split.train;
    let num: f64 = rows.iter().map(|&i| (x[i] + 1.0) * y[i]).sum();
    let den: f64 = rows.iter().map(|&i| (x[i] + 1.0).powi(2)).sum();
    let c = m.physics.parameters["C"];
    assert!(
        (c - num / den).abs() < 1e-9 * c.abs(),
        "{c} vs {}",
        num / den
    );
    assert!(m.physics.standard_errors["C"].is_some());
}

/// An activation energy calibrates in the law's own units: creep rates of 1e-10..1e-7 /s
/// from `A*s^4*exp(-Q/(8.314*T))`, noise-free, with `A` = 0.3 and `Q` = 3e5 J/mol started at
/// 0.1 and 2.8e5. The curvature of the squared error in `Q` is about 1e-21 here; with an
/// absolute damping floor of 1e-12 on the normal equations' diagonal `Q` stayed at its
/// start (measured: 280000.000001 on the creep table of issue 46) and `A` took up what it
/// could. Both must come back to 1e-6 relative.
#[test]
fn an_activation_energy_calibrates_in_its_own_units() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let n = 150;
    let s: Vec<f64> = (0..n).map(|_| rng.gen_range(50.0..200.0)).collect();
    let t: Vec<f64> = (0..n).map(|_| rng.gen_range(800.0..1000.0)).collect();
    let law = |s: f64, t: f64| 0.3 * s.powi(4) * (-3e5 / (8.314 * t)).exp();
    let y: Vec<f64> = s.iter().zip(&t).map(|(&s, &t)| law(s, t)).collect();
    assert!(y.iter().all(|&v| v < 1e-6), "rates are small");
    let table = table_of([("s", s), ("T", t), ("y", y)]);
    let mut cfg = quick(TableConfig::new("y", "A*s^4*exp(-Q/(8.314*T))"));
    cfg.calibrate = vec!["A".into(), "Q".into()];
    cfg.init = [("A".to_string(), 0.1), ("Q".to_string(), 2.8e5)]
        .into_iter()
        .collect();
    let m = fit(&table, &cfg, &mut |_| {}).unwrap();
    let p = &m.physics.parameters;
    assert!((p["Q"] - 3e5).abs() < 1e-6 * 3e5, "Q = {}", p["Q"]);
    assert!((p["A"] - 0.3).abs() < 1e-6 * 0.3, "A = {}", p["A"]);
}

/// The hybrid's one equation (sympy text, full precision) reproduces `predict` to 1e-9
/// relative on every row, for every correction form, with the joint refit, and for the
/// factor form's corrections (issue 46) as for the free form's.
#[test]
fn hybrid_equation_reproduces_predict() {
    let t = roughness(300, 1e-4, 1);
    for (form, joint, search) in [
        (CorrectionForm::Additive, false, Form::Free),
        (CorrectionForm::Multiplicative, false, Form::Free),
        (CorrectionForm::Log, false, Form::Free),
        (CorrectionForm::Additive, true, Form::Free),
        (CorrectionForm::Log, true, Form::Free),
        (CorrectionForm::Additive, false, Form::Factors),
        (CorrectionForm::Multiplicative, false, Form::Factors),
        (CorrectionForm::Log, false, Form::Factors),
        (CorrectionForm::Multiplicative, true, Form::Factors),
    ] {
        let mut cfg = cfg_roughness();
        cfg.correction = form;
        cfg.joint = joint;
        cfg.form = search;
        let m = fit(&t, &cfg, &mut |_| {}).unwrap();
        if search == Form::Factors {
            let factors = m.correction.factors.as_ref().expect("factors");
            assert!(!factors.is_empty(), "{}", m.correction.forms.equation);
            assert!(factors.iter().all(|f| f.complexity <= 5));
            assert_eq!(m.correction.form, Some(Form::Factors));
            // the product forms print the hybrid as one product: no exp(log(...)) left
            assert!(!m.hybrid.sympy.contains("exp(log"), "{}", m.hybrid.sympy);
        }
        let p = m.predict(&t).unwrap();
        let from_text = eval_text(&m.hybrid.sympy, &t);
        assert_rel(
            &from_text,
            &p.hybrid,
            1e-9,
            &format!("{form:?} joint {joint}"),
        );
        // and the physics' own substituted form reproduces the physics column
        assert_rel(
            &eval_text(&m.physics.sympy, &t),
            &p.physics,
            1e-9,
            "physics",
        );
        // the hybrid's printed parts: the hybrid equals its components
        for ((h, ph), d) in p.hybrid.iter().zip(&p.physics).zip(&p.correction) {
            let want = match form {
                CorrectionForm::Additive => ph + d,
                CorrectionForm::Multiplicative => ph * (1.0 + d),
                CorrectionForm::Log => ph * d.exp(),
            };
            assert_eq!(*h, want);
        }
        assert!(!m.hybrid.latex.is_empty() && !m.hybrid.equation.is_empty());
        assert_eq!(TableModel::from_json(&m.to_json()).unwrap(), m);
        if joint {
            let j = m.joint.as_ref().unwrap();
            assert!(j.joint_train_rmse <= j.sequential_train_rmse * (1.0 + 1e-12));
            assert!(j.sequential_parameters.contains_key("k"));
        } else {
            assert!(m.joint.is_none());
        }
    }
}

/// The hybrid learns the missing speed term: test RMSE well below the calibrated physics
/// (factor 3; noise sd 5.8e-5 against a 2e-4 v effect of sd ~0.014).
#[test]
fn hybrid_beats_the_physics_and_round_trips_through_json() {
    let t = roughness(400, 1e-4, 2);
    let m = fit(&t, &cfg_roughness(), &mut |_| {}).unwrap();
    let test = m.scores.test.unwrap();
    assert!(
        test.hybrid.rmse * 3.0 < test.physics.rmse,
        "{} vs {}",
        test.hybrid.rmse,
        test.physics.rmse
    );
    assert!(
        m.correction.forms.features.contains(&"v".to_string()),
        "{:?}",
        m.correction.forms.features
    );
    let back = TableModel::from_json(&m.to_json()).unwrap();
    assert_eq!(back, m);
    let ev = back
        .evaluate(&t.select_rows(&m.split.test).unwrap())
        .unwrap();
    assert_eq!(ev.n_samples, m.split.test.len());
    assert_eq!(ev.hybrid, test.hybrid);
    assert!(ev.improvement_pct > 50.0 && ev.t_test.unwrap().p_value < 1e-3);
    // predicting needs no target
    let mut no_target = t.clone();
    no_target.remove_column("Ra").unwrap();
    assert_eq!(
        back.predict(&no_target).unwrap().hybrid,
        back.predict(&t).unwrap().hybrid
    );
}

/// `explain` draws the intervals `predict` gives: the parity picture's intervals of `delta`
/// on the test rows are the hybrid's intervals there by the same method, taken back to
/// `delta` through the physics (`y / f_p - 1` here), for the default (conformal) and for
/// the delta method; the response band holds its curve; the method is named.
#[test]
fn explain_draws_the_intervals_of_the_chosen_method() {
    use hxai_hybrid::IntervalMethod;
    let t = roughness(200, 1e-3, 4);
    let mut cfg = cfg_roughness();
    cfg.correction = CorrectionForm::Multiplicative;
    let m = fit(&t, &cfg, &mut |_| {}).unwrap();
    let test = t.select_rows(&m.split.test).unwrap();
    let physics = m.predict(&test).unwrap().physics;
    for (asked, want) in [
        (None, IntervalMethod::Conformal),
        (Some(IntervalMethod::Delta), IntervalMethod::Delta),
    ] {
        let e = m.explain(Some(&t), 0.9, asked).unwrap();
        assert_eq!(e.method, Some(want));
        let iv = m.intervals_with(&test, 0.9, want).unwrap();
        let drawn = e.parity.unwrap().intervals.unwrap();
        assert_eq!(drawn.len(), iv.len());
        for ((_, lo, hi), ((ylo, yhi), p)) in drawn.iter().zip(iv.iter().zip(&physics)) {
            assert!(
                (lo - (ylo / p - 1.0)).abs() < 1e-12,
                "{want:?}: {lo} vs {}",
                ylo / p - 1.0
            );
            assert!(
                (hi - (yhi / p - 1.0)).abs() < 1e-12,
                "{want:?}: {hi} vs {}",
                yhi / p - 1.0
            );
        }
        for r in &e.responses {
            let band = r.band.as_ref().unwrap();
            for (c, (lo, hi)) in r.curve.iter().zip(band) {
                assert!(
                    lo <= c && c <= hi,
                    "{want:?}, {}: {lo} <= {c} <= {hi}",
                    r.feature
                );
            }
        }
    }
}

/// The traps of a table fit give warnings, stored with the model: a column that copies the
/// target, test rows that repeat training rows, a physics that changes sign under a
/// multiplicative correction, an extrapolation column of few values; and rows outside the
/// training ranges at prediction. A clean fit gives none.
#[test]
fn the_traps_of_a_table_fit_are_warned_about() {
    let clean = roughness(120, 1e-3, 8);
    let m = fit(&clean, &cfg_roughness(), &mut |_| {}).unwrap();
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let has = |w: &[String], needle: &str| w.iter().any(|x| x.contains(needle));
    // a copy of the target, and the first 30 rows repeated (some copies land in the test)
    let ra = clean.require("Ra").unwrap().to_vec();
    let rows: Vec<usize> = (0..120).chain(0..30).collect();
    let mut t = clean.select_rows(&rows).unwrap();
    let copy: Vec<f64> = rows.iter().map(|&i| 2.0 * ra[i] + 1.0).collect();
    t.push_column("copy".into(), copy).unwrap();
    let m = fit(&t, &cfg_roughness(), &mut |_| {}).unwrap();
    assert!(
        has(&m.warnings, "`copy` nearly copies the target"),
        "{:?}",
        m.warnings
    );
    assert!(
        has(&m.warnings, "repeat a training row"),
        "{:?}",
        m.warnings
    );
    // a physics that changes sign, multiplicative
    let mut c = cfg_roughness();
    c.physics = "k*f^2/(32*r) - 0.002".into();
    c.correction = CorrectionForm::Multiplicative;
    let m = fit(&clean, &c, &mut |_| {}).unwrap();
    assert!(has(&m.warnings, "changes sign"), "{:?}", m.warnings);
    // an extrapolation column of three values
    let mut t = clean.clone();
    t.push_column("level".into(), (0..120).map(|i| (i % 3) as f64).collect())
        .unwrap();
    let mut c = cfg_roughness();
    c.extrapolate = Some("level".into());
    c.exclude = vec!["level".into()];
    let m = fit(&t, &c, &mut |_| {}).unwrap();
    assert!(
        has(&m.warnings, "has 3 distinct values"),
        "{:?}",
        m.warnings
    );
    // predictions outside the training ranges (speed in mm/min instead of m/min; the
    // correction may have no value far outside in another column: its log of the feed)
    let m = fit(&clean, &cfg_roughness(), &mut |_| {}).unwrap();
    let inside = clean.select_rows(&m.split.train).unwrap();
    assert!(m.range_warnings(&inside).is_empty());
    let v: Vec<f64> = clean
        .require("v")
        .unwrap()
        .iter()
        .map(|v| v * 1000.0)
        .collect();
    let mut far = clean.clone();
    far.remove_column("v").unwrap();
    far.push_column("v".into(), v).unwrap();
    let w = m.range_warnings(&far);
    assert!(has(&w, "`v` outside its training range"), "{w:?}");
    assert!(m.evaluate(&far).unwrap().warnings == w);
}

/// Extrapolation puts the top share of the column in the test set; groups never straddle.
#[test]
fn extrapolation_and_grouped_splits() {
    let mut t = roughness(100, 0.0, 4);
    let g: Vec<f64> = (0..100).map(|i| (i / 5) as f64).collect();
    t.push_column("batch".into(), g.clone()).unwrap();
    let mut cfg = cfg_roughness();
    cfg.extrapolate = Some("v".into());
    let (s, kind) = split_rows(&t, &cfg).unwrap();
    assert_eq!(kind, "extrapolate");
    assert_eq!(s.test.len(), 20);
    let v = t.column("v").unwrap();
    let lowest_test = s.test.iter().map(|&i| v[i]).fold(f64::INFINITY, f64::min);
    assert!(s.train.iter().all(|&i| v[i] < lowest_test));
    let mut cfg = cfg_roughness();
    cfg.group = Some("batch".into());
    let (s, kind) = split_rows(&t, &cfg).unwrap();
    assert_eq!(kind, "grouped");
    for &i in &s.test {
        assert!(s.train.iter().all(|&j| g[j] != g[i]));
    }
    // and with both, whole groups by their mean
    cfg.extrapolate = Some("v".into());
    let (s, _) = split_rows(&t, &cfg).unwrap();
    for &i in &s.test {
        assert!(s.train.iter().all(|&j| g[j] != g[i]));
    }
    // the group column is not a default feature
    let m = fit(&t, &cfg, &mut |_| {}).unwrap();
    assert!(!m.correction.candidates.contains(&"batch".to_string()));
    assert_eq!(m.group.as_deref(), Some("batch"));
    // ties at the cut stay on one side: a column of ten values, each on ten rows, and a
    // fraction (0.25) that cuts through the third-highest value's rows; with a fraction
    // that would take every row's value, the tie goes to training
    let mut cfg = cfg_roughness();
    cfg.extrapolate = Some("batch10".into());
    cfg.test_fraction = 0.25;
    let steps: Vec<f64> = (0..100).map(|i| (i % 10) as f64).collect();
    let mut t2 = t.clone();
    t2.push_column("batch10".into(), steps.clone()).unwrap();
    let (s, _) = split_rows(&t2, &cfg).unwrap();
    let lowest_test = s
        .test
        .iter()
        .map(|&i| steps[i])
        .fold(f64::INFINITY, f64::min);
    assert!(
        s.train.iter().all(|&i| steps[i] < lowest_test),
        "a tie straddles the cut"
    );
    assert_eq!(s.test.len(), 30, "the tied rows of 7 join the test side");
    // a constant column has no high end to test on
    t2.push_column("flat".into(), vec![2.0; 100]).unwrap();
    cfg.extrapolate = Some("flat".into());
    let e = split_rows(&t2, &cfg).unwrap_err().to_string();
    assert!(
        e.contains("`flat`") && e.contains("no value above the others"),
        "{e}"
    );
}

/// `compare` scores the five models on one split and summarises k folds.
#[test]
fn compare_reports_every_model_and_the_folds() {
    let t = roughness(200, 1e-4, 5);
    let mut cfg = cfg_roughness();
    cfg.search.epochs = 2;
    cfg.search.candidates_per_epoch = 150;
    let c = compare(&t, &cfg, 3, &mut |_| {}).unwrap();
    let names: Vec<&str> = c.models.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, COMPARE_MODELS);
    assert_eq!(c.cv.len(), COMPARE_MODELS.len());
    for s in &c.cv {
        assert_eq!(s.r2_folds.len(), 3);
        assert!(s.r2_ci[0] <= s.r2_mean && s.r2_mean <= s.r2_ci[1]);
    }
    assert_eq!(c.t_test.as_ref().unwrap().baseline, "physics");
    assert_eq!(c.t_tests.len(), 5);
    let score = |n: &str| c.models.iter().find(|m| m.name == n).unwrap().metrics.rmse;
    // with k = 1 the uncalibrated law is 1.3x off: calibration must help
    assert!(score("physics_calibrated") < score("physics"));
    assert!(score("hybrid") < score("physics_calibrated"));
    // same split as fit
    let m = fit(&t, &cfg, &mut |_| {}).unwrap();
    assert_eq!(m.split, c.hybrid.split);
}

mod errors;
