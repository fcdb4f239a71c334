//! Summaries over folds (mean, sample standard deviation, confidence intervals) and the
//! paired two-tailed t-test.

use crate::EvalError;
use crate::check::{check_finite, check_open_fraction, check_paired};
use serde::{Deserialize, Serialize};
use statrs::distribution::{Continuous, ContinuousCDF, Normal, StudentsT};
use statrs::function::beta::beta_reg;

/// A two-sided confidence interval `[lower, upper]` at confidence `level` (e.g. 0.95).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Interval {
    /// Lower end.
    pub lower: f64,
    /// Upper end.
    pub upper: f64,
    /// Confidence level in (0, 1).
    pub level: f64,
}

/// Mean, spread and confidence intervals of a handful of values (typically one metric over
/// the folds of a cross-validation).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Number of values.
    pub n: usize,
    /// Arithmetic mean.
    pub mean: f64,
    /// Sample standard deviation (divisor `n - 1`).
    pub std: f64,
    /// Student-t interval `mean +- t(1 - alpha/2, n - 1) * std / sqrt(n)`: the correct one
    /// for a small number of folds (like `scipy.stats.t.interval`).
    pub ci_t: Interval,
    /// Normal approximation `mean +- z(1 - alpha/2) * std / sqrt(n)` (z = 1.95996 at 95 %),
    /// the interval the paper reported; too narrow for five folds. Kept for comparison only.
    pub ci_normal: Interval,
}

/// Result of a paired two-tailed t-test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TTest {
    /// `mean(d) / (sd(d) / sqrt(n))` with `d = a - b`.
    pub statistic: f64,
    /// Degrees of freedom, `n - 1`.
    pub df: f64,
    /// Two-tailed p-value `P(|T| >= |statistic|)`.
    pub p_value: f64,
    /// Number of pairs `n` (rows, or windows).
    #[serde(default)]
    pub pairs: usize,
}

fn check_level(level: f64) -> Result<(), EvalError> {
    check_open_fraction("confidence level", level)
}

fn mean_and_sd(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let ss: f64 = values.iter().map(|v| (v - mean) * (v - mean)).sum();
    (mean, (ss / (n - 1.0)).sqrt())
}

/// Two-tailed p-value of a t statistic with `df` degrees of freedom:
/// `P(|T| >= |t|) = I_{df/(df+t^2)}(df/2, 1/2)`.
///
/// The regularised incomplete beta is statrs' continued fraction. It is evaluated directly
/// at the small argument `df / (df + t^2)` for large `|t|` (no `1 - cdf` cancellation), so the
/// relative error stays near machine precision for p-values far below 1e-12 (checked against
/// scipy in `tests/it/reference.rs`).
pub fn t_two_tailed_p(t: f64, df: f64) -> f64 {
    if t.is_nan() || df.is_nan() || df <= 0.0 {
        return f64::NAN;
    }
    if t.is_infinite() {
        return 0.0;
    }
    let x = df / (df + t * t);
    // beta_reg only fails for arguments outside its domain, which x in [0, 1] never is.
    beta_reg(df / 2.0, 0.5, x.clamp(0.0, 1.0))
}

/// Upper quantile of Student's t: the `t` with `P(T > t) = q`, for `0 < q < 0.5` and
/// `df > 0` (NaN otherwise). A two-sided interval at level `P` uses `q = (1 - P) / 2`.
///
/// statrs' `inverse_cdf` (an inverse incomplete beta) gives the start; Newton steps on the
/// survival function polish it, so the quantile is as accurate as the p-value function.
pub fn t_upper_quantile(q: f64, df: f64) -> f64 {
    if q.is_nan() || q <= 0.0 || q >= 0.5 || df.is_nan() || df <= 0.0 {
        return f64::NAN;
    }
    let dist = match StudentsT::new(0.0, 1.0, df) {
        Ok(d) => d,
        Err(_) => return f64::NAN,
    };
    polished_upper_quantile(&dist, q)
}

/// Upper standard-normal quantile `z` with `P(Z > z) = q`, polished like [`t_upper_quantile`].
fn z_upper_quantile(q: f64) -> f64 {
    polished_upper_quantile(&Normal::standard(), q)
}

