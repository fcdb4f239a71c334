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
//! `log y - log mu_{-k}(x)`, for a multiplicative correction when every target and
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
use super::model::{Combined, ProcessModel, columns_of, combine};
use super::physics::{calibrate_physics, calibrated_slots, deltas, gather, physics_values};
use super::resolve::Resolved;
use super::{ProcessConfig, calibrate};
use crate::HybridError;
use hxai_eval::{IntervalMethod, ScaleModel, Split};
use hxai_symreg::eval::Evaluator;
use hxai_symreg::fit::{LmSettings, Unknowns, levenberg_marquardt};
use hxai_symreg::uncertainty::is_exact;
use hxai_symreg::{Model, Table};
use serde::{Deserialize, Serialize};

/// Folds of CV+ when none are given: 5, Barber et al.'s and MAPIE's usual choice (each fold
/// model sees 80 % of the rows).
pub const DEFAULT_CONFORMAL_FOLDS: usize = 5;

/// The scale on which residuals are scored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ResidualScale {
    /// `y - yhat`.
    Linear,
    /// `log y - log yhat` (multiplicative correction, every value positive).
    Log,
}

impl ResidualScale {
    fn to(self, v: f64) -> f64 {
        match self {
            ResidualScale::Linear => v,
            ResidualScale::Log => v.ln(),
        }
    }

    fn from(self, z: f64) -> f64 {
        match self {
            ResidualScale::Linear => z,
            ResidualScale::Log => z.exp(),
        }
    }
}

/// What conformal prediction intervals need, stored in the model file (key `conformal`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ConformalInfo {
    /// Folds of CV+ (`K`).
    pub folds: usize,
    /// The scale of the residuals (`linear` or `log`).
    pub scale: ResidualScale,
    /// For each fold, the whole hybrid's constants refitted without that fold (the
    /// parameters of the one-program hybrid, in the order of `hybrid.uncertainty`'s program).
    pub fold_params: Vec<Vec<f64>>,
    /// For each training row (in the order of `split.train`), its fold.
    pub fold_of: Vec<usize>,
    /// For each training row, `|r| / s` of its held-out residual.
    pub scores: Vec<f64>,
    /// The local scale `s` of the residuals against the prediction (on `scale`).
    pub scale_model: ScaleModel,
}

