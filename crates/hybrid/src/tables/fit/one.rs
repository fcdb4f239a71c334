//! The fit of one split in one correction form: the correction searched on the calibrated
//! physics' `delta` ([`super::search`]), its unearned terms dropped ([`super::earn`]), the
//! joint refit when asked ([`super::joint`]), the model written down
//! ([`super::assemble`]) with its warnings, per-level constants, scores and conformal
//! calibration.

use super::super::correction_per::fit_levels;
use super::super::model::{TableModel, columns_of};
use super::super::physics::{deltas, gather};
use super::super::{CorrectionForm, Form, TableProgress};
use super::assemble::{Fitted, model_of, scores_of};
use super::earn::earn;
use super::job::{Calibrated, SplitJob, Task};
use super::joint::joint_refit;
use super::search::{Searched, no_correction, search_factors, search_free};
use crate::HybridError;
use crate::correction::FormChoice;

/// The fit of `job`'s split in the correction form `form` (`choice`: how `auto` chose it)
/// from the split's calibrated physics `cal`; the joint refit works on its own copy of the
/// parameters. With `sample` (a large table's search sample, issue 67), the conformal
/// calibration's refits run on those rows.
pub(crate) fn fit_form(
    job: SplitJob,
    cal: &Calibrated,
    form: Form,
    choice: Option<FormChoice>,
    sample: Option<&[usize]>,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<TableModel, HybridError> {
    let (table, cfg, split, task) = (job.table, job.cfg, job.split, job.task);
    let Calibrated {
        res,
        phys,
        ses,
        physics,
    } = cal;
    let (mut phys, mut ses) = (phys.clone(), ses.clone());
    let y_all = table.require(&cfg.target)?;
    let delta = deltas(cfg.correction, y_all, physics, &split.train)?;
    let label = if task.1 > 1 {
        format!("correction ({}/{})", task.0, task.1)
    } else {
        "correction".to_string()
    };
    let searched = match form {
        Form::Free | Form::Auto => {
            search_free(job, res, &delta, Task { of: task, label }, progress)?
        }
        Form::Factors => {
            let n = split.train.len();
            progress(&TableProgress::phase(
                if n > cfg.search_rows {
                    format!(
                        "{label}: factor form on {} rows, constants on {n}",
                        cfg.search_rows
                    )
                } else {
                    format!("{label}: factor form on {n} rows")
                },
                0,
                1,
            ));
            search_factors(table, res, cfg, split, &delta, physics)?
        }
        Form::None => no_correction(table, res, split)?,
    };
    let Searched {
        ft,
        model: correction,
        mut selection,
        pareto,
        factors,
    } = searched;
    progress(&TableProgress::phase(
        "checking that every term of the correction earns its place",
        0,
        1,
    ));
    let (mut correction, earned) =
        earn(job, form, correction, &mut selection, (&ft, &delta), sample)?;
    let y_train = gather(y_all, &split.train);

    let mut joint = None;
    if cfg.joint {
        joint = Some(joint_refit(
            job,
            res,
            &mut phys,
            &mut correction,
            &mut ses,
            &y_train,
        )?);
    }

    let fitted = Fitted {
        phys,
        ses,
        correction,
        selection,
        joint,
    };
    let mut model = model_of(job, res, &ft, &pareto, fitted, (y_all, &y_train), sample)?;
    model.correction.form = Some(form);
    model.correction.choice = choice;
    model.correction.factors = factors;
    model.warnings =
        super::super::traps::fit_warnings(table, cfg, &res.features, split, y_all, physics);
    let mut read: Vec<String> = vec![cfg.target.clone()];
    for c in res.columns.iter().chain(&res.features) {
        if !read.contains(c) {
            read.push(c.clone());
        }
    }
    model
        .warnings
        .extend(super::super::traps::value_warnings(table, &read));
    model
        .warnings
        .extend(super::super::traps::parameter_warnings(
            &model.physics.standard_errors,
            &model.physics.parameters,
        ));
    model.warnings.extend(earned);
    model
        .warnings
        .extend(model.correction.choice.as_ref().and_then(none_warning));
    if let Some(u) = &model.correction.uncertainty {
        let spanning: Vec<String> = u
            .params
            .iter()
            .filter(|(_, p)| p.ci95.is_some_and(|[lo, hi]| lo < 0.0 && hi > 0.0))
            .map(|(n, _)| n.clone())
            .collect();
        if !spanning.is_empty() {
            model.warnings.push(format!(
                "the correction's constant(s) {} of `{}` have a 95 % interval that spans 0 and \
                 were kept: the rows do not show that their terms matter, but dropping them \
                 raised the held-out error by more than one standard error (or, in the factor \
                 form, their factor passed the forward selection's test)",
                spanning.join(", "),
                u.template
            ));
        }
    }
    if let Some(setting) = &cfg.correction_per {
        let shared = model.correction.fitted()?;
        let features = columns_of(table, &shared.feature_names, "correction feature")?;
        let cp = fit_levels(setting, (shared, &features), table, &split.train, &delta)?;
        if !cp.shared.is_empty() {
            model.warnings.push(format!(
                "--correction-per {}: level(s) {} have too few training rows to refit the \
                 correction's constants, and keep the shared ones",
                cp.column,
                cp.shared.join(", ")
            ));
        }
        model.correction_per = Some(cp);
    }
    model.scores = scores_of(&model, table, y_all, split)?;
    if cfg.conformal_folds > 0 && cfg.correction_per.is_none() {
        model.conformal = Some(super::super::conformal::calibrate(
            table,
            cfg,
            res,
            &model,
            sample.unwrap_or(&split.train),
            cfg.conformal_folds,
            &mut |k, of| {
                progress(&TableProgress::phase(
                    format!(
                        "conformal calibration on {} rows",
                        sample.map_or(split.train.len(), <[usize]>::len)
                    ),
                    k,
                    of,
                ))
            },
        )?);
    }
    let hybrid = model.predict(table)?.hybrid;
    model
        .warnings
        .extend(super::super::traps::interval_warnings(
            &y_train,
            &gather(&hybrid, &split.train),
            job.kind == "extrapolate",
            cfg.correction == CorrectionForm::Additive,
        ));
    Ok(model)
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
