//! Writing a fit down: what a fit found ([`Fitted`]) becomes its [`TableModel`], with the
//! physics' parameter intervals, the correction's and the whole hybrid's uncertainty, and
//! the scores on the fitting table's split.

use super::super::model::{
    EquationInfo, JointInfo, PairScores, PhysicsInfo, SCHEMA_VERSION, ScoresInfo, TableModel,
    columns_of, combine, combine_values, forms,
};
use super::super::physics::{calibrated_slots, deltas, gather, named_values, physics_values};
use super::super::resolve::Resolved;
use super::super::{CorrectionForm, TableConfig};
use super::job::SplitJob;
use crate::HybridError;
use crate::{CorrectionInfo, SplitInfo};
use hxai_eval::Split;
use hxai_symreg::infix::Compiled;
use hxai_symreg::{ParamEstimate, Table, Uncertainty};
use std::collections::BTreeMap;

/// What a fit found, before it is written down as a [`TableModel`]: the physics with its
/// parameters and their standard errors, the correction and how it was selected, and the
/// joint refit's record.
pub(super) struct Fitted {
    pub(super) phys: Compiled,
    pub(super) ses: BTreeMap<String, Option<f64>>,
    pub(super) correction: hxai_symreg::Model,
    pub(super) selection: hxai_symreg::SelectionReport,
    pub(super) joint: Option<JointInfo>,
}

/// The model file of a fit: the physics with its parameters' intervals, the correction with
/// its uncertainty and Pareto front, the hybrid as one equation with its uncertainty, and the
/// split; its scores are zero until [`scores_of`] fills them. The alternatives' intervals
/// are those of the rows they were fitted on (a large table's search `sample`).
pub(super) fn model_of(
    job: SplitJob,
    res: &Resolved,
    ft: &Table,
    pareto: &[hxai_symreg::Model],
    fitted: Fitted,
    (y_all, y_train): (&[f64], &[f64]),
    sample: Option<&[usize]>,
) -> Result<TableModel, HybridError> {
    let (table, cfg, split, kind) = (job.table, job.cfg, job.split, job.kind);
    let Fitted {
        phys,
        ses,
        correction,
        selection,
        joint,
    } = fitted;
    let parameters = named_values(&phys);
    let correction_delta = delta_train(cfg, y_all, &physics_values(table, res, &phys)?, split)?;
    let hybrid_uncertainty =
        hybrid_uncertainty(table, res, &phys, &correction, cfg, split, y_train)?;
    let n_cal = res.calibrate.len();
    let t = hxai_eval::t_upper_quantile(0.025, split.train.len().saturating_sub(n_cal) as f64);
    let physics_params: BTreeMap<String, ParamEstimate> = res
        .calibrate
        .iter()
        .map(|n| {
            let value = parameters.get(n).copied().unwrap_or(f64::NAN);
            let std_error = ses.get(n).copied().flatten();
            (
                n.clone(),
                ParamEstimate::with_interval(value, value, std_error, t),
            )
        })
        .collect();
    let training = super::super::model::TrainingRanges::of(
        table,
        &read_columns(&res.columns, &correction, cfg.group.as_deref()),
        y_all,
        &split.train,
    );
    let phys_expr = phys.expr();
    let phys_forms = forms(&phys_expr);
    let combined = combine(&phys, &correction, cfg.correction);
    let hybrid_expr =
        hxai_symreg::expr::Expr::from_program(&combined.program, &combined.params, &combined.names);
    Ok(TableModel {
        schema_version: SCHEMA_VERSION,
        target: cfg.target.clone(),
        physics: PhysicsInfo {
            equation: cfg.physics.clone(),
            columns: res.columns.clone(),
            parameters,
            standard_errors: ses,
            calibrated: res.calibrate.clone(),
            initial: res.initial.clone(),
            sympy: phys_forms.sympy,
            latex: phys_forms.latex,
            params: physics_params,
        },
        correction: CorrectionInfo {
            candidates: res.features.clone(),
            ..CorrectionInfo::learned(
                cfg.correction,
                correction,
                ft,
                &correction_delta,
                pareto,
                alternatives_uncertainty(selection, ft, &correction_delta, split, sample)?,
            )?
        },
        hybrid: EquationInfo {
            uncertainty: Some(hybrid_uncertainty),
            ..forms(&hybrid_expr)
        },
        split: SplitInfo::rows(kind.to_string(), split),
        group: cfg.group.clone(),
        joint,
        stability: None,
        conformal: None,
        warnings: Vec::new(),
        missing: None,
        per_class: None,
        correction_per: None,
        slots: Vec::new(),
        search_sample: None,
        training: Some(training),
        scores: ScoresInfo {
            black_boxes: None,
            train: PairScores {
                physics: zero_metrics(),
                hybrid: zero_metrics(),
            },
            test: None,
        },
    })
}

