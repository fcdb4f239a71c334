//! Every constant earns its place (issue 64): a term of the free form's correction whose
//! constant has a 95 % interval that spans 0 is dropped, and the other constants refitted,
//! when the cross-validated error without it does not rise by more than one standard error
//! ([`drop_unearned`]); and whether a correction is any better than the physics alone in
//! the same cross-validation ([`no_better_than_physics`]).
//!
//! The folds are [`EARN_FOLDS`] of the training rows (grouped like the form's choice); in
//! each, the model's structure is kept and its constants refitted on the fold's other rows
//! ([`hxai_symreg::Model::refitted`]), then scored by the squared error of the correction's
//! `delta` on the fold's held-out rows. The structure is not searched again, so the errors
//! are those of the constants alone: a term whose constant the rows cannot tell from 0 is
//! weighed by what it does to rows it was not fitted on.

use super::super::{Form, ValidTable};
use super::folds::{folds, mean_se};
use super::job::SplitJob;
use crate::HybridError;
use crate::correction::CvError;
use hxai_eval::Split;
use hxai_symreg::{Model, Table};

/// Folds of the rule: five, since each fold only refits the constants.
pub const EARN_FOLDS: usize = 5;

/// What [`drop_unearned`] found: the model kept and one note per term dropped.
pub(crate) struct Earned {
    pub(crate) model: Model,
    pub(crate) dropped: Vec<String>,
}

/// The folds of the rule on the training rows `train` of `table` (positions in `train`,
/// which are the rows of the correction's feature table), `None` when there are too few
/// rows or groups ([`super::auto::folds`]).
pub(crate) fn earn_folds(
    table: &Table,
    cfg: &ValidTable,
    train: &[usize],
) -> Result<Option<Vec<Split>>, HybridError> {
    folds(table, cfg, train, EARN_FOLDS)
}

/// The cross-validated error of `model`'s constants on `ft`, `delta` over `folds`
/// (see the module documentation): a fold whose refit fails or whose predictions are not
/// finite scores infinitely bad.
pub(crate) fn cv_error(
    model: &Model,
    ft: &Table,
    delta: &[f64],
    folds: &[Split],
) -> Result<CvError, HybridError> {
    let mut errors = Vec::with_capacity(folds.len());
    for fold in folds {
        let (train, test) = (ft.select_rows(&fold.train)?, ft.select_rows(&fold.test)?);
        let y_train: Vec<f64> = fold.train.iter().map(|&i| delta[i]).collect();
        let err = match model.refitted(&train, &y_train)? {
            Some(m) => {
                let p = m.predict(&test)?;
                fold.test
                    .iter()
                    .zip(&p)
                    .map(|(&i, v)| (delta[i] - v).powi(2))
                    .sum::<f64>()
                    / fold.test.len().max(1) as f64
            }
            None => f64::INFINITY,
        };
        errors.push(if err.is_finite() { err } else { f64::INFINITY });
    }
    Ok(mean_se(&errors))
}

/// The cross-validated error of the zero correction (the physics alone) over `folds`.
fn zero_error(delta: &[f64], folds: &[Split]) -> CvError {
    let errors: Vec<f64> = folds
        .iter()
        .map(|f| f.test.iter().map(|&i| delta[i].powi(2)).sum::<f64>() / f.test.len() as f64)
        .collect();
    mean_se(&errors)
}

/// Whether `model` is a correction that does something: it reads a column.
fn learned(model: &Model) -> bool {
    !model.feature_names.is_empty()
}

/// A warning when the correction `model` is no better than the physics alone in the
/// cross-validation of its constants over `folds`: its mean held-out error is not below the
/// zero correction's. `None` for the zero correction itself and when it is better.
pub(crate) fn no_better_than_physics(
    model: &Model,
    ft: &Table,
    delta: &[f64],
    folds: &[Split],
) -> Result<Option<String>, HybridError> {
    if !learned(model) {
        return Ok(None);
    }
    let (with, without) = (cv_error(model, ft, delta, folds)?, zero_error(delta, folds));
    Ok((with.mean >= without.mean).then(|| {
        format!(
            "the correction is no better than the physics alone in {} folds of the training \
             rows (held-out squared error of the correction's target {} with it, {} without): \
             it fits these rows, not the process; --form none or auto keeps the physics alone",
            folds.len(),
            g(with.mean),
            g(without.mean)
        )
    }))
}

