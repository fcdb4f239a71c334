//! One column table for the whole workspace: named columns of finite `f64`.
//!
//! Every crate that handles a table of numbers (the samples of the tool case, a user's
//! process table, the inputs of symbolic regression, the baselines' design matrix, the
//! metrics' inputs) uses [`Table`], so data moves between crates without copies or
//! transposes, and a table checked once stays checked.
//!
//! # Invariants
//! A [`Table`] always has:
//! - at least one column; every column the same length (zero rows is allowed);
//! - unique, non-empty column names;
//! - only finite values (no NaN, no infinity).
//!
//! They are checked by the constructors and kept by every method, so code that receives a
//! `Table` never checks them again.
//!
//! # Design decision: column-major, owned, no dtype
//! Symbolic regression evaluates a program over whole columns, and the metrics, splits and
//! features all work column by column, so columns are stored as contiguous `Vec<f64>`.
//! An algorithm that needs rows (the tree and forest baselines, the lasso's coordinate
//! descent) makes its row-major copy inside itself, where the layout is an implementation
//! detail. Text columns (record ids in `samples.csv`) stay in `hxai-data`'s mixed table;
//! this crate knows nothing about files, so it compiles in a second.
//!
//! A [`TableView`] borrows a contiguous range of rows (a window, a fold of ordered rows)
//! and hands out column slices without copying; [`Table::select_rows`] copies an arbitrary
//! set of rows (a shuffled split).
//!
//! [`Par`] also lives here: the thread count a caller gives a parallel call of `symreg`,
//! `baselines` or `sim`, which all depend on this crate and on no common other.
//!
//! # Example
//! ```
//! use hxai_table::Table;
//! let t = Table::new(
//!     vec!["f".into(), "r".into()],
//!     vec![vec![0.1, 0.2, 0.3], vec![0.8, 0.8, 1.2]],
//! )?;
//! assert_eq!(t.n_rows(), 3);
//! assert_eq!(t.column("r"), Some(&[0.8, 0.8, 1.2][..]));
//! let head = t.view(0..2)?;
//! assert_eq!(head.column("f"), Some(&[0.1, 0.2][..]));
//! let picked = t.select_rows(&[2, 0])?;
//! assert_eq!(picked.column("f"), Some(&[0.3, 0.1][..]));
//! # Ok::<(), hxai_table::TableError>(())
//! ```
#![deny(missing_docs)]

mod par;
mod words;

pub use par::{Par, Pool};
use serde::{Deserialize, Serialize};
use std::ops::Range;
pub use words::plain_json_error;

/// What is wrong with the columns given to a [`Table`] constructor or method.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    /// A table needs at least one column.
    #[error("the table has no columns")]
    NoColumns,
    /// `names` and `columns` differ in length.
    #[error("{names} column names for {columns} columns")]
    NamesColumnsMismatch {
        /// Number of names.
        names: usize,
        /// Number of columns.
        columns: usize,
    },
    /// A column name is empty or only white space.
    #[error("column {index} has an empty name")]
    EmptyName {
        /// Position of the column (0-based).
        index: usize,
    },
    /// Two columns share a name.
    #[error("column name '{0}' appears more than once")]
    DuplicateName(String),
    /// A column's length differs from the first column's.
    #[error("column '{name}' has {got} rows, expected {expected}")]
    RaggedColumns {
        /// The column.
        name: String,
        /// Length of the first column.
        expected: usize,
        /// Length of this column.
        got: usize,
    },
    /// A value is NaN or infinite.
    #[error("column '{name}', row {row}: {value} is not a finite number")]
    NonFinite {
        /// The column.
        name: String,
        /// Row (0-based).
        row: usize,
        /// The value.
        value: f64,
    },
    /// A column asked for by name is not in the table.
    #[error("no column '{name}' (columns: {available})")]
    UnknownColumn {
        /// The name asked for.
        name: String,
        /// The table's columns, comma-separated.
        available: String,
    },
    /// A row index or range reaches past the table.
    #[error("row {row} is out of range for a table of {n_rows} rows")]
    RowOutOfRange {
        /// The first offending row (0-based), or a range's end.
        row: usize,
        /// Rows in the table.
        n_rows: usize,
    },
}

/// Named columns of finite `f64`, all of one length. See the [crate docs](crate) for the
/// invariants.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
    #[serde(skip)]
    n_rows: usize,
}

impl<'de> Deserialize<'de> for Table {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        struct Raw {
            names: Vec<String>,
            columns: Vec<Vec<f64>>,
        }
        let raw = Raw::deserialize(d)?;
        Table::new(raw.names, raw.columns).map_err(serde::de::Error::custom)
    }
}

