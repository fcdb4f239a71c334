//! The one error type of `hxai-baselines`.

/// Everything that can go wrong when fitting or applying a baseline model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BaselineError {
    /// A matrix or target has no rows or no columns.
    #[error("{what} is empty: pass at least one row and one feature column")]
    Empty {
        /// Which input.
        what: &'static str,
    },
    /// The data of a matrix does not fill `nrows x ncols`, or rows/columns are ragged.
    #[error("matrix shape: {detail}")]
    Shape {
        /// What does not fit.
        detail: String,
    },
    /// Feature rows and target values differ in number.
    #[error("x has {rows} rows but y has {targets} values; pass one target per row")]
    LengthMismatch {
        /// Rows of x.
        rows: usize,
        /// Values in y.
        targets: usize,
    },
    /// A NaN or infinite value in the input.
    #[error(
        "{what} has a non-finite value ({value}) at row {row}, column {col}; remove or impute it first"
    )]
    NonFinite {
        /// "x" or "y".
        what: &'static str,
        /// Row of the first bad value.
        row: usize,
        /// Column of the first bad value (0 for y).
        col: usize,
        /// The value.
        value: f64,
    },
    /// `predict` was called before a successful `fit`.
    #[error("model `{model}` is not fitted: call fit first")]
    NotFitted {
        /// Model name.
        model: String,
    },
    /// `predict` got a different number of features than `fit`.
    #[error(
        "model was fitted on {fitted} features but got {got}; pass the same columns in the same order"
    )]
    FeatureCount {
        /// Features at fit time.
        fitted: usize,
        /// Features now.
        got: usize,
    },
    /// A hyper-parameter is out of range, or the data are too small for it.
    #[error("invalid parameter {what}: {detail}")]
    InvalidParameter {
        /// Which parameter.
        what: &'static str,
        /// Why it is invalid and how to mend it.
        detail: String,
    },
    /// A row index passed to [`crate::Matrix::select_rows`] is out of range.
    #[error("row index {index} is out of range for a matrix with {nrows} rows")]
    RowIndex {
        /// The index.
        index: usize,
        /// Number of rows.
        nrows: usize,
    },
    /// A numerical routine failed (e.g. the SVD did not converge).
    #[error("numerical failure in {what}: {detail}")]
    Numerical {
        /// Which routine.
        what: &'static str,
        /// Detail.
        detail: String,
    },
    /// Splitting or scoring failed.
    #[error(transparent)]
    Eval(#[from] hxai_eval::EvalError),
    /// The symbolic-regression engine failed.
    #[error("symbolic regression: {0}")]
    Symbolic(String),
}