/// `model` (the free form's correction of `delta` over the feature table `ft`) with the
/// terms whose constants do not earn their place dropped: while a constant's 95 % interval
/// spans 0, the least significant such constant (smallest `|fitted| / std_error`) whose
/// model without it ([`Model::without_constant`]) is defined over the box the search
/// required (`margin` of each column's range, [`hxai_symreg::enclosure::widened_box`]) and
/// whose cross-validated error is within one standard error of the current model's is
/// dropped, and the rest refitted on every row; the next such constant is tried when one
/// is not.
///
/// # Errors
/// Those of the table's row selection and the model's evaluation.
pub(crate) fn drop_unearned(
    mut model: Model,
    ft: &Table,
    delta: &[f64],
    folds: &[Split],
    margin: Option<f64>,
) -> Result<Earned, HybridError> {
    let mut dropped = Vec::new();
    // each round drops one parameter or stops
    for _ in 0..model.params.len() {
        if !learned(&model) {
            break;
        }
        let u = model.uncertainty(ft, delta)?;
        let mut spanning: Vec<(String, usize, [f64; 2], f64)> = u
            .params
            .iter()
            .zip(&u.slots)
            .filter_map(|((name, p), slot)| {
                let ci = p.ci95?;
                let se = p.std_error?;
                (ci[0] < 0.0 && ci[1] > 0.0 && slot.len() == 1)
                    .then(|| (name.clone(), slot[0], ci, p.fitted.abs() / se))
            })
            .collect();
        if spanning.is_empty() {
            break;
        }
        spanning.sort_by(|a, b| a.3.total_cmp(&b.3));
        let current = cv_error(&model, ft, delta, folds)?;
        let mut next = None;
        for (name, slot, ci, _) in spanning {
            let Some(reduced) = model.without_constant(slot, ft, delta)? else {
                continue;
            };
            if !defined(&reduced, ft, margin) {
                continue;
            }
            let without = cv_error(&reduced, ft, delta, folds)?;
            if without.mean <= current.mean + current.se {
                dropped.push(format!(
                    "dropped the correction's term of constant {name} (95 % interval [{}, {}] \
                     spans 0): without it the held-out error over {} folds is {}, within one \
                     standard error ({}) of {} with it; the rest refitted: `{}`",
                    g(ci[0]),
                    g(ci[1]),
                    folds.len(),
                    g(without.mean),
                    g(current.se),
                    g(current.mean),
                    reduced.equation()
                ));
                next = Some(reduced);
                break;
            }
        }
        match next {
            Some(m) => model = m,
            None => break,
        }
    }
    Ok(Earned { model, dropped })
}

/// Whether `m` is defined over the widened box of its columns in `ft` (true without a
/// margin).
fn defined(m: &Model, ft: &Table, margin: Option<f64>) -> bool {
    let Some(margin) = margin else {
        return true;
    };
    let cols: Option<Vec<&[f64]>> = m.feature_names.iter().map(|n| ft.column(n)).collect();
    let Some(cols) = cols else {
        return false;
    };
    let bounds = hxai_symreg::enclosure::widened_box(&cols, margin);
    hxai_symreg::enclosure::defined_over(
        &m.program,
        &m.params,
        &bounds,
        hxai_symreg::search::DEFINED_BOXES,
    )
    .is_ok()
}

/// What the rule does to a fit's correction (`form` the form fitted, `correction` found
/// by the search over the training rows' feature table `ft` for their `delta`): in the
/// free form, the terms that do not earn their place dropped ([`drop_unearned`]; the
/// selection's structure then follows the model); in every learned form, a warning when
/// the correction is no better than the physics ([`no_better_than_physics`]). Returns the
/// correction kept and the warnings (one per term dropped, then that one). With `sample`
/// (a large table's search sample, rows of the table among the training rows, issue 67)
/// the rule's cross-validation runs on those rows, and a model that lost a term has its
/// constants fitted again on every training row.
///
/// # Errors
/// Those of [`drop_unearned`].
pub(crate) fn earn(
    job: SplitJob,
    form: Form,
    correction: Model,
    selection: &mut hxai_symreg::SelectionReport,
    (ft, delta): (&Table, &[f64]),
    sample: Option<&[usize]>,
) -> Result<(Model, Vec<String>), HybridError> {
    let (rows, sub): (&[usize], Option<(Table, Vec<f64>)>) = match sample {
        Some(rows) => {
            let pos = super::job::positions_in(&job.split.train, rows);
            let d: Vec<f64> = pos.iter().map(|&p| delta[p]).collect();
            (rows, Some((ft.select_rows(&pos)?, d)))
        }
        None => (&job.split.train, None),
    };
    let (ft_s, delta_s) = sub.as_ref().map_or((ft, delta), |(t, d)| (t, d.as_slice()));
    let Some(folds) = earn_folds(job.table, job.cfg, rows)? else {
        return Ok((correction, Vec::new()));
    };
    let (model, mut warnings) = if form == Form::Free {
        let e = drop_unearned(
            correction,
            ft_s,
            delta_s,
            &folds,
            job.cfg.search().defined_margin,
        )?;
        if !e.dropped.is_empty() {
            selection.structure = hxai_symreg::stability::structure_of(&e.model);
        }
        let model = if sample.is_some() && !e.dropped.is_empty() {
            // the reduced model's constants on every training row
            let m = e.model;
            m.refitted(ft, delta)?.unwrap_or(m)
        } else {
            e.model
        };
        (model, e.dropped)
    } else {
        (correction, Vec::new())
    };
    warnings.extend(no_better_than_physics(&model, ft_s, delta_s, &folds)?);
    Ok((model, warnings))
}

