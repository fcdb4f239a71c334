//! Seeded train/test splits and k-fold cross-validation, plain and grouped.
//!
//! All index lists are sorted ascending. Randomness comes from a `ChaCha8Rng` seeded with
//! the `seed` argument, so a split depends on `(n or groups, parameters, seed)` only.

use crate::EvalError;
use crate::check::check_open_fraction;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::hash::Hash;

/// Sample indices of a train side and a test side (disjoint, each sorted ascending).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Split {
    /// Indices used for fitting.
    pub train: Vec<usize>,
    /// Indices held out for scoring.
    pub test: Vec<usize>,
}

fn check_fraction(test_fraction: f64) -> Result<(), EvalError> {
    check_open_fraction("test_fraction", test_fraction)
}

/// Number of test items for `n` items, scikit-learn's rule `ceil(test_fraction * n)`.
fn n_test(n: usize, test_fraction: f64, unit: &'static str) -> Result<usize, EvalError> {
    let n_test = (test_fraction * n as f64).ceil() as usize;
    if n_test == 0 || n_test >= n {
        return Err(EvalError::EmptySide {
            n,
            unit,
            test_fraction,
        });
    }
    Ok(n_test)
}

fn sorted(mut v: Vec<usize>) -> Vec<usize> {
    v.sort_unstable();
    v
}

/// Random train/test split of `n` samples: `ceil(test_fraction * n)` go to the test side.
///
/// # Errors
/// `test_fraction` outside (0, 1), or a side that would be empty (e.g. `n < 2`).
pub fn train_test_split(n: usize, test_fraction: f64, seed: u64) -> Result<Split, EvalError> {
    check_fraction(test_fraction)?;
    let n_test = n_test(n, test_fraction, "samples")?;
    let mut perm: Vec<usize> = (0..n).collect();
    perm.shuffle(&mut ChaCha8Rng::seed_from_u64(seed));
    let train = perm.split_off(n_test);
    Ok(Split {
        train: sorted(train),
        test: sorted(perm),
    })
}

/// Fold sizes of scikit-learn's `KFold`: the first `n % k` folds hold one extra sample.
fn fold_sizes(n: usize, k: usize) -> impl Iterator<Item = usize> {
    (0..k).map(move |i| n / k + usize::from(i < n % k))
}

fn check_k(n: usize, k: usize, unit: &'static str) -> Result<(), EvalError> {
    if k < 2 {
        return Err(EvalError::TooFewFolds { k });
    }
    if k > n {
        return Err(EvalError::TooManyFolds { k, n, unit });
    }
    Ok(())
}

fn folds_from_order(order: &[usize], k: usize) -> Vec<Split> {
    let n = order.len();
    let mut start = 0;
    fold_sizes(n, k)
        .map(|size| {
            let test = sorted(order[start..start + size].to_vec());
            let train = sorted(
                order[..start]
                    .iter()
                    .chain(&order[start + size..])
                    .copied()
                    .collect(),
            );
            start += size;
            Split { train, test }
        })
        .collect()
}

/// Shuffled k-fold cross-validation of `n` samples (like `KFold(k, shuffle=True)`):
/// the test sides partition `0..n`, fold sizes differ by at most one.
///
/// # Errors
/// `k < 2` or `k > n`.
pub fn kfold(n: usize, k: usize, seed: u64) -> Result<Vec<Split>, EvalError> {
    check_k(n, k, "samples")?;
    let mut perm: Vec<usize> = (0..n).collect();
    perm.shuffle(&mut ChaCha8Rng::seed_from_u64(seed));
    Ok(folds_from_order(&perm, k))
}

/// Unshuffled k-fold (scikit-learn's `KFold(k)` default, used by `LassoCV(cv=k)`):
/// fold `i` tests a contiguous block of indices.
///
/// # Errors
/// `k < 2` or `k > n`.
pub fn kfold_contiguous(n: usize, k: usize) -> Result<Vec<Split>, EvalError> {
    check_k(n, k, "samples")?;
    let order: Vec<usize> = (0..n).collect();
    Ok(folds_from_order(&order, k))
}