/// Folds of the training rows: grouped by `group` when the fit has one.
fn folds_of(
    table: &Table,
    cfg: &ProcessConfig,
    train: &[usize],
    k: usize,
) -> Result<Vec<Split>, HybridError> {
    let too_few = |n: usize, unit: &str| {
        HybridError::InvalidConfig(format!(
            "conformal intervals need at least {k} training {unit} for {k} folds, the split leaves {n}: \
             use fewer folds (--conformal-folds, at least 2), or 0 to fit without conformal intervals"
        ))
    };
    match &cfg.group {
        Some(g) => {
            let col = table.require(g)?;
            let keys: Vec<u64> = train.iter().map(|&i| (col[i] + 0.0).to_bits()).collect();
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

/// The correction's free constants (not whole or half numbers) refitted to `delta` on
/// `rows`, from the selected values.
fn refit_correction(
    table: &Table,
    correction: &Model,
    rows: &[usize],
    delta: &[f64],
) -> Result<Model, HybridError> {
    let all = columns_of(table, &correction.feature_names, "correction feature")?;
    let cols: Vec<Vec<f64>> = all.iter().map(|c| gather(c, rows)).collect();
    let cols: Vec<&[f64]> = cols.iter().map(Vec::as_slice).collect();
    let free: Vec<usize> = (0..correction.params.len())
        .filter(|&i| !is_exact(correction.params[i]))
        .collect();
    let mut m = correction.clone();
    let mut ev = Evaluator::new(&m.program);
    let settings = LmSettings::new(200, 1e-12);
    let mse = levenberg_marquardt(
        &m.program,
        &mut m.params,
        Unknowns::Free(&free),
        &cols,
        delta,
        &settings,
        &mut ev,
    );
    if !mse.is_finite() {
        // the selected constants themselves are not finite on these rows: keep them, the
        // held-out predictions below say whether they can be used
        return Ok(correction.clone());
    }
    Ok(m)
}

/// The hybrid's constants fitted on `rows` as the fit does: physics, correction, and with
/// `joint` both together (kept only when it lowers the error on `rows`).
fn fold_fit(
    table: &Table,
    cfg: &ProcessConfig,
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
        let after = calibrate::lm_tied(&c.program, &mut trial, &groups, &cols, &y_rows, 200, 1e-15);
        if after.is_finite() && after <= before {
            c.params = trial;
        }
    }
    Ok(c)
}

/// The one-program hybrid's predictions with `params` on every row of `table`.
fn predict_with(c: &Combined, params: &[f64], table: &Table) -> Result<Vec<f64>, HybridError> {
    let cols = columns_of(table, &c.names, "column")?;
    let mut out = Vec::new();
    Evaluator::new(&c.program).predict(&c.program, params, &cols, table.n_rows(), &mut out);
    Ok(out)
}

/// CV+ calibration of `model` (fitted with `cfg` on `table`, training rows `train`) over
/// `folds` folds: see the module documentation.
///
/// # Errors
/// Fewer training rows (or groups) than folds, fewer than 2 folds, a fold whose refitted
/// hybrid is not finite on its held-out rows, and the physics' errors on a fold.
pub(crate) fn calibrate(
    table: &Table,
    cfg: &ProcessConfig,
    res: &Resolved,
    model: &ProcessModel,
    train: &[usize],
    folds: usize,
) -> Result<ConformalInfo, HybridError> {
    if folds < 2 {
        return Err(HybridError::InvalidConfig(format!(
            "{folds} conformal fold(s): CV+ needs at least 2 (or 0 to fit without conformal intervals)"
        )));
    }
    let splits = folds_of(table, cfg, train, folds)?;
    let y = table.require(&cfg.target)?;
    let mut fold_params = Vec::with_capacity(splits.len());
    let mut fold_of = vec![0usize; train.len()];
    let mut held_pred = vec![f64::NAN; train.len()];
    for (k, s) in splits.iter().enumerate() {
        let rows: Vec<usize> = s.train.iter().map(|&i| train[i]).collect();
        let c = fold_fit(table, cfg, res, &model.correction.model, &rows)?;
        let pred = predict_with(&c, &c.params, table)?;
        for &i in &s.test {
            let row = train[i];
            if !pred[row].is_finite() {
                return Err(HybridError::InvalidConfig(format!(
                    "row {}: the hybrid refitted without its conformal fold predicts {}: \
                     fit with --conformal-folds 0 (no conformal intervals) or check the \
                     equation's domain",
                    row + 1,
                    pred[row]
                )));
            }
            fold_of[i] = k;
            held_pred[i] = pred[row];
        }
        fold_params.push(c.params);
    }
    let y_train = gather(y, train);
    let positive = |v: &[f64]| v.iter().all(|x| *x > 0.0);
    let scale = if model.correction.kind == CorrectionForm::Multiplicative
        && positive(&y_train)
        && positive(&held_pred)
    {
        ResidualScale::Log
    } else {
        ResidualScale::Linear
    };
    let z_pred: Vec<f64> = held_pred.iter().map(|p| scale.to(*p)).collect();
    let resid: Vec<f64> = y_train
        .iter()
        .zip(&z_pred)
        .map(|(y, z)| scale.to(*y) - z)
        .collect();
    let scale_model = ScaleModel::fit(&z_pred, &resid)?;
    let scores = resid
        .iter()
        .zip(&z_pred)
        .map(|(r, z)| r.abs() / scale_model.at(*z))
        .collect();
    Ok(ConformalInfo {
        folds: splits.len(),
        scale,
        fold_params,
        fold_of,
        scores,
        scale_model,
    })
}

impl ConformalInfo {
    /// Checks a record read from a file against the hybrid's program of `n_params`
    /// parameters.
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`] naming what does not fit.
    pub(crate) fn check(&self, n_params: usize) -> Result<(), HybridError> {
        let bad = |why: String| Err(HybridError::ModelFormat(format!("`conformal`: {why}")));
        if self.fold_params.len() != self.folds || self.folds < 2 {
            return bad(format!(
                "{} folds with {} parameter sets",
                self.folds,
                self.fold_params.len()
            ));
        }
        if let Some(p) = self.fold_params.iter().find(|p| p.len() != n_params) {
            return bad(format!(
                "a fold has {} parameters, the hybrid's program {n_params}",
                p.len()
            ));
        }
        if self.fold_of.len() != self.scores.len() || self.scores.is_empty() {
            return bad("`fold_of` and `scores` must have one entry per training row".into());
        }
        if self.fold_of.iter().any(|&k| k >= self.folds) {
            return bad("a row's fold is out of range".into());
        }
        if self.scores.iter().any(|s| !s.is_finite() || *s < 0.0) {
            return bad("a score is not a finite non-negative number".into());
        }
        if self.fold_params.iter().flatten().any(|p| !p.is_finite()) {
            return bad("a fold's parameter is not finite".into());
        }
        self.scale_model
            .check()
            .or_else(|e| bad(format!("scale model: {e}")))
    }

    /// Intervals `(lo, hi)` at `level` for every row of `table` by `method`
    /// ([`IntervalMethod::Conformal`]: CV+; [`IntervalMethod::Split`]: split conformal on
    /// the first fold). `c` is the model's one-program hybrid.
    ///
    /// # Errors
    /// `level` outside (0, 1), too few calibration scores for `level`, a missing column, a
    /// fold's prediction that is not finite (or not positive on the log scale), and
    /// [`IntervalMethod::Delta`] (not a conformal method).
    pub(crate) fn intervals(
        &self,
        c: &Combined,
        table: &Table,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        let working = |p: f64, row: usize| -> Result<f64, HybridError> {
            let z = self.scale.to(p);
            if z.is_finite() {
                Ok(z)
            } else {
                Err(HybridError::InvalidConfig(format!(
                    "row {}: a conformal fold's hybrid predicts {p}, where the interval (on the {} scale) is undefined",
                    row + 1,
                    match self.scale {
                        ResidualScale::Linear => "linear",
                        ResidualScale::Log => "log",
                    }
                )))
            }
        };
        match method {
            IntervalMethod::Delta => Err(HybridError::InvalidConfig(
                "the delta method is not a conformal method".into(),
            )),
            IntervalMethod::Split => {
                let scores: Vec<f64> = self
                    .scores
                    .iter()
                    .zip(&self.fold_of)
                    .filter(|(_, k)| **k == 0)
                    .map(|(s, _)| *s)
                    .collect();
                let q = hxai_eval::conformal_quantile(&scores, level)?;
                let pred = predict_with(c, &self.fold_params[0], table)?;
                pred.iter()
                    .enumerate()
                    .map(|(row, p)| {
                        let z = working(*p, row)?;
                        let half = self.scale_model.at(z) * q;
                        Ok((self.scale.from(z - half), self.scale.from(z + half)))
                    })
                    .collect()
            }
            IntervalMethod::Conformal => {
                hxai_eval::conformal_rank(self.scores.len(), level)?;
                let preds: Vec<Vec<f64>> = self
                    .fold_params
                    .iter()
                    .map(|p| predict_with(c, p, table))
                    .collect::<Result<_, _>>()?;
                let n = self.scores.len();
                let mut centre = vec![0.0; n];
                let mut radius = vec![0.0; n];
                let mut out = Vec::with_capacity(table.n_rows());
                let mut z_fold = vec![0.0; self.folds];
                for row in 0..table.n_rows() {
                    for (k, p) in preds.iter().enumerate() {
                        z_fold[k] = working(p[row], row)?;
                    }
                    for i in 0..n {
                        let z = z_fold[self.fold_of[i]];
                        centre[i] = z;
                        radius[i] = self.scale_model.at(z) * self.scores[i];
                    }
                    let (lo, hi) = hxai_eval::cv_plus(&centre, &radius, level)?;
                    out.push((self.scale.from(lo), self.scale.from(hi)));
                }
                Ok(out)
            }
        }
    }
}
