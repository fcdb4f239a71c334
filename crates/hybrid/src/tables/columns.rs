//! Which of a table's text columns a table hybrid can do without, and which it cannot.
//!
//! A table reader gives the numeric columns as a [`Table`](hxai_symreg::Table) and the
//! text columns apart, with their cells (`hxai_data::NumericView`). The fit sees only the
//! numbers, where a needed column that held text would be reported as missing. This module
//! judges the text columns against the configuration first: a column the model names (the
//! target, `features`, `extrapolate`, the physics) must be numbers; a column of numbers with
//! a bad cell (empty, or a typo such as `12O.5`) is named by its row, not taken for text; a real text column that
//! would have been a default feature is left out with a warning instead of in silence.

use super::TableConfig;
use crate::HybridError;

/// The first cell of a text column that is not a number, as an error naming its row
/// (counted from 1 as the file shows it) and content, when the column is numbers but for a
/// few cells (more than half of its non-empty cells are numbers): a gap (`""`) or a typo
/// (`12O.5`) in a column of numbers, which a reader that must choose one type per column
/// reads as text. `None` for a column of real text.
fn bad_cell(name: &str, cells: &[String], excludable: bool) -> Option<HybridError> {
    let filled = cells.iter().filter(|v| !v.trim().is_empty()).count();
    let numbers = cells
        .iter()
        .filter(|v| v.trim().parse::<f64>().is_ok_and(f64::is_finite))
        .count();
    if numbers == 0 || 2 * numbers <= filled {
        return None;
    }
    let (row, cell) = cells
        .iter()
        .enumerate()
        .find(|(_, v)| !v.trim().parse::<f64>().is_ok_and(f64::is_finite))?;
    let or_exclude = if excludable {
        format!(", or --exclude {name}")
    } else {
        String::new()
    };
    if cell.trim().is_empty() {
        let empty = cells.iter().filter(|v| v.trim().is_empty()).count();
        return Some(HybridError::NoData(format!(
            "row {}, column `{name}`: the cell is empty ({empty} empty cell(s) in the column); \
             hxai refuses empty cells by default: choose --missing drop (drop the rows with \
             an empty cell) or --missing impute (fill a feature's empty cells with its \
             training median){or_exclude}",
            row + 1
        )));
    }
    let what = format!("`{}` is not a number", cell.trim());
    Some(HybridError::NoData(format!(
        "row {}, column `{name}`: {what}; hxai hybrid needs a number in every row of a column \
         it uses (mend the cell or remove the row{or_exclude})",
        row + 1
    )))
}

/// What a text column holds, for a message: true/false values (a Parquet boolean, or such
/// words in a CSV), with how to use them, or text.
fn holds(cells: &[String]) -> &'static str {
    let flags = cells.iter().all(|v| {
        let t = v.trim();
        t.is_empty() || t.eq_ignore_ascii_case("true") || t.eq_ignore_ascii_case("false")
    });
    if flags {
        "true/false values (write them as 1/0 to use them)"
    } else if cells.iter().any(|v| !v.trim().is_empty())
        && cells
            .iter()
            .all(|v| v.trim().is_empty() || decimal_comma(v).is_some())
    {
        "numbers written with a decimal comma (`1.234,5` for 1234.5): write them with a \
         decimal point and no thousands separator (save the CSV from a spreadsheet set to an \
         English locale, or convert the column)"
    } else {
        "text"
    }
}

/// The value of a number written the European way, a decimal comma with an optional
/// thousands separator (`1.234,5`, `1 234,5`, `12,5`, `-0,25`); `None` for anything else.
fn decimal_comma(cell: &str) -> Option<f64> {
    let t = cell.trim();
    let (int, frac) = t.split_once(',')?;
    let digits = |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_digit());
    if !digits(frac) {
        return None;
    }
    let int = int.strip_prefix('-').unwrap_or(int);
    let groups: Vec<&str> = int.split(['.', ' ', '\u{a0}']).collect();
    let grouped = groups.len() > 1;
    let ok = groups.iter().enumerate().all(|(i, g)| {
        digits(g) && (!grouped || i == 0 || g.len() == 3) && (!grouped || i > 0 || g.len() <= 3)
    });
    if !ok {
        return None;
    }
    format!(
        "{}{}.{frac}",
        if t.starts_with('-') { "-" } else { "" },
        groups.concat()
    )
    .parse()
    .ok()
}

