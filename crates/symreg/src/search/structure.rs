//! [`fit_structure`]: fit the constants of one given structure, without a search.
use super::archive::{Archive, Candidate};
use super::config::{SearchConfig, ValidSearch};
use super::fitting::{Problem, check_target, variance};
use super::select::{Counts, Finalists, select};
use crate::model::Model;
use crate::program::Program;
use crate::{SrError, Table};
use std::time::Instant;

/// Fits the constants of one given structure (inputs by column index of `data`) to `target`
/// with Levenberg-Marquardt on all rows, from the canonical start and one seeded random
/// start, then snaps constants as [`search`](super::search) does. Useful to test whether a
/// law is expressible, and to refit a known structure on new data.
///
/// # Errors
/// As [`search`](super::search), plus [`SrError::MalformedModel`] for an invalid program.
pub fn fit_structure(
    data: &Table,
    target: &[f64],
    program: &Program,
    cfg: &SearchConfig,
) -> Result<Model, SrError> {
    fit_from(data, target, program, None, &cfg.check()?)
}

/// [`fit_structure`] of `model`'s structure, starting from its constants only (a model
/// found on other rows of the same columns, as [`crate::consensus`] refits its winner).
pub(crate) fn fit_structure_from(
    data: &Table,
    target: &[f64],
    model: &Model,
    cfg: &ValidSearch,
) -> Result<Model, SrError> {
    let names = data.names();
    let remap: Option<Vec<u16>> = model
        .feature_names
        .iter()
        .map(|f| {
            names
                .iter()
                .position(|n| n == f)
                .and_then(|j| u16::try_from(j).ok())
        })
        .collect();
    let Some(remap) = remap else {
        return Err(SrError::MalformedModel(
            "the model uses a column the data does not have".into(),
        ));
    };
    let mut program = model.program.clone();
    for n in &mut program.nodes {
        if let crate::program::Node::Var(j) = n {
            *j = remap.get(*j as usize).copied().unwrap_or(*j);
        }
    }
    if program.n_params() != model.params.len() {
        return Err(SrError::MalformedModel(
            "the model's constants do not match its program".into(),
        ));
    }
    fit_from(data, target, &program, Some(model.params.clone()), cfg)
}

fn fit_from(
    data: &Table,
    target: &[f64],
    program: &Program,
    params: Option<Vec<f64>>,
    cfg: &ValidSearch,
) -> Result<Model, SrError> {
    if !program.is_valid() || program.vars().iter().any(|&j| j as usize >= data.n_cols()) {
        return Err(SrError::MalformedModel(
            "the program is not a valid expression over the data's columns".into(),
        ));
    }
    check_target(data, target)?;
    let n = target.len();
    if n <= program.n_params() {
        return Err(SrError::TooFewRows {
            rows: n,
            needed: program.n_params() + 1,
        });
    }
    let y_var = variance(target);
    if target.iter().all(|&v| v == target[0]) {
        return Err(SrError::ConstantTarget(target[0]));
    }
    let problem = Problem::all_rows(data, target, y_var, cfg);
    let cand = Candidate {
        program: program.clone(),
        params,
        source: 0,
        tag: 0,
    };
    let f = problem.fit(&cand, cfg.seed);
    let mut archive = Archive::default();
    archive.offer(&f);
    let finalists = Finalists {
        archive: &archive,
        extra: &[],
    };
    let counts = Counts {
        evaluations: 1,
        duplicate_structures: 0,
    };
    select(
        &problem,
        data,
        finalists,
        counts,
        Instant::now(),
        &cfg.par.pool(),
    )
    .map(|r| r.best)
}
