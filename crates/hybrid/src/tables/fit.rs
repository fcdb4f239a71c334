//! Fitting a table model: the steps of one fit on one split ([`fit_inner`]; writing the
//! model down is `assemble`'s), its public
//! entry points, and the stability of the correction's structure.

use super::assemble::{Fitted, model_of, scores_of, train_rmse};
use super::model::{JointInfo, TableModel, columns_of, combine};
use super::physics::{
    calibrate_physics, calibrated_slots, deltas, gather, named_values, physics_values,
};
use super::resolve::{Resolved, resolve};
use super::split::{check_rows, split_rows};
use super::{Form, TableConfig, TableProgress, ValidTable, calibrate};
use crate::HybridError;
use hxai_eval::Split;
use hxai_symreg::Table;
use hxai_symreg::infix::Compiled;
use std::collections::BTreeMap;

/// The stability of the correction's structure of `model` (fitted with `cfg` on `table`):
/// the correction's search rerun on `runs` bootstrap resamples of the training rows, on
/// `delta` of the model's calibrated physics ([`hxai_symreg::stability()`]). `progress`
/// gets `(runs done, runs)`.
///
/// # Errors
/// A missing column, a physics value that cannot be used, and the search's errors.
pub fn stability(
    table: &Table,
    cfg: &TableConfig,
    model: &TableModel,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<hxai_symreg::Stability, HybridError> {
    let physics = model.predict(table)?.physics;
    let y = table.require(&model.target)?;
    let delta = deltas(model.correction.kind, y, &physics, &model.split.train)?;
    let ft = table
        .select_columns(&model.correction.candidates)?
        .select_rows(&model.split.train)?;
    if model.correction.form.as_deref() == Some(Form::Factors.name()) {
        let fp: Vec<f64> = model.split.train.iter().map(|&i| physics[i]).collect();
        return Ok(hxai_symreg::factors::factor_stability_on_physics(
            &ft,
            &delta,
            &fp,
            model.correction.kind.link(),
            &cfg.factor_config(&model.correction.candidates),
            runs,
            progress,
        )?);
    }
    Ok(hxai_symreg::stability(
        &ft,
        &delta,
        &cfg.search_config(),
        runs,
        progress,
    )?)
}

/// The share of resamples below which a correction's structure is warned about (issue 64:
/// a structure that came back in 0 % of 20 resamples was reported without a word).
pub const LOW_SHARE: f64 = 0.2;

/// Measures the stability of `model`'s correction ([`stability`]) and stores it in the
/// model: `model.stability`, and the shares of its selection report (the structure's and
/// each alternative's, [`hxai_symreg::SelectionReport::with_stability`]). What `hxai
/// hybrid fit --stability N` and Python's `HybridRegressor(stability_runs=N)` run.
///
/// # Errors
/// Those of [`stability`].
pub fn measure_stability(
    table: &Table,
    cfg: &TableConfig,
    model: &mut TableModel,
    runs: usize,
    progress: &mut (dyn FnMut(usize, usize) + Send),
) -> Result<(), HybridError> {
    if model.correction.form.as_deref() == Some(Form::None.name()) {
        // the physics alone: no structure to resample
        return Ok(());
    }
    let st = stability(table, cfg, model, runs, progress)?;
    let sel = model.correction.selection.take();
    model.correction.selection = sel.map(|sel| sel.with_stability(&st));
    model.stability = Some(st);
    if let Some(share) = model.correction.selection.as_ref().and_then(|s| s.share)
        && share < LOW_SHARE
    {
        model.warnings.push(format!(
            "the correction's structure came back in {:.0} % of the {runs} resamples (below \
             {:.0} %): the rows do not pin it down; read it as one of several that fit, or try \
             --form factors or none",
            100.0 * share,
            100.0 * LOW_SHARE
        ));
    }
    Ok(())
}

/// Fits on the split [`split_rows`] chooses.
///
/// # Errors
/// Bad configuration (see [`HybridError`]'s variants `UnknownName`, `ParameterIsColumn`,
/// `ParameterNotInEquation`, `TargetInPhysics`, `MissingColumn`, `NoFeatures`,
/// `Equation`), a physics value that cannot be used (`BadPhysics`), or a failed search.
pub fn fit(
    table: &Table,
    cfg: &TableConfig,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<TableModel, HybridError> {
    let cfg = &cfg.check()?;
    let (split, kind) = split_rows(table, cfg)?;
    let slots = super::slots::expand(table, cfg, &split.train, progress)?;
    let cfg = slots.as_ref().map_or(cfg, |e| &e.cfg);
    let job = SplitJob::single(table, cfg, &split, &kind);
    let cal = calibrate_split(job)?;
    let mut model = fit_calibrated(job, &cal, progress)?;
    model.scores.black_boxes = super::compare::black_box_scores(job, &cal, &model)?;
    if let Some(e) = &slots {
        e.finish(&mut model);
    }
    Ok(model)
}

/// Fits on a given split (test rows may be empty: everything is then training data).
///
/// # Errors
/// As [`fit`], and row indices out of range.
pub fn fit_split(
    table: &Table,
    cfg: &TableConfig,
    split: &Split,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<TableModel, HybridError> {
    let cfg = &cfg.check()?;
    check_rows(table, split)?;
    let slots = super::slots::expand(table, cfg, &split.train, progress)?;
    let cfg = slots.as_ref().map_or(cfg, |e| &e.cfg);
    let mut model = fit_inner(SplitJob::single(table, cfg, split, "given"), progress)?;
    if let Some(e) = &slots {
        e.finish(&mut model);
    }
    Ok(model)
}

/// A search as the progress reports name it: task `of.0` of `of.1`, called `label`.
pub(crate) struct Task {
    /// `(this task, tasks in all)`.
    pub(crate) of: (usize, usize),
    /// What the task is (`correction (2/11)`, `symbolic (3/11)`).
    pub(crate) label: String,
}

/// Symbolic regression of `y` (one value per training row of `split`) on the training rows
/// of the feature columns, reported as `task`: those rows' feature table and the search's
/// result.
pub(crate) fn search_training_rows(
    table: &Table,
    res: &Resolved,
    cfg: &ValidTable,
    split: &Split,
    y: &[f64],
    task: Task,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<(Table, hxai_symreg::SearchResult), HybridError> {
    let Task { of: task, label } = task;
    let ft = table
        .select_columns(&res.features)?
        .select_rows(&split.train)?;
    let found = hxai_symreg::search_checked(&ft, y, cfg.search(), &mut |p| {
        progress(&TableProgress {
            task: task.0,
            tasks: task.1,
            label: label.clone(),
            search: p.clone(),
        })
    })?;
    Ok((ft, found))
}

/// One fit on one split of a table: what [`fit_inner`] (and the comparison's
/// per-split predictions) work on.
#[derive(Clone, Copy)]
pub(crate) struct SplitJob<'a> {
    pub(crate) table: &'a Table,
    pub(crate) cfg: &'a ValidTable,
    pub(crate) split: &'a Split,
    /// Split kind, as the model file reports it (`random`, `given`, `fold`, ...).
    pub(crate) kind: &'a str,
    /// `(this task, tasks in all)`, for progress reports.
    pub(crate) task: (usize, usize),
}

impl<'a> SplitJob<'a> {
    /// The only task of a run.
    fn single(table: &'a Table, cfg: &'a ValidTable, split: &'a Split, kind: &'a str) -> Self {
        let task = (1, 1);
        Self {
            table,
            cfg,
            split,
            kind,
            task,
        }
    }
}

/// What every model of one split starts from, computed once per split
/// ([`calibrate_split`]): the physics resolved against the table, calibrated on the
/// training rows (with the standard errors of its parameters), and its values on every row.
#[derive(Clone, Debug)]
pub(crate) struct Calibrated {
    pub(crate) res: Resolved,
    pub(crate) phys: Compiled,
    pub(crate) ses: BTreeMap<String, Option<f64>>,
    /// The calibrated physics on every row of the table.
    pub(crate) physics: Vec<f64>,
}

/// Checks `job`'s rows, resolves the physics against the table and calibrates
/// it on the training rows: what the fit ([`fit_calibrated`]), the black boxes beside it
/// and the comparison's other models share.
///
/// # Errors
/// Rows out of range, and those of the physics' resolution and calibration (the settings
/// were checked by [`TableConfig::check`]).
pub(crate) fn calibrate_split(job: SplitJob) -> Result<Calibrated, HybridError> {
    let (table, cfg, split) = (job.table, job.cfg, job.split);
    check_rows(table, split)?;
    let res = resolve(table, cfg)?;
    let (phys, ses) = calibrate_physics(table, cfg, &res, &split.train)?;
    let physics = physics_values(table, &res, &phys)?;
    Ok(Calibrated {
        res,
        phys,
        ses,
        physics,
    })
}

/// Fits one split: calibrates the physics on the training rows, searches the correction of
/// its `delta`, refits both jointly when asked, and writes the model with its scores and,
/// with `conformal_folds`, its conformal calibration.
pub(crate) fn fit_inner(
    job: SplitJob,
    progress: &mut dyn FnMut(&TableProgress),
) -> Result<TableModel, HybridError> {
    fit_calibrated(job, &calibrate_split(job)?, progress)
}

/// [`fit_inner`] from the split's calibrated physics `cal` ([`calibrate_split`]); the
/// joint refit works on its own copy of the parameters.
pub(crate) fn fit_calibrated(
    job: SplitJob,
    cal: &Calibrated,
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
    let (form, choice) = match cfg.form {
        Form::Auto => super::auto::choose(job, progress)?,
        f => (f, None),
    };
    let searched = match form {
        Form::Free | Form::Auto => {
            let (ft, found) = search_training_rows(
                table,
                res,
                cfg,
                split,
                &delta,
                Task { of: task, label },
                progress,
            )?;
            Searched {
                selection: hxai_symreg::SelectionReport::of(&found, cfg.search()),
                model: found.best,
                pareto: found.pareto,
                factors: None,
                ft,
            }
        }
        Form::Factors => search_factors(table, res, cfg, split, &delta, physics)?,
        Form::None => no_correction(table, res, split)?,
    };
    let Searched {
        ft,
        model: correction,
        mut selection,
        pareto,
        factors,
    } = searched;
    let (mut correction, earned) =
        super::earn::earn(job, form, correction, &mut selection, &ft, &delta)?;
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
    let mut model = model_of(job, res, &ft, &pareto, fitted, y_all, &y_train)?;
    model.correction.form = Some(form.name().to_string());
    model.correction.choice = choice;
    model.correction.factors = factors;
    model.warnings = super::traps::fit_warnings(table, cfg, &res.features, split, y_all, physics);
    let mut read: Vec<String> = vec![cfg.target.clone()];
    for c in res.columns.iter().chain(&res.features) {
        if !read.contains(c) {
            read.push(c.clone());
        }
    }
    model
        .warnings
        .extend(super::traps::value_warnings(table, &read));
    model.warnings.extend(super::traps::parameter_warnings(
        &model.physics.standard_errors,
        &model.physics.parameters,
    ));
    model.warnings.extend(earned);
    model.warnings.extend(
        model
            .correction
            .choice
            .as_ref()
            .and_then(super::auto::none_warning),
    );
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
        let cp = super::correction_per::fit_levels(setting, &model, table, &split.train, &delta)?;
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
        model.conformal = Some(super::conformal::calibrate(
            table,
            cfg,
            res,
            &model,
            &split.train,
            cfg.conformal_folds,
        )?);
    }
    let hybrid = model.predict(table)?.hybrid;
    model.warnings.extend(super::traps::interval_warnings(
        &y_train,
        &gather(&hybrid, &split.train),
        job.kind == "extrapolate",
        cfg.correction == super::CorrectionForm::Additive,
    ));
    Ok(model)
}

/// The correction a search found on the training rows: their feature table, the model,
/// how it was selected, the models it was chosen from and, in the factor form, its factors.
struct Searched {
    ft: Table,
    model: hxai_symreg::Model,
    selection: hxai_symreg::SelectionReport,
    pareto: Vec<hxai_symreg::Model>,
    factors: Option<Vec<hxai_symreg::factors::Factor>>,
}

/// The factor form's search ([`hxai_symreg::factors::fit_factors`]) of `delta` on the
/// training rows: its alternatives are the selected columns with another shape that the
/// held-out error cannot tell apart. A multiplicative correction is fitted by the
/// hybrid's error in the target's units (`physics` on every row of the table).
/// The zero correction of `--form none` (or of `auto` when no correction pays): a
/// constant 0 over no column, its selection saying so.
fn no_correction(table: &Table, res: &Resolved, split: &Split) -> Result<Searched, HybridError> {
    let ft = table
        .select_columns(&res.features)?
        .select_rows(&split.train)?;
    let zero = hxai_symreg::Model::new(
        Vec::new(),
        hxai_symreg::Program {
            nodes: vec![hxai_symreg::Node::Const],
            affine: false,
        },
        vec![1.0, 0.0, 0.0],
    )?;
    let selection = hxai_symreg::SelectionReport {
        method: "none".into(),
        structure: "0".into(),
        share: None,
        runs: None,
        alternatives: Vec::new(),
        error_model: hxai_symreg::ErrorModel::Additive,
        prior: None,
    };
    Ok(Searched {
        ft,
        pareto: vec![zero.clone()],
        model: zero,
        selection,
        factors: None,
    })
}

fn search_factors(
    table: &Table,
    res: &Resolved,
    cfg: &TableConfig,
    split: &Split,
    delta: &[f64],
    physics: &[f64],
) -> Result<Searched, HybridError> {
    let ft = table
        .select_columns(&res.features)?
        .select_rows(&split.train)?;
    let fp: Vec<f64> = split.train.iter().map(|&i| physics[i]).collect();
    let fc = cfg.factor_config(&res.features);
    let fit =
        hxai_symreg::factors::fit_factors_on_physics(&ft, delta, &fp, cfg.correction.link(), &fc)?;
    let alternatives = fit
        .alternatives
        .iter()
        .take(3)
        .map(|m| hxai_symreg::Alternative {
            equation: m.equation(),
            sympy: m.sympy(),
            complexity: m.complexity(),
            structure: hxai_symreg::stability::structure_of(m),
            share: None,
            uncertainty: None,
            codelength: None,
        })
        .collect();
    let selection = hxai_symreg::SelectionReport {
        method: "factors".into(),
        structure: hxai_symreg::stability::structure_of(&fit.model),
        share: None,
        runs: None,
        alternatives,
        error_model: hxai_symreg::ErrorModel::Additive,
        prior: None,
    };
    let mut pareto = vec![fit.model.clone()];
    pareto.extend(fit.alternatives.iter().cloned());
    Ok(Searched {
        ft,
        model: fit.model,
        selection,
        pareto,
        factors: Some(fit.factors),
    })
}

/// The joint refit: physics parameters and the correction's fitted constants together on the
/// training rows, kept only when it does not raise the training RMSE; updates `phys`,
/// `correction` and `ses` then, and returns the record of both fits.
fn joint_refit(
    job: SplitJob,
    res: &Resolved,
    phys: &mut Compiled,
    correction: &mut hxai_symreg::Model,
    ses: &mut BTreeMap<String, Option<f64>>,
    y_train: &[f64],
) -> Result<JointInfo, HybridError> {
    let (table, cfg, split) = (job.table, job.cfg, job.split);
    let rmse_on_train = |phys: &Compiled, correction: &hxai_symreg::Model| {
        train_rmse(table, res, phys, correction, cfg.correction, split, y_train)
    };
    let before = rmse_on_train(phys, correction)?;
    let sequential_parameters = named_values(phys);
    let sequential_standard_errors = ses.clone();
    let sequential_correction = correction.sympy();
    let mut c = combine(phys, correction, cfg.correction);
    // physics unknowns (tied leaves), then each fitted correction constant; constants
    // the search snapped to exact values (integers, halves) stay fixed
    let mut groups = calibrated_slots(res, phys, &c);
    let n_phys = groups.len();
    for (i, &ci) in c.corr_map.iter().enumerate() {
        let v = correction.params[i];
        if (2.0 * v).fract() != 0.0 {
            groups.push(vec![ci]);
        }
    }
    let all = columns_of(table, &c.names, "column")?;
    let cols: Vec<Vec<f64>> = all.iter().map(|col| gather(col, &split.train)).collect();
    let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let mut trial = c.params.clone();
    let mse = calibrate::lm_tied(
        &c.program,
        &mut trial,
        &groups,
        &cols,
        y_train,
        &calibrate::settings(200, 1e-15),
    );
    if mse.is_finite() && mse.sqrt() <= before {
        let se = calibrate::standard_errors(&c.program, &trial, &groups, &cols, y_train);
        c.params = trial;
        for (&pi, &ci) in &c.phys_map {
            phys.params[pi] = c.params[ci];
        }
        for (i, &ci) in c.corr_map.iter().enumerate() {
            correction.params[i] = c.params[ci];
        }
        *ses = res
            .calibrate
            .iter()
            .cloned()
            .zip(se.into_iter().take(n_phys))
            .collect();
        // the physics must still be usable everywhere
        physics_values(table, res, phys)?;
    }
    let after = rmse_on_train(phys, correction)?;
    Ok(JointInfo {
        sequential_parameters,
        sequential_standard_errors,
        sequential_correction,
        sequential_train_rmse: before,
        joint_train_rmse: after,
    })
}
