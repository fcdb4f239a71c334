//! A small row-major feature matrix.

use crate::BaselineError;

/// A dense, row-major `nrows x ncols` matrix of `f64` (rows are samples, columns features).
#[derive(Debug, Clone, PartialEq)]
pub struct Matrix {
    nrows: usize,
    ncols: usize,
    data: Vec<f64>,
}

impl Matrix {
    /// Wraps row-major `data` of length `nrows * ncols`.
    ///
    /// # Errors
    /// [`BaselineError::Shape`] when the length does not match.
    pub fn new(nrows: usize, ncols: usize, data: Vec<f64>) -> Result<Self, BaselineError> {
        if nrows.checked_mul(ncols) != Some(data.len()) {
            return Err(BaselineError::Shape {
                detail: format!(
                    "{nrows} x {ncols} needs {} values, got {}",
                    nrows * ncols,
                    data.len()
                ),
            });
        }
        Ok(Self { nrows, ncols, data })
    }

    /// Builds a matrix from rows of equal length.
    ///
    /// # Errors
    /// [`BaselineError::Shape`] for ragged rows.
    pub fn from_rows(rows: &[Vec<f64>]) -> Result<Self, BaselineError> {
        let ncols = rows.first().map_or(0, Vec::len);
        let mut data = Vec::with_capacity(rows.len() * ncols);
        for (i, r) in rows.iter().enumerate() {
            if r.len() != ncols {
                return Err(BaselineError::Shape {
                    detail: format!("row {i} has {} values, row 0 has {ncols}", r.len()),
                });
            }
            data.extend_from_slice(r);
        }
        Self::new(rows.len(), ncols, data)
    }

    /// Builds a matrix from feature columns of equal length (e.g. a table's columns).
    ///
    /// # Errors
    /// [`BaselineError::Shape`] for columns of different lengths.
    pub fn from_columns(columns: &[Vec<f64>]) -> Result<Self, BaselineError> {
        let nrows = columns.first().map_or(0, Vec::len);
        if let Some((j, c)) = columns.iter().enumerate().find(|(_, c)| c.len() != nrows) {
            return Err(BaselineError::Shape {
                detail: format!("column {j} has {} values, column 0 has {nrows}", c.len()),
            });
        }
        let ncols = columns.len();
        let mut data = vec![0.0; nrows * ncols];
        for (j, c) in columns.iter().enumerate() {
            for (i, v) in c.iter().enumerate() {
                data[i * ncols + j] = *v;
            }
        }
        Self::new(nrows, ncols, data)
    }

    /// Number of rows (samples).
    pub fn nrows(&self) -> usize {
        self.nrows
    }

    /// Number of columns (features).
    pub fn ncols(&self) -> usize {
        self.ncols
    }

    /// Row `i`, or `None` when out of range.
    pub fn row(&self, i: usize) -> Option<&[f64]> {
        (i < self.nrows).then(|| &self.data[i * self.ncols..(i + 1) * self.ncols])
    }

    /// Iterator over the rows.
    pub fn rows(&self) -> impl Iterator<Item = &[f64]> {
        self.data.chunks_exact(self.ncols.max(1)).take(self.nrows)
    }

    /// Element `(i, j)`, or `None` when out of range.
    pub fn get(&self, i: usize, j: usize) -> Option<f64> {
        (i < self.nrows && j < self.ncols).then(|| self.data[i * self.ncols + j])
    }

    /// The row-major data.
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }

    /// Column `j` copied out, or `None` when out of range.
    pub fn column(&self, j: usize) -> Option<Vec<f64>> {
        (j < self.ncols).then(|| self.rows().map(|r| r[j]).collect())
    }

    /// All columns copied out (column-major view of the data).
    pub fn columns(&self) -> Vec<Vec<f64>> {
        (0..self.ncols)
            .map(|j| self.rows().map(|r| r[j]).collect())
            .collect()
    }

    /// A new matrix of the given rows, in the given order (e.g. one side of a split).
    ///
    /// # Errors
    /// [`BaselineError::RowIndex`] for an index out of range.
    pub fn select_rows(&self, indices: &[usize]) -> Result<Matrix, BaselineError> {
        let mut data = Vec::with_capacity(indices.len() * self.ncols);
        for &i in indices {
            match self.row(i) {
                Some(r) => data.extend_from_slice(r),
                None => {
                    return Err(BaselineError::RowIndex {
                        index: i,
                        nrows: self.nrows,
                    });
                }
            }
        }
        Matrix::new(indices.len(), self.ncols, data)
    }
}

/// Checks `x` and `y` for fitting: non-empty, matching lengths, finite.
pub(crate) fn check_fit(x: &Matrix, y: &[f64]) -> Result<(), BaselineError> {
    check_x(x)?;
    if y.len() != x.nrows() {
        return Err(BaselineError::LengthMismatch {
            rows: x.nrows(),
            targets: y.len(),
        });
    }
    if let Some(row) = y.iter().position(|v| !v.is_finite()) {
        return Err(BaselineError::NonFinite {
            what: "y",
            row,
            col: 0,
            value: y[row],
        });
    }
    Ok(())
}

/// Checks `x`: non-empty and finite.
pub(crate) fn check_x(x: &Matrix) -> Result<(), BaselineError> {
    if x.nrows() == 0 || x.ncols() == 0 {
        return Err(BaselineError::Empty { what: "x" });
    }
    if let Some(k) = x.as_slice().iter().position(|v| !v.is_finite()) {
        return Err(BaselineError::NonFinite {
            what: "x",
            row: k / x.ncols(),
            col: k % x.ncols(),
            value: x.as_slice()[k],
        });
    }
    Ok(())
}

/// Checks `x` for prediction with a model fitted on `fitted` features (`None`: not fitted).
pub(crate) fn check_predict(
    name: &str,
    fitted: Option<usize>,
    x: &Matrix,
) -> Result<(), BaselineError> {
    let Some(fitted) = fitted else {
        return Err(BaselineError::NotFitted {
            model: name.to_string(),
        });
    };
    check_x(x)?;
    if x.ncols() != fitted {
        return Err(BaselineError::FeatureCount {
            fitted,
            got: x.ncols(),
        });
    }
    Ok(())
}
