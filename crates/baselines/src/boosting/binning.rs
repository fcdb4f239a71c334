//! Quantile binning of each feature, scikit-learn's `_BinMapper` for continuous features.
//!
//! Histogram gradient boosting never looks at a feature's values while it grows trees: each
//! value is replaced by the index of its bin, at most `max_bins` (255) of them per feature,
//! and a split is "bin <= b". The bin edges ("thresholds") of a feature follow
//! `_find_binning_thresholds` in `sklearn/ensemble/_hist_gradient_boosting/binning.py`:
//!
//! * with at most `max_bins` distinct values, the midpoints `(a + b) / 2` of consecutive
//!   distinct values, so every distinct value has its own bin;
//! * otherwise the `max_bins - 1` inner percentiles `100 k / max_bins` of the values, with
//!   numpy's `method="averaged_inverted_cdf"` (a data value, or the mean of two neighbouring
//!   ones where the rank falls exactly between them), computed the way numpy computes them
//!   so the edges are scikit-learn's to the last bit; duplicate edges are dropped;
//! * a constant feature has no edge (one bin, never split).
//!
//! A value `x` falls in bin `i` when `t[i - 1] < x <= t[i]`, found by binary search; the
//! fitted trees keep the real edge `t[b]` of each split, so prediction compares raw values
//! (`x <= t[b]` goes left) and never bins. The edges are computed from at most
//! [`SUBSAMPLE`] rows, drawn with replacement from a seeded generator when the table is
//! larger (scikit-learn draws them with numpy's generator, so above that size the edges
//! differ slightly from scikit-learn's; below it they are equal).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Rows the bin edges are computed from at most (scikit-learn's `subsample=2e5`).
pub(crate) const SUBSAMPLE: usize = 200_000;

/// Edges are clipped to this value: scikit-learn keeps `+inf` for a split on missing values
/// only (LightGBM's `AvoidInf`). With finite inputs it never binds; kept for fidelity.
const ALMOST_INF: f64 = 1e300;

/// The bin edges of every feature and the binned training table.
#[derive(Debug)]
pub(crate) struct Binned {
    /// Per feature, the increasing bin edges (`n_bins - 1` of them).
    pub(crate) thresholds: Vec<Vec<f64>>,
    /// Per feature, the bin of each training row (column-major, like the table).
    pub(crate) bins: Vec<Vec<u8>>,
}

impl Binned {
    /// Bins the columns `cols` (rows `rows` of each) with at most `max_bins` bins per
    /// feature; `seed` draws the subsample above [`SUBSAMPLE`] rows. Features are binned
    /// in parallel on the caller's rayon pool; the result does not depend on it.
    pub(crate) fn fit(cols: &[Vec<f64>], rows: &[usize], max_bins: usize, seed: u64) -> Self {
        let sample: Option<Vec<usize>> = (rows.len() > SUBSAMPLE).then(|| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(1);
            (0..SUBSAMPLE)
                .map(|_| rows[rng.gen_range(0..rows.len())])
                .collect()
        });
        let edge_rows = sample.as_deref().unwrap_or(rows);
        let (thresholds, bins) = cols
            .par_iter()
            .map(|col| {
                let values: Vec<f64> = edge_rows.iter().map(|&i| col[i]).collect();
                let t = thresholds(values, max_bins);
                let b: Vec<u8> = rows.iter().map(|&i| bin_of(&t, col[i])).collect();
                (t, b)
            })
            .unzip();
        Self { thresholds, bins }
    }
}

/// The bin of `x` given the increasing edges `t`: the first `i` with `x <= t[i]`, or
/// `t.len()` when `x` is above every edge. At most 254 edges, so the bin fits in a `u8`.
pub(crate) fn bin_of(t: &[f64], x: f64) -> u8 {
    t.partition_point(|&e| e < x) as u8
}

/// The bin edges of one feature's `values` with at most `max_bins` bins (see the module
/// docs). `max_bins` is at least 2.
pub(crate) fn thresholds(mut values: Vec<f64>, max_bins: usize) -> Vec<f64> {
    values.sort_unstable_by(f64::total_cmp);
    let mut distinct = values.clone();
    distinct.dedup();
    if distinct.len() <= 1 {
        return Vec::new();
    }
    let mut edges: Vec<f64> = if distinct.len() <= max_bins {
        distinct.windows(2).map(|w| (w[0] + w[1]) / 2.0).collect()
    } else {
        let step = 100.0 / max_bins as f64;
        (1..max_bins)
            .map(|k| averaged_inverted_cdf(&values, k as f64 * step / 100.0))
            .collect()
    };
    edges.dedup();
    for e in &mut edges {
        *e = e.min(ALMOST_INF);
    }
    edges
}

/// numpy's `np.quantile(sorted, q, method="averaged_inverted_cdf")` of sorted, non-empty
/// values, step by step as numpy computes it (`numpy/lib/_function_base_impl.py`): virtual
/// index `n q - 1`; the value above it, or the mean of the two around it when the index
/// is a whole number, interpolated as numpy's `_lerp` does.
fn averaged_inverted_cdf(sorted: &[f64], q: f64) -> f64 {
    let n = sorted.len();
    let index = n as f64 * q - 1.0;
    let below = index.floor();
    let (lo, hi) = if index >= (n - 1) as f64 {
        (n - 1, n - 1)
    } else if index < 0.0 {
        (0, 0)
    } else {
        (below as usize, below as usize + 1)
    };
    let gamma = if index - below == 0.0 { 0.5 } else { 1.0 };
    let (a, b) = (sorted[lo], sorted[hi]);
    let diff = b - a;
    // numpy's _lerp: b - diff (1 - t) for t >= 0.5, a + diff t below (t is 0.5 or 1 here)
    b - diff * (1.0 - gamma)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn few_distinct_values_give_midpoints() {
        let t = thresholds(vec![3.0, 1.0, 2.0, 2.0, 1.0], 255);
        assert_eq!(t, vec![1.5, 2.5]);
        assert_eq!(bin_of(&t, 1.0), 0);
        assert_eq!(bin_of(&t, 1.5), 0);
        assert_eq!(bin_of(&t, 2.0), 1);
        assert_eq!(bin_of(&t, 9.0), 2);
        assert!(thresholds(vec![4.0; 7], 255).is_empty());
    }

    #[test]
    fn many_values_give_quantiles() {
        // 0..=9 in 4 bins: ranks 10 k / 4 - 1 = 1.5, 4, 6.5 -> values 2, mean(4, 5), 7
        let t = thresholds((0..10).map(f64::from).collect(), 4);
        assert_eq!(t, vec![2.0, 4.5, 7.0]);
    }
}
