//! Generic tables: numeric ones (inputs of `hxai sr` and `hxai compare`, outputs such as
//! `time_s,displacement_um`) and mixed ones with text columns (such as `samples.csv`).

use crate::cells::{check_all_finite, finite_column, is_numeric, require_rows, text_column};
use crate::raw::{self, OutColumn};
use crate::{DataError, Format};
use std::path::Path;

/// A table of numbers: one name per column, all columns equally long.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// Column names.
    pub names: Vec<String>,
    /// Columns, in the order of `names`.
    pub columns: Vec<Vec<f64>>,
}

impl Table {
    /// The column with the given name.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| self.columns[i].as_slice())
    }

    /// Number of rows (0 for a table without columns).
    pub fn height(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }
}

/// One column of a [`MixedTable`].
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    /// Finite numbers.
    Number(Vec<f64>),
    /// Text cells (empty string for an empty cell).
    Text(Vec<String>),
}

impl Column {
    /// Number of cells.
    pub fn len(&self) -> usize {
        match self {
            Column::Number(v) => v.len(),
            Column::Text(v) => v.len(),
        }
    }

    /// Whether the column has no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A table whose columns are numbers or text.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MixedTable {
    /// Column names.
    pub names: Vec<String>,
    /// Columns, in the order of `names`.
    pub columns: Vec<Column>,
}

impl MixedTable {
    /// The numeric columns as a [`Table`], and the names of the text columns left out.
    pub fn numeric(&self) -> (Table, Vec<String>) {
        let mut t = Table::default();
        let mut skipped = Vec::new();
        for (n, c) in self.names.iter().zip(&self.columns) {
            match c {
                Column::Number(v) => {
                    t.names.push(n.clone());
                    t.columns.push(v.clone());
                }
                Column::Text(_) => skipped.push(n.clone()),
            }
        }
        (t, skipped)
    }
}

/// Reads a table whose every cell is a finite number; CSV or Parquet by extension.
/// The first bad cell is reported with its row and column.
pub fn read_table(path: &Path) -> Result<Table, DataError> {
    let format = Format::from_path(path)?;
    let raw = raw::read(path, format)?;
    require_rows(path, &raw)?;
    let columns = (0..raw.names.len())
        .map(|i| finite_column(path, &raw, i))
        .collect::<Result<_, _>>()?;
    Ok(Table {
        names: raw.names,
        columns,
    })
}

/// Reads a table whose columns may be text. A column is numeric when every cell parses
/// as a number; numeric columns must be finite (NaN or infinity is an error naming row
/// and column), every other column is kept as text.
pub fn read_mixed_table(path: &Path) -> Result<MixedTable, DataError> {
    let format = Format::from_path(path)?;
    let raw = raw::read(path, format)?;
    require_rows(path, &raw)?;
    let mut columns = Vec::with_capacity(raw.names.len());
    for i in 0..raw.names.len() {
        columns.push(if is_numeric(&raw, i) {
            Column::Number(finite_column(path, &raw, i)?)
        } else {
            Column::Text(text_column(&raw, i))
        });
    }
    Ok(MixedTable {
        names: raw.names,
        columns,
    })
}

fn check_shape<'a>(
    path: &Path,
    names: &[String],
    lens: impl Iterator<Item = usize> + 'a,
    n_cols: usize,
) -> Result<(), DataError> {
    if names.len() != n_cols {
        return Err(DataError::NamesMismatch {
            path: path.to_path_buf(),
            names: names.len(),
            columns: n_cols,
        });
    }
    let lens: Vec<usize> = lens.collect();
    if let Some(&first) = lens.first() {
        for (i, &l) in lens.iter().enumerate() {
            if l != first {
                return Err(DataError::LengthMismatch {
                    path: path.to_path_buf(),
                    column: names[i].clone(),
                    len: l,
                    reference: names[0].clone(),
                    expected: first,
                });
            }
        }
    }
    for (i, n) in names.iter().enumerate() {
        if names[..i].contains(n) {
            return Err(DataError::DuplicateColumn {
                path: path.to_path_buf(),
                column: n.clone(),
            });
        }
    }
    Ok(())
}

/// Writes a numeric table; CSV or Parquet by extension. Values must be finite.
pub fn write_table(path: &Path, table: &Table) -> Result<(), DataError> {
    let format = Format::from_path(path)?;
    check_shape(
        path,
        &table.names,
        table.columns.iter().map(Vec::len),
        table.columns.len(),
    )?;
    for (n, c) in table.names.iter().zip(&table.columns) {
        check_all_finite(path, n, c)?;
    }
    let cols: Vec<OutColumn<'_>> = table.columns.iter().map(|c| OutColumn::Num(c)).collect();
    raw::write(path, format, &table.names, &cols)
}

/// Writes a mixed table; CSV or Parquet by extension. Numeric values must be finite.
pub fn write_mixed_table(path: &Path, table: &MixedTable) -> Result<(), DataError> {
    let format = Format::from_path(path)?;
    check_shape(
        path,
        &table.names,
        table.columns.iter().map(Column::len),
        table.columns.len(),
    )?;
    let cols: Vec<OutColumn<'_>> = table
        .names
        .iter()
        .zip(&table.columns)
        .map(|(n, c)| match c {
            Column::Number(v) => check_all_finite(path, n, v).map(|()| OutColumn::Num(v)),
            Column::Text(v) => Ok(OutColumn::Text(v)),
        })
        .collect::<Result<_, _>>()?;
    raw::write(path, format, &table.names, &cols)
}
