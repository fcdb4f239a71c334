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
    /// `A|B|C` with a level that is not a number: the levels of a text column (the class
    /// column of a model with constants per level), each drawn alike.
    Text(Vec<String>),
}

/// Seeded candidate settings: the numeric columns as a table, and the text columns' cells
/// (one level per row) beside it.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidates {
    /// The numeric columns.
    pub table: Table,
    /// Each text column and its cells, in the space's order.
    pub text: Vec<(String, Vec<String>)>,
}

/// Parses `col=lo:hi[:step],col=a|b` into `(column, SpaceColumn)` pairs.
///
/// # Errors
/// [`HybridError::InvalidConfig`] naming the part that is not `NAME=LO:HI[:STEP]` or
/// `NAME=A|B`, a range with `lo >= hi` or a step that is not positive, an empty level or
/// one given twice, or a column given twice. A list whose levels are all numbers is
/// [`SpaceColumn::Levels`], one with any other level [`SpaceColumn::Text`]; a single value
/// without `|` or `:` fixes the column there (`tool=A`, `depth=2`).
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
        if let Some((lo, hi)) = range_typo(value) {
            return Err(bad(
                part,
                &format!(
                    "looks like a range written with another separator: write {name}={lo}:{hi}"
                ),
            ));
        }
        let col = if value.contains('|') || !value.contains(':') {
            let words: Vec<&str> = value.split('|').map(str::trim).collect();
            if let Some(w) = words.iter().find(|w| w.is_empty()) {
                return Err(bad(part, &format!("has an empty level {w:?}")));
            }
            if let Some((i, w)) = words
                .iter()
                .enumerate()
                .find(|(i, w)| words[..*i].contains(w))
                .map(|(i, w)| (i, *w))
            {
                return Err(bad(
                    part,
                    &format!("gives the level {w:?} twice (level {})", i + 1),
                ));
            }
            match words.iter().map(|w| num(w)).collect::<Result<Vec<_>, _>>() {
                Ok(levels) => SpaceColumn::Levels(levels),
                // a level that parses as a number beside text ones stays text: `A|2`
                Err(_) => SpaceColumn::Text(words.iter().map(|w| (*w).to_string()).collect()),
            }
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

/// `(lo, hi)` when a single value (no `|`, no `:`) is two numbers joined by `-`, `..`, an
/// en dash or ` to ` (`45-89`, `45..89`), the usual ways to write a range elsewhere: read as
/// one text level it made the column text and the design refuse it by another name.
fn range_typo(value: &str) -> Option<(String, String)> {
    let v = value.trim();
    if v.contains('|') || v.contains(':') {
        return None;
    }
    let number = |s: &str| s.trim().parse::<f64>().is_ok_and(f64::is_finite);
    for sep in ["..", "\u{2013}", " to ", "-"] {
        for (at, _) in v.match_indices(sep) {
            let (a, b) = (&v[..at], &v[at + sep.len()..]);
            // the minus of a negative number or of an exponent is no separator
            if a.trim().is_empty() || a.ends_with(['e', 'E']) {
                continue;
            }
            if number(a) && number(b) {
                return Some((a.trim().to_string(), b.trim().to_string()));
            }
        }
    }
    None
}

/// [`RANDOM_CANDIDATES`] seeded random points of `space` (each column uniform over its
/// range, snapped to its step, or one of its levels, numbers or text alike).
///
/// # Errors
/// [`HybridError::InvalidConfig`] for a space of text columns only.
pub fn candidates(space: &[(String, SpaceColumn)], seed: u64) -> Result<Candidates, HybridError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut cols: Vec<Vec<f64>> = vec![Vec::with_capacity(RANDOM_CANDIDATES); space.len()];
    let mut cells: Vec<Vec<String>> = vec![Vec::new(); space.len()];
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
                SpaceColumn::Text(l) => {
                    cells[j].push(l[rng.gen_range(0..l.len())].clone());
                    continue;
                }
            };
            cols[j].push(v);
        }
    }
    let mut names = Vec::new();
    let mut numbers = Vec::new();
    let mut text = Vec::new();
    for (((name, c), col), cell) in space.iter().zip(cols).zip(cells) {
        if matches!(c, SpaceColumn::Text(_)) {
            text.push((name.clone(), cell));
        } else {
            names.push(name.clone());
            numbers.push(col);
        }
    }
    if names.is_empty() {
        return Err(HybridError::InvalidConfig(
            "--space: every column is text; a model reads at least one numeric column, so give \
             its range"
                .into(),
        ));
    }
    Ok(Candidates {
        table: Table::new(names, numbers)?,
        text,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A range written `45-89` (or `45..89`, `45 to 89`) is refused with how to write it
    /// (issue 63: it became a text level and the design refused `x1` by another name);
    /// negative numbers and exponents are not mistaken for one.
    #[test]
    fn a_range_typo_says_how_to_write_a_range() {
        for spec in [
            "hard=45-89",
            "hard=45..89",
            "hard=45 to 89",
            "hard = 45 - 89",
        ] {
            let e = parse_space(spec).expect_err(spec).to_string();
            assert!(e.contains("write hard=45:89"), "{spec}: {e}");
        }
        for ok in ["t=-5", "t=1e-3", "t=-5:-1", "t=-2|-1"] {
            assert!(parse_space(ok).is_ok(), "{ok}");
        }
    }

    #[test]
    fn spaces_parse_and_bad_ones_are_named() -> Result<(), HybridError> {
        let s = parse_space("f=0.05:0.3, v=80:300:20, tool=1|2, grade=P10|K20, depth=2")?;
        assert_eq!(s.len(), 5);
        assert_eq!(
            s[1].1,
            SpaceColumn::Range {
                lo: 80.0,
                hi: 300.0,
                step: Some(20.0)
            }
        );
        assert_eq!(s[2].1, SpaceColumn::Levels(vec![1.0, 2.0]));
        assert_eq!(s[3].1, SpaceColumn::Text(vec!["P10".into(), "K20".into()]));
        assert_eq!(s[4].1, SpaceColumn::Levels(vec![2.0]));
        // a text level beside a number keeps the list text; one word fixes a text column
        assert_eq!(
            parse_space("tool=A|2")?[0].1,
            SpaceColumn::Text(vec!["A".into(), "2".into()])
        );
        assert_eq!(
            parse_space("tool=A")?[0].1,
            SpaceColumn::Text(vec!["A".into()])
        );
        for bad in [
            "f",
            "f=3:1",
            "f=1:2:0",
            "f=1:2,f=2:3",
            "",
            "tool=A|",
            "tool=A||B",
            "tool=A|A",
            "f=a:2",
        ] {
            assert!(parse_space(bad).is_err(), "{bad}");
        }
        Ok(())
    }

    #[test]
    fn candidates_stay_inside_the_space() -> Result<(), HybridError> {
        let s = parse_space("f=0.05:0.3,v=80:300:20,t=1|2,tool=A|B|C")?;
        let c = candidates(&s, 7)?;
        assert_eq!(c.table.n_rows(), RANDOM_CANDIDATES);
        let col = |n: &str| c.table.column(n).map(<[f64]>::to_vec).unwrap_or_default();
        assert!(col("f").iter().all(|v| (0.05..=0.3).contains(v)));
        assert!(
            col("v")
                .iter()
                .all(|v| ((v - 80.0) / 20.0).fract().abs() < 1e-9 && *v <= 300.0)
        );
        assert!(col("t").iter().all(|v| *v == 1.0 || *v == 2.0));
        // the text column beside the numbers, every level drawn, nothing else
        assert_eq!(c.table.names(), ["f", "v", "t"]);
        assert_eq!(c.text.len(), 1);
        let (name, cells) = &c.text[0];
        assert_eq!(name, "tool");
        assert_eq!(cells.len(), RANDOM_CANDIDATES);
        for level in ["A", "B", "C"] {
            let k = cells.iter().filter(|c| *c == level).count();
            assert!(k > RANDOM_CANDIDATES / 4, "{level}: {k}");
        }
        assert!(cells.iter().all(|c| ["A", "B", "C"].contains(&c.as_str())));
        assert_eq!(candidates(&s, 7)?, c, "seeded");
        // a space of text only has no numeric column to build the candidates on
        assert!(candidates(&parse_space("tool=A|B")?, 7).is_err());
        Ok(())
    }
}
