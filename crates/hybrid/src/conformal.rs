//! Conformal prediction intervals (issue 28), shared by both halves: the calibration a
//! model file stores ([`ConformalInfo`]: each fold's constants, each training row's fold and
//! normalised score, the scale model) and the intervals computed from it, CV+ (Barber et al.
//! 2021) or split conformal (Lei et al. 2018), from the fold models' predictions at the new
//! rows. How the folds are fitted belongs to each half: the table hybrid refits its physics
//! and correction (`tables/conformal.rs`), the tool case its correction of the amplitude
//! (`model/fit.rs`).
use crate::HybridError;
use hxai_eval::{IntervalMethod, ScaleModel, Split};
use hxai_symreg::{Model, Table};
use serde::{Deserialize, Serialize};

mod refit;
mod widening;
pub(crate) use refit::step_within_domain;
pub use refit::{refit_constants, refit_these};
pub use widening::RangeWidening;

/// Folds of CV+ when none are given: 5, Barber et al.'s and MAPIE's usual choice (each fold
/// model sees 80 % of the rows).
pub const DEFAULT_CONFORMAL_FOLDS: usize = 5;

/// The cross-fitting loop of CV+ that both halves run: for each fold of `splits` (indices
/// `0..n` into the calibration rows), `fit_fold` refits on the fold's training indices and
/// returns the fold's parameters and its predictions, indexed by `row_of(i)` for the
/// calibration row `i` (the table's row). Returns every fold's parameters, each
/// calibration row's fold and its held-out prediction.
///
/// # Errors
/// Those of `fit_fold`, and a held-out prediction that is not finite (named by its table
/// row, counted from 1; `what` names the refitted model).
pub(crate) fn held_out(
    splits: &[Split],
    n: usize,
    what: &str,
    row_of: impl Fn(usize) -> usize,
    mut fit_fold: impl FnMut(&Split) -> Result<(Vec<f64>, Vec<f64>), HybridError>,
) -> Result<HeldOut, HybridError> {
    let mut fold_params = Vec::with_capacity(splits.len());
    let mut fold_of = vec![0usize; n];
    let mut held = vec![f64::NAN; n];
    for (k, s) in splits.iter().enumerate() {
        let (params, pred) = fit_fold(s)?;
        for &i in &s.test {
            let row = row_of(i);
            let p = pred.get(row).copied().unwrap_or(f64::NAN);
            if !p.is_finite() {
                return Err(HybridError::InvalidConfig(format!(
                    "row {}: the {what} refitted without its conformal fold predicts {p}: \
                     fit with --conformal-folds 0 (no conformal intervals) or check the \
                     equation's domain",
                    row + 1
                )));
            }
            fold_of[i] = k;
            held[i] = p;
        }
        fold_params.push(params);
    }
    Ok(HeldOut {
        fold_params,
        fold_of,
        held,
    })
}

/// The columns of `table` named `names`, in order; a missing one is
/// [`HybridError::InvalidConfig`] with the message `missing(name)`.
pub(crate) fn named_columns<'a>(
    table: &'a Table,
    names: &[String],
    missing: impl Fn(&str) -> String,
) -> Result<Vec<&'a [f64]>, HybridError> {
    names
        .iter()
        .map(|name| {
            table
                .column(name)
                .ok_or_else(|| HybridError::InvalidConfig(missing(name)))
        })
        .collect()
}

/// What [`held_out`] returns: each fold's parameters, each calibration row's fold and its
/// held-out prediction.
pub(crate) struct HeldOut {
    pub(crate) fold_params: Vec<Vec<f64>>,
    pub(crate) fold_of: Vec<usize>,
    pub(crate) held: Vec<f64>,
}

