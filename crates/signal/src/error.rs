//! The one error type of `hxai-signal`.

use thiserror::Error;

/// Everything that can go wrong in `hxai-signal`. Every message says what is wrong and how
/// to mend it.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SignalError {
    /// The input signal holds no samples.
    #[error("the input signal `{what}` is empty; pass at least one sample")]
    Empty {
        /// Which input was empty.
        what: &'static str,
    },
    /// The input is too short for the operation (for example the padding of `filtfilt`).
    #[error(
        "the input has {len} samples but {operation} needs more than {needed}; use a longer record or a lower filter order"
    )]
    TooShort {
        /// Number of samples given.
        len: usize,
        /// The input must be longer than this.
        needed: usize,
        /// What needed the samples.
        operation: &'static str,
    },
    /// A sample is NaN or infinite.
    #[error(
        "the input `{what}` holds a non-finite value (NaN or infinity) at index {index}; clean or interpolate the record first"
    )]
    NonFinite {
        /// Which input.
        what: &'static str,
        /// Index of the first bad sample.
        index: usize,
    },
    /// The sampling rate is not a positive finite number.
    #[error("the sampling rate must be a positive finite number of Hz, got {}", hxai_table::format_number(*.fs))]
    InvalidSampleRate {
        /// The rate given.
        fs: f64,
    },
    /// A cutoff frequency is not inside (0, fs/2).
    #[error(
        "the cutoff frequency {} Hz must lie strictly between 0 and the Nyquist frequency {} Hz; choose a cutoff inside that range or record at a higher rate",
        hxai_table::format_number(*.cutoff),
        hxai_table::format_number(*.nyquist)
    )]
    InvalidCutoff {
        /// The cutoff given.
        cutoff: f64,
        /// Half the sampling rate.
        nyquist: f64,
    },
    /// A band's lower edge is not below its upper edge.
    #[error(
        "the band's lower edge {} Hz must be below its upper edge {} Hz; swap or widen them",
        hxai_table::format_number(*.low),
        hxai_table::format_number(*.high)
    )]
    InvalidBand {
        /// Lower edge given.
        low: f64,
        /// Upper edge given.
        high: f64,
    },
    /// Filter order 0 was requested.
    #[error("the filter order must be at least 1")]
    ZeroOrder,
    /// A filter order above [`crate::MAX_ORDER`] was requested.
    #[error("the filter order {order} is too high; at most {max} is supported (typical: 2 to 8)")]
    OrderTooHigh {
        /// The order requested.
        order: usize,
        /// The highest order supported.
        max: usize,
    },
    /// A filter section is unusable (a0 = 0 or non-finite coefficients).
    #[error("filter section {index} is invalid: {reason}")]
    InvalidSection {
        /// Index of the section.
        index: usize,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The frequency given to a sine fit lies outside (0, fs/2).
    #[error(
        "the sine frequency {} Hz must lie strictly between 0 and the Nyquist frequency {} Hz",
        hxai_table::format_number(*.freq),
        hxai_table::format_number(*.nyquist)
    )]
    InvalidFrequency {
        /// The frequency given.
        freq: f64,
        /// Half the sampling rate.
        nyquist: f64,
    },
    /// A least-squares system could not be solved (for example a constant or too-short signal).
    #[error(
        "the least-squares problem is singular: {0}; use a longer record spanning at least one period"
    )]
    Singular(&'static str),
    /// An iteration did not converge.
    #[error(
        "{what} did not converge within {iterations} iterations; give a better starting frequency or a longer record"
    )]
    NoConvergence {
        /// Which iteration.
        what: &'static str,
        /// Iterations spent.
        iterations: usize,
    },
    /// A configuration value is invalid.
    #[error("invalid configuration: {0}")]
    InvalidConfig(String),
}

/// Returns the first non-finite sample as an error.
pub(crate) fn check_finite(x: &[f64], what: &'static str) -> Result<(), SignalError> {
    match x.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(SignalError::NonFinite { what, index }),
        None => Ok(()),
    }
}

/// Checks that `x` is non-empty and finite.
pub(crate) fn check_signal(x: &[f64], what: &'static str) -> Result<(), SignalError> {
    if x.is_empty() {
        return Err(SignalError::Empty { what });
    }
    check_finite(x, what)
}

/// Checks a sampling rate.
pub(crate) fn check_fs(fs: f64) -> Result<(), SignalError> {
    if fs.is_finite() && fs > 0.0 {
        Ok(())
    } else {
        Err(SignalError::InvalidSampleRate { fs })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Numbers in messages have at most 6 significant digits: a rate read from time stamps
    /// (`1 / 0.0005` in floating point) is printed as the user knows it.
    #[test]
    fn messages_print_numbers_short() {
        let fs = 1.0 / (0.1 * 0.005);
        let e = SignalError::InvalidCutoff {
            cutoff: 0.1 + 0.2,
            nyquist: fs / 2.0,
        };
        assert_eq!(
            e.to_string(),
            "the cutoff frequency 0.3 Hz must lie strictly between 0 and the Nyquist frequency \
             1000 Hz; choose a cutoff inside that range or record at a higher rate"
        );
        let band = SignalError::InvalidBand {
            low: 100.00000000000001,
            high: 10.0,
        };
        assert!(
            band.to_string()
                .contains("lower edge 100 Hz must be below its upper edge 10 Hz")
        );
        let e = crate::butter(4, crate::Band::Bandpass(1.0, 2.0), -0.1 - 0.2)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(e.ends_with("got -0.3"), "{e}");
    }
}
