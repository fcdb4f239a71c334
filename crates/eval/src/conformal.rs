//! Conformal prediction intervals: the finite-sample quantile of split conformal (Lei et
//! al. 2018) and the interval of CV+ (Barber et al. 2021), with scores normalised by a
//! simple model of the local scale.
//!
//! What is guaranteed, and under what: if the calibration rows and a new row are
//! exchangeable (drawn from one distribution, in any order), split conformal covers the new
//! row's truth with probability at least `P` and CV+ with at least `2P - 1` (in practice
//! near `P`), whatever the model and the noise. Nothing is guaranteed for a row drawn from
//! elsewhere (extrapolation: a new range of a column), where the width only follows the
//! [`ScaleModel`] fitted on the calibration rows.
//!
//! - [`conformal_rank`]: `k = ceil(P (n + 1))`, the rank of the conformal quantile among `n`
//!   scores (an error when `k > n`: too few scores for a finite interval at `P`).
//! - [`conformal_quantile`]: the `k`-th smallest score (split conformal's half-width).
//! - [`cv_plus`]: CV+'s interval from each calibration row's centre (its fold model's
//!   prediction at the new row) and radius (its score times the local scale).
//! - [`ScaleModel`]: `s(p) = max(a + b p, floor)`, the absolute residual regressed on the
//!   prediction, so the width follows the scatter.
//! - [`IntervalMethod`]: the names of the methods a front end offers.
//!
//! Design decision: the quantile is the `k`-th order statistic itself, not an interpolated
//! quantile, so its guarantee is exact; it equals numpy's `np.quantile(scores, q,
//! method="higher")` at any `q` with `(k - 2) / (n - 1) < q <= (k - 1) / (n - 1)`
//! (checked against stored vectors of `scripts/ref_conformal.py`).
//!
//! ```
//! use hxai_eval::conformal::{conformal_quantile, conformal_rank, cv_plus};
//! // 19 scores are the fewest that give a finite 95 % interval: k = ceil(0.95 * 20) = 19.
//! let scores: Vec<f64> = (1..=19).map(f64::from).collect();
//! assert_eq!(conformal_rank(19, 0.95)?, 19);
//! assert_eq!(conformal_quantile(&scores, 0.95)?, 19.0);
//! assert!(conformal_quantile(&scores[..18], 0.95).is_err());
//! // CV+ with every fold model predicting 10 at the new row: 10 -+ the quantile.
//! let (lo, hi) = cv_plus(&[10.0; 19], &scores, 0.95)?;
//! assert_eq!((lo, hi), (-9.0, 29.0));
//! # Ok::<(), hxai_eval::EvalError>(())
//! ```
use crate::EvalError;
use crate::check::{check_finite, check_open_fraction};
use serde::{Deserialize, Serialize};

/// How prediction intervals are made (`--interval-method`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum IntervalMethod {
    /// CV+ over the folds of the fit (Barber et al. 2021), scores normalised by the local
    /// scale.
    #[default]
    Conformal,
    /// Split conformal: one fold's model, calibrated on that fold's rows alone.
    Split,
    /// The delta method with a constant residual variance (`hxai_symreg::uncertainty`).
    Delta,
}

impl IntervalMethod {
    /// `conformal`, `split` or `delta`.
    pub fn name(self) -> &'static str {
        match self {
            IntervalMethod::Conformal => "conformal",
            IntervalMethod::Split => "split",
            IntervalMethod::Delta => "delta",
        }
    }
}

/// The tolerance of [`conformal_rank`] on `P (n + 1)`: a level written in decimal (0.9 with
/// `n + 1 = 10`) gives the rank computed by hand (9), not that of its binary rounding
/// (`0.9 * 10 = 9.000000000000002` would give 10).
const RANK_SLACK: f64 = 1e-9;

/// The rank `k = ceil(level (n + 1))` (1-based) of the conformal quantile among `n` scores.
///
/// # Errors
/// `level` outside (0, 1); [`EvalError::TooFewScores`] when `k > n` (the interval would be
/// infinite: more calibration rows or a lower level are needed).
pub fn conformal_rank(n: usize, level: f64) -> Result<usize, EvalError> {
    check_open_fraction("level", level)?;
    let k = (level * (n as f64 + 1.0) - RANK_SLACK).ceil().max(1.0) as usize;
    if k > n {
        return Err(EvalError::TooFewScores {
            n,
            level,
            need: fewest_scores(level),
        });
    }
    Ok(k)
}

/// The fewest scores that give a finite conformal quantile at `level`.
fn fewest_scores(level: f64) -> usize {
    // ceil(level (n + 1)) <= n  <=>  n >= level / (1 - level), up to the slack
    ((level / (1.0 - level)) - RANK_SLACK).ceil().max(1.0) as usize
}

