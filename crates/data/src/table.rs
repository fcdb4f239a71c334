//! Generic tables: numeric ones ([`hxai_table::Table`]) (inputs of `hxai sr` and `hxai compare`, outputs such as
//! `time_s,displacement_um`) and mixed ones with text columns (such as `samples.csv`).

use crate::cells::{check_all_finite, finite_column, is_numeric, require_rows, text_column};
use crate::raw::{self, OutColumn};
use crate::{DataError, Format};
use hxai_table::Table;
use std::path::Path;

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
    /// Blank lines and all-empty rows of the CSV that were skipped (0 for Parquet).
    pub skipped_rows: usize,
}

/// What a model sees of a [`MixedTable`]: its numeric columns, a group column whatever it
/// holds, and the text columns left out, each with its cells (so that a caller can tell a
/// column of numbers with a gap from real text, and name the row).
#[derive(Debug, Clone, PartialEq)]
pub struct NumericView {
    /// The numeric columns, in file order, and the group column as numbers (a text group
    /// numbered 0, 1, ... in order of first appearance).
    pub table: Table,
    /// The group column's cells as read, for outputs that repeat it (`hybrid predict`).
    pub group_cells: Option<Column>,
    /// Text columns left out (the group column excepted), with their cells.
    pub text: Vec<(String, Vec<String>)>,
}

impl MixedTable {
    /// The numeric columns as a [`Table`], and the names of the text columns left out.
    ///
    /// # Errors
    /// As [`MixedTable::numeric_view`].
    pub fn numeric(&self) -> Result<(Table, Vec<String>), hxai_table::TableError> {
        let view = self.numeric_view(None)?;
        Ok((view.table, view.text.into_iter().map(|(n, _)| n).collect()))
    }

    /// The numeric view of the table for a model whose rows may be grouped by the column
    /// `group` (see [`NumericView`]).
    ///
    /// # Errors
    /// [`hxai_table::TableError`] when there is no numeric column or the numeric columns
    /// break a table invariant (ragged, a duplicate name, a non-finite value).
    pub fn numeric_view(&self, group: Option<&str>) -> Result<NumericView, hxai_table::TableError> {
        let (mut names, mut columns, mut text) = (Vec::new(), Vec::new(), Vec::new());
        let mut group_cells = None;
        for (n, c) in self.names.iter().zip(&self.columns) {
            let is_group = Some(n.as_str()) == group;
            if is_group {
                group_cells = Some(c.clone());
            }
            match c {
                Column::Number(v) => {
                    names.push(n.clone());
                    columns.push(v.clone());
                }
                Column::Text(cells) if is_group => {
                    let mut ids: std::collections::HashMap<&str, usize> =
                        std::collections::HashMap::new();
                    let codes = cells
                        .iter()
                        .map(|s| {
                            let next = ids.len();
                            *ids.entry(s.as_str()).or_insert(next) as f64
                        })
                        .collect();
                    names.push(n.clone());
                    columns.push(codes);
                }
                Column::Text(cells) => text.push((n.clone(), cells.clone())),
            }
        }
        Ok(NumericView {
            table: Table::new(names, columns)?,
            group_cells,
            text,
        })
    }

    /// Appends the column `name`.
    pub fn push(&mut self, name: &str, column: Column) {
        self.names.push(name.to_owned());
        self.columns.push(column);
    }

