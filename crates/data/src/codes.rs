//! Missing-value codes read as empty cells (`--missing-codes`, issue 52).
//!
//! Data loggers and file formats write a number where a value is missing: `-9999`, `-999`,
//! NetCDF's fill value `9.96921e36`. Read as a measurement, one such cell wrecks a
//! calibration without a word. The user may name the codes of their files once per process
//! ([`set_missing_codes`], the command line's global `--missing-codes`); every table and
//! record read afterwards has each numeric cell equal to a code emptied before any check,
//! so that `--missing refuse|drop|impute` decides what happens to it, as for a cell that
//! was empty in the file.
//!
//! "Equal" allows for the digits a code loses on the way: a cell matches a code `c` when it
//! is within `1e-6 * |c|` of it ([`CODE_TOLERANCE`]), so `9.96921e36` as written in a CSV
//! matches the float32 fill value `9.969209968386869e36` stored in a file, and `-9999.0`
//! matches `-9999`; a code `0` matches only `0`. A text cell that is not a number is never a
//! code. What was emptied is counted per column and kept as notes ([`take_missing_code_notes`])
//! for the command line to show.

use crate::cells::{RawColumn, RawTable, parse_number};
use std::path::Path;
use std::sync::{Mutex, OnceLock};

/// The relative distance within which a cell equals a missing-value code.
pub const CODE_TOLERANCE: f64 = 1e-6;

static CODES: OnceLock<Vec<f64>> = OnceLock::new();
static NOTES: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Sets the missing-value codes of every read of this process (the command line's
/// `--missing-codes`); once per process, before the first read. Returns `false` when they
/// were already set (the first setting stays).
///
/// # Errors
/// A code that is not a finite number (an empty cell or a `NaN` needs no code).
pub fn set_missing_codes(codes: Vec<f64>) -> Result<bool, String> {
    if let Some(bad) = codes.iter().find(|c| !c.is_finite()) {
        return Err(format!(
            "--missing-codes: {bad} is not a finite number (empty cells and NaN are already \
             missing; give the numbers your files write for a missing value, e.g. -9999)"
        ));
    }
    Ok(CODES.set(codes).is_ok())
}

/// The missing-value codes of this process ([`set_missing_codes`]; none by default).
pub fn missing_codes() -> &'static [f64] {
    CODES.get().map_or(&[], Vec::as_slice)
}

/// The notes of the cells emptied so far ("`file`: read N cell(s) of `col` equal to a
/// missing-value code as empty"), removed from the store: the caller shows each once.
pub fn take_missing_code_notes() -> Vec<String> {
    NOTES
        .lock()
        .map(|mut n| std::mem::take(&mut *n))
        .unwrap_or_default()
}

/// Whether `x` equals one of `codes` within [`CODE_TOLERANCE`].
pub(crate) fn is_code(x: f64, codes: &[f64]) -> bool {
    codes
        .iter()
        .any(|&c| (x - c).abs() <= CODE_TOLERANCE * c.abs() || x == c)
}

/// Empties the cells of `raw` equal to `codes`, returning `(column, count)` for each column
/// that had some.
fn blank(raw: &mut RawTable, codes: &[f64]) -> Vec<(String, usize)> {
    let mut out = Vec::new();
    for (name, col) in raw.names.iter().zip(raw.columns.iter_mut()) {
        let mut n = 0usize;
        match col {
            RawColumn::Num(v) => {
                for c in v.iter_mut() {
                    if c.is_some_and(|x| is_code(x, codes)) {
                        *c = None;
                        n += 1;
                    }
                }
            }
            RawColumn::Text(v) => {
                for c in v.iter_mut() {
                    if c.as_deref()
                        .and_then(parse_number)
                        .is_some_and(|x| is_code(x, codes))
                    {
                        *c = None;
                        n += 1;
                    }
                }
            }
        }
        if n > 0 {
            out.push((name.clone(), n));
        }
    }
    out
}

/// Empties the cells of `raw` (read from `path`) equal to this process's codes, and keeps a
/// note of what it did.
pub(crate) fn apply(path: &Path, raw: &mut RawTable) {
    let codes = missing_codes();
    if codes.is_empty() {
        return;
    }
    let done = blank(raw, codes);
    if done.is_empty() {
        return;
    }
    let total: usize = done.iter().map(|(_, n)| n).sum();
    let cols: Vec<String> = done.iter().map(|(c, n)| format!("`{c}` {n}")).collect();
    let note = format!(
        "{}: read {total} cell(s) equal to a --missing-codes value as empty ({}); --missing \
         decides what happens to them",
        path.display(),
        cols.join(", ")
    );
    if let Ok(mut notes) = NOTES.lock() {
        notes.push(note);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> RawTable {
        RawTable {
            names: vec!["a".into(), "b".into()],
            columns: vec![
                RawColumn::Text(vec![
                    Some("1.5".into()),
                    Some(" -9999 ".into()),
                    Some("-9999.5".into()),
                    None,
                    Some("n/a".into()),
                ]),
                RawColumn::Num(vec![
                    Some(9.969_209_968_386_869e36),
                    Some(2.0),
                    Some(-9999.0),
                    Some(0.0),
                    None,
                ]),
            ],
            integer_type: vec![None, None],
            skipped: 0,
        }
    }

    #[test]
    fn cells_equal_to_a_code_are_emptied_and_counted() {
        let mut raw = table();
        let done = blank(&mut raw, &[-9999.0, 9.96921e36]);
        assert_eq!(done, vec![("a".to_string(), 1), ("b".to_string(), 2)]);
        match (&raw.columns[0], &raw.columns[1]) {
            (RawColumn::Text(a), RawColumn::Num(b)) => {
                // -9999.5 is not within 1e-6 relative of -9999; a word is never a code
                assert_eq!(a[1], None);
                assert_eq!(a[2].as_deref(), Some("-9999.5"));
                assert_eq!(a[4].as_deref(), Some("n/a"));
                assert_eq!(b[0], None);
                assert_eq!(b[2], None);
                assert_eq!(b[3], Some(0.0));
            }
            _ => unreachable!("the columns keep their kinds"),
        }
    }

    #[test]
    fn a_zero_code_matches_only_zero() {
        assert!(is_code(0.0, &[0.0]));
        assert!(!is_code(1e-300, &[0.0]));
        assert!(is_code(-999.0005, &[-999.0]));
        assert!(!is_code(-999.01, &[-999.0]));
    }

    #[test]
    fn no_codes_changes_nothing() {
        let mut raw = table();
        assert!(blank(&mut raw, &[]).is_empty());
        assert!(matches!(&raw.columns[0], RawColumn::Text(a) if a[1].is_some()));
    }
}