/// The columns the hybrid reads: the physics' and the correction's features, each once, the
/// group column left out (an identifier, not a setting).
fn read_columns(
    physics: &[String],
    correction: &hxai_symreg::Model,
    group: Option<&str>,
) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for c in physics.iter().chain(&correction.feature_names) {
        if Some(c.as_str()) != group && !out.contains(c) {
            out.push(c.clone());
        }
    }
    out
}

/// The scores of `model`'s physics and hybrid on the training rows of `split` and, when
/// there are any, its test rows.
pub(super) fn scores_of(
    model: &TableModel,
    table: &Table,
    y_all: &[f64],
    split: &Split,
) -> Result<ScoresInfo, HybridError> {
    let pred = model.predict(table)?;
    let pair = |rows: &[usize]| -> Result<PairScores, HybridError> {
        let y = gather(y_all, rows);
        let scored = |what: &str, p: &[f64]| -> Result<hxai_eval::Metrics, HybridError> {
            let m = hxai_eval::score(&y, &gather(p, rows))?;
            finite_scores(what, &m, rows, y_all, p)?;
            Ok(m)
        };
        Ok(PairScores {
            physics: scored("physics", &pred.physics)?,
            hybrid: scored("hybrid", &pred.hybrid)?,
        })
    };
    let train = pair(&split.train)?;
    // one test row has no R² (nor a spread): no test scores, and a warning (traps.rs)
    let test = if split.test.len() < 2 {
        None
    } else {
        Some(pair(&split.test)?)
    };
    Ok(ScoresInfo {
        train,
        test,
        black_boxes: None,
    })
}

/// Refuses scores that are not finite numbers (a squared error that overflows: a target of
/// 1e300, or a prediction that far off), naming the row with the largest error, since a
/// model file cannot hold them and "RMSE inf, R² 1" means nothing.
fn finite_scores(
    what: &str,
    m: &hxai_eval::Metrics,
    rows: &[usize],
    y: &[f64],
    p: &[f64],
) -> Result<(), HybridError> {
    if m.rmse.is_finite() && m.r2.is_finite() && m.mae.is_finite() {
        return Ok(());
    }
    let worst = rows
        .iter()
        .copied()
        .max_by(|&a, &b| (y[a] - p[a]).abs().total_cmp(&(y[b] - p[b]).abs()))
        .unwrap_or(0);
    let g = |v: f64| hxai_table::format_number(v);
    Err(HybridError::NoData(format!(
        "the {what}'s error is not a finite number (RMSE {}, R² {}): row {} has target {} and          {what} {}, too large for a squared error; check that row (a sentinel value such as          1e300 or 9.96921e36?), drop it, or rescale the target",
        g(m.rmse),
        g(m.r2),
        worst + 1,
        g(y[worst]),
        g(p[worst])
    )))
}

/// `delta` on the training rows with the final physics parameters (those of the joint refit
/// when there was one), the target of the correction's uncertainty.
fn delta_train(
    cfg: &TableConfig,
    y_all: &[f64],
    physics: &[f64],
    split: &Split,
) -> Result<Vec<f64>, HybridError> {
    deltas(cfg.correction, y_all, physics, &split.train)
}

