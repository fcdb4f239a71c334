//! Conformal prediction intervals of the table hybrid (issue 28): CV+ over folds of the
//! training rows (Barber et al. 2021), and split conformal on one fold.
//!
//! At fit time ([`calibrate`]) the training rows are cut into `K` folds (grouped folds when
//! the fit has a group column). For each fold the hybrid's constants are refitted on the
//! other `K - 1` folds, the way the fit itself found them: the physics calibrated from its
//! starting values, then the correction's free constants (those that are not whole or half
//! numbers) refitted to the new `delta` from the selected values, then, with `--joint`, both
//! together. The correction's **structure** is not searched again per fold: the search is
//! what costs minutes, and rerunning it `K` times would multiply the fit's time by `K + 1`.
//! So the structure was chosen seeing every training row, and the held-out rows are not
//! quite fresh for it: the guarantee holds for the fixed structure, and is approximate for
//! the whole procedure (a structure of a few operators has little room to overfit).
//!
//! Each training row then has its held-out residual `r = y - mu_{-k}(x)` (on the log scale,
//! `log y - log mu_{-k}(x)`, for a multiplicative or log correction when every target and
//! held-out prediction is positive: the scatter of such processes is multiplicative), a
//! [`ScaleModel`] `s` is fitted to `|r|` against the held-out prediction, and the row's
//! score is `|r| / s(mu_{-k}(x))`. The scale model is fitted on the same residuals it
//! normalises (two constants: the loss of exchangeability is of order `1 / n`).
//!
//! At prediction ([`ConformalInfo::intervals`]) the model file holds every fold's constants,
//! the scores and the scale model, so CV+'s interval of a new row is computed from the `K`
//! fold models' predictions there ([`hxai_eval::cv_plus`]); split conformal uses the first
//! fold's model and that fold's scores alone ([`hxai_eval::conformal_quantile`]).
use super::CorrectionForm;
use super::model::{Combined, TableModel, columns_of, combine};
use super::physics::{calibrate_physics, calibrated_slots, deltas, gather, physics_values};
use super::resolve::Resolved;
use super::{TableConfig, calibrate};
use crate::HybridError;
use crate::conformal::{ConformalInfo, HeldOut, RangeWidening, held_out, refit_constants};
use hxai_eval::Split;
use hxai_symreg::eval::Evaluator;
use hxai_symreg::uncertainty::is_exact;
use hxai_symreg::{Model, Table};

/// Folds of the training rows: grouped by `group` when the fit has one.
fn folds_of(
    table: &Table,
    cfg: &TableConfig,
    train: &[usize],
    k: usize,
) -> Result<Vec<Split>, HybridError> {
    let too_few = |n: usize, unit: &str| {
        HybridError::InvalidConfig(format!(
            "conformal intervals need at least {k} training {unit} for {k} folds, the split leaves {n}: \
             use fewer folds (--conformal-folds, at least 2), or 0 to fit without conformal intervals"
        ))
    };
    match fold_units(table, cfg, train)? {
        Some(keys) => {
            let mut distinct = keys.clone();
            distinct.sort_unstable();
            distinct.dedup();
            if distinct.len() < k {
                return Err(too_few(distinct.len(), "groups"));
            }
            Ok(hxai_eval::grouped_kfold(&keys, k, cfg.seed)?)
        }
        None => {
            if train.len() < k {
                return Err(too_few(train.len(), "rows"));
            }
            Ok(hxai_eval::kfold(train.len(), k, cfg.seed)?)
        }
    }
}

/// The group key of each training row (in the order of `train`) when the fit has a
/// `--group` column, which folds of the training rows keep whole; `None` without one.
pub(crate) fn fold_units(
    table: &Table,
    cfg: &TableConfig,
    train: &[usize],
) -> Result<Option<Vec<u64>>, HybridError> {
    match &cfg.group {
        Some(g) => {
            let col = table.require(g)?;
            Ok(Some(
                train.iter().map(|&i| (col[i] + 0.0).to_bits()).collect(),
            ))
        }
        None => Ok(None),
    }
}

/// The correction's free constants refitted to `delta` on `rows`, from the selected values.
fn refit_correction(
    table: &Table,
    correction: &Model,
    rows: &[usize],
    delta: &[f64],
) -> Result<Model, HybridError> {
    let all = columns_of(table, &correction.feature_names, "correction feature")?;
    let cols: Vec<Vec<f64>> = all.iter().map(|c| gather(c, rows)).collect();
    let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    Ok(refit_constants(correction, &cols, delta, &all))
}

/// The hybrid's constants fitted on `rows` as the fit does: physics, correction, and with
/// `joint` both together (kept only when it lowers the error on `rows`).
fn fold_fit(
    table: &Table,
    cfg: &TableConfig,
    res: &Resolved,
    correction: &Model,
    rows: &[usize],
) -> Result<Combined, HybridError> {
    let (phys, _) = calibrate_physics(table, cfg, res, rows)?;
    let y = table.require(&cfg.target)?;
    let physics = physics_values(table, res, &phys)?;
    let delta = deltas(cfg.correction, y, &physics, rows)?;
    let corr = refit_correction(table, correction, rows, &delta)?;
    let mut c = combine(&phys, &corr, cfg.correction);
    if cfg.joint {
        let mut groups = calibrated_slots(res, &phys, &c);
        for (i, &ci) in c.corr_map.iter().enumerate() {
            if !is_exact(corr.params[i]) {
                groups.push(vec![ci]);
            }
        }
        let all = columns_of(table, &c.names, "column")?;
        let cols: Vec<Vec<f64>> = all.iter().map(|col| gather(col, rows)).collect();
        let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
        let y_rows = gather(y, rows);
        let before = Evaluator::new(&c.program).mse(&c.program, &c.params, &cols, &y_rows);
        let mut trial = c.params.clone();
        let after = calibrate::lm_tied(
            &c.program,
            &mut trial,
            &groups,
            &cols,
            &y_rows,
            &calibrate::settings(200, 1e-15),
        );
        if after.is_finite() && after <= before {
            // as `refit_constants`: the step is halved until the hybrid is finite on every
            // row where it was (the fold's held-out rows among them; features only)
            if let Some(p) = crate::conformal::step_within_domain(&c.params, &trial, |p| {
                c.predict_with(p, table)
            })? {
                c.params = p;
            }
        }
    }
    Ok(c)
}

