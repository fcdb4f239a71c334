//! Folds of a split's training rows for the fit's cross-validations (the form's choice,
//! the terms that earn their place): grouped, in blocks of a column's range, stratified by
//! level, or random; and the mean and standard error of held-out errors.

use super::super::ValidTable;
use crate::HybridError;
use crate::correction::CvError;
use hxai_eval::Split;

/// Mean and standard error of the mean of errors `e` (`se` infinite with one error or an
/// infinite one).
pub(crate) fn mean_se(e: &[f64]) -> CvError {
    let k = e.len() as f64;
    let mean = e.iter().sum::<f64>() / k;
    let var = e.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (k - 1.0).max(1.0);
    CvError {
        mean,
        se: if e.len() > 1 && var.is_finite() {
            (var / k).sqrt()
        } else {
            f64::INFINITY
        },
    }
}

/// `k` folds of the training rows (positions in `train`): grouped by `--group`, else in
/// blocks of the `--extrapolate` column's range ([`block_folds`]), else stratified by the
/// per-class levels (`--calibrate-per`, `--correction-per`), else at random; `None`
/// when there are fewer rows than four times `k`, or groups than twice it.
pub(crate) fn folds(
    table: &hxai_symreg::Table,
    cfg: &ValidTable,
    train: &[usize],
    k: usize,
) -> Result<Option<Vec<Split>>, HybridError> {
    let units = super::super::conformal::fold_units(table, cfg, train)?;
    let enough = match &units {
        Some(keys) => {
            let mut distinct = keys.clone();
            distinct.sort_unstable();
            distinct.dedup();
            distinct.len() >= 2 * k
        }
        None => train.len() >= 4 * k,
    };
    if !enough {
        return Ok(None);
    }
    Ok(Some(match (units, &cfg.extrapolate) {
        (Some(keys), _) => hxai_eval::grouped_kfold(&keys, k, cfg.seed)?,
        // the split asks how the model extrapolates in a column: so do the folds, each
        // holding out one block of the training rows' range of that column
        (None, Some(col)) => {
            let v = table.require(col)?;
            block_folds(&train.iter().map(|&i| v[i]).collect::<Vec<_>>(), k)
        }
        // per-class constants: each level spread over the folds, so none is held out whole
        (None, None) if !cfg.strata.is_empty() => {
            let strata = super::super::split::strata_of(table, &cfg.strata)?;
            super::super::split::stratified_folds(
                &train.iter().map(|&i| strata[i]).collect::<Vec<_>>(),
                k,
                cfg.seed,
            )
        }
        (None, None) => hxai_eval::kfold(train.len(), k, cfg.seed)?,
    }))
}

/// `k` folds of the rows of `values` in which each fold's held-out rows are one block of
/// the rows sorted by value (ties kept in row order): the first fold holds out the lowest
/// values, the last the highest.
pub(crate) fn block_folds(values: &[f64], k: usize) -> Vec<Split> {
    let n = values.len();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b)));
    (0..k)
        .map(|b| {
            let mut test: Vec<usize> = order[b * n / k..(b + 1) * n / k].to_vec();
            test.sort_unstable();
            let train = (0..n).filter(|i| test.binary_search(i).is_err()).collect();
            Split { train, test }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// Stratified folds hold every row out once and spread each stratum over the folds: a
    /// stratum of 2 rows is held out in two different folds, one of 3 in all three.
    #[test]
    fn stratified_folds_spread_each_level() {
        let strata = [0, 0, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2];
        let folds = super::super::super::split::stratified_folds(&strata, 3, 42);
        let mut held = vec![0; strata.len()];
        for f in &folds {
            for &i in &f.test {
                held[i] += 1;
            }
            assert_eq!(f.train.len() + f.test.len(), strata.len());
        }
        assert!(held.iter().all(|&h| h == 1));
        for level in 0..3 {
            let rows = strata.iter().filter(|&&s| s == level).count();
            let folds_with = folds
                .iter()
                .filter(|f| f.test.iter().any(|&i| strata[i] == level))
                .count();
            assert_eq!(folds_with, rows.min(3), "level {level}");
        }
    }

    /// Every row is held out once, each fold's held-out rows are one block of the values,
    /// and the blocks go from the lowest values to the highest.
    #[test]
    fn block_folds_hold_out_blocks_of_the_range() {
        let v = [5.0, 1.0, 9.0, 3.0, 7.0, 2.0, 8.0, 4.0, 6.0];
        let folds = block_folds(&v, 3);
        let held: Vec<Vec<f64>> = folds
            .iter()
            .map(|f| {
                let mut h: Vec<f64> = f.test.iter().map(|&i| v[i]).collect();
                h.sort_by(f64::total_cmp);
                h
            })
            .collect();
        assert_eq!(
            held,
            vec![
                vec![1.0, 2.0, 3.0],
                vec![4.0, 5.0, 6.0],
                vec![7.0, 8.0, 9.0]
            ]
        );
        for f in &folds {
            assert_eq!(f.train.len() + f.test.len(), v.len());
            assert!(f.train.iter().all(|i| !f.test.contains(i)));
        }
    }
}
