//! What the composer reads and makes, window by window: one record as input, the latent
//! variables of a periodic response (paper eq. 8) and one window's sample (its features and
//! latent variables). The composer ([`super::composer`]) and the warnings about its input
//! ([`super::warnings`]) both read them.

use crate::HybridError;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::ops::Range;

/// The latent variables of a periodic response at a known frequency `f`:
/// `x(t) ~ offset + amplitude * sin(2 pi f t + phase)` (paper eq. 8), `t = i / fs` counted
/// from the first sample of the piece that was decomposed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Latent {
    /// Peak amplitude (the latent variable that is corrected).
    pub amplitude: f64,
    /// Phase, radians.
    pub phase: f64,
    /// Constant offset.
    pub offset: f64,
}

impl Latent {
    /// The latent-variable decomposition (LVD, eq. 8-11): the latent variables of `x`
    /// (sampled at `fs`) at frequency `frequency_hz`, by [`hxai_signal::fit_sine`] (least
    /// squares at the known frequency).
    ///
    /// # Errors
    /// Those of the sine fit.
    pub fn fit(x: &[f64], fs: f64, frequency_hz: f64) -> Result<Self, HybridError> {
        let f = hxai_signal::fit_sine(x, fs, frequency_hz)?;
        Ok(Latent {
            amplitude: f.amplitude,
            phase: f.phase,
            offset: f.offset,
        })
    }

    /// The reconstruction: the sine `offset + amplitude * sin(2 pi f (start + i) / fs +
    /// phase)` for `i = 0..n`; `start` may be negative or beyond the decomposed piece to
    /// extend it.
    pub fn sine(&self, fs: f64, frequency_hz: f64, start: i64, n: usize) -> Vec<f64> {
        let w = 2.0 * PI * frequency_hz / fs;
        (0..n)
            .map(|i| {
                let k = (start + i as i64) as f64;
                self.offset + self.amplitude * (w * k + self.phase).sin()
            })
            .collect()
    }
}

/// One record as the composer sees it (no files: the caller reads them).
#[derive(Debug, Clone, Copy)]
pub struct RecordInput<'a> {
    /// Record id.
    pub id: &'a str,
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// Known frequency of the periodic response (the commanded frequency), Hz.
    pub frequency_hz: f64,
    /// Measured signal the physics model and the features use (acceleration).
    pub signal: &'a [f64],
    /// Ground truth in the physics model's output unit (probe position), if recorded.
    pub truth: Option<&'a [f64]>,
}

/// One sample: a window of a record with its features and latent variables.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindowSample {
    /// Record id.
    pub record: String,
    /// Window index within the record, from 0.
    pub window: usize,
    /// Sample indices of the window within the record.
    pub range: Range<usize>,
    /// Features of the measured signal in the window.
    pub features: Vec<f64>,
    /// Latent variables of the physics prediction in the window.
    pub physics: Latent,
    /// Latent variables of the ground truth minus its window mean, when there is a truth.
    pub truth: Option<Latent>,
}

impl WindowSample {
    /// `A_phys`, the physics model's amplitude.
    pub fn a_phys(&self) -> f64 {
        self.physics.amplitude
    }

    /// `A_true`, the ground truth's amplitude, if known.
    pub fn a_true(&self) -> Option<f64> {
        self.truth.map(|t| t.amplitude)
    }

    /// `delta = A_true - A_phys` (eq. 9), if the truth is known.
    pub fn delta(&self) -> Option<f64> {
        self.a_true().map(|a| a - self.a_phys())
    }
}
