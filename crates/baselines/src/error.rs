//! The one error type of `hxai-baselines`.

/// Everything that can go wrong when fitting or applying a baseline model.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BaselineError {
    /// A feature table or target has no rows.
    #[error("{what} is empty: pass at least one row and one feature column")]
    Empty {
        /// Which input.
        what: &'static str,
    },
    /// A feature table could not be built or sliced (ragged, a missing column, a row out
    /// of range, a non-finite value).
    #[error("feature table: {0}")]
    Table(#[from] hxai_table::TableError),
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
    /// A row index of a split is out of range for the targets.
    #[error("row index {index} is out of range for {nrows} rows")]
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
    /// A model of a comparison failed; `source` says how.
    #[error("model `{model}`: {source}")]
    Model {
        /// The model's name.
        model: String,
        /// What went wrong.
        source: Box<BaselineError>,
    },
}
