//! The record half's composer: the physics model, the latent variables and the features of
//! records cut into windows, and a correction applied to them (paper section 2, steps 1-4).
//!
//! The paper describes its framework as four parts (physics model, latent-variable
//! decomposition, feature map, correction). Here they are plain functions of the case
//! study's settings, not traits: each has one implementation, and the other processes the
//! framework serves (the table half, [`crate::tables`]) have no windows, no latent
//! variable and no reconstruction, so no second implementation would plug in.

use crate::HybridError;
use crate::correction::CorrectionInfo;
use crate::records::sample::{Latent, RecordInput, WindowSample};
use crate::records::warnings::Warning;
use crate::records::window::WindowConfig;
use hxai_signal::PhysicsConfig;
use hxai_table::Table;
use serde::{Deserialize, Serialize};

/// The names of the features of every window, in the order the composer computes them:
/// the twelve of the paper's Table 2 ([`hxai_features::Features::NAMES`]).
pub fn feature_names() -> Vec<String> {
    hxai_features::Features::NAMES
        .iter()
        .map(|s| (*s).to_owned())
        .collect()
}

/// The samples of one record and the physics prediction they come from.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordSamples {
    /// Physics prediction for the whole record.
    pub physics: Vec<f64>,
    /// One sample per window, in time order.
    pub windows: Vec<WindowSample>,
}

/// The correction applied to one window.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowPrediction {
    /// Window index.
    pub window: usize,
    /// First sample of the window.
    pub start: usize,
    /// Number of samples in the window.
    pub len: usize,
    /// Latent variables of the physics prediction.
    pub physics: Latent,
    /// Predicted correction `delta_hat`.
    pub delta_hat: f64,
    /// `A_corr = A_phys + delta_hat` (eq. 10), with the physics phase and zero offset.
    pub corrected: Latent,
}

/// A hybrid prediction of one record.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordPrediction {
    /// Physics prediction for the whole record.
    pub physics: Vec<f64>,
    /// Hybrid prediction for the whole record, `x_hat = A_corr sin(omega t + phi_phys)`
    /// (eq. 11) window by window; samples before the first window (after the last) use the
    /// first (last) window's sine, extended.
    pub hybrid: Vec<f64>,
    /// Per-window corrections.
    pub windows: Vec<WindowPrediction>,
    /// The samples (features, latent variables).
    pub samples: Vec<WindowSample>,
    /// Implausible but legal input (filled by [`crate::records::RecordModel::predict`]; empty from
    /// the generic composer).
    pub warnings: Vec<Warning>,
}

/// The composer of the record half (paper section 2): the physics model (band-pass
/// filtering and double integration, [`hxai_signal::displacement`]), the latent variables
/// of each window ([`Latent::fit`]) and the features of the raw signal in each window
/// ([`hxai_features::extract_with`], paper Table 2; `f1` is the commanded frequency), on
/// records cut into windows by [`WindowConfig`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RecordHybrid {
    /// Step 1, the physics model's filter and integration settings.
    pub physics: PhysicsConfig,
    /// The feature map's sigma convention and PSD estimator.
    pub features: hxai_features::FeatureConfig,
    /// How records become samples.
    pub window: WindowConfig,
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

impl RecordHybrid {
    /// Step 1 and 2: the physics prediction of the whole record, then per window the
    /// physics latent variables, the features of the raw signal and, when there is a
    /// truth, the truth's latent variables (of the truth minus its window mean).
    pub fn samples(&self, input: &RecordInput<'_>) -> Result<RecordSamples, HybridError> {
        if let Some(t) = input.truth
            && t.len() != input.signal.len()
        {
            return Err(HybridError::LengthMismatch {
                record: input.id.to_owned(),
                signal: input.signal.len(),
                truth: t.len(),
            });
        }
        let ranges = self
            .window
            .windows(input.signal.len(), input.fs_hz, input.id)?;
        let physics = hxai_signal::displacement(input.signal, input.fs_hz, &self.physics)
            .map_err(|e| HybridError::from(e).in_record(input.id, None))?;
        let mut windows = Vec::with_capacity(ranges.len());
        for (k, r) in ranges.into_iter().enumerate() {
            let ctx = |e: HybridError| e.in_record(input.id, Some(k));
            let phys =
                Latent::fit(&physics[r.clone()], input.fs_hz, input.frequency_hz).map_err(ctx)?;
            let feats = hxai_features::extract_with(
                &input.signal[r.clone()],
                input.fs_hz,
                input.frequency_hz,
                &self.features,
            )
            .map_err(|e| ctx(e.into()))?
            .to_vec();
            let truth = match input.truth {
                None => None,
                Some(t) => {
                    let w = &t[r.clone()];
                    let m = mean(w);
                    let centred: Vec<f64> = w.iter().map(|v| v - m).collect();
                    Some(Latent::fit(&centred, input.fs_hz, input.frequency_hz).map_err(ctx)?)
                }
            };
            windows.push(WindowSample {
                record: input.id.to_owned(),
                window: k,
                range: r,
                features: feats,
                physics: phys,
                truth,
            });
        }
        Ok(RecordSamples { physics, windows })
    }

