//! Believe the world, not the rows (issue 64): no correction with a pole beside the data,
//! and harmonics only on the columns declared periodic.
#![allow(clippy::unwrap_used)]

use hxai_hybrid::tables::{Form, TableConfig, TableModel, fit};
use hxai_symreg::Table;
use hxai_symreg::enclosure::{defined_over, widened_box};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Whether `m`'s correction is proven defined over its features' training box widened by
/// 10 % (the box).
fn correction_defined_beside_the_rows(m: &TableModel, t: &Table) -> bool {
    let c = m.correction.model.as_ref().unwrap();
    let train = t.select_rows(&m.split.train).unwrap();
    let cols: Vec<&[f64]> = c
        .feature_names
        .iter()
        .map(|n| train.column(n).unwrap())
        .collect();
    defined_over(&c.program, &c.params, &widened_box(&cols, 0.1), 256).is_ok()
}

/// `y = 2 x + 0.02/(x - 0.5) + noise`, rows on both sides of the pole but none within 0.04
/// of it, and a distractor `z`: the rows alone reward a pole at 0.5, inside their range.
fn pole_table(seed: u64) -> Table {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut x, mut z, mut y) = (Vec::new(), Vec::new(), Vec::new());
    while x.len() < 120 {
        let v: f64 = rng.gen_range(0.0..1.0);
        if (v - 0.5).abs() < 0.04 {
            continue;
        }
        x.push(v);
        z.push(rng.gen_range(0.0..1.0));
        y.push(2.0 * v + 0.02 / (v - 0.5) + rng.gen_range(-0.01..0.01));
    }
    Table::new(vec!["x".into(), "z".into(), "y".into()], vec![x, z, y]).unwrap()
}

/// A pole inside the rows is never selected, by the free form or the factor form, however
/// well it fits them.
#[test]
fn a_pole_inside_the_rows_is_never_selected() {
    let t = pole_table(3);
    for form in [Form::Free, Form::Factors] {
        let mut cfg = TableConfig::new("y", "k*x");
        cfg.calibrate = vec!["k".into()];
        cfg.form = form;
        cfg.search.epochs = 4;
        cfg.search.candidates_per_epoch = 500;
        let m = fit(&t, &cfg, &mut |_| {}).unwrap();
        assert!(
            correction_defined_beside_the_rows(&m, &t),
            "{form:?}: {}",
            m.correction.forms.sympy
        );
    }
    // the search without the rule finds the pole: the test has teeth
    let mut cfg = TableConfig::new("y", "k*x");
    cfg.calibrate = vec!["k".into()];
    cfg.search.epochs = 4;
    cfg.search.candidates_per_epoch = 500;
    cfg.search.defined_margin = None;
    let m = fit(&t, &cfg, &mut |_| {}).unwrap();
    assert!(
        !correction_defined_beside_the_rows(&m, &t),
        "without the rule: {}",
        m.correction.forms.sympy
    );
}

/// A table whose correction repeats over `a` (an angle) and grows with `f`.
fn periodic_table() -> Table {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut a, mut f, mut y) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..200 {
        let av: f64 = rng.gen_range(0.0..4.0 * std::f64::consts::PI);
        let fv: f64 = rng.gen_range(1.0..3.0);
        a.push(av);
        f.push(fv);
        y.push(5.0 * fv + 0.8 * av.sin() + rng.gen_range(-0.05..0.05));
    }
    Table::new(vec!["a".into(), "f".into(), "y".into()], vec![a, f, y]).unwrap()
}