fn g(v: f64) -> String {
    hxai_table::format_number(v)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use hxai_symreg::{Node, Op, Program};

    /// Rows of `delta = 2 x + noise` with a column `z` that does nothing, and the model
    /// `a x + b z` fitted to them.
    fn rows() -> (Table, Vec<f64>, Model) {
        let n = 60;
        let x: Vec<f64> = (0..n).map(|i| f64::from(i) / 10.0).collect();
        let z: Vec<f64> = (0..n).map(|i| f64::from((i * 17) % 23)).collect();
        // an offset and deterministic noise of spread about 0.3
        let delta: Vec<f64> = (0..n)
            .map(|i| 2.0 * x[i as usize] + 0.5 + 0.3 * (f64::from(i) * 2.7).sin())
            .collect();
        let ft = Table::new(vec!["x".into(), "z".into()], vec![x, z]).unwrap();
        // scale * (c2 x + c3 z) + offset, the scale 1 (exact, held)
        let program = Program {
            nodes: vec![
                Node::Const,
                Node::Var(0),
                Node::Op(Op::Mul),
                Node::Const,
                Node::Var(1),
                Node::Op(Op::Mul),
                Node::Op(Op::Add),
            ],
            affine: false,
        };
        let m = Model::new(
            vec!["x".into(), "z".into()],
            program,
            vec![1.0, 0.1, 1.9, 0.003],
        )
        .unwrap()
        .refitted(&ft, &delta)
        .unwrap()
        .unwrap();
        (ft, delta, m)
    }

    #[test]
    fn an_insignificant_term_is_dropped_and_a_significant_one_kept() {
        let (ft, delta, m) = rows();
        // the fit's own uncertainty: z's weight spans 0, x's does not
        let u = m.uncertainty(&ft, &delta).unwrap();
        let spans = |name_slot: usize| {
            u.params
                .iter()
                .zip(&u.slots)
                .find(|(_, s)| s == &&vec![name_slot])
                .and_then(|((_, p), _)| p.ci95)
                .is_some_and(|[lo, hi]| lo < 0.0 && hi > 0.0)
        };
        assert!(spans(3), "{u:?}");
        assert!(!spans(2), "{u:?}");
        let folds = hxai_eval::kfold(ft.n_rows(), EARN_FOLDS, 7).unwrap();
        let e = drop_unearned(m, &ft, &delta, &folds, Some(0.1)).unwrap();
        assert_eq!(
            e.model.feature_names,
            vec!["x".to_string()],
            "{}",
            e.model.equation()
        );
        assert_eq!(e.dropped.len(), 1, "{:?}", e.dropped);
        assert!(e.dropped[0].contains("spans 0"), "{}", e.dropped[0]);
        // the correction does something: no warning that it is no better than the physics
        assert!(
            no_better_than_physics(&e.model, &ft, &delta, &folds)
                .unwrap()
                .is_none()
        );
    }

    /// A correction of pure noise is no better than the physics alone, and says so.
    #[test]
    fn a_correction_of_noise_is_reported_no_better_than_the_physics() {
        let (ft, _, m) = rows();
        let noise: Vec<f64> = (0..ft.n_rows())
            .map(|i| 0.3 * (i as f64 * 2.7).sin())
            .collect();
        let m = m.refitted(&ft, &noise).unwrap().unwrap();
        let folds = hxai_eval::kfold(ft.n_rows(), EARN_FOLDS, 7).unwrap();
        let w = no_better_than_physics(&m, &ft, &noise, &folds).unwrap();
        assert!(w.is_some_and(|w| w.contains("no better than the physics")));
    }
}
