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

use super::super::{Form, TableProgress};
use super::folds::{folds, mean_se};
use super::job::{SplitJob, calibrate_split};
use super::one::fit_form;
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
/// the free form (the factor form under a monotone constraint), unscored. Errors of a fold's calibration or search are returned.
pub(crate) fn choose(
    job: SplitJob,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<(Form, Option<FormChoice>), HybridError> {
    let (table, cfg, split) = (job.table, job.cfg, job.split);
    let Some(folds) = folds(table, cfg, &split.train, AUTO_FOLDS)? else {
        let form = if cfg.monotone() {
            Form::Factors
        } else {
            Form::Free
        };
        return Ok((form, None));
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
        progress(&TableProgress::phase(
            format!(
                "form auto: fold {}/{} on {} rows (none, factors, free)",
                k + 1,
                folds.len(),
                split.train.len()
            ),
            k,
            folds.len(),
        ));
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
        // a monotone constraint binds the factor form only: free is not a candidate then
        let forms: &[Form] = if cfg.monotone() {
            &[Form::Factors]
        } else {
            &[Form::Factors, Form::Free]
        };
        for &form in forms {
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
            let err = match fit_form(fold_job, &cal, form, None, None, progress)
                .and_then(|m| m.predict(table))
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
}
