//! Every way of modelling the target on the same splits (`hxai hybrid compare`).
use super::fit::{
    SplitJob, Task, black_box_predictions, calibrate_split, fit_calibrated, search_training_rows,
};
use super::model::BlackBox;
use super::model::defined_t_test;
use super::physics::{gather, physics_values};
use super::split::split_rows;
use super::{TableConfig, TableModel, TableProgress};
use crate::HybridError;
use hxai_eval::{Metrics, Split, TTest};
use hxai_symreg::Table;
use serde::{Deserialize, Serialize};

/// Test-split scores of one model.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ModelScore {
    /// `physics`, `physics_calibrated`, `symbolic`, `physics_forest`, `boosting` or
    /// `hybrid`.
    pub name: String,
    /// R^2, RMSE and MAE on the test rows (flattened into this object in JSON).
    #[serde(flatten)]
    pub metrics: Metrics,
}

/// Cross-validated R^2 of one model.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CvScore {
    /// Model name (as in [`ModelScore`]).
    pub name: String,
    /// Mean R^2 over the folds.
    pub r2_mean: f64,
    /// Sample standard deviation of R^2 over the folds.
    pub r2_sd: f64,
    /// Student-t 95 % interval of the mean.
    pub r2_ci: [f64; 2],
    /// Mean RMSE over the folds.
    pub rmse_mean: f64,
    /// R^2 of each fold.
    pub r2_folds: Vec<f64>,
}

/// A paired two-tailed t-test of per-row squared errors on the test rows.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct TTestScore {
    /// The model tested (`hybrid`).
    pub model: String,
    /// What it is compared with.
    pub baseline: String,
    /// The test on `se_baseline - se_model` (positive statistic: the model's errors are
    /// smaller); flattened into this object in JSON. `None` where the test is undefined
    /// (`reason` says why: the two models predict the same on every row).
    #[serde(flatten)]
    pub test: Option<TTest>,
    /// Why `test` is absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// What [`compare`] returns.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Comparison {
    /// The target column.
    pub target: String,
    /// Split kind (`random`, `grouped`, `extrapolate`).
    pub split: String,
    /// Training rows of the test split.
    pub n_train: usize,
    /// Test rows.
    pub n_test: usize,
    /// Test-split scores, in the order physics, physics_calibrated (with calibration),
    /// symbolic, physics_forest, boosting, hybrid.
    pub models: Vec<ModelScore>,
    /// The black box with the lowest test RMSE (`physics_forest` or `boosting`).
    pub best_black_box: BlackBox,
    /// The hybrid's test RMSE divided by the best black box's: below 1 the readable
    /// equation is the more accurate.
    pub hybrid_over_best_black_box: f64,
    /// k-fold cross-validation (empty when fewer than 2 folds were asked for).
    pub cv: Vec<CvScore>,
    /// Folds of the cross-validation.
    pub folds: usize,
    /// Hybrid vs the physics as given (uncalibrated), on the test rows; `null` where the
    /// test is undefined (`t_test_reason` says why), every other number still reported.
    pub t_test: Option<TTestScore>,
    /// Why `t_test` is `null`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_test_reason: Option<String>,
    /// Every paired test of the hybrid: vs `physics`, vs `physics_calibrated` (with
    /// calibration), vs `physics_forest`, vs `symbolic`.
    pub t_tests: Vec<TTestScore>,
    /// Coverage and median width of the hybrid's prediction intervals on the test rows
    /// (at [`crate::DEFAULT_INTERVAL`] by the model's default method; absent when the model
    /// has none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interval: Option<crate::IntervalReport>,
    /// The hybrid fitted on the test split's training rows.
    pub hybrid: TableModel,
}

/// Test-row predictions of every model on one split.
struct SplitPredictions {
    names: Vec<&'static str>,
    preds: Vec<Vec<f64>>,
    model: TableModel,
}

