//! Per-class constants of the physics (`--calibrate-per`, issue 48) on `MASS::whiteside`:
//! gas consumption against outside temperature, before and after cavity-wall insulation.
//! One line per level, `a[level] + b[level]*temp`, calibrated on all 56 weeks, must equal R's
//! `lm(Gas ~ Insul/Temp)`: the reference values and standard errors were written by
//! `scripts/ref_per_class.py` (numpy's least squares, checked against statsmodels) to
//! `testdata/per_class/whiteside_lm.json`. Tolerance: 1e-6 relative (issue 48's goal).
use hxai_eval::Split;
use hxai_hybrid::tables::{TableConfig, fit_split, per_class};
use hxai_symreg::Table;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The whiteside table: the numeric columns and the `insul` cells.
fn whiteside() -> (Table, Vec<String>) {
    let text = std::fs::read_to_string(root().join("testdata/real/whiteside.csv")).expect("csv");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("insul,temp,gas"));
    let (mut insul, mut temp, mut gas) = (Vec::new(), Vec::new(), Vec::new());
    for l in lines.filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = l.split(',').collect();
        insul.push(f[0].to_string());
        temp.push(f[1].parse::<f64>().expect("temp"));
        gas.push(f[2].parse::<f64>().expect("gas"));
    }
    let t = Table::new(vec!["temp".into(), "gas".into()], vec![temp, gas]).expect("table");
    (t, insul)
}

fn close(got: f64, want: f64, what: &str) {
    assert!(
        (got - want).abs() <= 1e-6 * want.abs(),
        "{what}: hxai {got}, reference {want}"
    );
}

#[test]
fn whiteside_lines_per_level_equal_rs_lm() {
    let (mut table, insul) = whiteside();
    let mut cfg = TableConfig::new("gas", "a + b*temp");
    cfg.search.epochs = 1;
    cfg.search.candidates_per_epoch = 50;
    cfg.conformal_folds = 0;
    let info = per_class::expand(
        &mut cfg,
        &mut table,
        "insul",
        &insul,
        &["a".to_string(), "b".to_string()],
    )
    .expect("expand");
    assert_eq!(info.levels, ["After", "Before"]);
    assert!(
        cfg.exclude.contains(&"insul=After".to_string()),
        "indicators are not features"
    );
    // calibrated on every row, as lm is
    let split = Split {
        train: (0..table.n_rows()).collect(),
        test: Vec::new(),
    };
    let model = fit_split(&table, &cfg, &split, &mut |_| {}).expect("fit");
    let reference: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("testdata/per_class/whiteside_lm.json"))
            .expect("reference"),
    )
    .expect("json");
    for level in ["After", "Before"] {
        let r = &reference["levels"][level];
        let p = &model.physics;
        for (param, key) in [("a", "intercept"), ("b", "slope")] {
            let name = format!("{param}[{level}]");
            close(p.parameters[&name], r[key].as_f64().expect("value"), &name);
            let se = p.standard_errors[&name].expect("standard error");
            close(
                se,
                r[format!("{key}_se")].as_f64().expect("se"),
                &format!("se {name}"),
            );
        }
    }
    // the correction never reads the level indicators
    if let Some(m) = &model.correction.model {
        assert!(
            m.feature_names.iter().all(|f| !f.contains('=')),
            "{:?}",
            m.feature_names
        );
    }
}

/// A parameter named per class must be in the physics, not fixed, and the column must have
/// two levels or more; each refusal names what is wrong.
#[test]
fn bad_per_class_settings_are_refused_by_name() {
    let (table, insul) = whiteside();
    let try_expand = |physics: &str, params: &[&str], cells: &[String], set: Option<&str>| {
        let mut cfg = TableConfig::new("gas", physics);
        if let Some(s) = set {
            cfg.set.insert(s.to_string(), 1.0);
        }
        let mut t = table.clone();
        let params: Vec<String> = params.iter().map(|s| s.to_string()).collect();
        per_class::expand(&mut cfg, &mut t, "insul", cells, &params)
            .map(|_| ())
            .expect_err("refused")
            .to_string()
    };
    let e = try_expand("a + b*temp", &["c"], &insul, None);
    assert!(e.contains("`c`"), "{e}");
    let e = try_expand("a + b*temp", &["a"], &insul, Some("a"));
    assert!(e.contains("--set"), "{e}");
    let one: Vec<String> = vec!["Before".into(); insul.len()];
    let e = try_expand("a + b*temp", &["a"], &one, None);
    assert!(e.contains("one level"), "{e}");
    let mut gap = insul.clone();
    gap[4] = String::new();
    let e = try_expand("a + b*temp", &["a"], &gap, None);
    assert!(e.contains("row 5") && e.contains("empty level"), "{e}");
}

