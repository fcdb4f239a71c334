//! The space of settings a design chooses in: ranges given on the command line
//! ([`parse_space`]) and the seeded random candidates drawn from them ([`candidates`]).

use crate::HybridError;
use hxai_symreg::Table;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Candidates drawn from ranges.
pub const RANDOM_CANDIDATES: usize = 4000;

/// One column of a space given as ranges.
#[derive(Clone, Debug, PartialEq)]
pub enum SpaceColumn {
    /// `lo:hi`, or `lo:hi:step` (values `lo + k*step` up to `hi`).
    Range {
        /// Lowest value.
        lo: f64,
        /// Highest value.
        hi: f64,
        /// Step of the levels, if any.
        step: Option<f64>,
    },
    /// `a|b|c`: these values only.
    Levels(Vec<f64>),
}

/// Parses `col=lo:hi[:step],col=a|b` into `(column, SpaceColumn)` pairs.
///
/// # Errors
/// [`HybridError::InvalidConfig`] naming the part that is not `NAME=LO:HI[:STEP]` or
/// `NAME=A|B`, a range with `lo >= hi` or a step that is not positive, a level that is not a
/// number (text levels are not built yet), or a column given twice.
pub fn parse_space(spec: &str) -> Result<Vec<(String, SpaceColumn)>, HybridError> {
    let bad = |part: &str, why: &str| {
        HybridError::InvalidConfig(format!(
            "--space: {part:?} {why}; write NAME=LO:HI, NAME=LO:HI:STEP or NAME=A|B|C, \
             comma-separated (or give a CSV of feasible settings)"
        ))
    };
    let mut out: Vec<(String, SpaceColumn)> = Vec::new();
    for part in spec.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (name, value) = part
            .split_once('=')
            .ok_or_else(|| bad(part, "has no `=`"))?;
        let name = name.trim().trim_matches('`').to_string();
        if name.is_empty() {
            return Err(bad(part, "has no column name"));
        }
        if out.iter().any(|(n, _)| *n == name) {
            return Err(bad(part, "names a column twice"));
        }
        let num = |s: &str| {
            s.trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(part, &format!("has {:?}, not a number", s.trim())))
        };
        let col = if value.contains('|') {
            let levels = value.split('|').map(num).collect::<Result<Vec<_>, _>>()?;
            SpaceColumn::Levels(levels)
        } else {
            let f: Vec<&str> = value.split(':').collect();
            let (lo, hi, step) = match f.as_slice() {
                [lo, hi] => (num(lo)?, num(hi)?, None),
                [lo, hi, st] => (num(lo)?, num(hi)?, Some(num(st)?)),
                _ => return Err(bad(part, "is neither a range nor a list of levels")),
            };
            if lo >= hi {
                return Err(bad(part, "has its low end at or above its high end"));
            }
            if step.is_some_and(|s| s <= 0.0) {
                return Err(bad(part, "has a step that is not positive"));
            }
            SpaceColumn::Range { lo, hi, step }
        };
        out.push((name, col));
    }
    if out.is_empty() {
        return Err(bad(spec, "names no column"));
    }
    Ok(out)
}

/// [`RANDOM_CANDIDATES`] seeded random points of `space` (each column uniform over its
/// range, snapped to its step, or one of its levels).
///
/// # Errors
/// A table that cannot be built (never, for a parsed space).
pub fn candidates(space: &[(String, SpaceColumn)], seed: u64) -> Result<Table, HybridError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut cols: Vec<Vec<f64>> = vec![Vec::with_capacity(RANDOM_CANDIDATES); space.len()];
    for _ in 0..RANDOM_CANDIDATES {
        for (j, (_, c)) in space.iter().enumerate() {
            let v = match c {
                SpaceColumn::Range { lo, hi, step: None } => rng.gen_range(*lo..=*hi),
                SpaceColumn::Range {
                    lo,
                    hi,
                    step: Some(s),
                } => {
                    let k = ((hi - lo) / s + 1e-9).floor() as u64;
                    lo + s * rng.gen_range(0..=k) as f64
                }
                SpaceColumn::Levels(l) => l[rng.gen_range(0..l.len())],
            };
            cols[j].push(v);
        }
    }
    Ok(Table::new(
        space.iter().map(|(n, _)| n.clone()).collect(),
        cols,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spaces_parse_and_bad_ones_are_named() -> Result<(), HybridError> {
        let s = parse_space("f=0.05:0.3, v=80:300:20, tool=1|2")?;
        assert_eq!(s.len(), 3);
        assert_eq!(
            s[1].1,
            SpaceColumn::Range {
                lo: 80.0,
                hi: 300.0,
                step: Some(20.0)
            }
        );
        for bad in ["f", "f=3:1", "f=1:2:0", "tool=A|B", "f=1:2,f=2:3", ""] {
            assert!(parse_space(bad).is_err(), "{bad}");
        }
        Ok(())
    }

    #[test]
    fn candidates_stay_inside_the_space() -> Result<(), HybridError> {
        let s = parse_space("f=0.05:0.3,v=80:300:20,t=1|2")?;
        let c = candidates(&s, 7)?;
        assert_eq!(c.n_rows(), RANDOM_CANDIDATES);
        let col = |n: &str| c.column(n).map(<[f64]>::to_vec).unwrap_or_default();
        assert!(col("f").iter().all(|v| (0.05..=0.3).contains(v)));
        assert!(
            col("v")
                .iter()
                .all(|v| ((v - 80.0) / 20.0).fract().abs() < 1e-9 && *v <= 300.0)
        );
        assert!(col("t").iter().all(|v| *v == 1.0 || *v == 2.0));
        assert_eq!(candidates(&s, 7)?, c, "seeded");
        Ok(())
    }
}
