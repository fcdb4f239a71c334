//! How prediction intervals are judged, the same in both halves: the share of points whose
//! truth lies inside and the median width (JSON `interval` of an evaluation).

use hxai_eval::IntervalMethod;
use serde::{Deserialize, Serialize};

/// The nominal level of prediction intervals when none is given: 95 %.
pub const DEFAULT_INTERVAL: f64 = 0.95;

/// How often the truth falls inside prediction intervals, and how wide they are (JSON
/// `interval`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IntervalReport {
    /// How the intervals were made (`conformal`, `split` or `delta`; reports written before
    /// the key existed were all `delta`).
    #[serde(default = "delta_method")]
    pub method: IntervalMethod,
    /// The nominal level `P` of the intervals.
    pub nominal: f64,
    /// The share of points whose truth lies inside (closed interval).
    pub coverage: f64,
    /// How many points were checked.
    pub n: usize,
    /// The median of `hi - lo` over the points (`null` when there are none, and in reports
    /// written before the key existed).
    #[serde(default)]
    pub median_width: Option<f64>,
}

/// The interval method a model file serves by default at `level`, the same rule in both
/// halves: conformal where it stores a calibration with enough scores for `level`, else the
/// delta method where it stores the uncertainty of its constants, else none.
pub(crate) fn default_method(
    conformal: Option<&crate::conformal::ConformalInfo>,
    has_uncertainty: bool,
    level: f64,
) -> Option<IntervalMethod> {
    if conformal.is_some_and(|c| c.serves(level)) {
        Some(IntervalMethod::Conformal)
    } else if has_uncertainty {
        Some(IntervalMethod::Delta)
    } else {
        None
    }
}

/// `level` checked as a probability strictly between 0 and 1 (both halves' intervals).
pub(crate) fn check_level(level: f64) -> Result<(), crate::HybridError> {
    if level > 0.0 && level < 1.0 {
        Ok(())
    } else {
        Err(crate::HybridError::InvalidConfig(format!(
            "interval level {level}: give a probability between 0 and 1, such as 0.95"
        )))
    }
}

/// The refusal of a conformal `method` by a model file that stores no calibration, telling
/// the user to refit with `command` (`hxai fit` or `hxai hybrid fit`) or use the delta method.
pub(crate) fn no_conformal(method: IntervalMethod, command: &str) -> crate::HybridError {
    crate::HybridError::InvalidConfig(format!(
        "this model file stores no conformal calibration (written before conformal \
         intervals existed, or fitted with --conformal-folds 0): refit it with \
         `{command}`, or use --interval-method delta instead of {}",
        method.name()
    ))
}

fn delta_method() -> IntervalMethod {
    IntervalMethod::Delta
}

impl IntervalReport {
    /// The report of `intervals` (made by `method`) against `truth` at level `nominal`.
    pub fn of(
        method: IntervalMethod,
        nominal: f64,
        truth: &[f64],
        intervals: &[(f64, f64)],
    ) -> Self {
        let inside = truth
            .iter()
            .zip(intervals)
            .filter(|(t, (lo, hi))| lo <= *t && *t <= hi)
            .count();
        let n = truth.len().min(intervals.len());
        let mut widths: Vec<f64> = intervals[..n].iter().map(|(lo, hi)| hi - lo).collect();
        widths.sort_by(f64::total_cmp);
        let median_width = match n {
            0 => None,
            n if n % 2 == 1 => Some(widths[n / 2]),
            n => Some(0.5 * (widths[n / 2 - 1] + widths[n / 2])),
        };
        IntervalReport {
            method,
            nominal,
            coverage: if n > 0 { inside as f64 / n as f64 } else { 0.0 },
            n,
            median_width,
        }
    }
}