/// CV+ calibration of a symbolic `model` of `target` on the rows of `data` over the folds
/// `splits` (indices into those rows): for each fold the model's free constants are
/// refitted on the other folds ([`refit_constants`]), the held-out rows predicted, and
/// [`ConformalInfo::from_held_out`] scores them on the linear scale. The model's structure
/// is not searched again per fold.
///
/// # Errors
/// A missing feature column, a fold model that is not finite on its held-out rows (named by
/// row, counted from 1), and those of [`ConformalInfo::from_held_out`].
pub fn calibrate_model(
    model: &Model,
    data: &Table,
    target: &[f64],
    splits: &[Split],
) -> Result<ConformalInfo, HybridError> {
    let cols = named_columns(data, &model.feature_names, |name| {
        format!("conformal calibration: no column `{name}`")
    })?;
    let HeldOut {
        fold_params,
        fold_of,
        held,
    } = held_out(
        splits,
        data.n_rows(),
        "correction",
        |i| i,
        |s| {
            let sub: Vec<Vec<f64>> = cols
                .iter()
                .map(|c| s.train.iter().map(|&i| c[i]).collect())
                .collect();
            let sub: Vec<&[f64]> = sub.iter().map(Vec::as_slice).collect();
            let y: Vec<f64> = s.train.iter().map(|&i| target[i]).collect();
            let m = refit_constants(model, &sub, &y, &cols);
            let pred = m.predict(data)?;
            Ok((m.params, pred))
        },
    )?;
    ConformalInfo::from_held_out(fold_params, fold_of, &held, target, false)
}

/// The scale on which residuals are scored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ResidualScale {
    /// `y - yhat`.
    Linear,
    /// `log y - log yhat` (multiplicative or log correction, every value positive).
    Log,
}

impl ResidualScale {
    pub(crate) fn to(self, v: f64) -> f64 {
        match self {
            ResidualScale::Linear => v,
            ResidualScale::Log => v.ln(),
        }
    }

