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
use crate::search::{SearchConfig, ValidSearch};
use crate::{Model, Par, SrError, Table};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Mutex;

/// Mixing constant of the seeds of the runs (SplitMix64's increment): run `r` of seed `s`
/// draws its resample from `s ^ (r + 1) * RUN_MIX`, and searches with seed `s + r + 1`.
const RUN_MIX: u64 = 0x9E37_79B9_7F4A_7C15;

/// One structure and the share of runs that selected it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StructureShare {
    /// The structure, every constant written `c`.
    pub template: String,
    /// Share of runs (0 to 1).
    pub share: f64,
}

/// Mean and sample standard deviation of R^2 over the runs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct R2Spread {
    /// Mean R^2 on the out-of-bag rows.
    pub mean: f64,
    /// Sample standard deviation (0 for a single run).
    pub sd: f64,
}

/// What [`stability`] reports (JSON `stability`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Stability {
    /// Number of runs.
    pub runs: usize,
    /// Each feature offered, with the share of runs whose selected model uses it.
    pub features: BTreeMap<String, f64>,
    /// Structures selected, most frequent first (ties by text).
    pub structures: Vec<StructureShare>,
    /// R^2 of each run's model on the rows its resample left out (runs whose out-of-bag
    /// rows are fewer than two, or whose prediction is not finite there, are left out;
    /// `null` when no run is left).
    pub r2: Option<R2Spread>,
    /// Factor corrections only ([`crate::factors`]): per column that any run kept, the
    /// share of runs with each factor shape (by its template); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factors: Option<BTreeMap<String, BTreeMap<String, f64>>>,
    /// Factor corrections only: each set of factor columns (sorted, an interaction written
    /// `a:b`) with the share of runs that kept exactly that set, most frequent first.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub factor_sets: Option<Vec<StructureShare>>,
    /// Factor corrections only: each one-column factor's response over the runs that kept
    /// it, on a grid of its column (the 5-95 % spread).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bands: Option<BTreeMap<String, crate::factors::FactorBand>>,
}

/// The rows of bootstrap run `r` of `n` rows under `seed` (drawn with replacement from the
/// run's own generator), and the rows it left out (out-of-bag). [`crate::consensus`] draws
/// its resamples here too, so its run `r` and this module's see the same rows.
pub(crate) fn bootstrap_rows(seed: u64, r: usize, n: usize) -> (Vec<usize>, Vec<usize>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ (r as u64 + 1).wrapping_mul(RUN_MIX));
    let rows: Vec<usize> = (0..n).map(|_| rng.gen_range(0..n)).collect();
    let mut drawn = vec![false; n];
    for &i in &rows {
        drawn[i] = true;
    }
    let oob = (0..n).filter(|&i| !drawn[i]).collect();
    (rows, oob)
}

/// Each counted key with its share of `runs`, most frequent first (ties by text).
pub(crate) fn shares(counts: BTreeMap<String, usize>, runs: usize) -> Vec<StructureShare> {
    let mut v: Vec<StructureShare> = counts
        .into_iter()
        .map(|(template, c)| StructureShare {
            template,
            share: c as f64 / runs as f64,
        })
        .collect();
    v.sort_by(|a, b| {
        b.share
            .total_cmp(&a.share)
            .then(a.template.cmp(&b.template))
    });
    v
}

/// Mean and sample standard deviation of the runs' R^2 (`None` without any).
pub(crate) fn r2_spread(r2s: &[f64]) -> Option<R2Spread> {
    (!r2s.is_empty()).then(|| {
        let m = r2s.len() as f64;
        let mean = r2s.iter().sum::<f64>() / m;
        let sd = if r2s.len() > 1 {
            (r2s.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (m - 1.0)).sqrt()
        } else {
            0.0
        };
        R2Spread { mean, sd }
    })
}

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