/// CV+ calibration of `model` (fitted with `cfg` on `table`, training rows `train`) over
/// `folds` folds: see the module documentation.
///
/// # Errors
/// Fewer training rows (or groups) than folds, fewer than 2 folds, a fold whose refitted
/// hybrid is not finite on its held-out rows, and the physics' errors on a fold.
pub(crate) fn calibrate(
    table: &Table,
    cfg: &TableConfig,
    res: &Resolved,
    model: &TableModel,
    train: &[usize],
    folds: usize,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<ConformalInfo, HybridError> {
    if folds < 2 {
        return Err(HybridError::InvalidConfig(format!(
            "{folds} conformal fold(s): CV+ needs at least 2 (or 0 to fit without conformal intervals)"
        )));
    }
    let splits = folds_of(table, cfg, train, folds)?;
    let y = table.require(&cfg.target)?;
    let fitted = model.correction.fitted()?;
    let mut done = 0;
    progress(done, splits.len());
    let HeldOut {
        fold_params,
        fold_of,
        held: held_pred,
    } = held_out(
        &splits,
        train.len(),
        "hybrid",
        |i| train[i],
        |s| {
            let rows: Vec<usize> = s.train.iter().map(|&i| train[i]).collect();
            let c = fold_fit(table, cfg, res, fitted, &rows)?;
            let pred = c.predict_with(&c.params, table)?;
            done += 1;
            progress(done, splits.len());
            Ok((c.params, pred))
        },
    )?;
    let y_train = gather(y, train);
    let multiplies = matches!(
        model.correction.kind,
        CorrectionForm::Multiplicative | CorrectionForm::Log
    );
    let mut info =
        ConformalInfo::from_held_out(fold_params, fold_of, &held_pred, &y_train, multiplies)?;
    info.widening = Some(widening(table, cfg, res, model, train, &info)?);
    Ok(info)
}

/// Share of the training rows held out at each end of a column by [`widening`].
const RANGE_HOLDOUT: f64 = 0.2;

/// The [`RangeWidening`] of the fit: for each input column of the one-program hybrid, the
/// top and bottom fifth of the training rows by that column held out in turn, the hybrid's
/// constants refitted on the rest ([`fold_fit`]), and each held-out row's normalised score
/// and distance outside the ranges of the rows fitted. A hold-out whose refit fails, or
/// that leaves fewer rows than the hybrid has constants, is skipped.
fn widening(
    table: &Table,
    cfg: &TableConfig,
    res: &Resolved,
    model: &TableModel,
    train: &[usize],
    info: &ConformalInfo,
) -> Result<RangeWidening, HybridError> {
    let phys = model.physics_program()?;
    let c = combine(&phys, model.correction.fitted()?, model.correction.kind);
    let cols = columns_of(table, &c.names, "column")?;
    let y = table.require(&cfg.target)?;
    let extent = |rows: &[usize]| -> (Vec<f64>, Vec<f64>) {
        cols.iter()
            .map(|col| {
                rows.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &r| {
                        (l.min(col[r]), h.max(col[r]))
                    })
            })
            .unzip()
    };
    let (lo, hi) = extent(train);
    let mut held_out = Vec::new();
    let mut x = vec![0.0; cols.len()];
    for col in &cols {
        let mut values: Vec<f64> = train.iter().map(|&r| col[r]).collect();
        values.sort_by(f64::total_cmp);
        let n = values.len();
        let cut = ((RANGE_HOLDOUT * n as f64).ceil() as usize).clamp(1, n);
        let low_cut = values[cut - 1];
        let high_cut = values[n - cut];
        for top in [true, false] {
            let (fit, out): (Vec<usize>, Vec<usize>) = train.iter().partition(|&&r| {
                if top {
                    col[r] < high_cut
                } else {
                    col[r] > low_cut
                }
            });
            if out.is_empty() || fit.len() <= c.params.len() {
                continue;
            }
            let Ok(f) = fold_fit(table, cfg, res, model.correction.fitted()?, &fit) else {
                continue;
            };
            let pred = f.predict_with(&f.params, table)?;
            let (flo, fhi) = extent(&fit);
            for &r in &out {
                let z = info.scale.to(pred[r]);
                let t = info.scale.to(y[r]);
                if !(z.is_finite() && t.is_finite()) {
                    continue;
                }
                for (v, c) in x.iter_mut().zip(&cols) {
                    *v = c[r];
                }
                let d = RangeWidening::distance(&flo, &fhi, &x);
                let e = (t - z).abs() / info.scale_model.at(z);
                if d.is_finite() && e.is_finite() {
                    held_out.push([d, e]);
                }
            }
        }
    }
    Ok(RangeWidening {
        columns: c.names.clone(),
        lo,
        hi,
        held_out,
    })
}
