//! The one error type of `hxai-sim`.

/// Everything that can go wrong when simulating: all of it is a bad [`crate::SimConfig`],
/// found by [`crate::SimConfig::check`] before any work starts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// A parameter is outside its valid range.
    #[error("invalid simulator parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as in `SimConfig` (dotted for nested groups).
        name: &'static str,
        /// The offending value, printed.
        value: String,
        /// What the valid range is and how to mend the value.
        reason: String,
    },
    /// A list parameter (amplitudes or frequencies) is empty.
    #[error("`{name}` is empty: give at least one value")]
    EmptyList {
        /// The parameter's name.
        name: &'static str,
    },
    /// The requested data set would be too large to hold in memory.
    #[error(
        "{samples} samples per record is too many (limit {limit}): lower `duration_s` or `fs_hz`"
    )]
    TooLarge {
        /// Samples one record would hold (warm-up included, at the internal rate).
        samples: u64,
        /// The limit.
        limit: u64,
    },
    /// The colored-noise generator failed (an FFT error; should not happen for valid lengths).
    #[error("noise generation failed: {0}")]
    Noise(String),
    /// `hxai simulate --case` was given a name that is not a generator.
    #[error("unknown case `{name}` (known: {known})")]
    UnknownCase {
        /// The name asked for.
        name: String,
        /// The known case names, comma-separated.
        known: String,
    },
    /// A generated table broke the table's invariants (a non-finite value: a bug or an
    /// extreme configuration).
    #[error("generated table: {0}")]
    Table(#[from] hxai_table::TableError),
}