/// Ten levels of 2-4 rows and a random 20 % split (issue 63): every level keeps training
/// rows at every seed, so its constant is fitted, not left at its start; a level of one row
/// is refused by name.
#[test]
fn a_random_split_keeps_every_level_in_the_training_rows() {
    use hxai_hybrid::HybridError;
    use hxai_hybrid::tables::split_rows;
    let mut cells = Vec::new();
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for level in 0..10 {
        for r in 0..(2 + level % 3) {
            cells.push(format!("L{level}"));
            let xv = 1.0 + r as f64;
            x.push(xv);
            y.push(10.0 * level as f64 + 2.0 * xv + 0.01 * (r as f64).sin());
        }
    }
    for seed in 0..20 {
        let mut table =
            Table::new(vec!["x".into(), "y".into()], vec![x.clone(), y.clone()]).expect("table");
        let mut cfg = TableConfig::new("y", "a + b*x");
        cfg.calibrate = vec!["b".into()];
        cfg.seed = seed;
        per_class::expand(&mut cfg, &mut table, "lvl", &cells, &["a".to_string()]).expect("expand");
        let (split, kind) = split_rows(&table, &cfg).expect("split");
        assert_eq!(kind, "random");
        assert!(!split.test.is_empty());
        for level in 0..10 {
            let ind = table.column(&format!("lvl=L{level}")).expect("indicator");
            assert!(
                split.train.iter().any(|&i| ind[i] == 1.0),
                "seed {seed}: level L{level} has no training row"
            );
        }
    }
    let mut one = cells.clone();
    one[0] = "lonely".into();
    let mut table = Table::new(vec!["x".into(), "y".into()], vec![x, y]).expect("table");
    let mut cfg = TableConfig::new("y", "a + b*x");
    let err = per_class::expand(&mut cfg, &mut table, "lvl", &one, &["a".to_string()])
        .expect_err("a level of one row");
    match err {
        HybridError::InvalidConfig(m) => assert!(m.contains("\"lonely\" (1 row)"), "{m}"),
        other => panic!("{other}"),
    }
}

/// A level without training rows (a given split that holds all its rows out) leaves its
/// own constant undetermined, and only it: every other parameter keeps its standard error,
/// and the warning names that constant alone (issue 63: every error was dropped).
#[test]
fn a_level_without_training_rows_leaves_only_its_constant_undetermined() {
    let (mut table, insul) = whiteside();
    let mut cfg = TableConfig::new("gas", "a + b*temp");
    cfg.calibrate = vec!["b".into()];
    cfg.search.epochs = 1;
    cfg.search.candidates_per_epoch = 50;
    cfg.conformal_folds = 0;
    per_class::expand(&mut cfg, &mut table, "insul", &insul, &["a".to_string()]).expect("expand");
    let (train, test): (Vec<usize>, Vec<usize>) =
        (0..table.n_rows()).partition(|&i| insul[i] == "Before");
    let model = fit_split(&table, &cfg, &Split { train, test }, &mut |_| {}).expect("fit");
    let se = &model.physics.standard_errors;
    assert!(se["a[After]"].is_none(), "{se:?}");
    assert!(se["a[Before]"].is_some_and(|v| v > 0.0), "{se:?}");
    assert!(se["b"].is_some_and(|v| v > 0.0), "{se:?}");
    let w = model
        .warnings
        .iter()
        .find(|w| w.contains("a[After]"))
        .expect("a warning naming a[After]");
    assert!(!w.contains("a[Before]") && !w.contains(" b"), "{w}");
}
