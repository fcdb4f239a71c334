//! Cutting records into the windows that become samples.

use crate::HybridError;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// How a record is cut into samples.
///
/// Defaults: discard 0.25 s at each end, then consecutive, non-overlapping 0.5 s windows
/// (a trailing remainder shorter than a window is not used). The ends are discarded because
/// the physics model's zero-phase band-pass (`filtfilt`) and the drift removal after each
/// integration distort the first and last few tenths of a second of a record (filter edge
/// transients); a sample taken there would measure the filter, not the machine. 0.5 s holds
/// five periods at the lowest command frequency (10 Hz), enough for a stable sine fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowConfig {
    /// Window length, s (default 0.5).
    pub length_s: f64,
    /// Time discarded at each end of a record, s (default 0.25).
    pub discard_s: f64,
}

impl Default for WindowConfig {
    fn default() -> Self {
        Self {
            length_s: 0.5,
            discard_s: 0.25,
        }
    }
}

/// Longest window or discarded time accepted, s (one million seconds, about 11.6 days):
/// far beyond any recording, and small enough that sample counts cannot overflow.
pub const MAX_WINDOW_SECONDS: f64 = 1e6;

impl WindowConfig {
    /// Checks the settings: a positive, finite length and a non-negative, finite discard,
    /// both at most [`MAX_WINDOW_SECONDS`].
    pub fn check(&self) -> Result<(), HybridError> {
        if !(self.length_s.is_finite()
            && self.length_s > 0.0
            && self.length_s <= MAX_WINDOW_SECONDS)
        {
            return Err(HybridError::InvalidConfig(format!(
                "the window length must be a positive number of seconds up to {MAX_WINDOW_SECONDS:e}, got {}",
                crate::error::num(self.length_s)
            )));
        }
        if !(self.discard_s.is_finite()
            && self.discard_s >= 0.0
            && self.discard_s <= MAX_WINDOW_SECONDS)
        {
            return Err(HybridError::InvalidConfig(format!(
                "the time discarded at each record end must be 0 to {MAX_WINDOW_SECONDS:e} seconds, got {}",
                crate::error::num(self.discard_s)
            )));
        }
        Ok(())
    }

    /// Window length in samples at rate `fs` (rounded, at least 1).
    pub fn length_samples(&self, fs: f64) -> usize {
        ((self.length_s * fs).round() as usize).max(1)
    }

    /// Samples discarded at each end at rate `fs` (rounded).
    pub fn discard_samples(&self, fs: f64) -> usize {
        (self.discard_s * fs).round() as usize
    }

    /// The windows of a record of `n` samples at rate `fs`, as index ranges, in time order.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] for bad settings, [`HybridError::RecordTooShort`] when
    /// not even one window fits (the error names `record`).
    pub fn windows(
        &self,
        n: usize,
        fs: f64,
        record: &str,
    ) -> Result<Vec<Range<usize>>, HybridError> {
        self.check()?;
        if !(fs.is_finite() && fs > 0.0) {
            return Err(HybridError::InvalidConfig(format!(
                "sampling rate must be positive, got {}",
                crate::error::num(fs)
            )));
        }
        // Counted in f64 first: a window of 1e6 s at 1 GHz does not fit in any record, and
        // must say so rather than overflow.
        let too_short = || HybridError::RecordTooShort {
            record: record.to_owned(),
            seconds: n as f64 / fs,
            needed_s: 2.0 * self.discard_s + self.length_s,
            window_s: self.length_s,
            discard_s: self.discard_s,
        };
        let (len_f, skip_f) = (
            (self.length_s * fs).round().max(1.0),
            (self.discard_s * fs).round(),
        );
        if 2.0 * skip_f + len_f > n as f64 {
            return Err(too_short());
        }
        let len = self.length_samples(fs);
        let skip = self.discard_samples(fs);
        let usable = n.saturating_sub(skip.saturating_mul(2));
        let count = usable / len;
        if count == 0 {
            return Err(HybridError::RecordTooShort {
                record: record.to_owned(),
                seconds: n as f64 / fs,
                needed_s: (2 * skip + len) as f64 / fs,
                window_s: self.length_s,
                discard_s: self.discard_s,
            });
        }
        Ok((0..count)
            .map(|k| skip + k * len..skip + (k + 1) * len)
            .collect())
    }
}
