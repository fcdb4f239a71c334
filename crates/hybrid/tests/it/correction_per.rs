//! Per-class constants of the correction (`--correction-per`, issue 48): the same correction
//! structure for every batch, its constants per batch. A simulated table whose truth is
//! `y = 2*x + c[batch]*z` with `c` 1, 2.5 and 4 over three batches (1 % noise): the physics
//! `k*x` misses the `z` term, the shared correction finds one slope for it (the batches'
//! mean), and the per-batch refit recovers each batch's slope.
//!
//! Checked: the model file holds each level's constants, equation and training rows, and
//! reads back; each level's correction is linear in `z` with the batch's slope within 5 %
//! (1 % noise on 100 training rows a batch); the test RMSE is less than half the shared
//! correction's (a level-blind correction cannot follow three slopes); prediction refuses
//! a row in no level and intervals in words; `--joint` with it is refused.
use hxai_eval::Split;
use hxai_hybrid::tables::{TableConfig, TableModel, correction_per, fit_split};
use hxai_symreg::Table;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SLOPES: [f64; 3] = [1.0, 2.5, 4.0];

/// The table (x, z, y, and the batch of each row) and a split every third row to test.
fn table() -> (Table, Vec<String>, Split) {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let n = 450;
    let (mut x, mut z, mut y, mut batch) = (vec![], vec![], vec![], vec![]);
    for i in 0..n {
        let b = i % 3;
        let xi: f64 = rng.gen_range(1.0..5.0);
        let zi: f64 = rng.gen_range(0.5..3.0);
        let clean = 2.0 * xi + SLOPES[b] * zi;
        x.push(xi);
        z.push(zi);
        y.push(clean * (1.0 + 0.01 * rng.gen_range(-1.7..1.7)));
        batch.push(["A", "B", "C"][b].to_string());
    }
    let t = Table::new(vec!["x".into(), "z".into(), "y".into()], vec![x, z, y]).expect("table");
    let test: Vec<usize> = (0..n).filter(|i| (i / 3) % 4 == 0).collect();
    let train: Vec<usize> = (0..n).filter(|i| (i / 3) % 4 != 0).collect();
    (t, batch, Split { train, test })
}

fn config() -> TableConfig {
    let mut cfg = TableConfig::new("y", "k*x");
    cfg.calibrate = vec!["k".into()];
    cfg.search.epochs = 3;
    cfg.conformal_folds = 0;
    cfg
}

fn test_rmse(m: &TableModel) -> f64 {
    m.scores
        .test
        .as_ref()
        .map(|s| s.hybrid.rmse)
        .unwrap_or(f64::NAN)
}

#[test]
fn each_batch_gets_its_own_constants() {
    let (table, batch, split) = table();
    let shared = fit_split(&table, &config(), &split, &mut |_| {}).expect("shared fit");

    let mut cfg = config();
    let mut t = table.clone();
    let setting = correction_per::expand(&mut cfg, &mut t, "batch", &batch).expect("expand");
    assert_eq!(setting.levels, ["A", "B", "C"]);
    let per = fit_split(&t, &cfg, &split, &mut |_| {}).expect("per-level fit");
    let cp = per.correction_per.as_ref().expect("correction_per");
    assert_eq!(cp.levels, ["A", "B", "C"]);
    assert!(cp.shared.is_empty());
    assert_eq!(cp.rows.values().sum::<usize>(), split.train.len());
    // the per-level model's shared structure is the shared fit's (same search, same rows)
    assert_eq!(
        per.correction.forms.equation,
        shared.correction.forms.equation
    );

    // each level's correction, on z from 1 to 2 at fixed x, rises by its batch's slope
    // (plus what the physics' k missed of 2*x, which does not depend on z)
    let shared_model = per.correction.model.as_ref().expect("model");
    for (l, level) in cp.levels.iter().enumerate() {
        let m = cp.model_at(shared_model, level).expect("level model");
        let probe = Table::new(
            vec!["x".into(), "z".into()],
            vec![vec![3.0, 3.0], vec![1.0, 2.0]],
        )
        .expect("probe");
        let d = m.predict(&probe).expect("predict");
        let slope = d[1] - d[0];
        assert!(
            (slope - SLOPES[l]).abs() <= 0.05 * SLOPES[l],
            "level {level}: slope {slope}, truth {} ({})",
            SLOPES[l],
            cp.equations[level]
        );
    }
    let (a, b) = (test_rmse(&per), test_rmse(&shared));
    assert!(a < 0.5 * b, "per-level test RMSE {a}, shared {b}");

    // the file reads back, with the same predictions
    let back = TableModel::from_json(&per.to_json()).expect("read back");
    assert_eq!(back.correction_per, per.correction_per);
    let p1 = per.predict(&t).expect("predict").hybrid;
    let p2 = back.predict(&t).expect("predict").hybrid;
    assert_eq!(p1, p2);

    // a row in no level, and intervals, are refused in words
    let mut none = table.select_rows(&[0, 1]).expect("rows");
    for level in ["A", "B", "C"] {
        none.push_column(format!("batch={level}"), vec![0.0, 0.0])
            .expect("indicator");
    }
    let e = per
        .predict(&none)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.contains("row 1") && e.contains("no level"), "{e}");
    assert!(per.default_interval_method(0.95).is_none());
    let e = per
        .intervals_with(&t, 0.95, hxai_hybrid::IntervalMethod::Delta)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.contains("--correction-per"), "{e}");
}

#[test]
fn joint_with_per_level_constants_is_refused() {
    let (table, batch, split) = table();
    let mut cfg = config();
    cfg.joint = true;
    let mut t = table;
    correction_per::expand(&mut cfg, &mut t, "batch", &batch).expect("expand");
    let e = fit_split(&t, &cfg, &split, &mut |_| {})
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.contains("--joint"), "{e}");
}