/// Distinct groups in order of first appearance, with the indices of their members.
fn group_members<G: Eq + Hash>(groups: &[G]) -> Vec<Vec<usize>> {
    let mut index: HashMap<&G, usize> = HashMap::new();
    let mut members: Vec<Vec<usize>> = Vec::new();
    for (i, g) in groups.iter().enumerate() {
        let slot = *index.entry(g).or_insert_with(|| {
            members.push(Vec::new());
            members.len() - 1
        });
        members[slot].push(i);
    }
    members
}

/// Train/test split that never puts members of one group on both sides (like
/// scikit-learn's `GroupShuffleSplit`): `ceil(test_fraction * n_groups)` whole groups go
/// to the test side.
///
/// # Errors
/// `test_fraction` outside (0, 1), or fewer than two distinct groups.
pub fn grouped_train_test_split<G: Eq + Hash>(
    groups: &[G],
    test_fraction: f64,
    seed: u64,
) -> Result<Split, EvalError> {
    check_fraction(test_fraction)?;
    let members = group_members(groups);
    let n_test = n_test(members.len(), test_fraction, "groups")?;
    let mut order: Vec<usize> = (0..members.len()).collect();
    order.shuffle(&mut ChaCha8Rng::seed_from_u64(seed));
    let collect = |gs: &[usize]| {
        sorted(
            gs.iter()
                .flat_map(|&g| members[g].iter().copied())
                .collect(),
        )
    };
    Ok(Split {
        train: collect(&order[n_test..]),
        test: collect(&order[..n_test]),
    })
}

/// Grouped k-fold: each group lies in exactly one test fold. Groups are shuffled with the
/// seed, then (like scikit-learn's `GroupKFold`) taken largest first and each given to the
/// fold with the fewest samples so far, which balances fold sizes.
///
/// # Errors
/// `k < 2` or fewer distinct groups than `k`.
pub fn grouped_kfold<G: Eq + Hash>(
    groups: &[G],
    k: usize,
    seed: u64,
) -> Result<Vec<Split>, EvalError> {
    let members = group_members(groups);
    check_k(members.len(), k, "groups")?;
    let mut order: Vec<usize> = (0..members.len()).collect();
    order.shuffle(&mut ChaCha8Rng::seed_from_u64(seed));
    // Stable sort: equal-sized groups keep their shuffled order.
    order.sort_by_key(|&g| std::cmp::Reverse(members[g].len()));
    let mut fold_of_group = vec![0usize; members.len()];
    let mut load = vec![0usize; k];
    for &g in &order {
        let lightest = (0..k).min_by_key(|&f| (load[f], f)).unwrap_or(0);
        fold_of_group[g] = lightest;
        load[lightest] += members[g].len();
    }
    Ok((0..k)
        .map(|f| {
            let mut train = Vec::new();
            let mut test = Vec::new();
            for (g, m) in members.iter().enumerate() {
                if fold_of_group[g] == f {
                    test.extend(m)
                } else {
                    train.extend(m)
                }
            }
            Split {
                train: sorted(train),
                test: sorted(test),
            }
        })
        .collect())
}

/// How many rows of `test` repeat a row of `train`, comparing every column (each side given
/// as the same list of columns, equally long within a side; `-0` equals `0`). A test row
/// that repeats a training row measures recall, not prediction: `hxai compare` and the
/// table hybrid's traps warn about them.
///
/// ```
/// let (x, y) = ([1.0, 2.0, 3.0], [0.0, 5.0, 6.0]);
/// let (tx, ty) = ([2.0, 2.0, 3.0], [-0.0, 5.0, 7.0]);
/// // row 2 of the test (2, 5) is row 2 of the training side; (2, -0) and (3, 7) are not
/// assert_eq!(hxai_eval::shared_rows(&[&x, &y], &[&tx, &ty]), 1);
/// assert_eq!(hxai_eval::shared_rows(&[&x, &y], &[&x, &y]), 3);
/// ```
pub fn shared_rows(train: &[&[f64]], test: &[&[f64]]) -> usize {
    let key = |cols: &[&[f64]], i: usize| -> Vec<u64> {
        cols.iter().map(|c| (c[i] + 0.0).to_bits()).collect()
    };
    let rows = |cols: &[&[f64]]| cols.first().map_or(0, |c| c.len());
    let seen: std::collections::HashSet<Vec<u64>> =
        (0..rows(train)).map(|i| key(train, i)).collect();
    (0..rows(test))
        .filter(|&i| seen.contains(&key(test, i)))
        .count()
}