    pub(crate) fn from(self, z: f64) -> f64 {
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
    /// For each training row (in the order of `split.train`, or of the search sample of a
    /// large table, `search_sample`), its fold.
    pub fold_of: Vec<usize>,
    /// For each training row, `|r| / s` of its held-out residual.
    pub scores: Vec<f64>,
    /// The local scale `s` of the residuals against the prediction (on `scale`).
    pub scale_model: ScaleModel,
    /// How the width grows outside the training ranges ([`RangeWidening`]); absent where
    /// the fit did not measure it (the tool case, `hxai sr` models, older files), which then
    /// keep the width of the scale model alone everywhere.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub widening: Option<RangeWidening>,
}

impl ConformalInfo {
    /// Checks a record read from a file against a model of `n_params` parameters.
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`] naming what does not fit.
    pub fn check(&self, n_params: usize) -> Result<(), HybridError> {
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
        if let Some(w) = &self.widening {
            w.check().or_else(bad)?;
        }
        self.scale_model
            .check()
            .or_else(|e| bad(format!("scale model: {e}")))
    }

    /// Whether CV+ at `level` can be finite with these scores (`ceil(level (n + 1)) <= n`):
    /// a model calibrated on few rows serves 90 % but not 99 %.
    pub fn serves(&self, level: f64) -> bool {
        hxai_eval::conformal_rank(self.scores.len(), level).is_ok()
    }

    /// Intervals `(lo, hi)` at `level` by `method` from the fold models' predictions made
    /// by `predict` (given a fold's constants, the predictions at the new rows): every
    /// fold's for CV+, the first fold's alone for split conformal; then
    /// [`ConformalInfo::intervals_from`].
    ///
    /// # Errors
    /// Those of `predict` and of [`ConformalInfo::intervals_from`].
    pub fn intervals_by(
        &self,
        mut predict: impl FnMut(&[f64]) -> Result<Vec<f64>, HybridError>,
        distance: Option<&[f64]>,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        let used = if method == IntervalMethod::Split {
            &self.fold_params[..1]
        } else {
            &self.fold_params[..]
        };
        let preds: Vec<Vec<f64>> = used.iter().map(|p| predict(p)).collect::<Result<_, _>>()?;
        self.intervals_from(&preds, distance, level, method)
    }

    /// [`ConformalInfo::intervals_by`] for a symbolic `model` calibrated by
    /// [`calibrate_model`]: each fold's model is `model` with that fold's constants,
    /// predicting the rows of `data`.
    ///
    /// # Errors
    /// As [`ConformalInfo::intervals_by`], and the model's (a missing column).
    pub fn model_intervals(
        &self,
        model: &Model,
        data: &Table,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        let mut fold_model = model.clone();
        self.intervals_by(
            |p| {
                fold_model.params.clear();
                fold_model.params.extend_from_slice(p);
                Ok(fold_model.predict(data)?)
            },
            None,
            level,
            method,
        )
    }

    /// Intervals `(lo, hi)` at `level` by `method` for the `n` rows whose predictions by
    /// each fold's model are `fold_pred[k]` (`fold_pred[k][row]`, on the natural scale)
    /// ([`IntervalMethod::Conformal`]: CV+ over every fold; [`IntervalMethod::Split`]: split
    /// conformal with the first fold's model and that fold's scores alone). `fold_pred`
    /// needs the first fold only for `Split`.
    ///
    /// # Errors
    /// `level` outside (0, 1), too few calibration scores for `level`, and
    /// [`IntervalMethod::Delta`] (not a conformal method). A row where a fold's prediction
    /// is not finite (or not positive on the log scale) gets `(NaN, NaN)`: no interval.
    pub fn intervals_from(
        &self,
        fold_pred: &[Vec<f64>],
        distance: Option<&[f64]>,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        // the widening factor of each row: 1 inside the training ranges
        let kappa = match (&self.widening, distance) {
            (Some(w), Some(_)) => {
                w.slope(hxai_eval::conformal_quantile(&self.scores, level)?, level)
            }
            _ => 0.0,
        };
        let factor = |row: usize| 1.0 + kappa * distance.map_or(0.0, |d| d[row]);
        // the working-scale value of a fold's prediction; `None` where it has none (not
        // finite, or not positive on the log scale): that row gets no interval (NaN, NaN),
        // and every other row keeps its own (issue 63: one such row aborted an evaluation)
        let working = |p: f64| -> Option<f64> { Some(self.scale.to(p)).filter(|z| z.is_finite()) };
        const NONE: (f64, f64) = (f64::NAN, f64::NAN);
        let n_rows = fold_pred.first().map_or(0, Vec::len);
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
                fold_pred[0]
                    .iter()
                    .enumerate()
                    .map(|(row, p)| {
                        let Some(z) = working(*p) else {
                            return Ok(NONE);
                        };
                        let half = self.scale_model.at(z) * q * factor(row);
                        Ok((self.scale.from(z - half), self.scale.from(z + half)))
                    })
                    .collect()
            }
            IntervalMethod::Conformal => {
                hxai_eval::conformal_rank(self.scores.len(), level)?;
                if fold_pred.len() != self.folds || fold_pred.iter().any(|p| p.len() != n_rows) {
                    return Err(HybridError::InvalidConfig(format!(
                        "CV+ needs the predictions of all {} fold models",
                        self.folds
                    )));
                }
                let n = self.scores.len();
                let mut centre = vec![0.0; n];
                let mut radius = vec![0.0; n];
                let mut out = Vec::with_capacity(n_rows);
                let mut z_fold = vec![0.0; self.folds];
                'rows: for row in 0..n_rows {
                    for (k, p) in fold_pred.iter().enumerate() {
                        match working(p[row]) {
                            Some(z) => z_fold[k] = z,
                            None => {
                                out.push(NONE);
                                continue 'rows;
                            }
                        }
                    }
                    let f = factor(row);
                    for i in 0..n {
                        let z = z_fold[self.fold_of[i]];
                        centre[i] = z;
                        radius[i] = self.scale_model.at(z) * self.scores[i] * f;
                    }
                    let (lo, hi) = hxai_eval::cv_plus(&centre, &radius, level)?;
                    out.push((self.scale.from(lo), self.scale.from(hi)));
                }
                Ok(out)
            }
        }
    }

    /// The calibration from each training row's held-out prediction `held_pred` (by the
    /// model of its fold `fold_of`, fitted without that fold) and target `y`: residuals on
    /// the log scale when `log_if_positive` and every target and held-out prediction is
    /// positive, else on the linear scale; a [`ScaleModel`] of `|r|` on the prediction; the
    /// scores `|r| / s`.
    ///
    /// # Errors
    /// The scale model's (fewer than 2 rows, values not finite).
    pub fn from_held_out(
        fold_params: Vec<Vec<f64>>,
        fold_of: Vec<usize>,
        held_pred: &[f64],
        y: &[f64],
        log_if_positive: bool,
    ) -> Result<Self, HybridError> {
        let positive = |v: &[f64]| v.iter().all(|x| *x > 0.0);
        let scale = if log_if_positive && positive(y) && positive(held_pred) {
            ResidualScale::Log
        } else {
            ResidualScale::Linear
        };
        let z_pred: Vec<f64> = held_pred.iter().map(|p| scale.to(*p)).collect();
        let resid: Vec<f64> = y
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
            folds: fold_params.len(),
            scale,
            fold_params,
            fold_of,
            scores,
            scale_model,
            widening: None,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{HeldOut, RangeWidening, Split, held_out, refit_constants};
    use hxai_symreg::{Model, Node, Op, Program};

    /// `log(x - d)` with `d = 0.05`, refitted to `log(x - 0.1)` on rows with `x >= 0.2`:
    /// unguarded the refit reaches `d = 0.1`, where the row `x = 0.08` (which the refit did
    /// not see) has no value; guarded, the step stops short of it. Where nothing leaves the
    /// domain the refit is the plain one.
    #[test]
    fn a_refit_stays_where_the_model_is_defined() {
        let program = Program {
            nodes: vec![
                Node::Var(0),
                Node::Const,
                Node::Op(Op::Sub),
                Node::Op(Op::Log),
            ],
            affine: false,
        };
        let model =
            Model::new(vec!["x".into()], program, vec![1.0, 0.0, 0.05]).expect("a valid model");
        let x: Vec<f64> = (0..40).map(|i| 0.2 + 0.02 * f64::from(i)).collect();
        let y: Vec<f64> = x.iter().map(|v| (v - 0.1).ln()).collect();
        let free = refit_constants(&model, &[&x], &y, &[&x]);
        assert!((free.params[2] - 0.1).abs() < 1e-6, "{:?}", free.params);
        let mut with_edge = x.clone();
        with_edge.push(0.08);
        let guarded = refit_constants(&model, &[&x], &y, &[&with_edge]);
        let d = guarded.params[2];
        assert!(d > 0.05 && d < 0.08, "{d}");
        // the step was halved, not abandoned: half of it (0.075) is the first that keeps
        // x = 0.08 defined
        assert!((d - 0.075).abs() < 1e-6, "{d}");
    }

    /// Each calibration row gets its fold and its fold's prediction (read at its table row);
    /// a fold that predicts a non-finite value there is refused, naming the table row.
    #[test]
    fn held_out_predictions_come_from_each_rows_own_fold() {
        let splits = [
            Split {
                train: vec![1, 2],
                test: vec![0],
            },
            Split {
                train: vec![0],
                test: vec![1, 2],
            },
        ];
        // calibration rows 0, 1, 2 are the table's rows 10, 11, 12
        let row_of = |i: usize| 10 + i;
        let fit = |k: f64| move |s: &Split| Ok((vec![k], vec![k * (s.test.len() as f64); 13]));
        let HeldOut {
            fold_params,
            fold_of,
            held,
        } = held_out(&splits, 3, "model", row_of, fit(1.0)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(fold_params, [vec![1.0], vec![1.0]]);
        assert_eq!(fold_of, [0, 1, 1]);
        assert_eq!(held, [1.0, 2.0, 2.0]);
        let bad = |_: &Split| Ok((vec![0.0], vec![f64::NAN; 13]));
        let err = held_out(&splits, 3, "model", row_of, bad)
            .err()
            .map(|e| e.to_string());
        assert!(
            err.as_deref()
                .is_some_and(|e| e.contains("row 11: the model refitted")),
            "{err:?}"
        );
    }

    #[test]
    fn distance_counts_each_column_in_its_own_width() {
        let (lo, hi) = ([0.0, 10.0], [2.0, 20.0]);
        assert_eq!(RangeWidening::distance(&lo, &hi, &[1.0, 15.0]), 0.0);
        assert_eq!(RangeWidening::distance(&lo, &hi, &[3.0, 15.0]), 0.5);
        assert_eq!(RangeWidening::distance(&lo, &hi, &[-2.0, 25.0]), 1.5);
        // a column of zero width counts by its absolute difference
        assert_eq!(RangeWidening::distance(&[1.0], &[1.0], &[1.5]), 0.5);
    }

    #[test]
    fn slope_is_the_conformal_quantile_of_the_excess_ratios() {
        // rows outside at d = 1 with scores e: ratios (e / q - 1) / d with q = 2
        let w = RangeWidening {
            columns: vec!["x".into()],
            lo: vec![0.0],
            hi: vec![1.0],
            held_out: (1..=19)
                .map(|k| [1.0, 2.0 * (1.0 + 0.1 * k as f64)])
                .chain([[0.0, 100.0]]) // inside: not counted
                .collect(),
        };
        // 19 ratios 0.1..1.9; at 0.9 the rank is ceil(0.9 * 20) = 18
        assert!((w.slope(2.0, 0.9) - 1.8).abs() < 1e-12);
        // too few for 0.99: the largest
        assert!((w.slope(2.0, 0.99) - 1.9).abs() < 1e-12);
        // scores below the quantile give no widening
        let calm = RangeWidening {
            held_out: vec![[1.0, 1.0], [2.0, 0.5]],
            ..w.clone()
        };
        assert_eq!(calm.slope(2.0, 0.5), 0.0);
        let none = RangeWidening {
            held_out: Vec::new(),
            ..w
        };
        assert_eq!(none.slope(2.0, 0.95), 0.0);
    }

    /// A row where a fold's model has no value on the log scale (a negative prediction)
    /// gets no interval, (NaN, NaN), and every other row keeps its own, by both conformal
    /// methods (issue 63: one such row aborted a whole evaluation).
    #[test]
    fn a_row_without_an_interval_does_not_stop_the_others() {
        use super::{ConformalInfo, IntervalMethod, ResidualScale};
        let n = 40;
        let y: Vec<f64> = (0..n).map(|i| 10.0 + f64::from(i)).collect();
        let held: Vec<f64> = y
            .iter()
            .enumerate()
            .map(|(i, v)| v * if i % 2 == 0 { 1.05 } else { 0.96 })
            .collect();
        let fold_of: Vec<usize> = (0..y.len()).map(|i| i % 2).collect();
        let c = ConformalInfo::from_held_out(vec![vec![1.0], vec![1.0]], fold_of, &held, &y, true)
            .expect("a calibration");
        assert_eq!(c.scale, ResidualScale::Log);
        let fold_pred = vec![vec![12.0, -0.104, 30.0], vec![12.5, 5.0, 29.0]];
        for method in [IntervalMethod::Conformal, IntervalMethod::Split] {
            let iv = c
                .intervals_from(&fold_pred, None, 0.9, method)
                .expect("intervals");
            assert_eq!(iv.len(), 3);
            if method == IntervalMethod::Conformal {
                assert!(iv[1].0.is_nan() && iv[1].1.is_nan(), "{iv:?}");
            }
            for (lo, hi) in [iv[0], iv[2]] {
                assert!(lo.is_finite() && hi.is_finite() && lo < hi, "{iv:?}");
            }
        }
        // split conformal uses the first fold alone, whose prediction at row 2 is -0.104
        let split = c
            .intervals_from(&fold_pred, None, 0.9, IntervalMethod::Split)
            .expect("intervals");
        assert!(split[1].0.is_nan());
    }
}
