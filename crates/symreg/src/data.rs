//! Column-major data sets.
use crate::SrError;

/// A table of named input columns, stored column-major (one `Vec<f64>` per feature), all
/// values finite.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    names: Vec<String>,
    columns: Vec<Vec<f64>>,
    n_rows: usize,
}

impl Dataset {
    /// Builds a data set from column names and columns of equal length.
    ///
    /// # Errors
    /// No columns, names/columns mismatch, duplicate or empty names, ragged columns, or a
    /// NaN/infinite value.
    pub fn new(names: Vec<String>, columns: Vec<Vec<f64>>) -> Result<Self, SrError> {
        if columns.is_empty() {
            return Err(SrError::NoColumns);
        }
        if names.len() != columns.len() {
            return Err(SrError::NamesColumnsMismatch {
                names: names.len(),
                columns: columns.len(),
            });
        }
        for (i, n) in names.iter().enumerate() {
            if n.trim().is_empty() {
                return Err(SrError::EmptyName(i));
            }
            if names[..i].contains(n) {
                return Err(SrError::DuplicateName(n.clone()));
            }
        }
        let n_rows = columns[0].len();
        for (name, col) in names.iter().zip(&columns) {
            if col.len() != n_rows {
                return Err(SrError::RaggedColumns {
                    name: name.clone(),
                    expected: n_rows,
                    got: col.len(),
                });
            }
            if let Some((row, &value)) = col.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(SrError::NonFinite {
                    name: name.clone(),
                    row,
                    value,
                });
            }
        }
        Ok(Self {
            names,
            columns,
            n_rows,
        })
    }

    /// Number of rows.
    pub fn n_rows(&self) -> usize {
        self.n_rows
    }

    /// Number of columns.
    pub fn n_cols(&self) -> usize {
        self.columns.len()
    }

    /// Column names.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// All columns.
    pub fn columns(&self) -> &[Vec<f64>] {
        &self.columns
    }

    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.index_of(name).map(|i| self.columns[i].as_slice())
    }

    /// Index of the column called `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// A new data set with the given rows (in the given order).
    pub fn select_rows(&self, rows: &[usize]) -> Dataset {
        let columns = self
            .columns
            .iter()
            .map(|c| rows.iter().map(|&r| c[r]).collect())
            .collect();
        Dataset {
            names: self.names.clone(),
            columns,
            n_rows: rows.len(),
        }
    }
}