/// The upper quantile `x` with `P(X > x) = q` of `dist`: statrs' `inverse_cdf` for the
/// start, then up to 20 Newton steps on the survival function, stopping when a step is
/// below 1e-16 relative.
fn polished_upper_quantile<D>(dist: &D, q: f64) -> f64
where
    D: ContinuousCDF<f64, f64> + Continuous<f64, f64>,
{
    let mut x = dist.inverse_cdf(1.0 - q);
    for _ in 0..20 {
        let step = (dist.sf(x) - q) / dist.pdf(x);
        x += step;
        if step.abs() <= 1e-16 * x.abs() {
            break;
        }
    }
    x
}

/// [`summarize_at`] with a 95 % confidence level.
///
/// # Errors
/// Fewer than two values, or a non-finite value.
pub fn summarize(values: &[f64]) -> Result<Summary, EvalError> {
    summarize_at(values, 0.95)
}

/// Mean, sample standard deviation and both confidence intervals at `level`.
///
/// # Errors
/// Fewer than two values, a non-finite value, or `level` outside (0, 1).
pub fn summarize_at(values: &[f64], level: f64) -> Result<Summary, EvalError> {
    check_finite("values", values, 2)?;
    check_level(level)?;
    let n = values.len();
    let (mean, std) = mean_and_sd(values);
    let se = std / (n as f64).sqrt();
    let q = (1.0 - level) / 2.0;
    let t = t_upper_quantile(q, (n - 1) as f64);
    let z = z_upper_quantile(q);
    Ok(Summary {
        n,
        mean,
        std,
        ci_t: Interval {
            lower: mean - t * se,
            upper: mean + t * se,
            level,
        },
        ci_normal: Interval {
            lower: mean - z * se,
            upper: mean + z * se,
            level,
        },
    })
}

/// Paired two-tailed t-test of `a` against `b` (like `scipy.stats.ttest_rel(a, b)`).
///
/// The paper applies it to per-sample squared errors of two models on one test set
/// (see [`crate::squared_errors`]). When all differences are equal but not zero the
/// statistic is infinite and the p-value 0.
///
/// # Errors
/// Fewer than two pairs, different lengths, a non-finite value, or `a == b` exactly
/// (the statistic would be 0/0).
pub fn paired_t_test(a: &[f64], b: &[f64]) -> Result<TTest, EvalError> {
    check_paired("a vs b", ("a", a), ("b", b), 2)?;
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    let n = d.len() as f64;
    let (mean, sd) = mean_and_sd(&d);
    let df = n - 1.0;
    if sd == 0.0 {
        if mean == 0.0 {
            return Err(EvalError::IdenticalSamples);
        }
        return Ok(TTest {
            statistic: mean.signum() * f64::INFINITY,
            df,
            p_value: 0.0,
            pairs: d.len(),
        });
    }
    let statistic = mean / (sd / n.sqrt());
    Ok(TTest {
        statistic,
        df,
        p_value: t_two_tailed_p(statistic, df),
        pairs: d.len(),
    })
}

/// Smallest, largest and mean value of a sample (the descriptive columns of a results table).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Extent {
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// Arithmetic mean, the values summed in order.
    pub mean: f64,
}

/// Smallest, largest and mean value of `values`.
///
/// # Errors
/// No value, or a non-finite value.
pub fn extent(values: &[f64]) -> Result<Extent, EvalError> {
    check_finite("values", values, 1)?;
    Ok(Extent {
        min: values.iter().copied().fold(f64::INFINITY, f64::min),
        max: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        mean: values.iter().sum::<f64>() / values.len() as f64,
    })
}

/// The mean value of each key of `(key, value)` pairs, in increasing key order (a curve of
/// means over conditions such as frequencies). Keys are compared after rounding to 1e-6,
/// so the same condition read from two places counts once.
pub fn means_by_key(pairs: impl IntoIterator<Item = (f64, f64)>) -> Vec<(f64, f64)> {
    let mut groups: std::collections::BTreeMap<i64, Vec<f64>> = std::collections::BTreeMap::new();
    for (k, v) in pairs {
        groups.entry((k * 1e6).round() as i64).or_default().push(v);
    }
    groups
        .into_iter()
        .map(|(k, v)| (k as f64 / 1e6, v.iter().sum::<f64>() / v.len() as f64))
        .collect()
}
