//! The one error type of the crate.
use thiserror::Error;

/// Everything that can go wrong in symbolic regression. Every message says what is wrong
/// and how to mend it.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SrError {
    /// The input table is malformed (no columns, duplicate or empty names, ragged or
    /// non-finite columns, an unknown column).
    #[error(transparent)]
    Table(#[from] hxai_table::TableError),
    /// A value is NaN or infinite.
    #[error(
        "column `{name}` row {row} is {value}: remove or impute non-finite values before symbolic regression"
    )]
    NonFinite {
        /// Column name (or `target`).
        name: String,
        /// Row index (0-based).
        row: usize,
        /// The offending value.
        value: f64,
    },
    /// Target and data have different numbers of rows.
    #[error(
        "the target has {target} rows but the data set has {data}: pass one target value per row"
    )]
    TargetLength {
        /// Target rows.
        target: usize,
        /// Data rows.
        data: usize,
    },
    /// The target does not vary.
    #[error("the target is constant ({}): symbolic regression needs a target that varies", hxai_table::format_number(*.0))]
    ConstantTarget(f64),
    /// Too few rows.
    #[error(
        "too few rows ({rows}): need at least {needed} (more than the parameters of the largest model)"
    )]
    TooFewRows {
        /// Rows given.
        rows: usize,
        /// Rows needed.
        needed: usize,
    },
    /// An operator name is not known.
    #[error(
        "unknown operator `{0}`: choose from add sub mul div exp log sqrt square inverse sin cos tanh abs gaussian gaussian2"
    )]
    UnknownOperator(String),
    /// A column the model needs is missing from the data.
    #[error("the model needs column `{0}` but the data set has no such column")]
    UnknownColumn(String),
    /// A configuration value is out of range.
    #[error("invalid configuration: {0}")]
    InvalidConfig(String),
    /// The search found no model with finite loss.
    #[error(
        "no candidate model had a finite loss on the training data: check the data scale or allow more operators"
    )]
    NoModel,
    /// A saved model is malformed.
    #[error("malformed model: {0}")]
    MalformedModel(String),
    /// An equation's text does not parse ([`crate::infix`]).
    #[error("character {position}: {message}")]
    Parse {
        /// 1-based character position.
        position: usize,
        /// What is wrong there.
        message: String,
    },
    /// An equation uses a name that is neither an input nor a known constant.
    #[error("unknown symbol `{name}` at character {position}")]
    UnknownSymbol {
        /// The name.
        name: String,
        /// 1-based character position of its first use.
        position: usize,
    },
}
