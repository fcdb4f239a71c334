//! The generic hybrid physics + symbolic-regression composer of hxai (paper section 2).
//!
//! A physics model `f_p` predicts; its error against the truth is a *correction factor*
//! `delta`; an interpretable model learns `delta` from features; the hybrid prediction is
//! the physics prediction corrected by it. This crate holds that framework as four traits
//! and one composer, and the tool-position case study as one implementation of them.
//!
//! # Main types
//!
//! - Traits: [`PhysicsModel`] (signal -> physical prediction), [`Decomposition`] (signal ->
//!   [`Latent`] amplitude, phase, offset at a known frequency, and back; eq. 8-11),
//!   [`FeatureMap`] (window -> named feature vector) and [`Correction`] (features ->
//!   `delta_hat`; [`SymbolicCorrection`] and [`ZeroCorrection`] implement it).
//! - [`Hybrid`]: the composer. [`Hybrid::samples`] cuts a [`RecordInput`] into windows
//!   ([`WindowConfig`]) and computes per window the physics latent variables, the features
//!   and the truth's latent variables ([`WindowSample`], with `A_phys`, `A_true`, `delta`);
//!   [`Hybrid::predict`] applies a correction: `A_corr = A_phys + delta_hat`,
//!   `x_hat = A_corr sin(omega t + phi_phys)`.
//! - [`evaluate()`]: physics vs hybrid against the truth ([`Evaluation`]).
//! - [`stream::Estimator`]: the same model applied sample by sample, causally, in bounded
//!   memory (`hxai stream`).
//! - [`explain`]: the numbers behind `hxai explain`'s pictures (response curves with
//!   prediction bands, predicted vs true, the Pareto front).
//! - The tool-position case: [`DoubleIntegration`], [`SineDecomposition`],
//!   [`AccelFeatures`]; [`fit`] with [`FitConfig`] returns a [`HybridModel`], the
//!   serialisable model file (schema [`SCHEMA_VERSION`]).
//!
//! # Design decision: windows, not whole records, are the samples
//!
//! One record gives one condition (amplitude, frequency); 56 conditions are too few rows
//! to fit and test a regression honestly. Each record is therefore cut into windows
//! (0.5 s after discarding 0.25 s at each end, where the zero-phase filter's edge
//! transients live), and each window is one sample. Because neighbouring windows of one
//! record are nearly alike, the default train/test split is *grouped by record*
//! ([`SplitKind::Record`]): a record's windows never sit on both sides, so the test score
//! measures generalisation to unseen recordings, not recall of a neighbour. The physics
//! prediction is computed on the whole record and then windowed, so windowing does not add
//! filter transients of its own.
//!
//! The crate reads no files (only `hxai-data` does) and prints nothing.
//!
//! # Example
//!
//! ```
//! use hxai_hybrid::{CorrectionInfo, RecordInput, tool_hybrid, WindowConfig};
//! use hxai_signal::PhysicsConfig;
//! # fn main() -> Result<(), hxai_hybrid::HybridError> {
//! let (fs, f, amp_um) = (2000.0, 20.0, 5.0);
//! let w = 2.0 * std::f64::consts::PI * f;
//! let t: Vec<f64> = (0..4000).map(|i| i as f64 / fs).collect();
//! // x = A sin(w t) um, so a = -A w^2 sin(w t) * 1e-6 m/s^2.
//! let accel: Vec<f64> = t.iter().map(|t| -amp_um * 1e-6 * w * w * (w * t).sin()).collect();
//! let probe: Vec<f64> = t.iter().map(|t| amp_um * (w * t).sin()).collect();
//! let hybrid = tool_hybrid(&PhysicsConfig::default(), WindowConfig::default());
//! let rec = RecordInput { id: "r1", fs_hz: fs, frequency_hz: f, signal: &accel, truth: Some(&probe) };
//! let samples = hybrid.samples(&rec)?;
//! assert_eq!(samples.windows.len(), 3); // 2 s - 2 x 0.25 s = 1.5 s = three 0.5 s windows
//! let a_phys = samples.windows[0].a_phys();
//! assert!((a_phys - amp_um).abs() < 0.05 * amp_um);
//! // With a zero correction the hybrid is the physics model's sine representation.
//! let pred = hybrid.predict(&rec, &CorrectionInfo::zero())?;
//! assert_eq!(pred.windows[0].corrected.amplitude, a_phys);
//! # Ok(())
//! # }
//! ```
#![deny(missing_docs)]

mod composer;
pub mod conformal;
mod correction;
mod error;
pub mod evaluate;
pub mod explain;
mod model;
pub mod process;
mod split;
pub mod stream;
mod warnings;
mod window;

pub use composer::{
    Latent, RecordInput, RecordPrediction, RecordSamples, ToolHybrid, WindowPrediction,
    WindowSample, corrected_latent, feature_names, reconstruct_record,
};
pub use correction::CorrectionInfo;
pub use error::HybridError;
pub use evaluate::{DEFAULT_INTERVAL, EvalInput, Evaluation, IntervalReport, evaluate};
pub use hxai_eval::IntervalMethod;
pub use model::{
    CorrectionKind, FeatureInfo, FitConfig, FitOutput, FitProgress, HybridModel, SCHEMA_VERSION,
    SamplesTable, SplitKind, TrainingInfo, fit, samples_table, split_samples, tool_hybrid,
    tool_hybrid_with,
};
pub use split::{SplitInfo, WindowId};
pub use warnings::{
    AMPLITUDE_RATIO_LIMIT, MIN_PERIODS_PER_WINDOW, PLAUSIBLE_FS_HZ, Warning, amplitude_warning,
    input_warnings, record_warnings, units_warning,
};
pub use window::{MAX_WINDOW_SECONDS, WindowConfig};