/// No sine or cosine in a correction unless its column is declared periodic; declared,
/// the factor form finds the harmonic of the angle; a periodic column that is not a
/// feature is refused by name.
#[test]
fn harmonics_only_where_declared() {
    let t = periodic_table();
    let base = |form: Form| {
        let mut cfg = TableConfig::new("y", "k*f");
        cfg.calibrate = vec!["k".into()];
        cfg.form = form;
        cfg.search.epochs = 3;
        cfg.search.candidates_per_epoch = 400;
        cfg.search.operators = ["add", "sub", "mul", "div", "sin", "cos", "exp"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        cfg
    };
    let trig = |m: &TableModel| {
        let e = &m.correction.forms.sympy;
        e.contains("sin") || e.contains("cos")
    };
    for form in [Form::Free, Form::Factors] {
        let m = fit(&t, &base(form), &mut |_| {}).unwrap();
        assert!(
            !trig(&m),
            "{form:?} without --periodic: {}",
            m.correction.forms.sympy
        );
    }
    let mut declared = base(Form::Factors);
    declared.periodic = vec!["a".into()];
    let m = fit(&t, &declared, &mut |_| {}).unwrap();
    assert!(trig(&m), "declared: {}", m.correction.forms.sympy);
    let mut wrong = base(Form::Factors);
    wrong.periodic = vec!["y".into()];
    let e = fit(&t, &wrong, &mut |_| {}).unwrap_err().to_string();
    assert!(e.contains("--periodic y"), "{e}");
}

/// `--form auto` (issue 64): on a table whose physics is exact, the physics alone
/// (`none`); on a product of power laws that the physics lacks, the factors; the model file
/// says which and why, and reads back.
#[test]
fn auto_picks_none_for_exact_physics_and_factors_for_power_laws() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let n = 150;
    let (mut x, mut z, mut w): (Vec<f64>, Vec<f64>, Vec<f64>) =
        (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        x.push(rng.gen_range(1.0..5.0));
        z.push(rng.gen_range(1.0..4.0));
        w.push(rng.gen_range(0.5..2.0));
    }
    let noise: Vec<f64> = (0..n).map(|_| 1.0 + rng.gen_range(-0.01..0.01)).collect();
    let exact: Vec<f64> = (0..n).map(|i| 3.0 * x[i].powf(1.5) * noise[i]).collect();
    let power: Vec<f64> = (0..n)
        .map(|i| 2.0 * x[i] * z[i].powf(0.7) * w[i].powf(-0.5) * noise[i])
        .collect();
    let names = vec!["x".into(), "z".into(), "w".into(), "y".into()];
    let quick = |physics: &str| {
        let mut cfg = TableConfig::new("y", physics);
        cfg.calibrate = vec!["k".into()];
        cfg.form = Form::Auto;
        cfg.search.epochs = 3;
        cfg.search.candidates_per_epoch = 300;
        cfg.correction = hxai_hybrid::tables::CorrectionForm::Multiplicative;
        cfg
    };
    let t = Table::new(names.clone(), vec![x.clone(), z.clone(), w.clone(), exact]).unwrap();
    let m = fit(&t, &quick("k*x^1.5"), &mut |_| {}).unwrap();
    let choice = m.correction.choice.as_ref().unwrap();
    assert_eq!(choice.picked, "none", "{choice:?}");
    assert_eq!(m.correction.form, Some(hxai_hybrid::tables::Form::None));
    assert_eq!(m.predict(&t).unwrap().correction, vec![0.0; n]);
    // (the zero model's training loss is NaN: compare the files, not the values)
    let json = m.to_checked_json().unwrap();
    assert_eq!(TableModel::from_json(&json).unwrap().to_json(), json);

    let t = Table::new(names, vec![x, z, w, power]).unwrap();
    let m = fit(&t, &quick("k*x"), &mut |_| {}).unwrap();
    let choice = m.correction.choice.as_ref().unwrap();
    assert_eq!(choice.picked, "factors", "{choice:?}");
    assert!(
        choice.cv["factors"].mean < choice.cv["none"].mean / 10.0,
        "{choice:?}"
    );
    // (the zero model's training loss is NaN: compare the files, not the values)
    let json = m.to_checked_json().unwrap();
    assert_eq!(TableModel::from_json(&json).unwrap().to_json(), json);
}
