//! The width that grows with the distance from the training ranges, for rows that the
//! conformal guarantee does not cover (issue 28 item 2).
use crate::HybridError;
use hxai_symreg::Table;
use serde::{Deserialize, Serialize};

/// A width that grows with the distance from the training ranges (issue 28 item 2), for
/// rows the conformal guarantee does not cover: those outside the range of the training
/// rows in some column.
///
/// At fit time, for each input column the top and the bottom fifth of the training rows (by
/// that column) are held out in turn, the model's constants refitted on the rest, and each
/// held-out row's normalised score `e` (as the conformal scores: `|r| / s`) is stored with
/// its distance `d` outside the ranges of the rows fitted: `d = sum_j max(0, lo_j - x_j,
/// x_j - hi_j) / (hi_j - lo_j)`. At level `P`, with `q` the conformal quantile of the
/// ordinary scores, the slope `kappa` is the conformal `P`-quantile of `(e / q - 1) / d`
/// over the held-out rows outside (`d > 0`): the half-width at a new row is multiplied by
/// `1 + kappa d(x)`, with `d(x)` its distance outside the whole training ranges. So the
/// width grows as much as the model's error grew when it was made to extrapolate inside
/// its own training data. This is a heuristic, not a guarantee: it assumes the error keeps
/// growing linearly in the distance beyond the ranges measured.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct RangeWidening {
    /// The model's input columns.
    pub columns: Vec<String>,
    /// Smallest training value of each column.
    pub lo: Vec<f64>,
    /// Largest training value of each column.
    pub hi: Vec<f64>,
    /// `[d, e]` of every row held out by range.
    pub held_out: Vec<[f64; 2]>,
}

impl RangeWidening {
    /// The distance of `x` (one value per column) outside the box `lo`..`hi`, in units of
    /// each column's width (a column of zero width counts by its absolute difference).
    pub fn distance(lo: &[f64], hi: &[f64], x: &[f64]) -> f64 {
        lo.iter()
            .zip(hi)
            .zip(x)
            .map(|((l, h), v)| {
                let out = (l - v).max(v - h).max(0.0);
                let w = h - l;
                if w > 0.0 { out / w } else { out }
            })
            .sum()
    }

    /// Each row's distance outside the training ranges.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] naming a missing column.
    pub fn distances(&self, table: &Table) -> Result<Vec<f64>, HybridError> {
        let cols = super::named_columns(table, &self.columns, |c| {
            format!("no column `{c}` for the interval's width")
        })?;
        let mut x = vec![0.0; cols.len()];
        Ok((0..table.n_rows())
            .map(|r| {
                for (v, c) in x.iter_mut().zip(&cols) {
                    *v = c[r];
                }
                Self::distance(&self.lo, &self.hi, &x)
            })
            .collect())
    }

    /// The slope `kappa` at `level` given the conformal quantile `q` of the ordinary scores
    /// (0 when no held-out row lay outside; the largest ratio when they are too few for the
    /// level's rank).
    pub fn slope(&self, q: f64, level: f64) -> f64 {
        let mut ratios: Vec<f64> = self
            .held_out
            .iter()
            .filter(|[d, _]| *d > 0.0)
            .map(|[d, e]| ((e / q.max(f64::MIN_POSITIVE) - 1.0) / d).max(0.0))
            .filter(|r| r.is_finite())
            .collect();
        if ratios.is_empty() {
            return 0.0;
        }
        ratios.sort_by(f64::total_cmp);
        let k = hxai_eval::conformal_rank(ratios.len(), level).unwrap_or(ratios.len());
        ratios[k.clamp(1, ratios.len()) - 1]
    }

    pub(super) fn check(&self) -> Result<(), String> {
        let n = self.columns.len();
        if self.lo.len() != n || self.hi.len() != n {
            return Err("`widening`: one lo and hi per column".into());
        }
        if self.lo.iter().chain(&self.hi).any(|v| !v.is_finite())
            || self.lo.iter().zip(&self.hi).any(|(l, h)| l > h)
        {
            return Err("`widening`: ranges must be finite with lo <= hi".into());
        }
        if self
            .held_out
            .iter()
            .any(|[d, e]| !(d.is_finite() && *d >= 0.0 && e.is_finite() && *e >= 0.0))
        {
            return Err("`widening`: held-out rows must be finite non-negative pairs".into());
        }
        Ok(())
    }
}
