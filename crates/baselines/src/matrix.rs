//! The checks every model runs on its input table, and the row-major copy the predictors
//! that walk rows (trees, forest, linear models) make of it.

use crate::BaselineError;
use hxai_table::Table;

/// A dense row-major copy of a [`Table`] (rows are samples, columns features), made inside
/// a model that walks rows; the public API takes [`Table`]s.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RowMajor {
    ncols: usize,
    data: Vec<f64>,
}

impl RowMajor {
    /// The rows of `x`, copied out.
    pub(crate) fn of(x: &Table) -> Self {
        Self {
            ncols: x.n_cols(),
            data: x.to_row_major(),
        }
    }

    /// Iterator over the rows.
    pub(crate) fn rows(&self) -> impl Iterator<Item = &[f64]> {
        self.data.chunks_exact(self.ncols.max(1))
    }
}

/// Checks `x` and `y` for fitting: rows present, one finite target per row (the table's
/// own invariants already guarantee finite features).
pub(crate) fn check_fit(x: &Table, y: &[f64]) -> Result<(), BaselineError> {
    check_x(x)?;
    if y.len() != x.n_rows() {
        return Err(BaselineError::LengthMismatch {
            rows: x.n_rows(),
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

/// Checks `x`: at least one row.
pub(crate) fn check_x(x: &Table) -> Result<(), BaselineError> {
    if x.n_rows() == 0 {
        return Err(BaselineError::Empty { what: "x" });
    }
    Ok(())
}

/// Checks `x` for prediction with a model fitted on `fitted` features (`None`: not fitted).
pub(crate) fn check_predict(
    name: &str,
    fitted: Option<usize>,
    x: &Table,
) -> Result<(), BaselineError> {
    let Some(fitted) = fitted else {
        return Err(BaselineError::NotFitted {
            model: name.to_string(),
        });
    };
    check_x(x)?;
    if x.n_cols() != fitted {
        return Err(BaselineError::FeatureCount {
            fitted,
            got: x.n_cols(),
        });
    }
    Ok(())
}
