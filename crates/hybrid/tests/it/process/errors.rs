//! Every bad input of a table fit gives one line naming the culprit: unknown names,
//! unusable physics values (named by row), and names that only look like constants.

use super::*;

/// `pi` inside a longer name (`pipe`, `api`) is that name, not the constant: such columns
/// are not refused.
fn uses_pi_word_boundaries() -> bool {
    let pipe: Vec<f64> = (0..40).map(|i| 1.0 + i as f64 * 0.1).collect();
    let api: Vec<f64> = (0..40).map(|i| ((i * 7) % 11) as f64).collect();
    let y: Vec<f64> = pipe
        .iter()
        .zip(&api)
        .map(|(p, a)| 2.0 * p + 0.1 * a)
        .collect();
    let t = Table::new(
        vec!["pipe".into(), "api".into(), "y".into()],
        vec![pipe, api, y],
    )
    .unwrap();
    let mut c = quick(TableConfig::new("y", "k*pipe"));
    c.calibrate = vec!["k".into()];
    match fit(&t, &c, &mut |_| {}) {
        Ok(_) => true,
        Err(e) => panic!("{e}"),
    }
}

fn err(cfg: &TableConfig, t: &Table) -> String {
    let e = fit(t, cfg, &mut |_| {}).unwrap_err();
    let s = e.to_string();
    assert!(!s.contains('\n'), "one line: {s}");
    s
}

/// Every bad input of issue 13 gives a one-line error naming the culprit.
#[test]
fn bad_input_is_named() {
    let t = roughness(60, 0.0, 6);
    // a name that is neither a column nor a parameter
    let mut c = cfg_roughness();
    c.physics = "k*f^2/(32*rr)".into();
    let s = err(&c, &t);
    assert!(s.contains("`rr`") && s.contains("character 11"), "{s}");
    // a parameter that is also a column
    let mut c = cfg_roughness();
    c.calibrate = vec!["k".into(), "r".into()];
    let s = err(&c, &t);
    assert!(s.contains("`r`") && s.contains("column"), "{s}");
    let mut c = cfg_roughness();
    c.set = BTreeMap::from([("v".into(), 1.0)]);
    assert!(err(&c, &t).contains("`v`"));
    // a calibrated parameter that does not appear
    let mut c = cfg_roughness();
    c.calibrate.push("n".into());
    let s = err(&c, &t);
    assert!(s.contains("`n`") && s.contains("does not appear"), "{s}");
    // a syntax error
    let mut c = cfg_roughness();
    c.physics = "k*f^2/(32*r".into();
    let s = err(&c, &t);
    assert!(s.contains("character 12") && s.contains("`)`"), "{s}");
    // an empty feature set
    let mut c = cfg_roughness();
    c.exclude = vec!["f".into(), "r".into(), "v".into(), "d".into()];
    let s = err(&c, &t);
    assert!(s.contains("no feature column"), "{s}");
    assert!(matches!(
        fit(&t, &c, &mut |_| {}),
        Err(HybridError::NoFeatures(_))
    ));
    // the target inside the physics
    let mut c = cfg_roughness();
    c.physics = "k*f^2/(32*r) + 0*Ra".into();
    let s = err(&c, &t);
    assert!(
        s.contains("target") && s.contains("`Ra`") && s.contains("character 18"),
        "{s}"
    );
    // the target as the group column
    let mut c = cfg_roughness();
    c.group = Some("Ra".into());
    let s = err(&c, &t);
    assert!(s.contains("group column `Ra` is the target"), "{s}");
    // a column named `pi`: the physics would read the constant, the printed hybrid would be
    // ambiguous; refused in the physics and as a feature, accepted when left out
    let named_pi = Table::new(
        t.names()
            .iter()
            .map(|n| if n == "d" { "pi".into() } else { n.clone() })
            .collect(),
        t.names()
            .iter()
            .map(|n| t.require(n).unwrap().to_vec())
            .collect(),
    )
    .unwrap();
    let mut c = cfg_roughness();
    c.physics = "k*f^2/(32*r) + 0*pi".into();
    c.exclude = vec!["pi".into()];
    let s = err(&c, &named_pi);
    assert!(
        s.contains("`pi`") && s.contains("as the physics does here"),
        "{s}"
    );
    let s = err(&cfg_roughness(), &named_pi);
    assert!(s.contains("`pi`") && s.contains("--exclude pi"), "{s}");
    let mut c = cfg_roughness();
    c.exclude = vec!["pi".into()];
    assert!(fit(&named_pi, &c, &mut |_| {}).is_ok());
    assert!(uses_pi_word_boundaries());
    // one test row: no test scores (a warning says why), and neither evaluate nor compare
    // scores it
    let mut c = cfg_roughness();
    c.test_fraction = 0.01;
    let m = fit(&t, &c, &mut |_| {}).unwrap();
    assert_eq!(m.split.test.len(), 1);
    assert!(m.scores.test.is_none());
    assert!(
        m.warnings.iter().any(|w| w.contains("1 row")),
        "{:?}",
        m.warnings
    );
    let one = t.select_rows(&m.split.test).unwrap();
    let e = m.evaluate(&one).unwrap_err().to_string();
    assert!(e.contains("at least 2"), "{e}");
    let e = compare(&t, &c, 0, &mut |_| {}).unwrap_err().to_string();
    assert!(
        e.contains("at least") && e.contains("--test-fraction"),
        "{e}"
    );
    // one fold: nothing to train on (0 skips the cross-validation)
    let e = compare(&t, &cfg_roughness(), 1, &mut |_| {}).unwrap_err();
    assert!(e.to_string().contains("at least 2 folds"), "{e}");
    // a missing target, an unknown feature
    let mut c = cfg_roughness();
    c.target = "Rz".into();
    assert!(err(&c, &t).contains("`Rz`"));
    let mut c = cfg_roughness();
    c.features = Some(vec!["q".into()]);
    assert!(err(&c, &t).contains("`q`"));
    // an unknown function
    let mut c = cfg_roughness();
    c.physics = "k*sqr(f)".into();
    let s = err(&c, &t);
    assert!(s.contains("`sqr`") && s.contains("character 3"), "{s}");
}