/// The `k`-th smallest of `values` (1-based), `values` finite and `1 <= k <= len`.
fn kth_smallest(values: &[f64], k: usize) -> f64 {
    let mut v = values.to_vec();
    let (_, x, _) = v.select_nth_unstable_by(k - 1, f64::total_cmp);
    *x
}

/// Split conformal's quantile: the `ceil(level (n + 1))`-th smallest of the `n` scores.
///
/// # Errors
/// No score, a non-finite score, `level` outside (0, 1), or too few scores
/// ([`conformal_rank`]).
pub fn conformal_quantile(scores: &[f64], level: f64) -> Result<f64, EvalError> {
    check_finite("scores", scores, 1)?;
    let k = conformal_rank(scores.len(), level)?;
    Ok(kth_smallest(scores, k))
}

/// CV+'s interval at one new row (Barber et al. 2021, eq. 6 with the scores scaled):
/// calibration row `i` has `centre[i]`, the prediction of the model fitted without its fold
/// at the new row, and `radius[i]`, its score times the local scale at the new row. The
/// lower end is the `floor((1 - level)(n + 1))`-th smallest of `centre - radius`, the upper
/// the `ceil(level (n + 1))`-th smallest of `centre + radius`.
///
/// # Errors
/// Lengths that differ, no row, a non-finite value, a negative radius, `level` outside
/// (0, 1), or too few rows ([`conformal_rank`]).
pub fn cv_plus(centre: &[f64], radius: &[f64], level: f64) -> Result<(f64, f64), EvalError> {
    crate::check::check_paired("cv_plus", ("centre", centre), ("radius", radius), 1)?;
    if let Some(i) = radius.iter().position(|r| *r < 0.0) {
        return Err(EvalError::NonPositive {
            what: "radius",
            value: radius[i],
        });
    }
    let k = conformal_rank(centre.len(), level)?;
    let lower: Vec<f64> = centre.iter().zip(radius).map(|(c, r)| r - c).collect();
    let upper: Vec<f64> = centre.iter().zip(radius).map(|(c, r)| c + r).collect();
    Ok((-kth_smallest(&lower, k), kth_smallest(&upper, k)))
}

/// The share of the mean absolute residual below which the local scale never falls: where
/// the linear fit nears zero, a tiny scale would blow the normalised scores (and so every
/// width) up; a tenth keeps the narrowest band at a tenth of the typical residual's width.
pub const SCALE_FLOOR_SHARE: f64 = 0.1;

/// The local scale of the residuals, `s(p) = max(intercept + slope p, floor)`: the absolute
/// residual regressed on the prediction `p` by least squares, floored at
/// [`SCALE_FLOOR_SHARE`] times the mean absolute residual, so it is always positive.
/// Scores `|y - p| / s(p)` then have about one spread wherever the scatter grows with the
/// prediction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScaleModel {
    /// `a`.
    pub intercept: f64,
    /// `b`.
    pub slope: f64,
    /// The least value of `s` (positive).
    pub floor: f64,
}

impl ScaleModel {
    /// The scale that is 1 everywhere (unnormalised scores).
    pub fn constant() -> Self {
        ScaleModel {
            intercept: 1.0,
            slope: 0.0,
            floor: 1.0,
        }
    }

    /// Fits `|residual|` on `prediction` by least squares. With every residual zero the
    /// scale is [`ScaleModel::constant`]; with every prediction equal, the mean absolute
    /// residual.
    ///
    /// # Errors
    /// Lengths that differ, fewer than two rows, or a non-finite value.
    pub fn fit(prediction: &[f64], residual: &[f64]) -> Result<Self, EvalError> {
        crate::check::check_paired(
            "ScaleModel::fit",
            ("prediction", prediction),
            ("residual", residual),
            2,
        )?;
        let n = prediction.len() as f64;
        let abs: Vec<f64> = residual.iter().map(|r| r.abs()).collect();
        let mean_abs = abs.iter().sum::<f64>() / n;
        if mean_abs <= 0.0 {
            return Ok(Self::constant());
        }
        let mean_p = prediction.iter().sum::<f64>() / n;
        let (mut sxy, mut sxx) = (0.0, 0.0);
        for (p, a) in prediction.iter().zip(&abs) {
            sxy += (p - mean_p) * (a - mean_abs);
            sxx += (p - mean_p) * (p - mean_p);
        }
        let slope = if sxx > 0.0 && (sxy / sxx).is_finite() {
            sxy / sxx
        } else {
            0.0
        };
        Ok(ScaleModel {
            intercept: mean_abs - slope * mean_p,
            slope,
            floor: SCALE_FLOOR_SHARE * mean_abs,
        })
    }

    /// `s(p)`, positive for any finite `p` of a fitted or read model (a non-finite `p`
    /// gives the floor).
    pub fn at(&self, p: f64) -> f64 {
        let s = self.intercept + self.slope * p;
        if s.is_finite() {
            s.max(self.floor)
        } else {
            self.floor
        }
    }

