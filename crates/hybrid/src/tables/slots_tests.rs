//! Tests of learned slots: the bump times a power, a slot over two columns, a slot
//! beside a per-class constant, and the refusals.

use super::super::{Form, TableConfig, fit};
use crate::HybridError;
use hxai_symreg::Table;

/// A deterministic uniform in [0, 1) from an index (no random crate in tests).
fn u(i: usize, k: u64) -> f64 {
    let mut x =
        (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ k.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 31;
    x = x.wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^= x >> 29;
    (x >> 11) as f64 / (1u64 << 53) as f64
}

/// A standard normal by Box-Muller from two uniforms.
fn normal(i: usize, k: u64) -> f64 {
    let (a, b) = (u(i, k).max(1e-12), u(i, k + 1));
    (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
}

/// The table: `1.7 exp(-((E - 0.9)/0.2)^2) C^0.3` with 3 % noise.
fn bump_table(n: usize) -> (Table, f64) {
    let e: Vec<f64> = (0..n).map(|i| 0.4 + u(i, 1)).collect();
    let c: Vec<f64> = (0..n).map(|i| 0.5 + 9.5 * u(i, 2)).collect();
    let truth: Vec<f64> = (0..n)
        .map(|i| 1.7 * (-((e[i] - 0.9) / 0.2).powi(2)).exp() * c[i].powf(0.3))
        .collect();
    let noise = 0.03 * truth.iter().sum::<f64>() / n as f64;
    let y: Vec<f64> = (0..n).map(|i| truth[i] + noise * normal(i, 3)).collect();
    let t = Table::new(vec!["E".into(), "C".into(), "NOx".into()], vec![e, c, y]).unwrap();
    (t, noise)
}

fn bump_config() -> TableConfig {
    let mut cfg = TableConfig::new("NOx", "A*exp(-((E - E0)/w)^2)*f(C)");
    cfg.calibrate = vec!["A".into(), "E0".into(), "w".into()];
    cfg.init = [("E0".into(), 1.0), ("w".into(), 0.3)].into();
    cfg.form = Form::Auto;
    cfg.conformal_folds = 0;
    cfg
}

/// The goal: the slot becomes a power of C, and the test RMSE is within 1.3x the
/// noise.
#[test]
fn a_bump_times_a_learned_power() {
    let (table, noise) = bump_table(400);
    let model = fit(&table, &bump_config(), &mut |_| {}).unwrap();
    let slot = &model.slots[0];
    assert_eq!(
        (slot.name.as_str(), slot.columns.as_slice()),
        ("f", &["C".to_string()][..])
    );
    assert!(
        slot.template.contains("C^") || slot.template.contains("C**"),
        "{slot:?}"
    );
    let rmse = model.scores.test.as_ref().unwrap().hybrid.rmse;
    assert!(
        rmse <= 1.3 * noise,
        "test RMSE {rmse} vs noise {noise}: {}",
        model.physics.equation
    );
    // the exponent is 0.3 within its interval, and the file says so
    let exponent = slot
        .uncertainty
        .values()
        .find(|p| (p.value - 0.3).abs() < 0.1)
        .unwrap_or_else(|| panic!("{slot:?}"));
    let [lo, hi] = exponent.ci95.unwrap();
    assert!(lo <= 0.3 && 0.3 <= hi, "{exponent:?}");
    // the physics alone at `none` has no training error of its own (NaN), so the file is
    // compared as text
    let back = super::super::TableModel::from_json(&model.to_json()).unwrap();
    assert_eq!(back.to_json(), model.to_json());
    assert!(
        model.warnings.iter().all(|w| !w.contains("cannot tell")),
        "{:?}",
        model.warnings
    );
    let p = back.predict(&table).unwrap().hybrid;
    let q = model.predict(&table).unwrap().hybrid;
    assert_eq!(p, q);
}

/// A slot over two columns: `k*g(T, v)` with `g = T^0.5 v^-0.2`.
#[test]
fn a_slot_of_two_columns() {
    let n = 300;
    let t: Vec<f64> = (0..n).map(|i| 300.0 + 500.0 * u(i, 4)).collect();
    let v: Vec<f64> = (0..n).map(|i| 1.0 + 9.0 * u(i, 5)).collect();
    let y: Vec<f64> = (0..n)
        .map(|i| 2.0 * t[i].sqrt() * v[i].powf(-0.2) * (1.0 + 0.01 * normal(i, 6)))
        .collect();
    let table = Table::new(vec!["T".into(), "v".into(), "y".into()], vec![t, v, y]).unwrap();
    let mut cfg = TableConfig::new("y", "k*g(T, v)");
    cfg.calibrate = vec!["k".into()];
    cfg.form = Form::Factors;
    cfg.conformal_folds = 0;
    let model = fit(&table, &cfg, &mut |_| {}).unwrap();
    let slot = &model.slots[0];
    assert_eq!(slot.columns, vec!["T".to_string(), "v".to_string()]);
    assert!(
        slot.template.contains('T') && slot.template.contains('v'),
        "{slot:?}"
    );
    let r2 = model.scores.test.as_ref().unwrap().hybrid.r2;
    assert!(r2 > 0.99, "R² {r2}: {}", model.physics.equation);
}

/// A slot beside a per-class constant: the physics `A[level]*f(C)` keeps one `A` per level
/// and one learned `f`.
#[test]
fn a_slot_beside_a_per_class_constant() {
    let (mut table, noise) = bump_table(300);
    let cells: Vec<String> = (0..300)
        .map(|i| if i % 2 == 0 { "a".into() } else { "b".into() })
        .collect();
    // level b reads 20 % higher
    let (names, mut cols) = table.clone().into_parts();
    for (i, y) in cols[2].iter_mut().enumerate() {
        if i % 2 == 1 {
            *y *= 1.2;
        }
    }
    table = Table::new(names, cols).unwrap();
    let mut cfg = bump_config();
    cfg.calibrate = vec!["E0".into(), "w".into()];
    let info =
        super::super::per_class::expand(&mut cfg, &mut table, "line", &cells, &["A".to_string()]);
    // `A` is not yet calibrated: per-class expansion needs it in the equation
    let info = info.unwrap();
    let model = fit(&table, &cfg, &mut |_| {}).unwrap();
    let a = |l: &str| model.physics.parameters[&super::super::PerClassInfo::parameter("A", l)];
    let ratio = a("b") / a("a");
    assert!((ratio - 1.2).abs() < 0.05, "A[b]/A[a] = {ratio}");
    assert_eq!(model.slots.len(), 1);
    let rmse = model.scores.test.as_ref().unwrap().hybrid.rmse;
    assert!(rmse <= 1.5 * noise * 1.1, "{rmse} vs {noise}");
    assert_eq!(info.parameters, vec!["A".to_string()]);
}

/// Refusals: a slot over a column the table lacks, over the target, named as a column, and
/// with `--form none`.
#[test]
fn bad_slots_are_refused_by_name() {
    let (table, _) = bump_table(60);
    let cases: [(&str, Form, &str); 5] = [
        ("A*sqr(C)", Form::Auto, "one letter from `sqrt`"),
        ("A*f(Q)", Form::Auto, "Q"),
        ("A*f(NOx)", Form::Auto, "target"),
        ("A*E(C)", Form::Auto, "column"),
        ("A*f(C)", Form::None, "--form none"),
    ];
    for (physics, form, says) in cases {
        let mut cfg = TableConfig::new("NOx", physics);
        cfg.calibrate = vec!["A".into()];
        cfg.form = form;
        let err = fit(&table, &cfg, &mut |_| {}).unwrap_err();
        let text = err.to_string();
        assert!(text.contains(says), "{physics}: {text}");
        if physics == "A*f(Q)" {
            assert!(matches!(
                err,
                HybridError::MissingColumn {
                    what: "slot column",
                    ..
                }
            ));
        }
    }
}
