//! Bootstrap resamples of the rows and what runs over them report: the rows of run `r`
//! ([`bootstrap_rows`], the same for [`crate::stability()`], the consensus of
//! [`crate::consensus`] and the factor bands of [`crate::factors`]), the shares of what the
//! runs gave back, and the [`Stability`] report they fill. Below the search: nothing here
//! runs one.
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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

/// What [`crate::stability()`] reports (JSON `stability`).
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
    pub bands: Option<BTreeMap<String, FactorBand>>,
}

/// The rows of bootstrap run `r` of `n` rows under `seed` (drawn with replacement from the
/// run's own generator), and the rows it left out (out-of-bag). [`crate::stability()`],
/// [`crate::consensus`] and the factor bands all draw their resamples here, so their runs
/// `r` see the same rows.
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

/// A one-column factor's response over the runs that kept it (JSON: an entry of
/// `stability.bands`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FactorBand {
    /// Runs that kept a factor of this column.
    pub runs: usize,
    /// Grid over the column's range in the rows.
    pub grid: Vec<f64>,
    /// 5 % quantile of the normalised response at each grid point.
    pub lo: Vec<f64>,
    /// Median.
    pub median: Vec<f64>,
    /// 95 % quantile.
    pub hi: Vec<f64>,
}
