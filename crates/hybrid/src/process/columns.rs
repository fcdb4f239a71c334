//! Which of a table's text columns a table hybrid can do without, and which it cannot.
//!
//! A table reader gives the numeric columns as a [`Table`](hxai_symreg::Table) and the
//! text columns apart, with their cells (`hxai_data::NumericView`). The fit sees only the
//! numbers, where a needed column that held text would be reported as missing. This module
//! judges the text columns against the configuration first: a column the model names (the
//! target, `features`, `extrapolate`, the physics) must be numbers; a column of numbers with
//! an empty cell is a gap in the data, named by its row, not text; a real text column that
//! would have been a default feature is left out with a warning instead of in silence.

use super::ProcessConfig;
use crate::HybridError;

/// Checks the text columns of a table (each with its cells, rows in file order) against
/// `cfg`, and returns the warnings for those left out of the correction's features.
///
/// # Errors
/// [`HybridError::InvalidConfig`]: a column the model uses, or a default feature, holds
/// numbers with an empty cell (the row is named, counted from 1 as the file shows it); a
/// column the model names holds text or true/false values.
pub fn check_text_columns(
    cfg: &ProcessConfig,
    text: &[(String, Vec<String>)],
) -> Result<Vec<String>, HybridError> {
    let mut named: Vec<String> = vec![cfg.target.clone()];
    named.extend(cfg.features.iter().flatten().cloned());
    named.extend(cfg.extrapolate.iter().cloned());
    if let Ok(p) = hxai_symreg::infix::parse(&cfg.physics) {
        named.extend(p.names().into_iter().map(str::to_string));
    }
    let default_feature = |n: &str| {
        cfg.features.is_none()
            && !cfg.exclude.iter().any(|e| e.trim() == n)
            && cfg.group.as_deref() != Some(n)
    };
    let mut left_out = Vec::new();
    for (n, cells) in text {
        if !named.contains(n) && !default_feature(n) {
            continue;
        }
        let numbers_with_gaps = cells
            .iter()
            .all(|v| v.trim().is_empty() || v.trim().parse::<f64>().is_ok());
        if numbers_with_gaps && let Some(row) = cells.iter().position(|v| v.trim().is_empty()) {
            return Err(HybridError::InvalidConfig(format!(
                "row {}, column `{n}`: the cell is empty; hxai hybrid needs a number in every row \
                 of a column it uses (fill it, remove the row, or --exclude {n})",
                row + 1
            )));
        }
        // true/false (a Parquet boolean, or such words in a CSV) is not text to a reader
        let flags = cells.iter().all(|v| {
            let t = v.trim();
            t.is_empty() || t.eq_ignore_ascii_case("true") || t.eq_ignore_ascii_case("false")
        });
        let holds = if flags {
            "true/false values (write them as 1/0 to use them)"
        } else {
            "text"
        };
        if named.contains(n) {
            return Err(HybridError::InvalidConfig(format!(
                "column `{n}` holds {holds}, not numbers: hxai hybrid needs numeric columns \
                 (text is allowed only in the --group column)"
            )));
        }
        left_out.push(format!(
            "column `{n}` holds {holds} and is left out of the correction's features (--exclude {n} to say so)"
        ));
    }
    Ok(left_out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cells(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| (*s).to_string()).collect()
    }

    #[test]
    fn gaps_text_and_flags_are_told_apart() {
        let cfg = ProcessConfig::new("y", "k*x");
        let gap = vec![("v".to_string(), cells(&["1", "2", " ", "4"]))];
        let e = check_text_columns(&cfg, &gap).err().map(|e| e.to_string());
        assert!(
            e.as_deref().is_some_and(|e| e.contains("row 3, column `v`: the cell is empty")),
            "{e:?}"
        );
        let words = vec![
            ("batch".to_string(), cells(&["a", "b"])),
            ("coolant".to_string(), cells(&["true", "FALSE"])),
        ];
        let w = check_text_columns(&cfg, &words).unwrap_or_default();
        assert_eq!(w.len(), 2);
        assert!(w[0].starts_with("column `batch` holds text and is left out"));
        assert!(w[1].starts_with("column `coolant` holds true/false values"));
        // excluded, or not a default feature: no word
        let mut quiet = cfg.clone();
        quiet.exclude = vec!["batch".into(), "coolant".into()];
        assert_eq!(check_text_columns(&quiet, &words).ok(), Some(vec![]));
        // named by the physics: refused
        let named = ProcessConfig::new("y", "k*batch");
        let e = check_text_columns(&named, &words).err().map(|e| e.to_string());
        assert!(e.is_some_and(|e| e.contains("column `batch` holds text, not numbers")));
    }
}
