//! The one error type of `hxai-eval`.

/// Everything that can go wrong when scoring, splitting or testing.
///
/// Each message says what was wrong with the input and how to mend it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EvalError {
    /// No samples were given.
    #[error("{what} is empty: pass at least {need} value(s)")]
    Empty {
        /// Which input was empty.
        what: &'static str,
        /// How many values are needed at least.
        need: usize,
    },
    /// Two inputs that must be paired have different lengths.
    #[error("{what}: lengths differ ({left} vs {right}); pass one value per sample on both sides")]
    LengthMismatch {
        /// Which pair of inputs.
        what: &'static str,
        /// Length of the first input.
        left: usize,
        /// Length of the second input.
        right: usize,
    },
    /// A value is NaN or infinite.
    #[error("{what}[{index}] is {}: remove or impute non-finite values first", hxai_table::format_number(*.value))]
    NonFinite {
        /// Which input.
        what: &'static str,
        /// Position of the first bad value.
        index: usize,
        /// The bad value.
        value: f64,
    },
    /// A fraction or level is outside the open interval (0, 1).
    #[error("{what} must lie strictly between 0 and 1, got {}", hxai_table::format_number(*.value))]
    FractionOutOfRange {
        /// Which parameter.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// The split would leave one side empty.
    #[error(
        "splitting {n} {unit} with test fraction {} leaves an empty side; \
         use more {unit} or a test fraction nearer 0.5",
        hxai_table::format_number(*.test_fraction)
    )]
    EmptySide {
        /// Number of samples or groups.
        n: usize,
        /// "samples" or "groups".
        unit: &'static str,
        /// The test fraction given.
        test_fraction: f64,
    },
    /// Fewer than two folds were asked for.
    #[error("k-fold needs k >= 2, got k = {k}")]
    TooFewFolds {
        /// The k given.
        k: usize,
    },
    /// More folds than samples (or groups).
    #[error("cannot make {k} folds from {n} {unit}: use k <= {n}")]
    TooManyFolds {
        /// The k given.
        k: usize,
        /// Number of samples or groups.
        n: usize,
        /// "samples" or "groups".
        unit: &'static str,
    },
    /// A value that must be positive is not.
    #[error("{what} must be positive, got {}", hxai_table::format_number(*.value))]
    NonPositive {
        /// Which parameter.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// Too few conformal scores for a finite interval at the level asked for.
    #[error(
        "{n} calibration score(s) cannot give a finite conformal interval at level {}: \
         it needs at least {need} (more rows, fewer folds, or a lower level)",
        hxai_table::format_number(*.level)
    )]
    TooFewScores {
        /// Scores given.
        n: usize,
        /// The level asked for.
        level: f64,
        /// The fewest scores that give a finite interval at this level.
        need: usize,
    },
    /// A paired t-test whose differences are all exactly zero has no defined statistic.
    #[error("the two error vectors are identical: the paired t-test is undefined (0/0)")]
    IdenticalSamples,
}
