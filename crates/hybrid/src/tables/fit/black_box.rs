//! The black boxes beside the hybrid on one split: the calibrated physics plus a random
//! forest on its `delta`, and gradient boosting of the target
//! ([`black_box_predictions`]); and their test errors against the fitted model's
//! ([`black_box_scores`], the model file's `scores.black_boxes`).

use super::super::TableConfig;
use super::super::model::{BlackBox, BlackBoxScores, TableModel, columns_of, combine_values};
use super::super::physics::{deltas, gather};
use super::super::resolve::Resolved;
use super::job::{Calibrated, SplitJob};
use crate::HybridError;
use hxai_baselines::{GradientBoosting, Par, RandomForest, Regressor};
use hxai_eval::Split;
use hxai_symreg::Table;

/// A random forest of `delta` (training rows of `split`) on `features`, predicted on the
/// test rows.
fn forest_delta(
    table: &Table,
    features: &[String],
    split: &Split,
    delta: &[f64],
    seed: u64,
    par: Par,
) -> Result<Vec<f64>, HybridError> {
    columns_of(table, features, "feature")?;
    let x = table.select_columns(features)?;
    let pick = |rows: &[usize]| -> Result<Table, HybridError> { Ok(x.select_rows(rows)?) };
    let mut forest = RandomForest::with_seed(seed);
    forest.par = par;
    forest.fit(&pick(&split.train)?, delta)?;
    Ok(forest.predict(&pick(&split.test)?)?)
}

/// Gradient boosting ([`GradientBoosting`], scikit-learn's `HistGradientBoostingRegressor`
/// defaults) of the target itself on `columns` (the physics' columns and the correction's
/// features): the black box an engineer reaches for, with no physics.
fn boosting_on(
    table: &Table,
    columns: &[String],
    split: &Split,
    y_train: &[f64],
    seed: u64,
    par: Par,
) -> Result<Vec<f64>, HybridError> {
    let x = table.select_columns(columns)?;
    let mut b = GradientBoosting::with_seed(seed);
    b.par = par;
    b.fit(&x.select_rows(&split.train)?, y_train)?;
    Ok(b.predict(&x.select_rows(&split.test)?)?)
}

/// The black boxes' test-row predictions on `split`: the calibrated `physics` (every row)
/// plus a forest on its `delta`, and gradient boosting of the target on the physics' columns
/// and the correction's features.
pub(crate) fn black_box_predictions(
    table: &Table,
    cfg: &TableConfig,
    res: &Resolved,
    split: &Split,
    physics: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), HybridError> {
    let y = table.require(&cfg.target)?;
    let delta = deltas(cfg.correction, y, physics, &split.train)?;
    let d = forest_delta(
        table,
        &res.features,
        split,
        &delta,
        cfg.seed,
        cfg.search.par,
    )?;
    let forest = split
        .test
        .iter()
        .zip(&d)
        .map(|(&i, &d)| combine_values(cfg.correction, physics[i], d))
        .collect();
    let mut columns = res.columns.clone();
    for f in &res.features {
        if !columns.contains(f) {
            columns.push(f.clone());
        }
    }
    let boosted = boosting_on(
        table,
        &columns,
        split,
        &gather(y, &split.train),
        cfg.seed,
        cfg.search.par,
    )?;
    Ok((forest, boosted))
}

/// Training rows the fit's black boxes are trained on at most (issue 67: a forest on 10^6
/// rows took longer than the whole hybrid): a larger table's black boxes are trained on a
/// sample of this many training rows stratified on the target, and the model says so
/// (`scores.black_boxes.training_rows`). `hxai hybrid compare` trains them on every row.
pub const BLACK_BOX_ROWS: usize = 20_000;

/// The black boxes of `hxai hybrid compare` (physics + forest, boosting) on `job`'s split,
/// from its calibrated physics `cal` (the fit's), scored against the fitted `model`'s test
/// RMSE; `None` with fewer than two test rows, or where a black box has no error (the ratio
/// would not be a number). Trained on at most [`BLACK_BOX_ROWS`] training rows.
pub(crate) fn black_box_scores(
    job: SplitJob,
    cal: &Calibrated,
    model: &TableModel,
) -> Result<Option<BlackBoxScores>, HybridError> {
    let (table, cfg, split) = (job.table, job.cfg, job.split);
    let Some(test) = model.scores.test.as_ref().filter(|_| split.test.len() >= 2) else {
        return Ok(None);
    };
    let y = table.require(&cfg.target)?;
    let yt = gather(y, &split.test);
    let sample = super::job::sample_of(job, &cal.res, BLACK_BOX_ROWS)?;
    let sub;
    let on = match &sample {
        Some(rows) => {
            sub = Split {
                train: rows.clone(),
                test: split.test.clone(),
            };
            &sub
        }
        None => split,
    };
    let (forest, boosted) = black_box_predictions(table, cfg, &cal.res, on, &cal.physics)?;
    let physics_forest = hxai_eval::rmse(&yt, &forest)?;
    let boosting = hxai_eval::rmse(&yt, &boosted)?;
    let best_black_box = if boosting < physics_forest {
        BlackBox {
            name: "boosting".into(),
            rmse: boosting,
        }
    } else {
        BlackBox {
            name: "physics_forest".into(),
            rmse: physics_forest,
        }
    };
    let ratio = test.hybrid.rmse / best_black_box.rmse;
    // a black box without error (a constant target) leaves no ratio to report
    if !(ratio.is_finite() && physics_forest.is_finite() && boosting.is_finite()) {
        return Ok(None);
    }
    Ok(Some(BlackBoxScores {
        physics_forest,
        boosting,
        hybrid_over_best_black_box: ratio,
        best_black_box,
        training_rows: sample.map(|r| r.len()),
    }))
}