/// The hybrid as one template over the columns, the calibrated parameters (by name) and
/// the correction's free constants (those that are not whole or half numbers, named `p0`,
/// `p1`, ... past the names already taken), with their covariance at the model's values on
/// the training rows.
fn hybrid_uncertainty(
    table: &Table,
    res: &Resolved,
    phys: &Compiled,
    correction: &hxai_symreg::Model,
    cfg: &TableConfig,
    split: &Split,
    y_train: &[f64],
) -> Result<Uncertainty, HybridError> {
    let c = combine(phys, correction, cfg.correction);
    let mut slots = calibrated_slots(res, phys, &c);
    let mut names: Vec<String> = res.calibrate.clone();
    let mut taken: Vec<String> = c.names.clone();
    taken.extend(phys.slots.keys().cloned());
    let free: Vec<usize> = c
        .corr_map
        .iter()
        .enumerate()
        .filter(|(i, _)| !hxai_symreg::uncertainty::is_exact(correction.params[*i]))
        .map(|(_, &ci)| ci)
        .collect();
    names.extend(hxai_symreg::uncertainty::parameter_names(
        free.len(),
        &taken,
    ));
    slots.extend(free.iter().map(|&i| vec![i]));
    let all = columns_of(table, &c.names, "column")?;
    let cols: Vec<Vec<f64>> = all.iter().map(|col| gather(col, &split.train)).collect();
    let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let cov = hxai_symreg::uncertainty::covariance(
        &c.program,
        &c.params,
        hxai_symreg::fit::Unknowns::Tied(&slots),
        &cols,
        y_train,
    );
    Ok(Uncertainty::build(
        &c.program, &c.params, &c.params, &c.names, names, slots, &cov,
    ))
}

fn zero_metrics() -> hxai_eval::Metrics {
    hxai_eval::Metrics {
        r2: 0.0,
        rmse: 0.0,
        mae: 0.0,
    }
}

pub(super) fn train_rmse(
    table: &Table,
    res: &Resolved,
    phys: &Compiled,
    correction: &hxai_symreg::Model,
    kind: CorrectionForm,
    split: &Split,
    y_train: &[f64],
) -> Result<f64, HybridError> {
    let p = physics_values(table, res, phys)?;
    let d = correction.predict(table)?;
    let h: Vec<f64> = split
        .train
        .iter()
        .map(|&i| combine_values(kind, p[i], d[i]))
        .collect();
    Ok(hxai_eval::rmse(y_train, &h)?)
}

/// `selection` with each alternative's constants' covariance on the training rows (`ft`,
/// `delta`, the rows and target the selected correction's own is taken on), so that `hxai
/// hybrid design` can weigh each equation by its own prediction variance. An alternative
/// whose text does not compile back, or whose covariance does not exist, keeps none.
/// [`with_alternatives_uncertainty`] on the rows the alternatives were fitted on: the
/// training rows (`ft`, `delta`), or a large table's search sample (`sample`, rows of the
/// table among `split`'s training rows, issue 67), where the selection found them with
/// their constants.
fn alternatives_uncertainty(
    selection: hxai_symreg::SelectionReport,
    ft: &Table,
    delta: &[f64],
    split: &Split,
    sample: Option<&[usize]>,
) -> Result<hxai_symreg::SelectionReport, HybridError> {
    let Some(rows) = sample.filter(|_| !selection.alternatives.is_empty()) else {
        return Ok(with_alternatives_uncertainty(selection, ft, delta));
    };
    let pos = super::job::positions_in(&split.train, rows);
    let d: Vec<f64> = pos.iter().map(|&p| delta[p]).collect();
    Ok(with_alternatives_uncertainty(
        selection,
        &ft.select_rows(&pos)?,
        &d,
    ))
}

fn with_alternatives_uncertainty(
    mut selection: hxai_symreg::SelectionReport,
    ft: &Table,
    delta: &[f64],
) -> hxai_symreg::SelectionReport {
    for a in &mut selection.alternatives {
        a.uncertainty = hxai_symreg::infix::compile_text(&a.sympy, &Default::default())
            .ok()
            .map(|c| hxai_symreg::Model {
                feature_names: c.inputs,
                program: c.program,
                params: c.params,
                complexity: a.complexity,
                train_mse: f64::NAN,
                score: f64::NAN,
            })
            .and_then(|m| m.uncertainty(ft, delta).ok())
            .filter(|u| !u.covariance.is_empty() && u.residual_variance.is_finite());
    }
    selection
}
