//! The generic composer: physics model + decomposition + feature map (+ a correction) on
//! records cut into windows.

use crate::HybridError;
use crate::traits::{Correction, Decomposition, FeatureMap, Latent, PhysicsModel};
use crate::window::WindowConfig;
use hxai_table::Table;
use serde::{Deserialize, Serialize};
use std::ops::Range;

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
    /// Implausible but legal input (filled by [`crate::HybridModel::predict`]; empty from
    /// the generic composer).
    pub warnings: Vec<crate::Warning>,
}

/// The generic hybrid composer (paper section 2): any physics model, decomposition and
/// feature map, on records cut into windows by [`WindowConfig`].
#[derive(Debug, Clone, PartialEq)]
pub struct Hybrid<P, D, F> {
    /// Step 1, the physics model.
    pub physics: P,
    /// The latent-variable decomposition.
    pub decomposition: D,
    /// The feature map.
    pub features: F,
    /// How records become samples.
    pub window: WindowConfig,
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

impl<P: PhysicsModel, D: Decomposition, F: FeatureMap> Hybrid<P, D, F> {
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
        let physics = self
            .physics
            .predict(input.signal, input.fs_hz)
            .map_err(|e| e.in_record(input.id, None))?;
        let mut windows = Vec::with_capacity(ranges.len());
        for (k, r) in ranges.into_iter().enumerate() {
            let ctx = |e: HybridError| e.in_record(input.id, Some(k));
            let phys = self
                .decomposition
                .decompose(&physics[r.clone()], input.fs_hz, input.frequency_hz)
                .map_err(ctx)?;
            let feats = self
                .features
                .features(&input.signal[r.clone()], input.fs_hz, input.frequency_hz)
                .map_err(ctx)?;
            let truth = match input.truth {
                None => None,
                Some(t) => {
                    let w = &t[r.clone()];
                    let m = mean(w);
                    let centred: Vec<f64> = w.iter().map(|v| v - m).collect();
                    Some(
                        self.decomposition
                            .decompose(&centred, input.fs_hz, input.frequency_hz)
                            .map_err(ctx)?,
                    )
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
        feature_table(self.features.names(), samples)
    }

    /// Steps 3-4 on one record: correct each window's amplitude by `correction` and
    /// reconstruct `x_hat = A_corr sin(omega t + phi_phys)`.
    pub fn predict<C: Correction + ?Sized>(
        &self,
        input: &RecordInput<'_>,
        correction: &C,
    ) -> Result<RecordPrediction, HybridError> {
        let rs = self.samples(input)?;
        let table = self.feature_table(&rs.windows)?;
        let delta_hat = correction
            .predict(&table)
            .map_err(|e| e.in_record(input.id, None))?;
        let windows: Vec<WindowPrediction> = rs
            .windows
            .iter()
            .zip(&delta_hat)
            .map(|(s, &d)| WindowPrediction {
                window: s.window,
                start: s.range.start,
                len: s.range.len(),
                physics: s.physics,
                delta_hat: d,
                corrected: corrected_latent(&s.physics, d),
            })
            .collect();
        let hybrid = self.reconstruct_record(
            &windows,
            input.signal.len(),
            input.fs_hz,
            input.frequency_hz,
        );
        Ok(RecordPrediction {
            physics: rs.physics,
            hybrid,
            windows,
            samples: rs.windows,
            warnings: Vec::new(),
        })
    }

    /// The whole-record signal from per-window latent variables: each sample uses the
    /// window it lies in; samples before the first window (after the last) use the first
    /// (last) window's reconstruction, extended.
    pub fn reconstruct_record(
        &self,
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
            let piece = self.decomposition.reconstruct(
                &w.corrected,
                fs,
                frequency_hz,
                from as i64 - w.start as i64,
                to - from,
            );
            out[from..to].copy_from_slice(&piece);
        }
        out
    }
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
