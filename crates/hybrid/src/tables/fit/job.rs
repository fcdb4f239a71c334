//! One fit's job on one split ([`SplitJob`]): the physics resolved and calibrated on its
//! training rows ([`calibrate_split`]), and the free search of a target on those rows
//! ([`search_training_rows`]). Everything else of the fit builds on these.

use super::super::physics::{calibrate_physics, physics_values};
use super::super::resolve::{Resolved, resolve};
use super::super::split::check_rows;
use super::super::{TableProgress, ValidTable};
use crate::HybridError;
use hxai_eval::Split;
use hxai_symreg::Table;
use hxai_symreg::infix::Compiled;
use std::collections::BTreeMap;

/// A search as the progress reports name it: task `of.0` of `of.1`, called `label`.
pub(crate) struct Task {
    /// `(this task, tasks in all)`.
    pub(crate) of: (usize, usize),
    /// What the task is (`correction (2/11)`, `symbolic (3/11)`).
    pub(crate) label: String,
}

/// Symbolic regression of `y` (one value per training row of `split`) on the training rows
/// of the feature columns, reported as `task`: those rows' feature table and the search's
/// result.
pub(crate) fn search_training_rows(
    table: &Table,
    res: &Resolved,
    cfg: &ValidTable,
    split: &Split,
    y: &[f64],
    task: Task,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<(Table, hxai_symreg::SearchResult), HybridError> {
    let Task { of: task, label } = task;
    let ft = table
        .select_columns(&res.features)?
        .select_rows(&split.train)?;
    let found = hxai_symreg::search_checked(&ft, y, cfg.search(), &mut |p| {
        progress(&TableProgress {
            task: task.0,
            tasks: task.1,
            label: label.clone(),
            search: p.clone(),
            step: false,
        })
    })?;
    Ok((ft, found))
}

/// One fit on one split of a table: what [`fit_inner`] (and the comparison's
/// per-split predictions) work on.
#[derive(Clone, Copy)]
pub(crate) struct SplitJob<'a> {
    pub(crate) table: &'a Table,
    pub(crate) cfg: &'a ValidTable,
    pub(crate) split: &'a Split,
    /// Split kind, as the model file reports it (`random`, `given`, `fold`, ...).
    pub(crate) kind: &'a str,
    /// `(this task, tasks in all)`, for progress reports.
    pub(crate) task: (usize, usize),
}

impl<'a> SplitJob<'a> {
    /// The only task of a run.
    pub(crate) fn single(
        table: &'a Table,
        cfg: &'a ValidTable,
        split: &'a Split,
        kind: &'a str,
    ) -> Self {
        let task = (1, 1);
        Self {
            table,
            cfg,
            split,
            kind,
            task,
        }
    }
}

/// What every model of one split starts from, computed once per split
/// ([`calibrate_split`]): the physics resolved against the table, calibrated on the
/// training rows (with the standard errors of its parameters), and its values on every row.
#[derive(Clone, Debug)]
pub(crate) struct Calibrated {
    pub(crate) res: Resolved,
    pub(crate) phys: Compiled,
    pub(crate) ses: BTreeMap<String, Option<f64>>,
    /// The calibrated physics on every row of the table.
    pub(crate) physics: Vec<f64>,
}

/// Checks `job`'s rows, resolves the physics against the table and calibrates
/// it on the training rows: what the fit ([`fit_calibrated`]), the black boxes beside it
/// and the comparison's other models share.
///
/// # Errors
/// Rows out of range, and those of the physics' resolution and calibration (the settings
/// were checked by [`TableConfig::check`]).
pub(crate) fn calibrate_split(job: SplitJob) -> Result<Calibrated, HybridError> {
    let (table, cfg, split) = (job.table, job.cfg, job.split);
    check_rows(table, split)?;
    let res = resolve(table, cfg)?;
    let (phys, ses) = calibrate_physics(table, cfg, &res, &split.train)?;
    let physics = physics_values(table, &res, &phys)?;
    Ok(Calibrated {
        res,
        phys,
        ses,
        physics,
    })
}

/// The training rows (`train`, rows of the table) the correction's structure is searched on
/// (issue 67): `None` when they are at most `search_rows`, else a sample of that many
/// stratified on the target `y`, seeded by `seed`, with the training rows that hold the
/// smallest and largest value of each of `columns` (the columns the model reads: the
/// search then sees their whole box, [`hxai_eval::stratified_sample_spanning`]), in
/// increasing row order.
pub(crate) fn search_sample(
    y: &[f64],
    columns: &[&[f64]],
    train: &[usize],
    search_rows: usize,
    seed: u64,
) -> Option<Vec<usize>> {
    (train.len() > search_rows).then(|| {
        let pick = |v: &[f64]| -> Vec<f64> { train.iter().map(|&i| v[i]).collect() };
        let cols: Vec<Vec<f64>> = columns.iter().map(|c| pick(c)).collect();
        let refs: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        hxai_eval::stratified_sample_spanning(&pick(y), search_rows, seed, &refs)
            .into_iter()
            .map(|p| train[p])
            .collect()
    })
}

/// The positions in `train` of `rows` (rows of the table among the training rows; a row
/// not among them is skipped).
pub(crate) fn positions_in(train: &[usize], rows: &[usize]) -> Vec<usize> {
    let at: std::collections::HashMap<usize, usize> =
        train.iter().enumerate().map(|(p, &r)| (r, p)).collect();
    rows.iter().filter_map(|r| at.get(r).copied()).collect()
}

/// [`search_sample`] of `job`'s training rows over the columns the resolved physics and
/// correction read (`res`), at most `rows` of them (and the columns' extreme rows).
///
/// # Errors
/// A target the table lacks.
pub(crate) fn sample_of(
    job: SplitJob,
    res: &Resolved,
    rows: usize,
) -> Result<Option<Vec<usize>>, HybridError> {
    let y = job.table.require(&job.cfg.target)?;
    let read: Vec<String> = res.columns.iter().chain(&res.features).cloned().collect();
    let columns = columns_named(job.table, &read);
    Ok(search_sample(
        y,
        &columns,
        &job.split.train,
        rows,
        job.cfg.seed,
    ))
}

/// The columns of `table` named in `names` that it holds (those [`search_sample`] spans).
pub(crate) fn columns_named<'t>(table: &'t Table, names: &[String]) -> Vec<&'t [f64]> {
    names.iter().filter_map(|n| table.column(n)).collect()
}

/// How [`search_sample`] draws its rows, as the model file says it.
pub(crate) fn sample_method(seed: u64) -> String {
    format!(
        "one training row drawn at random (seed {seed}) from each of equal-count strata of \
         the target, and the training rows of each column's smallest and largest value; the \
         physics' calibration and the correction's constants on every training row"
    )
}
