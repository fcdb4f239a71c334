//! The record half: hybrid models of a periodic motion measured as records (the paper's
//! tool-centre-point case, `hxai fit`, `hxai predict`, `hxai evaluate`, `hxai stream`).
//!
//! A record is a measured signal (acceleration) with, when fitting, its ground truth (probe
//! position), at a known frequency. Records are cut into windows ([`WindowConfig`]); each
//! window is one sample with the physics model's latent variables ([`Latent`]: amplitude,
//! phase, offset), the features of the raw signal and, with a truth, `delta = A_true -
//! A_phys` ([`WindowSample`]). The correction learns `delta` from the features; the hybrid
//! is reconstructed as `x_hat = (A_phys + delta_hat) sin(omega t + phi_phys)`.
//!
//! - [`RecordHybrid`]: the composer (samples, prediction, reconstruction).
//! - [`fit`] with [`RecordConfig`] returns a [`RecordModel`], the serialisable model file
//!   (schema [`SCHEMA_VERSION`]), with [`RecordModel::predict`], [`RecordModel::evaluate`]
//!   and [`RecordModel::explain`].
//! - [`evaluate()`]: physics vs hybrid against the truth ([`Evaluation`]).
//! - [`stream::Estimator`]: the same model sample by sample, causally, in bounded memory.
//! - [`SamplesTable`]: the rows of `samples.csv`, written and read back in one place.

mod composer;
mod evaluation;
mod model;
mod rows;
mod sample;
pub mod stream;
mod warnings;
mod window;

pub use composer::{
    RecordHybrid, RecordPrediction, RecordSamples, WindowPrediction, corrected_latent,
    feature_names, reconstruct_record,
};
pub(crate) use evaluation::metrics_um;
pub use evaluation::{EvalInput, Evaluation, evaluate};
pub use model::{
    CorrectionKind, FeatureInfo, FitOutput, FitProgress, RecordConfig, RecordModel, SCHEMA_VERSION,
    SamplesTable, SplitKind, TrainingInfo, fit, record_hybrid, record_hybrid_with, samples_table,
    split_samples,
};
pub use rows::WindowRow;
pub use sample::{Latent, RecordInput, WindowSample};
pub use warnings::{
    AMPLITUDE_RATIO_LIMIT, MIN_PERIODS_PER_WINDOW, PLAUSIBLE_FS_HZ, Warning, amplitude_warning,
    input_warnings, record_warnings, units_warning,
};
pub use window::{MAX_WINDOW_SECONDS, WindowConfig};