    /// Checks a scale model read from a file: finite values and a positive floor.
    ///
    /// # Errors
    /// [`EvalError::NonPositive`] or [`EvalError::NonFinite`] naming the bad field.
    pub fn check(&self) -> Result<(), EvalError> {
        check_finite("scale model", &[self.intercept, self.slope, self.floor], 3)?;
        if self.floor <= 0.0 {
            return Err(EvalError::NonPositive {
                what: "scale model floor",
                value: self.floor,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn rank_follows_the_finite_sample_correction() {
        assert_eq!(conformal_rank(19, 0.95), Ok(19));
        assert_eq!(conformal_rank(100, 0.95), Ok(96));
        // 0.9 * 10 is 9.000000000000002 in binary: the rank is still 9
        assert_eq!(conformal_rank(9, 0.9), Ok(9));
        assert_eq!(
            conformal_rank(18, 0.95),
            Err(EvalError::TooFewScores {
                n: 18,
                level: 0.95,
                need: 19
            })
        );
        assert!(matches!(
            conformal_rank(100, 1.0),
            Err(EvalError::FractionOutOfRange { .. })
        ));
        assert!(matches!(
            conformal_rank(100, 0.0),
            Err(EvalError::FractionOutOfRange { .. })
        ));
        assert!(matches!(
            conformal_rank(100, f64::NAN),
            Err(EvalError::FractionOutOfRange { .. })
        ));
    }

    #[test]
    fn bad_scores_are_refused() {
        assert!(matches!(
            conformal_quantile(&[], 0.5),
            Err(EvalError::Empty { .. })
        ));
        assert!(matches!(
            conformal_quantile(&[1.0, f64::NAN, 2.0], 0.5),
            Err(EvalError::NonFinite { index: 1, .. })
        ));
        assert!(matches!(
            cv_plus(&[1.0, 2.0], &[1.0], 0.5),
            Err(EvalError::LengthMismatch { .. })
        ));
        assert!(matches!(
            cv_plus(&[1.0, 2.0], &[1.0, -1.0], 0.5),
            Err(EvalError::NonPositive { .. })
        ));
    }

    #[test]
    fn scale_model_follows_a_linear_scatter_and_stays_positive() {
        let p: Vec<f64> = (0..50).map(f64::from).collect();
        // |r| = 1 + 0.5 p exactly
        let r: Vec<f64> = p
            .iter()
            .enumerate()
            .map(|(i, p)| {
                if i % 2 == 0 {
                    1.0 + 0.5 * p
                } else {
                    -(1.0 + 0.5 * p)
                }
            })
            .collect();
        let s = ScaleModel::fit(&p, &r).expect("fit");
        approx::assert_relative_eq!(s.intercept, 1.0, max_relative = 1e-12);
        approx::assert_relative_eq!(s.slope, 0.5, max_relative = 1e-12);
        assert_eq!(s.at(-100.0), s.floor);
        assert!(s.floor > 0.0);
        assert_eq!(
            ScaleModel::fit(&p, &vec![0.0; 50]),
            Ok(ScaleModel::constant())
        );
        assert!(ScaleModel::fit(&[1.0], &[1.0]).is_err());
        let bad = ScaleModel {
            floor: 0.0,
            ..ScaleModel::constant()
        };
        assert!(bad.check().is_err());
    }

    proptest! {
        // Invariant: at least ceil(P (n+1)) of the n scores are <= the quantile, and fewer
        // than that are < it (it is an order statistic, not an interpolation).
        #[test]
        fn quantile_is_the_order_statistic(
            scores in proptest::collection::vec(0.0f64..100.0, 1..200),
            level in 0.05f64..0.95,
        ) {
            let n = scores.len();
            match conformal_quantile(&scores, level) {
                Ok(q) => {
                    let k = conformal_rank(n, level).expect("rank");
                    prop_assert!(scores.iter().filter(|s| **s <= q).count() >= k);
                    prop_assert!(scores.iter().filter(|s| **s < q).count() < k);
                }
                Err(e) => {
                    let too_few = matches!(e, EvalError::TooFewScores { .. });
                    prop_assert!(too_few);
                    prop_assert!((level * (n as f64 + 1.0)).ceil() as usize > n);
                }
            }
        }

        // Invariant: with every centre equal, CV+ is centre -+ the conformal quantile of
        // the radii (split conformal's interval).
        #[test]
        fn cv_plus_reduces_to_split_conformal(
            radius in proptest::collection::vec(0.0f64..10.0, 19..100),
            c in -5.0f64..5.0,
        ) {
            let centre = vec![c; radius.len()];
            let (lo, hi) = cv_plus(&centre, &radius, 0.9).expect("cv+");
            let q = conformal_quantile(&radius, 0.9).expect("q");
            prop_assert_eq!(hi, c + q);
            prop_assert_eq!(lo, c - q);
        }
    }
}