fn predictions_on(
    job: SplitJob,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<SplitPredictions, HybridError> {
    let (table, cfg, split, tasks) = (job.table, job.cfg, job.split, job.task);
    if split.test.is_empty() {
        return Err(HybridError::NoData("the split has no test rows".into()));
    }
    // resolved and calibrated once: the physics calibrated alone (the hybrid's own physics
    // differs under --joint), the forest on its delta and the hybrid's fit all start here
    let cal = calibrate_split(job)?;
    let (res, physics) = (&cal.res, &cal.physics);
    let y = table.require(&cfg.target)?;
    let mut names = vec!["physics"];
    let mut preds = vec![gather(
        &physics_values(table, res, &res.compiled)?,
        &split.test,
    )];
    if !res.calibrate.is_empty() {
        names.push("physics_calibrated");
        preds.push(gather(physics, &split.test));
    }

    let model = fit_calibrated(job, &cal, progress)?;
    let hp = model.predict(table)?;

    let label = format!("symbolic ({}/{})", tasks.0 + 1, tasks.1);
    let (_, sym) = search_training_rows(
        table,
        res,
        cfg,
        split,
        &gather(y, &split.train),
        Task {
            of: (tasks.0 + 1, tasks.1),
            label,
        },
        progress,
    )?;
    let test_table = table.select_rows(&split.test)?;
    names.push("symbolic");
    preds.push(sym.best.predict(&test_table)?);

    let (forest, boosted) = black_box_predictions(table, cfg, res, split, physics)?;
    names.push("physics_forest");
    preds.push(forest);
    names.push("boosting");
    preds.push(boosted);

    names.push("hybrid");
    preds.push(gather(&hp.hybrid, &split.test));
    Ok(SplitPredictions {
        names,
        preds,
        model,
    })
}

fn t_test(
    y: &[f64],
    model: &[f64],
    baseline: &[f64],
    mname: &str,
    bname: &str,
) -> Result<TTestScore, HybridError> {
    let se_m = hxai_eval::squared_errors(y, model)?;
    let se_b = hxai_eval::squared_errors(y, baseline)?;
    let (test, reason) = defined_t_test(&se_b, &se_m, &format!("{mname} and {bname}"))?;
    Ok(TTestScore {
        model: mname.into(),
        baseline: bname.into(),
        test,
        reason,
    })
}

/// Fits and scores, on the split of [`fit`](super::fit): `physics` (the
/// equation with `--init`/`--set` values, uncalibrated), `physics_calibrated` (when
/// parameters are calibrated), `symbolic` (symbolic regression of the target on the
/// features, no physics), `physics_forest` (calibrated physics + a random forest on the
/// same `delta`), `boosting` (gradient boosting of the target on the physics' columns and
/// the features, no physics), `hybrid`, and the hybrid's test RMSE over the best black
/// box's; then the same over `folds` folds (grouped when `cfg.group` is
/// set; skipped when `folds` is 0), and paired t-tests of the hybrid on the test rows. The
/// Student-t interval of the folds' mean R² is cut at 1, which no R² exceeds (with few
/// folds the symmetric interval can reach past it).
///
/// # Errors
/// As [`fit`](super::fit), fewer rows (or groups) than folds, a test split
/// of fewer than 2 rows, and
/// `folds` of 1 ([`HybridError::InvalidConfig`]: one fold has nothing to train on; 0 skips
/// the cross-validation).
pub fn compare(
    table: &Table,
    cfg: &TableConfig,
    folds: usize,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<Comparison, HybridError> {
    if folds == 1 {
        return Err(HybridError::InvalidConfig(
            "1 fold: cross-validation needs at least 2 folds (0 skips it)".into(),
        ));
    }
    let cfg = &cfg.check()?;
    let (split, kind) = split_rows(table, cfg)?;
    // learned slots are written out on the training rows once; every model and fold of the
    // comparison then starts from that physics (its slot constants calibrated per split)
    let slots = super::slots::expand(table, cfg, &split.train, progress)?;
    let cfg = slots.as_ref().map_or(cfg, |e| &e.cfg);
    if split.test.len() < 2 {
        return Err(HybridError::InvalidConfig(format!(
            "the test split has {} row(s): the comparison's R² and paired t-tests need at least \
             2; raise --test-fraction",
            split.test.len()
        )));
    }
    let cv_splits: Vec<Split> = if folds >= 2 {
        match &cfg.group {
            Some(g) => {
                let col = table.require(g)?;
                let keys: Vec<u64> = col.iter().map(|v| (v + 0.0).to_bits()).collect();
                hxai_eval::grouped_kfold(&keys, folds, cfg.seed)?
            }
            None => hxai_eval::kfold(table.n_rows(), folds, cfg.seed)?,
        }
    } else {
        Vec::new()
    };
    let tasks = 2 * (1 + cv_splits.len());
    let y = table.require(&cfg.target)?;
    let job = |split, kind, task| SplitJob {
        table,
        cfg,
        split,
        kind,
        task,
    };
    let main = predictions_on(job(&split, &kind, (1, tasks)), progress)?;
    let y_test = gather(y, &split.test);
    let mut models = Vec::new();
    for (name, p) in main.names.iter().zip(&main.preds) {
        models.push(ModelScore {
            name: (*name).to_string(),
            metrics: hxai_eval::score(&y_test, p)?,
        });
    }
    let pred_of = |name: &str| {
        main.names
            .iter()
            .position(|n| *n == name)
            .map(|i| main.preds[i].as_slice())
    };
    let hybrid = pred_of("hybrid").unwrap_or(&[]);
    let mut t_tests = Vec::new();
    for base in [
        "physics",
        "physics_calibrated",
        "physics_forest",
        "symbolic",
        "boosting",
    ] {
        if let Some(b) = pred_of(base) {
            t_tests.push(t_test(&y_test, hybrid, b, "hybrid", base)?);
        }
    }
    let (t_test_physics, t_test_reason) = match t_tests.first() {
        Some(t) if t.test.is_some() => (Some(t.clone()), None),
        Some(t) => (None, t.reason.clone()),
        None => (None, Some("no physics prediction to test against".into())),
    };
    let rmse_of = |name: &str| {
        models
            .iter()
            .find(|m| m.name == name)
            .map(|m| m.metrics.rmse)
    };
    let best_black_box = ["physics_forest", "boosting"]
        .into_iter()
        .filter_map(|n| {
            rmse_of(n).map(|r| BlackBox {
                name: n.to_string(),
                rmse: r,
            })
        })
        .min_by(|a, b| a.rmse.total_cmp(&b.rmse))
        .ok_or_else(|| HybridError::NoData("no black box was scored".into()))?;
    let hybrid_over_best_black_box = rmse_of("hybrid").unwrap_or(f64::NAN) / best_black_box.rmse;

    let mut per_model: Vec<(Vec<f64>, Vec<f64>)> = vec![(Vec::new(), Vec::new()); main.names.len()];
    for (f, s) in cv_splits.iter().enumerate() {
        let fold = predictions_on(job(s, "fold", (3 + 2 * f, tasks)), progress)?;
        let yt = gather(y, &s.test);
        for (k, p) in fold.preds.iter().enumerate() {
            let m = hxai_eval::score(&yt, p)?;
            per_model[k].0.push(m.r2);
            per_model[k].1.push(m.rmse);
        }
    }
    let mut cv = Vec::new();
    if !cv_splits.is_empty() {
        for (name, (r2s, rmses)) in main.names.iter().zip(&per_model) {
            let s = hxai_eval::summarize(r2s)?;
            cv.push(CvScore {
                name: (*name).to_string(),
                r2_mean: s.mean,
                r2_sd: s.std,
                r2_ci: [s.ci_t.lower.min(1.0), s.ci_t.upper.min(1.0)],
                rmse_mean: rmses.iter().sum::<f64>() / rmses.len() as f64,
                r2_folds: r2s.clone(),
            });
        }
    }
    let interval = match main.model.default_interval_method(crate::DEFAULT_INTERVAL) {
        Some(method) => main
            .model
            .test_interval(table, crate::DEFAULT_INTERVAL, method)?,
        None => None,
    };
    Ok(Comparison {
        interval,
        target: cfg.target.clone(),
        split: kind,
        n_train: split.train.len(),
        n_test: split.test.len(),
        models,
        cv,
        folds: cv_splits.len(),
        t_test: t_test_physics,
        t_test_reason,
        t_tests,
        best_black_box,
        hybrid_over_best_black_box,
        hybrid: main.model,
    })
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::t_test;

    /// Hybrid and baseline with the same predictions: the test row is kept with `None` and
    /// the reason (issue 63: `hybrid compare` aborted), and it serialises as an object without
    /// a p-value that reads back.
    #[test]
    fn an_undefined_t_test_is_a_result() {
        let y = [1.0, 2.5, 2.9, 4.2];
        let p = [1.1, 2.4, 3.0, 4.0];
        let t = t_test(&y, &p, &p, "hybrid", "physics_calibrated").unwrap();
        assert!(t.test.is_none());
        assert!(t.reason.as_deref().unwrap().contains("physics_calibrated"));
        let json = serde_json::to_string(&t).unwrap();
        assert!(!json.contains("p_value"), "{json}");
        let back: super::TTestScore = serde_json::from_str(&json).unwrap();
        assert_eq!(back, t);
        let defined = t_test(&y, &[1.0, 2.5, 2.95, 4.1], &p, "hybrid", "physics").unwrap();
        assert!(defined.test.is_some() && defined.reason.is_none());
        let back: super::TTestScore =
            serde_json::from_str(&serde_json::to_string(&defined).unwrap()).unwrap();
        assert_eq!(back, defined);
    }
}
