//! The four parts of a hybrid model, as traits (paper section 2, steps 1-4).

use crate::HybridError;
use hxai_table::Table;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Step 1, the physics model `f_p`: a measured signal in, a physical prediction out
/// (same length, same sampling).
pub trait PhysicsModel {
    /// Short name for reports.
    fn name(&self) -> String;
    /// The physical prediction for the whole `signal` sampled at `fs` Hz.
    fn predict(&self, signal: &[f64], fs: f64) -> Result<Vec<f64>, HybridError>;
}

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
    /// The sine `offset + amplitude * sin(2 pi f (start + i) / fs + phase)` for
    /// `i = 0..n`; `start` may be negative or beyond the decomposed piece to extend it.
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

/// The latent-variable decomposition (LVD, eq. 8-11): a signal to its latent variables at
/// a known frequency, and back.
pub trait Decomposition {
    /// Latent variables of `x` (sampled at `fs`) at frequency `frequency_hz`.
    fn decompose(&self, x: &[f64], fs: f64, frequency_hz: f64) -> Result<Latent, HybridError>;
    /// Reconstruction: `n` samples of the signal the latent variables describe, starting
    /// `start` samples after the first sample of the decomposed piece.
    fn reconstruct(
        &self,
        latent: &Latent,
        fs: f64,
        frequency_hz: f64,
        start: i64,
        n: usize,
    ) -> Vec<f64> {
        latent.sine(fs, frequency_hz, start, n)
    }
}

/// The feature map: a window of the measured signal to a feature vector.
pub trait FeatureMap {
    /// Names of the features, in the order [`FeatureMap::features`] returns them.
    fn names(&self) -> Vec<String>;
    /// Features of one window sampled at `fs`, of a record commanded at `frequency_hz`.
    fn features(&self, window: &[f64], fs: f64, frequency_hz: f64)
    -> Result<Vec<f64>, HybridError>;
}

/// The correction model `f_xai`: features to the correction `delta_hat` of the latent
/// amplitude (eq. 10: `A_corr = A_phys + delta_hat`).
pub trait Correction {
    /// Readable equation of the correction.
    fn equation(&self) -> String;
    /// One `delta_hat` per row of `features` (columns are looked up by name).
    fn predict(&self, features: &Table) -> Result<Vec<f64>, HybridError>;
}

/// The zero correction: `delta_hat = 0`, so the hybrid model is the physics model's sine
/// representation. The baseline every other correction is measured against.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ZeroCorrection;

impl Correction for ZeroCorrection {
    fn equation(&self) -> String {
        "0".into()
    }

    fn predict(&self, features: &Table) -> Result<Vec<f64>, HybridError> {
        Ok(vec![0.0; features.n_rows()])
    }
}

/// A symbolic model from `hxai-symreg` as the correction.
#[derive(Debug, Clone, PartialEq)]
pub struct SymbolicCorrection {
    /// The fitted model.
    pub model: hxai_symreg::Model,
}

impl Correction for SymbolicCorrection {
    fn equation(&self) -> String {
        self.model.equation()
    }

    fn predict(&self, features: &Table) -> Result<Vec<f64>, HybridError> {
        for name in self.model.features() {
            if features.index_of(&name).is_none() {
                return Err(HybridError::UnknownFeature {
                    name,
                    available: features.names().join(", "),
                });
            }
        }
        if features.n_rows() == 0 {
            return Ok(Vec::new());
        }
        Ok(self.model.predict(features)?)
    }
}