impl Table {
    /// Builds a table from column names and columns of equal length.
    ///
    /// # Errors
    /// No columns, names/columns mismatch, an empty or duplicate name, ragged columns, or a
    /// NaN/infinite value (the first one, with its column and row).
    pub fn new(names: Vec<String>, columns: Vec<Vec<f64>>) -> Result<Self, TableError> {
        if columns.is_empty() {
            return Err(TableError::NoColumns);
        }
        if names.len() != columns.len() {
            return Err(TableError::NamesColumnsMismatch {
                names: names.len(),
                columns: columns.len(),
            });
        }
        for (index, n) in names.iter().enumerate() {
            check_name(&names[..index], n, index)?;
        }
        let n_rows = columns[0].len();
        for (name, col) in names.iter().zip(&columns) {
            check_column(name, col, n_rows)?;
        }
        Ok(Self {
            names,
            columns,
            n_rows,
        })
    }

    /// Builds a table from rows, each in the order of `names`.
    ///
    /// # Errors
    /// As [`Table::new`]; a row of the wrong length is reported as a ragged column.
    pub fn from_rows(names: Vec<String>, rows: &[Vec<f64>]) -> Result<Self, TableError> {
        let mut columns = vec![Vec::with_capacity(rows.len()); names.len()];
        for row in rows {
            if row.len() != names.len() {
                return Err(TableError::RaggedColumns {
                    name: format!("row of {} values", row.len()),
                    expected: names.len(),
                    got: row.len(),
                });
            }
            for (c, v) in row.iter().enumerate() {
                columns[c].push(*v);
            }
        }
        Self::new(names, columns)
    }

    /// Number of rows.
    pub fn n_rows(&self) -> usize {
        self.n_rows
    }

    /// Number of columns (at least 1).
    pub fn n_cols(&self) -> usize {
        self.columns.len()
    }

    /// Column names, in column order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// All columns, in the order of [`Table::names`].
    pub fn columns(&self) -> &[Vec<f64>] {
        &self.columns
    }

    /// The names and columns, giving up the table.
    pub fn into_parts(self) -> (Vec<String>, Vec<Vec<f64>>) {
        (self.names, self.columns)
    }

    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.index_of(name).map(|i| self.columns[i].as_slice())
    }

    /// The column called `name`, or an error that lists the table's columns.
    ///
    /// # Errors
    /// [`TableError::UnknownColumn`].
    pub fn require(&self, name: &str) -> Result<&[f64], TableError> {
        self.column(name).ok_or_else(|| self.unknown(name))
    }

    /// Index of the column called `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// One row, in column order.
    ///
    /// # Panics
    /// Never for `row < n_rows()`; out of range panics like slice indexing.
    pub fn row(&self, row: usize) -> Vec<f64> {
        self.columns.iter().map(|c| c[row]).collect()
    }

    /// The values in row-major order (`n_rows * n_cols`), for algorithms that walk rows.
    pub fn to_row_major(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.n_rows * self.n_cols());
        for r in 0..self.n_rows {
            out.extend(self.columns.iter().map(|c| c[r]));
        }
        out
    }

    /// A new table with the given rows, in the given order (repeats allowed).
    ///
    /// # Errors
    /// [`TableError::RowOutOfRange`] for an index `>= n_rows()`.
    pub fn select_rows(&self, rows: &[usize]) -> Result<Table, TableError> {
        if let Some(&row) = rows.iter().find(|&&r| r >= self.n_rows) {
            return Err(TableError::RowOutOfRange {
                row,
                n_rows: self.n_rows,
            });
        }
        let columns = self
            .columns
            .iter()
            .map(|c| rows.iter().map(|&r| c[r]).collect())
            .collect();
        Ok(Table {
            names: self.names.clone(),
            columns,
            n_rows: rows.len(),
        })
    }

    /// A new table with the named columns, in the given order.
    ///
    /// # Errors
    /// An unknown name, a name given twice, or no names.
    pub fn select_columns<S: AsRef<str>>(&self, names: &[S]) -> Result<Table, TableError> {
        let mut out_names = Vec::with_capacity(names.len());
        let mut columns = Vec::with_capacity(names.len());
        for n in names {
            let n = n.as_ref();
            let col = self.require(n)?;
            if out_names.iter().any(|o: &String| o == n) {
                return Err(TableError::DuplicateName(n.to_string()));
            }
            out_names.push(n.to_string());
            columns.push(col.to_vec());
        }
        if columns.is_empty() {
            return Err(TableError::NoColumns);
        }
        Ok(Table {
            names: out_names,
            columns,
            n_rows: self.n_rows,
        })
    }

    /// Adds a column at the end.
    ///
    /// # Errors
    /// An empty or existing name, a length other than `n_rows()`, or a non-finite value.
    pub fn push_column(&mut self, name: String, values: Vec<f64>) -> Result<(), TableError> {
        check_name(&self.names, &name, self.names.len())?;
        check_column(&name, &values, self.n_rows)?;
        self.names.push(name);
        self.columns.push(values);
        Ok(())
    }

    /// Removes the column called `name` and returns it.
    ///
    /// # Errors
    /// An unknown name, or the table's only column.
    pub fn remove_column(&mut self, name: &str) -> Result<Vec<f64>, TableError> {
        let i = self.index_of(name).ok_or_else(|| self.unknown(name))?;
        if self.columns.len() == 1 {
            return Err(TableError::NoColumns);
        }
        self.names.remove(i);
        Ok(self.columns.remove(i))
    }

    /// A borrowed view of the rows in `rows` (contiguous).
    ///
    /// # Errors
    /// [`TableError::RowOutOfRange`] when the range reaches past the table or is reversed.
    pub fn view(&self, rows: Range<usize>) -> Result<TableView<'_>, TableError> {
        if rows.start > rows.end || rows.end > self.n_rows {
            return Err(TableError::RowOutOfRange {
                row: rows.end.max(rows.start),
                n_rows: self.n_rows,
            });
        }
        Ok(TableView { table: self, rows })
    }

    /// A view of every row.
    pub fn as_view(&self) -> TableView<'_> {
        TableView {
            table: self,
            rows: 0..self.n_rows,
        }
    }

    fn unknown(&self, name: &str) -> TableError {
        TableError::UnknownColumn {
            name: name.to_string(),
            available: self.names.join(", "),
        }
    }
}

