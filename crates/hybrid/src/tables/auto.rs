//! `--form auto` (issue 64): which correction these rows support, `none` (the calibrated
//! physics alone), `factors` or `free`, chosen by K-fold cross-validation on the training
//! rows with the one-standard-error rule toward the simpler.
//!
//! Each fold is a whole fit on the fold's training rows (the physics calibrated again, the
//! correction searched again), scored by the hybrid's squared error on the fold's held-out
//! rows, so a correction that fits the rows and breaks beside them pays for it. The folds'
//! free-form searches run with `1/(2K)` of the epochs each (at least one,
//! [`AUTO_EPOCH_SHARE`]), which keeps `auto` near twice the free form's cost; the form picked
//! is then fitted with the full budget on every training row.

use super::fit::{SplitJob, calibrate_split, fit_calibrated};
use super::{Form, TableProgress};
use crate::HybridError;
pub use crate::correction::{CvError, FormChoice};
use hxai_eval::Split;
use std::collections::BTreeMap;

/// Folds of the choice: 3, not the 5 of the search's own selection, since every fold is a
/// whole fit of both corrections (at 5 the choice cost about four free-form fits).
pub const AUTO_FOLDS: usize = 3;

/// The folds' free-form searches run with `1 / (AUTO_EPOCH_SHARE * K)` of the epochs
/// each (at least one): together half a free-form search, which keeps `auto` within about
/// twice the free form's time when it picks the free form, and below when it picks another.
pub const AUTO_EPOCH_SHARE: usize = 2;

/// Standard errors of the rule: a more complex form is picked only when its held-out error
/// is lower than the simpler one's by more than one standard error of the best.
pub const AUTO_SE_RULE: f64 = 1.0;

