//! The correction's search on the training rows in each concrete form: free
//! ([`search_free`]), factors ([`search_factors`]) or none ([`no_correction`]).

use super::super::resolve::Resolved;
use super::super::{TableConfig, TableProgress};
use super::job::{SplitJob, Task, search_training_rows};
use crate::HybridError;
use crate::correction::factor_search;
use hxai_eval::Split;
use hxai_symreg::Table;

/// The correction a search found on the training rows: their feature table, the model,
/// how it was selected, the models it was chosen from and, in the factor form, its factors.
pub(super) struct Searched {
    pub(super) ft: Table,
    pub(super) model: hxai_symreg::Model,
    pub(super) selection: hxai_symreg::SelectionReport,
    pub(super) pareto: Vec<hxai_symreg::Model>,
    pub(super) factors: Option<Vec<hxai_symreg::factors::Factor>>,
}

/// The factor form's search ([`hxai_symreg::factors::fit_factors`]) of `delta` on the
/// training rows: its alternatives are the selected columns with another shape that the
/// held-out error cannot tell apart. A multiplicative correction is fitted by the
/// hybrid's error in the target's units (`physics` on every row of the table).
/// The zero correction of `--form none` (or of `auto` when no correction pays): a
/// constant 0 over no column, its selection saying so.
pub(super) fn no_correction(
    table: &Table,
    res: &Resolved,
    split: &Split,
) -> Result<Searched, HybridError> {
    let ft = table
        .select_columns(&res.features)?
        .select_rows(&split.train)?;
    let zero = hxai_symreg::Model::new(
        Vec::new(),
        hxai_symreg::Program {
            nodes: vec![hxai_symreg::Node::Const],
            affine: false,
        },
        vec![1.0, 0.0, 0.0],
    )?;
    let selection = hxai_symreg::SelectionReport {
        method: "none".into(),
        structure: "0".into(),
        share: None,
        runs: None,
        alternatives: Vec::new(),
        error_model: hxai_symreg::ErrorModel::Additive,
        prior: None,
    };
    Ok(Searched {
        ft,
        pareto: vec![zero.clone()],
        model: zero,
        selection,
        factors: None,
    })
}

pub(super) fn search_factors(
    table: &Table,
    res: &Resolved,
    cfg: &TableConfig,
    split: &Split,
    delta: &[f64],
    physics: &[f64],
) -> Result<Searched, HybridError> {
    let ft = table
        .select_columns(&res.features)?
        .select_rows(&split.train)?;
    let fp: Vec<f64> = split.train.iter().map(|&i| physics[i]).collect();
    let fc = cfg.factor_config(&res.features);
    let found = factor_search(&ft, delta, Some(&fp), cfg.correction.link(), &fc)?;
    Ok(Searched {
        ft,
        model: found.model,
        selection: found.selection,
        pareto: found.pareto,
        factors: Some(found.factors),
    })
}

/// The free form's search ([`hxai_symreg::search()`]) of `delta` on `job`'s training rows.
pub(super) fn search_free(
    job: SplitJob,
    res: &Resolved,
    delta: &[f64],
    task: Task,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<Searched, HybridError> {
    let (ft, found) =
        search_training_rows(job.table, res, job.cfg, job.split, delta, task, progress)?;
    Ok(Searched {
        selection: hxai_symreg::SelectionReport::of(&found, job.cfg.search()),
        model: found.best,
        pareto: found.pareto,
        factors: None,
        ft,
    })
}
