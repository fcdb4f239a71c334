//! Fitting a table model, in layers with no circle: `job` (one split's calibrated physics
//! and search), `search` (the correction in each concrete form), `earn`, `joint` and
//! `assemble` (its steps), `one` (the fit of one split in one form), `folds` and `auto`
//! (the form chosen by cross-validation of `one`'s fits), `black_box` (the black boxes
//! beside it); this file the public entry points and the stability of the correction's
//! structure.

mod assemble;
pub mod auto;
mod black_box;
mod earn;
mod folds;
pub(crate) mod job;
mod joint;
mod one;
mod search;

pub(crate) use black_box::black_box_predictions;
pub(crate) use job::{Calibrated, SplitJob, Task, calibrate_split, search_training_rows};
use job::{sample_method, search_sample};

use super::physics::deltas;
use super::split::{check_rows, split_rows};
use super::{Form, TableConfig, TableModel, TableProgress};
use crate::HybridError;
use hxai_eval::Split;
use hxai_symreg::Table;

/// The stability of the correction's structure of `model` (fitted with `cfg` on `table`):
/// the correction's search rerun on `runs` bootstrap resamples of the training rows, on
/// `delta` of the model's calibrated physics ([`hxai_symreg::stability()`]); on more than
/// `cfg.search_rows` training rows, resamples of the same stratified sample the structure
/// was searched on. `progress`
/// gets `(runs done, runs)`.
///
/// # Errors
/// A missing column, a physics value that cannot be used, and the search's errors.
pub fn stability(
    table: &Table,
    cfg: &TableConfig,
    model: &TableModel,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<hxai_symreg::Stability, HybridError> {
    let physics = model.predict(table)?.physics;
    let y = table.require(&model.target)?;
    // on the sample the structure was searched on (issue 67), when there was one
    let read: Vec<String> = model
        .physics
        .columns
        .iter()
        .chain(&model.correction.candidates)
        .cloned()
        .collect();
    let columns = job::columns_named(table, &read);
    let rows = search_sample(y, &columns, &model.split.train, cfg.search_rows, cfg.seed)
        .unwrap_or_else(|| model.split.train.clone());
    let delta = deltas(model.correction.kind, y, &physics, &rows)?;
    let ft = table
        .select_columns(&model.correction.candidates)?
        .select_rows(&rows)?;
    if model.correction.form == Some(Form::Factors) {
        let fp: Vec<f64> = rows.iter().map(|&i| physics[i]).collect();
        return Ok(hxai_symreg::factors::factor_stability_on_physics(
            &ft,
            &delta,
            &fp,
            model.correction.kind.link(),
            &cfg.factor_config(&model.correction.candidates),
            runs,
            progress,
        )?);
    }
    Ok(hxai_symreg::stability(
        &ft,
        &delta,
        &cfg.search_config(),
        runs,
        progress,
    )?)
}

/// The share of resamples below which a correction's structure is warned about (issue 64:
/// a structure that came back in 0 % of 20 resamples was reported without a word).
pub const LOW_SHARE: f64 = 0.2;

/// Measures the stability of `model`'s correction ([`stability`]) and stores it in the
/// model: `model.stability`, and the shares of its selection report (the structure's and
/// each alternative's, [`hxai_symreg::SelectionReport::with_stability`]). What `hxai
/// hybrid fit --stability N` and Python's `HybridRegressor(stability_runs=N)` run.
///
/// # Errors
/// Those of [`stability`].
pub fn measure_stability(
    table: &Table,
    cfg: &TableConfig,
    model: &mut TableModel,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<(), HybridError> {
    if model.correction.form == Some(Form::None) {
        // the physics alone: no structure to resample
        return Ok(());
    }
    let st = stability(table, cfg, model, runs, progress)?;
    let sel = model.correction.selection.take();
    model.correction.selection = sel.map(|sel| sel.with_stability(&st));
    model.stability = Some(st);
    if let Some(share) = model.correction.selection.as_ref().and_then(|s| s.share)
        && share < LOW_SHARE
    {
        model.warnings.push(format!(
            "the correction's structure came back in {:.0} % of the {runs} resamples (below \
             {:.0} %): the rows do not pin it down; read it as one of several that fit, or try \
             --form factors or none",
            100.0 * share,
            100.0 * LOW_SHARE
        ));
    }
    Ok(())
}

/// Fits on the split [`split_rows`] chooses.
///
/// # Errors
/// Bad configuration (see [`HybridError`]'s variants `UnknownName`, `ParameterIsColumn`,
/// `ParameterNotInEquation`, `TargetInPhysics`, `MissingColumn`, `NoFeatures`,
/// `Equation`), a physics value that cannot be used (`BadPhysics`), or a failed search.
pub fn fit(
    table: &Table,
    cfg: &TableConfig,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<TableModel, HybridError> {
    let cfg = &cfg.check()?;
    let (split, kind) = split_rows(table, cfg)?;
    let slots = super::slots::expand(table, cfg, &split.train, progress)?;
    let cfg = slots.as_ref().map_or(cfg, |e| &e.cfg);
    let job = SplitJob::single(table, cfg, &split, &kind);
    progress(&TableProgress::phase(
        format!(
            "calibrating the physics on {} training rows",
            split.train.len()
        ),
        0,
        1,
    ));
    let cal = calibrate_split(job)?;
    let mut model = fit_calibrated(job, &cal, progress)?;
    progress(&TableProgress::phase(
        format!(
            "black boxes beside the hybrid (forest, boosting) on {} training rows",
            split.train.len().min(black_box::BLACK_BOX_ROWS)
        ),
        0,
        1,
    ));
    model.scores.black_boxes = black_box::black_box_scores(job, &cal, &model)?;
    if let Some(e) = &slots {
        model.slots = e.finished(&model.physics.params, &model.physics.parameters);
    }
    Ok(model)
}

/// Fits on a given split (test rows may be empty: everything is then training data).
///
/// # Errors
/// As [`fit`], and row indices out of range.
pub fn fit_split(
    table: &Table,
    cfg: &TableConfig,
    split: &Split,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<TableModel, HybridError> {
    let cfg = &cfg.check()?;
    check_rows(table, split)?;
    let slots = super::slots::expand(table, cfg, &split.train, progress)?;
    let cfg = slots.as_ref().map_or(cfg, |e| &e.cfg);
    let mut model = fit_inner(SplitJob::single(table, cfg, split, "given"), progress)?;
    if let Some(e) = &slots {
        model.slots = e.finished(&model.physics.params, &model.physics.parameters);
    }
    Ok(model)
}

/// Fits one split: calibrates the physics on the training rows, searches the correction of
/// its `delta`, refits both jointly when asked, and writes the model with its scores and,
/// with `conformal_folds`, its conformal calibration.
pub(crate) fn fit_inner(
    job: SplitJob,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<TableModel, HybridError> {
    fit_calibrated(job, &calibrate_split(job)?, progress)
}

/// [`fit_inner`] from the split's calibrated physics `cal` ([`calibrate_split`]): the form
/// `auto` chosen first ([`auto::choose`]), then the fit of that form ([`one::fit_form`]).
pub(crate) fn fit_calibrated(
    job: SplitJob,
    cal: &Calibrated,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<TableModel, HybridError> {
    let sample = job::sample_of(job, &cal.res, job.cfg.search_rows)?;
    let (form, choice) = match (job.cfg.form, &sample) {
        (Form::Auto, None) => auto::choose(job, progress)?,
        (Form::Auto, Some(rows)) => {
            let sub = Split {
                train: rows.clone(),
                test: Vec::new(),
            };
            auto::choose(SplitJob { split: &sub, ..job }, progress)?
        }
        (f, _) => (f, None),
    };
    let mut model = one::fit_form(job, cal, form, choice, sample.as_deref(), progress)?;
    model.search_sample = sample.map(|rows| super::SearchSample {
        rows: rows.len(),
        training_rows: job.split.train.len(),
        method: sample_method(job.cfg.seed),
    });
    Ok(model)
}
