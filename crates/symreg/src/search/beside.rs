//! No blow-up beside the rows (issue 64): a model that is finite over the widened box of
//! its inputs ([`crate::enclosure::defined_over`]) can still explode there, as an
//! `exp(17 x)` with a tiny factor that fits one extreme row does (1.2 at the fastest car,
//! 3e7 one step further). Such a model is not offered to selection when a witness shows
//! it: a point of the box, made of a row with one input moved to an end of its widened
//! range, where its value leaves the target's range by more than [`BLOW_UP_RANGES`] times
//! its width.
//!
//! Design decision: at selection, not during the search. Turning candidates down while
//! searching changed the course of searches whose reported models were all tame (the
//! paper's case among them); the selection's few models are what a user reads.
//!
//! Design decision: witnesses, not interval bounds. An enclosure's bound over-estimates
//! products of a large factor and a small exponential (`5e5*x*exp(-(0.04*z + 2)^2)`), and
//! rejecting on it changed the searches of candidates that are in truth tame; a value at a
//! concrete point is a proof, and the points are few (16 rows, two ends per input).
use crate::Table;
use crate::enclosure::Interval;
use crate::eval::Evaluator;
use crate::model::Model;
use crate::program::Program;

/// How many times the target's range (its width) a candidate's values may leave it by
/// beside the rows before they count as a blow-up: a true exponential law whose rows
/// span `D` decades grows by `D/10` decades over a tenth of its range, so 10^4 turns down
/// none spanning fewer than 40; a spike that fits one extreme row grows by many more.
pub const BLOW_UP_RANGES: f64 = 1e4;

/// Rows the witnesses are built from (evenly spaced over the table), at most.
const WITNESS_ROWS: usize = 16;

/// The values a candidate may take beside the rows: the target's finite range widened by
/// [`BLOW_UP_RANGES`] times its width (at least a 1e-12 share of its magnitude) on each
/// side; everything when the target has no finite value.
pub(crate) fn allowed_of(target: &[f64]) -> Interval {
    let (lo, hi) = target
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        return Interval::new(f64::NEG_INFINITY, f64::INFINITY);
    }
    let width = (hi - lo).max(lo.abs().max(hi.abs()) * 1e-12).max(1e-300);
    Interval::new(lo - BLOW_UP_RANGES * width, hi + BLOW_UP_RANGES * width)
}

/// Whether `prog` with `params` over the columns `cols` (the rows; `bounds[j]` the widened
/// range of `cols[j]`) takes a value outside `allowed` at a witness point: one of up to
/// [`WITNESS_ROWS`] rows with one column the program reads moved to either end of its
/// range. A value that is not finite there counts too.
pub(crate) fn blows_up(
    prog: &Program,
    params: &[f64],
    cols: &[&[f64]],
    bounds: &[(f64, f64)],
    allowed: Interval,
) -> bool {
    let n = cols.first().map_or(0, |c| c.len());
    let read: Vec<usize> = prog.vars().into_iter().map(usize::from).collect();
    if n == 0 || read.is_empty() || read.iter().any(|&j| j >= cols.len() || j >= bounds.len()) {
        return false;
    }
    let rows: Vec<usize> = (0..WITNESS_ROWS.min(n))
        .map(|i| i * n / WITNESS_ROWS.min(n))
        .collect();
    let mut points: Vec<Vec<f64>> = vec![Vec::new(); cols.len()];
    for &r in &rows {
        for &j in &read {
            for end in [bounds[j].0, bounds[j].1] {
                for (k, p) in points.iter_mut().enumerate() {
                    p.push(if k == j { end } else { cols[k][r] });
                }
            }
        }
    }
    let refs: Vec<&[f64]> = points.iter().map(|c| c.as_slice()).collect();
    let m = points[0].len();
    let mut out = Vec::with_capacity(m);
    Evaluator::new(prog).predict(prog, params, &refs, m, &mut out);
    out.iter()
        .any(|v| !v.is_finite() || *v < allowed.lo || *v > allowed.hi)
}

/// Drops from `models` (over columns of `data`) each that blows up beside the rows
/// ([`blows_up`] over `domain`, the widened box of `data`'s columns, against `allowed`),
/// unless every one does; nothing without a domain
/// ([`crate::SearchConfig::defined_margin`] `None`).
pub(crate) fn drop_blow_ups(
    (domain, allowed): (Option<&[(f64, f64)]>, Interval),
    models: &mut Vec<Model>,
    data: &Table,
) {
    let Some(domain) = domain else {
        return;
    };
    let tame = |m: &Model| {
        let Ok(cols) = m.columns(data) else {
            return true;
        };
        bounds_of(m, data, domain)
            .is_none_or(|b| !blows_up(&m.program, &m.params, &cols, &b, allowed))
    };
    let keep: Vec<bool> = models.iter().map(tame).collect();
    if keep.iter().any(|&k| k) {
        let mut flags = keep.into_iter();
        models.retain(|_| flags.next().unwrap_or(true));
    }
}

/// The ranges of `domain` (one per column of `data`) of the columns `m` reads, in its
/// features' order; `None` when one of them is not a column of `data`.
pub(crate) fn bounds_of(m: &Model, data: &Table, domain: &[(f64, f64)]) -> Option<Vec<(f64, f64)>> {
    m.feature_names
        .iter()
        .map(|n| {
            data.names()
                .iter()
                .position(|x| x == n)
                .and_then(|j| domain.get(j).copied())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::infix::compile_text;
    use std::collections::BTreeMap;

    /// A spike that fits the largest row (`exp(16.84 x - 404)`: 1.2 at x = 24, 1.6e15 at
    /// 26.1, the widened box's end) is a blow-up; a true exponential law over its own rows
    /// (`exp(0.5 x)`: 1 to 148 on x in 0..10, 245 at 11) is not, nor is a product of a large
    /// factor and a small exponential whose interval bound is loose.
    #[test]
    fn a_spike_beside_the_rows_blows_up_and_a_law_does_not() {
        let c = |t: &str| compile_text(t, &BTreeMap::new()).unwrap();
        let x: Vec<f64> = (0..=20).map(|i| 4.0 + f64::from(i)).collect();
        let spike = c("exp(16.84*x - 404)");
        let allowed = allowed_of(&[2.0, 120.0]);
        assert!(blows_up(
            &spike.program,
            &spike.params,
            &[&x],
            &[(1.9, 26.1)],
            allowed
        ));
        assert!(!blows_up(
            &spike.program,
            &spike.params,
            &[&x],
            &[(4.0, 24.0)],
            allowed
        ));
        let x: Vec<f64> = (0..=10).map(f64::from).collect();
        let y: Vec<f64> = x.iter().map(|v| (0.5 * v).exp()).collect();
        let law = c("exp(0.5*x)");
        assert!(!blows_up(
            &law.program,
            &law.params,
            &[&x],
            &[(0.0, 11.0)],
            allowed_of(&y)
        ));
        let z: Vec<f64> = (0..=10).map(|i| 40.0 + f64::from(i)).collect();
        let hump = c("5e5*x*exp(-(0.04*z + 2)^2)");
        let y: Vec<f64> = x
            .iter()
            .zip(&z)
            .map(|(a, b)| 5e5 * a * (-(0.04 * b + 2.0f64).powi(2)).exp())
            .collect();
        assert!(!blows_up(
            &hump.program,
            &hump.params,
            &[&x, &z],
            &[(0.0, 11.0), (39.0, 51.0)],
            allowed_of(&y)
        ));
    }
}