    /// Appends every column of `table`, as numbers, in its order.
    pub fn push_table(&mut self, table: Table) {
        let (names, columns) = table.into_parts();
        self.names.extend(names);
        self.columns.extend(columns.into_iter().map(Column::Number));
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
    Table::new(raw.names, columns).map_err(|source| DataError::Table {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads a CSV table whose first row under the header holds each column's unit (`m`, `kg`,
/// `m/s^2`, `1` for a dimensionless column: the units of `hxai sr --units`) and whose other
/// cells are finite numbers; returns the table of those rows and the units, by column.
/// Rows named in errors are counted from the first row of numbers.
///
/// # Errors
/// [`DataError::UnitsRow`] for a Parquet file (its columns are typed, so it has no units
/// row) or an empty unit cell, naming the column; [`DataError::Empty`] when no row of
/// numbers follows; and those of [`read_table`] for the numbers.
pub fn read_table_with_units(path: &Path) -> Result<(Table, Vec<String>), DataError> {
    let format = Format::from_path(path)?;
    if format == Format::Parquet {
        return Err(DataError::UnitsRow {
            path: path.to_path_buf(),
            reason: "a Parquet file types its columns and has none: give the units as \
                     COLUMN=UNIT pairs instead"
                .into(),
        });
    }
    let mut raw = raw::read(path, format)?;
    require_rows(path, &raw)?;
    let mut units = Vec::with_capacity(raw.names.len());
    for i in 0..raw.names.len() {
        let unit = text_column(&raw, i).swap_remove(0).trim().to_owned();
        if unit.is_empty() {
            return Err(DataError::UnitsRow {
                path: path.to_path_buf(),
                reason: format!(
                    "column `{}` has no unit (write `1` for a dimensionless column)",
                    raw.names[i]
                ),
            });
        }
        units.push(unit);
        raw.columns[i].drop_first();
    }
    if units
        .iter()
        .all(|u| u != "1" && crate::cells::parse_number(u).is_some())
    {
        return Err(DataError::UnitsRow {
            path: path.to_path_buf(),
            reason: format!(
                "it holds numbers ({}): the table has no units row",
                units.join(", ")
            ),
        });
    }
    require_rows(path, &raw)?;
    let columns = (0..raw.names.len())
        .map(|i| finite_column(path, &raw, i))
        .collect::<Result<_, _>>()?;
    let table = Table::new(raw.names, columns).map_err(|source| DataError::Table {
        path: path.to_path_buf(),
        source,
    })?;
    Ok((table, units))
}

/// Reads a table whose columns may be text. A column is numeric when every cell parses
/// as a finite number; every other column is kept as text, including a column of numbers
/// with a NaN, an infinity or an overflow such as `1e400` (a caller that uses the column
/// refuses it naming row and cell; one that does not, ignores it).
pub fn read_mixed_table(path: &Path) -> Result<MixedTable, DataError> {
    let format = Format::from_path(path)?;
    let raw = raw::read(path, format)?;
    require_rows(path, &raw)?;
    let mut columns = Vec::with_capacity(raw.names.len());
    for i in 0..raw.names.len() {
        columns.push(if is_numeric(&raw, i) {
            match finite_column(path, &raw, i) {
                Ok(v) => Column::Number(v),
                // numbers, but one is NaN, infinite or 1e400: kept as text, so that a column
                // the caller does not use (excluded, or the target at prediction) costs
                // nothing, and one it uses is refused by the caller, naming row and cell
                Err(DataError::NonFinite { .. }) => Column::Text(text_column(&raw, i)),
                Err(e) => return Err(e),
            }
        } else {
            Column::Text(text_column(&raw, i))
        });
    }
    Ok(MixedTable {
        names: raw.names,
        columns,
        skipped_rows: raw.skipped,
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

/// Writes a numeric table; CSV or Parquet by extension. A [`Table`] is rectangular,
/// uniquely named and finite by construction, so only the file can fail.
pub fn write_table(path: &Path, table: &Table) -> Result<(), DataError> {
    stage_table(path, table)?.commit()
}

/// [`write_table`] staged, not committed (see [`crate::stage`]): a command renames it into
/// place once its report on stdout is printed.
pub fn stage_table(path: &Path, table: &Table) -> Result<crate::AtomicFile, DataError> {
    let format = Format::from_path(path)?;
    let cols: Vec<OutColumn<'_>> = table.columns().iter().map(|c| OutColumn::Num(c)).collect();
    raw::stage(path, format, table.names(), &cols)
}

/// Writes a mixed table; CSV or Parquet by extension. Numeric values must be finite.
pub fn write_mixed_table(path: &Path, table: &MixedTable) -> Result<(), DataError> {
    stage_mixed_table(path, table)?.commit()
}

/// [`write_mixed_table`] staged, not committed (see [`crate::stage`]).
pub fn stage_mixed_table(path: &Path, table: &MixedTable) -> Result<crate::AtomicFile, DataError> {
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
    raw::stage(path, format, &table.names, &cols)
}
