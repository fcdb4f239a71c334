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