/// Chooses the form of `job`'s correction: see the module documentation.
///
/// # Errors
/// Fewer training rows (or groups) than [`AUTO_FOLDS`] are not an error: the choice is then
/// the free form, unscored. Errors of a fold's calibration or search are returned.
pub(crate) fn choose(
    job: SplitJob,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<(Form, Option<FormChoice>), HybridError> {
    let (table, cfg, split) = (job.table, job.cfg, job.split);
    let Some(folds) = folds(table, cfg, &split.train, AUTO_FOLDS)? else {
        return Ok((Form::Free, None));
    };
    let y = table.require(&cfg.target)?;
    let mut per_form: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
    for (k, fold) in folds.iter().enumerate() {
        let sub = Split {
            train: fold.train.iter().map(|&i| split.train[i]).collect(),
            test: fold.test.iter().map(|&i| split.train[i]).collect(),
        };
        // each held-out row's squared error
        let errors = |pred: &[f64]| -> Vec<f64> {
            sub.test.iter().map(|&i| (y[i] - pred[i]).powi(2)).collect()
        };
        let cal = calibrate_split(SplitJob {
            table,
            cfg,
            split: &sub,
            kind: "fold",
            task: (k + 1, folds.len()),
        })?;
        per_form
            .entry("none")
            .or_default()
            .extend(errors(&cal.physics));
        for form in [Form::Factors, Form::Free] {
            let mut c = cfg.config().clone();
            c.form = form;
            c.conformal_folds = 0;
            c.search.epochs = (c.search.epochs / (AUTO_EPOCH_SHARE * folds.len())).max(1);
            let c = c.check()?;
            let fold_job = SplitJob {
                table,
                cfg: &c,
                split: &sub,
                kind: "fold",
                task: (k + 1, folds.len()),
            };
            // a fold whose correction has no value on a held-out row scores as the physics
            // would not: infinitely bad, so that form is not picked on its account
            let err = match fit_calibrated(fold_job, &cal, progress).and_then(|m| m.predict(table))
            {
                Ok(p) => errors(&p.hybrid),
                Err(HybridError::BadCorrection { .. } | HybridError::BadPhysics { .. }) => {
                    vec![f64::INFINITY; sub.test.len()]
                }
                Err(e) => return Err(e),
            };
            per_form.entry(form.name()).or_default().extend(err);
        }
    }
    let (cv, picked) = pick(&per_form);
    Ok((
        picked,
        Some(FormChoice {
            cv,
            picked: picked.name().to_string(),
            rule: format!(
                "{} folds of the training rows, each a whole fit, every training row held out \
                 once; the simplest of none < factors < free whose mean held-out squared error \
                 is within {AUTO_SE_RULE} standard error of the lowest (from its rows' spread)",
                folds.len()
            ),
        }),
    ))
}

/// The warning of a choice that picked `none`: no correction these rows support, so the
/// model is the calibrated physics alone (a legitimate answer the user should not miss).
pub(crate) fn none_warning(c: &FormChoice) -> Option<String> {
    (c.picked == Form::None.name()).then(|| {
        let errors: Vec<String> =
            c.cv.iter()
                .map(|(f, e)| format!("{f} {}", hxai_table::format_number(e.mean)))
                .collect();
        format!(
            "--form auto picked none: no correction beat the calibrated physics alone by more \
             than one standard error in cross-validation (held-out mean squared error {}), so \
             the model is the physics alone; --form factors or free fits one anyway",
            errors.join(", ")
        )
    })
}

/// The rule of the choice over each form's held-out squared errors, one per training row
/// (`errors`): each form's mean and standard error, and the simplest form whose mean is
/// within [`AUTO_SE_RULE`] standard errors of the lowest mean (the standard error of that
/// lowest mean, from its rows' spread: steadier than the spread of three folds' means);
/// `none` when no form has a finite error. A row whose error is not a number counts as
/// infinitely bad.
fn pick(errors: &BTreeMap<&str, Vec<f64>>) -> (BTreeMap<String, CvError>, Form) {
    let cv: BTreeMap<String, CvError> = errors
        .iter()
        .map(|(f, e)| {
            let e: Vec<f64> = e
                .iter()
                .map(|v| if v.is_nan() { f64::INFINITY } else { *v })
                .collect();
            ((*f).to_string(), mean_se(&e))
        })
        .collect();
    let Some(best) = cv
        .values()
        .filter(|e| e.mean.is_finite())
        .min_by(|a, b| a.mean.total_cmp(&b.mean))
        .copied()
    else {
        return (cv, Form::None);
    };
    let bar = best.mean + AUTO_SE_RULE * best.se;
    let picked = [Form::None, Form::Factors, Form::Free]
        .into_iter()
        .find(|f| cv.get(f.name()).is_some_and(|e| e.mean <= bar))
        .unwrap_or(Form::None);
    (cv, picked)
}

/// Mean and standard error of the mean of errors `e` (`se` infinite with one error or an
/// infinite one).
pub(super) fn mean_se(e: &[f64]) -> CvError {
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
pub(super) fn folds(
    table: &hxai_symreg::Table,
    cfg: &super::ValidTable,
    train: &[usize],
    k: usize,
) -> Result<Option<Vec<Split>>, HybridError> {
    let units = super::conformal::fold_units(table, cfg, train)?;
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
            let strata = super::split::strata_of(table, &cfg.strata)?;
            super::split::stratified_folds(
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
pub(super) fn block_folds(values: &[f64], k: usize) -> Vec<Split> {
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

    /// A form better on every row by less than one standard error of the best's mean is
    /// not picked over a simpler one, one better by more is, a form with an error that is
    /// not a number never is, and the simplest of several within the bar wins.
    #[test]
    fn the_simplest_within_one_standard_error_is_picked() {
        let base: Vec<f64> = (0..30).map(|i| 1.0 + f64::from(i % 10) / 10.0).collect();
        let shifted = |d: f64| base.iter().map(|v| v - d).collect::<Vec<f64>>();
        let se = mean_se(&base).se;
        let mut e: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
        e.insert("none", base.clone());
        e.insert("free", shifted(0.5 * se));
        assert_eq!(pick(&e).1, Form::None);
        e.insert("free", shifted(2.0 * se));
        assert_eq!(pick(&e).1, Form::Free);
        e.insert("factors", shifted(1.5 * se));
        assert_eq!(pick(&e).1, Form::Factors);
        let mut nan = shifted(3.0 * se);
        nan[4] = f64::NAN;
        e.insert("factors", nan);
        let (cv, picked) = pick(&e);
        assert_eq!(picked, Form::Free);
        assert!(cv["factors"].mean.is_infinite());
    }

    /// Stratified folds hold every row out once and spread each stratum over the folds: a
    /// stratum of 2 rows is held out in two different folds, one of 3 in all three.
    #[test]
    fn stratified_folds_spread_each_level() {
        let strata = [0, 0, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2];
        let folds = super::super::split::stratified_folds(&strata, 3, 42);
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