    /// The feature table of some samples, columns named by the feature map.
    pub fn feature_table<'s>(
        &self,
        samples: impl IntoIterator<Item = &'s WindowSample>,
    ) -> Result<Table, HybridError> {
        feature_table(feature_names(), samples)
    }

    /// Steps 3-4 on one record: correct each window's amplitude by `correction` and
    /// reconstruct `x_hat = A_corr sin(omega t + phi_phys)`.
    ///
    /// # Errors
    /// Those of [`RecordHybrid::samples`] and of the correction.
    pub fn predict<K>(
        &self,
        input: &RecordInput<'_>,
        correction: &CorrectionInfo<K>,
    ) -> Result<RecordPrediction, HybridError> {
        let rs = self.samples(input)?;
        let table = self.feature_table(&rs.windows)?;
        let delta_hat = correction
            .predict(&table)
            .map_err(|e| e.in_record(input.id, None))?;
        Ok(self.apply(input, rs, &delta_hat))
    }

    /// Step 3-4 with given corrections: each window of `samples` (of `input`) corrected by
    /// its `delta_hat`, and the record reconstructed.
    pub fn apply(
        &self,
        input: &RecordInput<'_>,
        samples: RecordSamples,
        delta_hat: &[f64],
    ) -> RecordPrediction {
        let windows: Vec<WindowPrediction> = samples
            .windows
            .iter()
            .zip(delta_hat)
            .map(|(s, &d)| WindowPrediction {
                window: s.window,
                start: s.range.start,
                len: s.range.len(),
                physics: s.physics,
                delta_hat: d,
                corrected: corrected_latent(&s.physics, d),
            })
            .collect();
        let hybrid = reconstruct_record(
            &windows,
            input.signal.len(),
            input.fs_hz,
            input.frequency_hz,
        );
        RecordPrediction {
            physics: samples.physics,
            hybrid,
            windows,
            samples: samples.windows,
            warnings: Vec::new(),
        }
    }
}

/// The whole-record signal from per-window latent variables: each sample uses the
/// window it lies in; samples before the first window (after the last) use the first
/// (last) window's reconstruction, extended.
pub fn reconstruct_record(
    windows: &[WindowPrediction],
    n: usize,
    fs: f64,
    frequency_hz: f64,
) -> Vec<f64> {
    let mut out = vec![0.0; n];
    for (k, w) in windows.iter().enumerate() {
        let from = if k == 0 { 0 } else { w.start };
        let to = if k + 1 == windows.len() {
            n
        } else {
            (w.start + w.len).min(n)
        };
        if from >= to {
            continue;
        }
        let piece = w
            .corrected
            .sine(fs, frequency_hz, from as i64 - w.start as i64, to - from);
        out[from..to].copy_from_slice(&piece);
    }
    out
}

/// The features of `samples` as a table, one column per name of `names`.
///
/// # Errors
/// [`HybridError::InvalidConfig`] for a sample with another number of features,
/// [`HybridError::Table`] for a non-finite feature.
pub(crate) fn feature_table<'s>(
    names: Vec<String>,
    samples: impl IntoIterator<Item = &'s WindowSample>,
) -> Result<Table, HybridError> {
    let mut columns = vec![Vec::new(); names.len()];
    for (r, s) in samples.into_iter().enumerate() {
        if s.features.len() != names.len() {
            return Err(HybridError::InvalidConfig(format!(
                "feature row {r} has {} values but there are {} feature names",
                s.features.len(),
                names.len()
            )));
        }
        for (column, v) in columns.iter_mut().zip(&s.features) {
            column.push(*v);
        }
    }
    Ok(Table::new(names, columns)?)
}

/// Eq. 10-11: `A_corr = A_phys + delta_hat`, phase from the physics signal, offset zero.
pub fn corrected_latent(physics: &Latent, delta_hat: f64) -> Latent {
    Latent {
        amplitude: physics.amplitude + delta_hat,
        phase: physics.phase,
        offset: 0.0,
    }
}
