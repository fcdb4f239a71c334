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
    /// Points that have no interval (a bound not a number: the model has no value on the
    /// interval's scale there), left out of `n`, `coverage` and `median_width`; absent when
    /// none.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub undefined: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// The warning for `report`'s points without an interval (`None` when every point has one).
pub fn undefined_warning(report: &IntervalReport, what: &str) -> Option<String> {
    (report.undefined > 0).then(|| {
        format!(
            "{} {what} have no prediction interval (the {} method has no value there, e.g. a \
             fold's model predicts a value the interval's log scale cannot take): they are left \
             out of the coverage and the width",
            report.undefined,
            report.method.name()
        )
    })
}

/// `intervals` widened where needed to hold their point `predictions` (an interval always
/// holds its point, issue 63: a conformal interval is built from the folds' models, which
/// beside the data can all lie on one side of the full model's prediction). Rows without an
/// interval (NaN bounds) or without a finite point stay as they are.
pub(crate) fn holding_points(
    mut intervals: Vec<(f64, f64)>,
    predictions: &[f64],
) -> Vec<(f64, f64)> {
    for ((lo, hi), &p) in intervals.iter_mut().zip(predictions) {
        if p.is_finite() && !lo.is_nan() && !hi.is_nan() {
            *lo = lo.min(p);
            *hi = hi.max(p);
        }
    }
    intervals
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
        let m = truth.len().min(intervals.len());
        let defined: Vec<(f64, (f64, f64))> = truth[..m]
            .iter()
            .zip(&intervals[..m])
            .filter(|(_, (lo, hi))| !lo.is_nan() && !hi.is_nan())
            .map(|(t, iv)| (*t, *iv))
            .collect();
        let inside = defined
            .iter()
            .filter(|(t, (lo, hi))| lo <= t && t <= hi)
            .count();
        let n = defined.len();
        let mut widths: Vec<f64> = defined.iter().map(|(_, (lo, hi))| hi - lo).collect();
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
            undefined: m - n,
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::{IntervalReport, holding_points, undefined_warning};
    use hxai_eval::IntervalMethod;

    /// An interval always holds its point (issue 63: predicted -157.6 with the interval
    /// [-144.1, -42.6]); intervals that hold it, and rows without one, are unchanged.
    #[test]
    fn an_interval_holds_its_point() {
        let iv = vec![
            (-144.1, -42.6),
            (1.0, 2.0),
            (f64::NAN, f64::NAN),
            (0.0, 1.0),
        ];
        let p = [-157.6, 1.5, 3.0, 7.0];
        let out = holding_points(iv, &p);
        assert_eq!(out[0], (-157.6, -42.6));
        assert_eq!(out[1], (1.0, 2.0));
        assert!(out[2].0.is_nan() && out[2].1.is_nan());
        assert_eq!(out[3], (0.0, 7.0));
    }

    /// Rows without an interval are left out of the coverage and the width, counted, and
    /// warned about.
    #[test]
    fn rows_without_an_interval_are_counted_not_scored() {
        let iv = [(0.0, 2.0), (f64::NAN, f64::NAN), (0.0, 1.0), (5.0, 6.0)];
        let r = IntervalReport::of(IntervalMethod::Conformal, 0.95, &[1.0, 1.0, 2.0, 5.5], &iv);
        assert_eq!((r.n, r.undefined), (3, 1));
        assert!((r.coverage - 2.0 / 3.0).abs() < 1e-15);
        assert_eq!(r.median_width, Some(1.0));
        assert!(
            undefined_warning(&r, "row(s)")
                .unwrap()
                .starts_with("1 row(s)")
        );
        let all = IntervalReport::of(IntervalMethod::Delta, 0.95, &[1.0], &[(0.0, 2.0)]);
        assert!(undefined_warning(&all, "row(s)").is_none());
        assert!(!serde_json::to_string(&all).unwrap().contains("undefined"));
    }
}
