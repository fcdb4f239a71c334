//! Stability of the selected structure: the search rerun on bootstrap resamples.
//!
//! One search gives one equation; whether its structure is more than one draw shows when the
//! search is rerun on resamples of the rows. [`stability`] runs it on `runs` bootstrap
//! resamples (rows drawn with replacement, each resample from its own generator seeded by
//! `(seed, run)`) and reports how often each feature is used, how often each structure is
//! selected, and the spread of R^2 on the rows each resample left out (out-of-bag).
//!
//! Structures are compared up to their constants and their algebra: [`structure_of`] is
//! the canonical form of [`crate::canonical`] (equality saturation), printed with every
//! constant written `c`. So `c*x1*x2 + c` and `c + c*x2*x1` are one structure, and so are
//! `x*(c*(c*y))` and `c*x*y`, `gaussian(x)` and `exp(-x^2)`, `c*exp(c + x)` and
//! `c*exp(x)`, `sub(x, y)` and `add(x, y)` when inputs carry their own scale (`c*x - c*y`
//! is `c*x + c*y` with another constant). Structures equal only through rules the canonical
//! form does not have (expanding a product of sums: `x*(y + z)` against `x*y + x*z`;
//! trigonometric identities) count as different; so, rarely, do structures whose e-graph
//! hit its size limit (see [`crate::canonical`]'s limits).
//!
//! Runs are searched in parallel (on the threads `cfg.par` chooses) and collected in run order; each search is itself
//! independent of the thread count, so the result depends only on the seed and the data.
pub use crate::bootstrap::{R2Spread, Stability, StructureShare};
use crate::bootstrap::{bootstrap_rows, r2_spread, shares};
use crate::search::{SearchConfig, ValidSearch};
use crate::{Model, Par, SrError, Table};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::sync::Mutex;

/// The structure of a model with its constants ignored (see the module docs); defined in
/// [`crate::canonical`], where selection reads it too, and named here where users look.
pub use crate::canonical::structure_of;

/// Reruns the search on `runs` bootstrap resamples of the rows of `data` (see the module
/// docs). `progress` is called with `(runs done, runs)` as runs finish (from worker threads,
/// one call at a time).
///
/// # Errors
/// `runs` of 0 ([`SrError::InvalidConfig`]), and the errors of [`crate::search()`] (a resample
/// whose target is constant, say).
pub fn stability(
    data: &Table,
    target: &[f64],
    cfg: &SearchConfig,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<Stability, SrError> {
    stability_of(
        data,
        target,
        &cfg.check()?,
        runs,
        progress,
        &|train, y, run_cfg| crate::search_checked(train, y, run_cfg, &mut |_| {}),
    )
}

/// One bootstrap run's search: the resampled rows, their target and the run's settings.
pub(crate) type RunSearch<'a> =
    dyn Fn(&Table, &[f64], &ValidSearch) -> Result<crate::SearchResult, SrError> + Sync + 'a;

/// [`stability`] with each run's search done by `run_search` (on the resampled rows and
/// target, with the run's configuration): how [`crate::units::stability`] searches on the
/// dimensionless groups and composes back.
pub(crate) fn stability_of(
    data: &Table,
    target: &[f64],
    cfg: &ValidSearch,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
    run_search: &RunSearch<'_>,
) -> Result<Stability, SrError> {
    if runs == 0 {
        return Err(SrError::InvalidConfig(
            "--stability needs at least one run".into(),
        ));
    }
    if target.len() != data.n_rows() {
        return Err(SrError::TargetLength {
            target: target.len(),
            data: data.n_rows(),
        });
    }
    let n = data.n_rows();
    let done = Mutex::new((0usize, progress));
    // the runs share `cfg.par`'s pool; each search inside runs on it (`Par::Current`)
    let results: Vec<Result<(Model, Option<f64>), SrError>> = cfg.par.run(|| {
        (0..runs)
            .into_par_iter()
            .map(|r| {
                let (rows, oob) = bootstrap_rows(cfg.seed, r, n);
                let train = data.select_rows(&rows)?;
                let y: Vec<f64> = rows.iter().map(|&i| target[i]).collect();
                let run_cfg = cfg.with_seed_par(cfg.seed.wrapping_add(r as u64 + 1), Par::Current);
                let res = run_search(&train, &y, &run_cfg)?;
                let r2 = if oob.len() >= 2 {
                    let test = data.select_rows(&oob)?;
                    let yt: Vec<f64> = oob.iter().map(|&i| target[i]).collect();
                    res.best
                        .predict(&test)
                        .ok()
                        .and_then(|p| hxai_eval::r2(&yt, &p).ok())
                        .filter(|v| v.is_finite())
                } else {
                    None
                };
                if let Ok(mut g) = done.lock() {
                    g.0 += 1;
                    let k = g.0;
                    (g.1)(k, runs);
                }
                Ok((res.best, r2))
            })
            .collect()
    });
    // counted in whole runs and divided once, so a feature in every run has share 1 exactly
    // (adding 1/runs twenty times gives 1.0000000000000002)
    let mut used: BTreeMap<String, usize> = data.names().iter().map(|n| (n.clone(), 0)).collect();
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut r2s = Vec::new();
    for r in results {
        let (model, r2) = r?;
        for f in model.features() {
            *used.entry(f).or_insert(0) += 1;
        }
        *counts.entry(structure_of(&model)).or_insert(0) += 1;
        r2s.extend(r2);
    }
    let features: BTreeMap<String, f64> = used
        .into_iter()
        .map(|(name, c)| (name, c as f64 / runs as f64))
        .collect();
    let structures = shares(counts, runs);
    let r2 = r2_spread(&r2s);
    Ok(Stability {
        runs,
        features,
        structures,
        r2,
        factors: None,
        factor_sets: None,
        bands: None,
    })
}