/// The physics must be usable at every row: zero (multiplicative) or non-finite values are
/// refused with the row named.
#[test]
fn unusable_physics_names_the_row() {
    let mut t = roughness(50, 0.0, 7);
    let mut z = vec![1.0; 50];
    z[17] = 0.0;
    t.push_column("z".into(), z).unwrap();
    let mut c = cfg_roughness();
    c.physics = "k*z*f^2/(32*r)".into();
    c.exclude = vec!["z".into()];
    c.correction = CorrectionForm::Multiplicative;
    let split = hxai_eval::Split {
        train: (0..50).collect(),
        test: vec![],
    };
    let e = fit_split(&t, &c, &split, &mut |_| {})
        .unwrap_err()
        .to_string();
    // Index 17 is row 18 counted from 1, as the file shows it (issue 27: one convention).
    assert!(e.contains("row 18 ") && e.contains("multiplicative"), "{e}");
    c.physics = "k*log(z)".into();
    c.correction = CorrectionForm::Additive;
    let e = fit_split(&t, &c, &split, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("row 18 ") && e.contains("finite"), "{e}");
}

/// Settings that need no table are refused by `TableConfig::check` before any search has
/// run (a single conformal fold used to be refused only after the whole fit): no progress
/// is reported, for `fit` and `compare` alike.
#[test]
fn settings_are_checked_before_any_work() {
    let t = roughness(60, 0.0, 6);
    let mut bad = vec![];
    let mut c = cfg_roughness();
    c.conformal_folds = 1;
    bad.push((c, "conformal fold"));
    let mut c = cfg_roughness();
    c.joint = true;
    c.correction_per = Some(hxai_hybrid::tables::CorrectionPer {
        column: "d".into(),
        levels: vec!["a".into(), "b".into()],
    });
    bad.push((c, "--joint with --correction-per"));
    let mut c = cfg_roughness();
    c.search.operators = vec!["add".into(), "frobnicate".into()];
    bad.push((c, "frobnicate"));
    for (cfg, needle) in bad {
        assert!(cfg.check().is_err(), "{needle}");
        let mut reported = 0;
        let e = fit(&t, &cfg, &mut |_| reported += 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{needle}: {e}");
        let e = compare(&t, &cfg, 2, &mut |_| reported += 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains(needle), "{needle}: {e}");
        assert_eq!(reported, 0, "{needle}: a search ran before the refusal");
    }
    // the checked value reads as its configuration, and its search configuration carries
    // the table's seed (which overrides the search's own) and the parsed operators
    let mut c = cfg_roughness();
    c.seed = 7;
    c.search.seed = 99;
    let checked = c.check().unwrap();
    assert_eq!(checked.target, c.target);
    assert_eq!(checked.config().physics, c.physics);
    assert_eq!(checked.search().seed, 7);
    assert_eq!(checked.search().operators().len(), c.search.operators.len());
}

/// A typo in the physics among 40 long column names names the three nearest columns, not
/// all 40 (issue 63).
#[test]
fn a_typo_among_many_columns_names_the_nearest() {
    let n = 30;
    let mut names: Vec<String> = (0..40)
        .map(|i| format!("measured_spindle_temperature_channel_{i:02}"))
        .collect();
    let mut cols: Vec<Vec<f64>> = (0..40)
        .map(|i| (0..n).map(|r| ((r * (i + 3)) % 17) as f64).collect())
        .collect();
    names.push("y".into());
    cols.push((0..n).map(|r| r as f64).collect());
    let t = Table::new(names, cols).unwrap();
    let mut c = quick(TableConfig::new(
        "y",
        "k*measured_spindle_temperatur_channel_03",
    ));
    c.calibrate = vec!["k".into()];
    let s = err(&c, &t);
    assert!(
        s.contains("the nearest of 41: measured_spindle_temperature_channel_03,"),
        "{s}"
    );
    assert!(!s.contains("channel_39"), "{s}");
}

/// A target of 1e300 (a missing-value code, a unit mistake) is refused naming its row,
/// where the search said only that no candidate had a finite loss (issue 63).
#[test]
fn a_huge_target_is_named_by_its_row() {
    let mut t = roughness(40, 0.0, 7);
    let mut y = t.column("Ra").unwrap().to_vec();
    y[7] = -1e300;
    t.remove_column("Ra").unwrap();
    t.push_column("Ra".into(), y).unwrap();
    let s = err(&cfg_roughness(), &t);
    assert!(s.contains("row 8") && s.contains("-1e300"), "{s}");
}