/// At most `k` of the positions of `y`, stratified on its values: the positions sorted by
/// `y` (ties by position), cut into `k` strata of (nearly) equal count, one position drawn
/// from each with a seeded generator; returned in increasing order. Every position when
/// `k >= y.len()`. The sample spans the target's range as a random one of the same size
/// does only on average: the few rows of a tail are always represented. Values that are
/// not numbers sort last.
pub fn stratified_sample(y: &[f64], k: usize, seed: u64) -> Vec<usize> {
    use rand::Rng;
    let n = y.len();
    if k >= n {
        return (0..n).collect();
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| y[a].total_cmp(&y[b]).then(a.cmp(&b)));
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out: Vec<usize> = (0..k)
        .map(|s| {
            let (lo, hi) = (s * n / k, (s + 1) * n / k);
            order[rng.gen_range(lo..hi)]
        })
        .collect();
    out.sort_unstable();
    out
}

/// [`stratified_sample`] of `y` with, besides, the positions of the smallest and the
/// largest value of each of `columns` (one slice per column, each `y`'s length; values that
/// are not numbers ignored): a structure searched on the sample then sees the whole box of
/// the columns, so a pole or a logarithm that would break on a rare row at an edge (a zero
/// in a column of sizes) is refused there, not found on the full rows afterwards. At most
/// `k + 2 * columns.len()` positions, in increasing order; every position when `k >=
/// y.len()`.
pub fn stratified_sample_spanning(
    y: &[f64],
    k: usize,
    seed: u64,
    columns: &[&[f64]],
) -> Vec<usize> {
    let mut out = stratified_sample(y, k, seed);
    if out.len() == y.len() {
        return out;
    }
    for col in columns {
        let finite = || col.iter().enumerate().filter(|(_, v)| v.is_finite());
        let lo = finite().min_by(|a, b| a.1.total_cmp(b.1)).map(|(i, _)| i);
        let hi = finite().max_by(|a, b| a.1.total_cmp(b.1)).map(|(i, _)| i);
        out.extend(lo.into_iter().chain(hi));
    }
    out.sort_unstable();
    out.dedup();
    out
}

#[cfg(test)]
mod sample_tests {
    #![allow(clippy::unwrap_used)]
    use super::{stratified_sample, stratified_sample_spanning};

    /// The rows of each column's extremes join the sample, once each.
    #[test]
    fn the_extremes_of_every_column_are_in_the_sample() {
        let y: Vec<f64> = (0..500).map(f64::from).collect();
        let x: Vec<f64> = (0..500).map(|i| f64::from((i * 37) % 500)).collect();
        let s = stratified_sample_spanning(&y, 20, 1, &[&x, &y]);
        let lo = x.iter().position(|&v| v == 0.0).unwrap();
        let hi = x.iter().position(|&v| v == 499.0).unwrap();
        assert!(s.contains(&lo) && s.contains(&hi) && s.contains(&0) && s.contains(&499));
        assert!(s.len() <= 24 && s.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(
            stratified_sample_spanning(&y[..10], 20, 1, &[&x[..10]]).len(),
            10
        );
    }

    /// `k` distinct positions in increasing order, one per stratum of the sorted values
    /// (so the smallest and largest `n / k` values are each represented), the same for the
    /// same seed, and every position when `k` is not below the length.
    #[test]
    fn one_position_per_stratum() {
        let y: Vec<f64> = (0..1000).map(|i| f64::from((i * 7919) % 1000)).collect();
        let s = stratified_sample(&y, 100, 3);
        assert_eq!(s.len(), 100);
        assert!(s.windows(2).all(|w| w[0] < w[1]));
        let mut vals: Vec<f64> = s.iter().map(|&i| y[i]).collect();
        vals.sort_by(f64::total_cmp);
        for (j, v) in vals.iter().enumerate() {
            assert!(
                *v >= 10.0 * j as f64 && *v < 10.0 * (j + 1) as f64,
                "{j}: {v}"
            );
        }
        assert_eq!(s, stratified_sample(&y, 100, 3));
        assert_ne!(s, stratified_sample(&y, 100, 4));
        assert_eq!(
            stratified_sample(&y[..50], 100, 3),
            (0..50).collect::<Vec<_>>()
        );
    }
}
