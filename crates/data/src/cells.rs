//! A file's cells as read ([`RawTable`], filled by the reader in `raw`), and turning them
//! into checked numbers, with errors that name row and column.

use crate::DataError;
use std::path::Path;

/// One column as read from a file.
#[derive(Debug, Clone)]
pub(crate) enum RawColumn {
    /// Numeric cells (Parquet numeric types); `None` is a null.
    Num(Vec<Option<f64>>),
    /// Cells as text (CSV, or Parquet text columns); `None` is an empty cell / null.
    Text(Vec<Option<String>>),
}

impl RawColumn {
    /// Removes the first cell (a units row read ahead of the numbers).
    pub(crate) fn drop_first(&mut self) {
        match self {
            RawColumn::Num(v) if !v.is_empty() => {
                v.remove(0);
            }
            RawColumn::Text(v) if !v.is_empty() => {
                v.remove(0);
            }
            _ => {}
        }
    }

    fn len(&self) -> usize {
        match self {
            RawColumn::Num(v) => v.len(),
            RawColumn::Text(v) => v.len(),
        }
    }
}

/// A file's columns before any checking.
#[derive(Debug, Clone)]
pub(crate) struct RawTable {
    pub names: Vec<String>,
    pub columns: Vec<RawColumn>,
    /// For each column stored as integers (Parquet), the type's name; `None` otherwise.
    pub integer_type: Vec<Option<String>>,
    /// Blank lines and all-empty rows of a CSV, skipped.
    pub skipped: usize,
}

impl RawTable {
    pub fn height(&self) -> usize {
        self.columns.first().map_or(0, RawColumn::len)
    }

    pub fn find(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
}

/// Parses one text cell as a number; `None` when it is not one.
pub(crate) fn parse_number(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok()
}

/// The column `name` as finite numbers, or the first bad cell as an error.
pub(crate) fn finite_column(
    path: &Path,
    raw: &RawTable,
    index: usize,
) -> Result<Vec<f64>, DataError> {
    let name = &raw.names[index];
    let mut out = Vec::with_capacity(raw.height());
    match &raw.columns[index] {
        RawColumn::Num(cells) => {
            for (i, c) in cells.iter().enumerate() {
                let v = c.ok_or_else(|| missing(path, i, name))?;
                out.push(check_finite(path, i, name, v)?);
            }
        }
        RawColumn::Text(cells) => {
            for (i, c) in cells.iter().enumerate() {
                let s = match c.as_deref().map(str::trim) {
                    None | Some("") => return Err(missing(path, i, name)),
                    Some(s) => s,
                };
                let v = parse_number(s).ok_or_else(|| DataError::NonNumeric {
                    path: path.to_path_buf(),
                    row: i + 1,
                    column: name.clone(),
                    value: s.to_owned(),
                })?;
                out.push(check_finite(path, i, name, v)?);
            }
        }
    }
    Ok(out)
}

/// The column as text cells (numbers printed back in shortest round-trip form).
pub(crate) fn text_column(raw: &RawTable, index: usize) -> Vec<String> {
    match &raw.columns[index] {
        RawColumn::Num(cells) => cells
            .iter()
            .map(|c| c.map(|v| v.to_string()).unwrap_or_default())
            .collect(),
        RawColumn::Text(cells) => cells
            .iter()
            .map(|c| c.as_deref().unwrap_or("").to_owned())
            .collect(),
    }
}

/// Whether every cell of the column is present and parses as a number.
pub(crate) fn is_numeric(raw: &RawTable, index: usize) -> bool {
    match &raw.columns[index] {
        RawColumn::Num(cells) => cells.iter().all(Option::is_some),
        RawColumn::Text(cells) => cells
            .iter()
            .all(|c| c.as_deref().and_then(parse_number).is_some()),
    }
}

fn missing(path: &Path, i: usize, name: &str) -> DataError {
    DataError::MissingValue {
        path: path.to_path_buf(),
        row: i + 1,
        column: name.to_owned(),
    }
}

fn check_finite(path: &Path, i: usize, name: &str, v: f64) -> Result<f64, DataError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(DataError::NonFinite {
            path: path.to_path_buf(),
            row: i + 1,
            column: name.to_owned(),
            value: v,
        })
    }
}

/// Checks that every value of an in-memory column is finite (before writing).
pub(crate) fn check_all_finite(path: &Path, name: &str, values: &[f64]) -> Result<(), DataError> {
    for (i, &v) in values.iter().enumerate() {
        check_finite(path, i, name, v)?;
    }
    Ok(())
}

/// Requires the file to have at least one data row.
pub(crate) fn require_rows(path: &Path, raw: &RawTable) -> Result<(), DataError> {
    if raw.height() == 0 {
        return Err(DataError::Empty {
            path: path.to_path_buf(),
            header_only: !raw.names.is_empty(),
        });
    }
    Ok(())
}

/// Index of a required column.
pub(crate) fn require_column(path: &Path, raw: &RawTable, name: &str) -> Result<usize, DataError> {
    raw.find(name).ok_or_else(|| DataError::MissingColumn {
        path: path.to_path_buf(),
        column: name.to_owned(),
        found: raw.names.clone(),
    })
}