/// Refuses a text column among `used` (the columns a model reads): a column of numbers
/// with a bad cell (more than half of its cells are numbers) is named by its row and cell,
/// another by what it holds.
///
/// # Errors
/// [`HybridError::NoData`] for the first such column.
pub fn check_used_columns(
    used: &[String],
    text: &[(String, Vec<String>)],
) -> Result<(), HybridError> {
    if let Some((n, cells)) = text.iter().find(|(n, _)| used.contains(n)) {
        if let Some(e) = bad_cell(n, cells, false) {
            return Err(e);
        }
        let holds = holds(cells);
        let example = cells
            .iter()
            .enumerate()
            .find(|(_, v)| !v.trim().is_empty())
            .map(|(i, v)| format!(" (row {}: `{}`)", i + 1, v.trim()))
            .unwrap_or_default();
        if holds.starts_with("numbers written") {
            return Err(HybridError::NoData(format!(
                "column `{n}` holds {holds}{example}"
            )));
        }
        return Err(HybridError::NoData(format!(
            "column `{n}` holds {holds}{example}, not numbers: hxai hybrid needs numeric columns \
             (text is allowed only in the --group column)"
        )));
    }
    Ok(())
}

/// The first column of `text` that is numbers but for a few bad cells (a gap, a typo, a
/// header repeated mid-file), as the error naming its row and cell; `None` when every text
/// column is real text.
pub fn first_bad_cell(text: &[(String, Vec<String>)]) -> Option<HybridError> {
    text.iter().find_map(|(n, cells)| bad_cell(n, cells, false))
}

/// Checks the text columns of a table (each with its cells, rows in file order) against
/// `cfg`, and returns the warnings for those left out of the correction's features.
///
/// # Errors
/// [`HybridError::NoData`]: a column the model names (target, features,
/// extrapolation column, physics) holds text, or a column the model uses or would take as a
/// default feature is numbers with a bad cell (a gap or a typo: the row and cell are named).
pub fn check_text_columns(
    cfg: &TableConfig,
    text: &[(String, Vec<String>)],
) -> Result<Vec<String>, HybridError> {
    let mut named: Vec<String> = vec![cfg.target.clone()];
    named.extend(cfg.features.iter().flatten().cloned());
    named.extend(cfg.extrapolate.iter().cloned());
    if let Ok((p, _)) = hxai_symreg::infix::parse_with_slots(&cfg.physics) {
        named.extend(p.names().into_iter().map(str::to_string));
    }
    check_used_columns(&named, text)?;
    let default_feature = |n: &str| {
        cfg.features.is_none()
            && !cfg.exclude.iter().any(|e| e.trim() == n)
            && cfg.group.as_deref() != Some(n)
    };
    let mut left_out = Vec::new();
    for (n, cells) in text.iter().filter(|(n, _)| default_feature(n)) {
        if let Some(e) = bad_cell(n, cells, true) {
            return Err(e);
        }
        let holds = holds(cells);
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
        let cfg = TableConfig::new("y", "k*x");
        let gap = vec![("v".to_string(), cells(&["1", "2", " ", "4"]))];
        let e = check_text_columns(&cfg, &gap).err().map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|e| e.contains("row 3, column `v`: the cell is empty")),
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
        // named by the physics: refused, with a cell shown
        let named = TableConfig::new("y", "k*batch");
        let e = check_text_columns(&named, &words)
            .err()
            .map(|e| e.to_string());
        assert!(
            e.as_deref()
                .is_some_and(|e| e.contains("column `batch` holds text (row 1: `a`), not numbers")),
            "{e:?}"
        );
        // numbers with a decimal comma are named as such, with how to write them
        let euro = vec![(
            "x".to_string(),
            cells(&["1.234,5", "2.345,1", "-0,25", "12 345,0"]),
        )];
        let e = check_text_columns(&TableConfig::new("y", "k*x"), &euro)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(
            e.contains("decimal comma") && e.contains("decimal point"),
            "{e}"
        );
        assert_eq!(decimal_comma("1.234,5"), Some(1234.5));
        assert_eq!(decimal_comma("-0,25"), Some(-0.25));
        assert_eq!(decimal_comma("12.34,5"), None);
        assert_eq!(decimal_comma("abc"), None);
        // a typo in a column of numbers is named by row and cell, used or not
        let typo = vec![("v".to_string(), cells(&["120.5", "12O.5", "130", "140"]))];
        for cfg in [TableConfig::new("y", "k*x"), TableConfig::new("y", "k*v")] {
            let e = check_text_columns(&cfg, &typo).err().map(|e| e.to_string());
            assert!(
                e.as_deref()
                    .is_some_and(|e| e.contains("row 2, column `v`: `12O.5` is not a number")),
                "{e:?}"
            );
        }
        // a text column with a few numbers is still text
        let ids = vec![("lot".to_string(), cells(&["A1", "B2", "7"]))];
        assert_eq!(
            check_text_columns(&cfg, &ids).map(|w| w.len()).ok(),
            Some(1)
        );
    }
}
