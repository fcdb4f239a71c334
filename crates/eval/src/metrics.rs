//! Regression metrics with scikit-learn's definitions.

use crate::EvalError;
use crate::check::{check_finite, check_paired};
use serde::{Deserialize, Serialize};

/// Checks a truth and a prediction: equal lengths, non-empty, finite.
fn check_pair(y_true: &[f64], y_pred: &[f64]) -> Result<(), EvalError> {
    check_paired(
        "y_true vs y_pred",
        ("y_true", y_true),
        ("y_pred", y_pred),
        1,
    )
}

/// Coefficient of determination `1 - SS_res / SS_tot`, like `sklearn.metrics.r2_score`.
///
/// When `y_true` is constant (`SS_tot = 0`) scikit-learn's `force_finite` rule applies:
/// 1.0 for a perfect prediction, 0.0 otherwise. A constant `y_true` is recognised up to the
/// rounding of its mean (`SS_tot` at most `n (8 eps max|y|)^2`): ten copies of 0.1 have a
/// mean that is not exactly 0.1, and `SS_tot` of 1e-33 would otherwise give an R² of -1e27.
///
/// # Errors
/// Empty input, different lengths, or a non-finite value.
pub fn r2(y_true: &[f64], y_pred: &[f64]) -> Result<f64, EvalError> {
    check_pair(y_true, y_pred)?;
    let n = y_true.len() as f64;
    let mean = y_true.iter().sum::<f64>() / n;
    let ss_res: f64 = y_true
        .iter()
        .zip(y_pred)
        .map(|(t, p)| (t - p) * (t - p))
        .sum();
    let ss_tot: f64 = y_true.iter().map(|t| (t - mean) * (t - mean)).sum();
    let scale = y_true.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let rounding = n * (8.0 * f64::EPSILON * scale).powi(2);
    if ss_tot <= rounding {
        return Ok(if ss_res <= rounding { 1.0 } else { 0.0 });
    }
    Ok(1.0 - ss_res / ss_tot)
}

/// Root mean squared error, like `sklearn.metrics.root_mean_squared_error`.
///
/// # Errors
/// Empty input, different lengths, or a non-finite value.
pub fn rmse(y_true: &[f64], y_pred: &[f64]) -> Result<f64, EvalError> {
    check_pair(y_true, y_pred)?;
    let sse: f64 = y_true
        .iter()
        .zip(y_pred)
        .map(|(t, p)| (t - p) * (t - p))
        .sum();
    Ok((sse / y_true.len() as f64).sqrt())
}

/// Mean absolute error, like `sklearn.metrics.mean_absolute_error`.
///
/// # Errors
/// Empty input, different lengths, or a non-finite value.
pub fn mae(y_true: &[f64], y_pred: &[f64]) -> Result<f64, EvalError> {
    check_pair(y_true, y_pred)?;
    let sae: f64 = y_true.iter().zip(y_pred).map(|(t, p)| (t - p).abs()).sum();
    Ok(sae / y_true.len() as f64)
}

/// Per-sample squared errors `(y_true[i] - y_pred[i])^2`, the input of the paper's t-test.
///
/// # Errors
/// Empty input, different lengths, or a non-finite value.
pub fn squared_errors(y_true: &[f64], y_pred: &[f64]) -> Result<Vec<f64>, EvalError> {
    check_pair(y_true, y_pred)?;
    Ok(y_true
        .iter()
        .zip(y_pred)
        .map(|(t, p)| (t - p) * (t - p))
        .collect())
}

/// Per-sample errors `y_pred[i] - y_true[i]` (positive where the prediction lies above the
/// truth), as an error-over-time plot shows them.
///
/// # Errors
/// Empty input, different lengths, or a non-finite value.
pub fn residuals(y_true: &[f64], y_pred: &[f64]) -> Result<Vec<f64>, EvalError> {
    check_pair(y_true, y_pred)?;
    Ok(y_true.iter().zip(y_pred).map(|(t, p)| p - t).collect())
}

/// Relative RMSE reduction in percent: `(rmse_phys - rmse_hybrid) / rmse_phys * 100`.
///
/// # Errors
/// `rmse_phys` must be finite and positive, `rmse_hybrid` finite.
pub fn improvement_pct(rmse_phys: f64, rmse_hybrid: f64) -> Result<f64, EvalError> {
    check_finite("rmse_phys", &[rmse_phys], 1)?;
    check_finite("rmse_hybrid", &[rmse_hybrid], 1)?;
    if rmse_phys <= 0.0 {
        return Err(EvalError::NonPositive {
            what: "rmse_phys",
            value: rmse_phys,
        });
    }
    Ok((rmse_phys - rmse_hybrid) / rmse_phys * 100.0)
}

/// R^2, RMSE and MAE of one prediction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Coefficient of determination ([`r2`]).
    pub r2: f64,
    /// Root mean squared error ([`rmse`]).
    pub rmse: f64,
    /// Mean absolute error ([`mae`]).
    pub mae: f64,
}

/// All three metrics at once.
///
/// # Errors
/// Empty input, different lengths, or a non-finite value.
pub fn score(y_true: &[f64], y_pred: &[f64]) -> Result<Metrics, EvalError> {
    Ok(Metrics {
        r2: r2(y_true, y_pred)?,
        rmse: rmse(y_true, y_pred)?,
        mae: mae(y_true, y_pred)?,
    })
}