/// A contiguous range of a [`Table`]'s rows, borrowed: column slices without copies.
#[derive(Debug, Clone)]
pub struct TableView<'a> {
    table: &'a Table,
    rows: Range<usize>,
}

impl<'a> TableView<'a> {
    /// Number of rows in the view.
    pub fn n_rows(&self) -> usize {
        self.rows.end - self.rows.start
    }

    /// Number of columns.
    pub fn n_cols(&self) -> usize {
        self.table.n_cols()
    }

    /// Column names.
    pub fn names(&self) -> &'a [String] {
        self.table.names()
    }

    /// The rows of the underlying table this view covers.
    pub fn rows(&self) -> Range<usize> {
        self.rows.clone()
    }

    /// The slice of the column called `name` in this view's rows.
    pub fn column(&self, name: &str) -> Option<&'a [f64]> {
        let rows = self.rows.clone();
        self.table.column(name).map(|c| &c[rows])
    }

    /// The slice of column `index` in this view's rows.
    ///
    /// # Panics
    /// When `index >= n_cols()`, like slice indexing.
    pub fn column_at(&self, index: usize) -> &'a [f64] {
        &self.table.columns[index][self.rows.clone()]
    }

    /// Every column's slice, in column order.
    pub fn columns(&self) -> Vec<&'a [f64]> {
        (0..self.n_cols()).map(|i| self.column_at(i)).collect()
    }

    /// An owned copy of the view.
    pub fn to_table(&self) -> Table {
        Table {
            names: self.table.names.clone(),
            columns: self.columns().into_iter().map(<[f64]>::to_vec).collect(),
            n_rows: self.n_rows(),
        }
    }
}

fn check_name(earlier: &[String], name: &str, index: usize) -> Result<(), TableError> {
    if name.trim().is_empty() {
        return Err(TableError::EmptyName { index });
    }
    if earlier.iter().any(|n| n == name) {
        return Err(TableError::DuplicateName(name.to_string()));
    }
    Ok(())
}

fn check_column(name: &str, col: &[f64], n_rows: usize) -> Result<(), TableError> {
    if col.len() != n_rows {
        return Err(TableError::RaggedColumns {
            name: name.to_string(),
            expected: n_rows,
            got: col.len(),
        });
    }
    if let Some((row, &value)) = col.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(TableError::NonFinite {
            name: name.to_string(),
            row,
            value,
        });
    }
    Ok(())
}

/// A number for a message: at most 6 significant digits, exponent form outside 1e-4..1e6,
/// so that a value such as `1e300` is not printed as 301 digits.
///
/// ```
/// assert_eq!(hxai_table::format_number(1e300), "1e300");
/// assert_eq!(hxai_table::format_number(0.000123456789), "0.000123457");
/// assert_eq!(hxai_table::format_number(-2.5e-7), "-2.5e-7");
/// assert_eq!(hxai_table::format_number(12.5), "12.5");
/// assert_eq!(hxai_table::format_number(10000.0), "10000");
/// ```
pub fn format_number(v: f64) -> String {
    fn trim(s: &str) -> &str {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.')
        } else {
            s
        }
    }
    if v == 0.0 || !v.is_finite() {
        return v.to_string();
    }
    let a = v.abs();
    if (1e-4..1e6).contains(&a) {
        let d = (5 - a.log10().floor() as i32).clamp(0, 9) as usize;
        trim(&format!("{v:.d$}")).to_owned()
    } else {
        let s = format!("{v:.5e}");
        match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim(m)),
            None => s,
        }
    }
}
