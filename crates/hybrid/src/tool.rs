//! The tool-position case study as one implementation of the traits: physics by band-pass
//! filtering and double integration, latent variables by a three-parameter sine fit at the
//! command frequency, features by the paper's Table 2.

use crate::HybridError;
use crate::traits::{Decomposition, FeatureMap, Latent, PhysicsModel};
use hxai_signal::PhysicsConfig;

/// Physics model of the case study: [`hxai_signal::displacement`] (acceleration in m/s^2 to
/// displacement, in micrometres with the default settings).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DoubleIntegration {
    /// Filter and integration settings.
    pub config: PhysicsConfig,
}

impl PhysicsModel for DoubleIntegration {
    fn name(&self) -> String {
        "band-pass + double integration".into()
    }

    fn predict(&self, signal: &[f64], fs: f64) -> Result<Vec<f64>, HybridError> {
        Ok(hxai_signal::displacement(signal, fs, &self.config)?)
    }
}

/// Latent variables by [`hxai_signal::fit_sine`] (least squares at the known frequency).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SineDecomposition;

impl Decomposition for SineDecomposition {
    fn decompose(&self, x: &[f64], fs: f64, frequency_hz: f64) -> Result<Latent, HybridError> {
        let f = hxai_signal::fit_sine(x, fs, frequency_hz)?;
        Ok(Latent {
            amplitude: f.amplitude,
            phase: f.phase,
            offset: f.offset,
        })
    }
}

/// The twelve features of the paper's Table 2 from the raw acceleration window, by
/// [`hxai_features::extract_with`]; `f1` is the commanded frequency.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AccelFeatures {
    /// Sigma convention and PSD estimator.
    pub config: hxai_features::FeatureConfig,
}

impl FeatureMap for AccelFeatures {
    fn names(&self) -> Vec<String> {
        hxai_features::Features::NAMES
            .iter()
            .map(|s| (*s).to_owned())
            .collect()
    }

    fn features(
        &self,
        window: &[f64],
        fs: f64,
        frequency_hz: f64,
    ) -> Result<Vec<f64>, HybridError> {
        Ok(hxai_features::extract_with(window, fs, frequency_hz, &self.config)?.to_vec())
    }
}
