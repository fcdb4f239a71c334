//! Hybrid physics + symbolic-regression models (paper section 2), in two halves.
//!
//! A physics model `f_p` predicts; its error against the truth is a *correction* `delta`;
//! an interpretable model learns `delta` from features; the hybrid prediction is the
//! physics prediction corrected by it. The crate holds that framework twice, once for each
//! shape the data comes in:
//!
//! - [`records`]: a periodic motion measured as records (the paper's tool-centre-point
//!   case; `hxai fit`, `predict`, `evaluate`, `stream`). Records are cut into windows, the
//!   physics model's latent amplitude is corrected, and the signal is reconstructed.
//!   [`records::fit`] returns a [`records::RecordModel`].
//! - [`tables`]: any process on a table (`hxai hybrid ...`, Python `HybridRegressor`). A
//!   physics equation over the columns with calibrated parameters, the correction entering
//!   additively, multiplicatively or on the log scale. [`tables::fit`] returns a
//!   [`tables::TableModel`].
//!
//! Shared by both: the correction as a model file stores it ([`CorrectionInfo`], generic
//! over its kind: made from a search, predicting `delta_hat`, explained the same way), the
//! split ([`SplitInfo`]: record ids or row indices), conformal prediction intervals
//! ([`conformal`]), how intervals are judged ([`IntervalReport`]), the numbers behind
//! `hxai explain` ([`explain`]) and the one error type ([`HybridError`]).
//!
//! # Design decision: two halves, no trait composer
//!
//! The paper names four parts of a hybrid model (physics model, latent-variable
//! decomposition, feature map, correction), and an earlier version of this crate made each
//! a trait. Each had one implementation, and the table half implemented none of them: a
//! table has no windows, no latent variable and no reconstruction. So the parts are plain
//! functions of the record half ([`records::RecordHybrid`]), and what the halves really
//! share, the correction and its split, is one concrete type each.
//!
//! # Design decision: windows, not whole records, are the samples
//!
//! One record gives one condition (amplitude, frequency); 56 conditions are too few rows
//! to fit and test a regression honestly. Each record is therefore cut into windows
//! (0.5 s after discarding 0.25 s at each end, where the zero-phase filter's edge
//! transients live), and each window is one sample. Because neighbouring windows of one
//! record are nearly alike, the default train/test split is *grouped by record*
//! ([`records::SplitKind::Record`]): a record's windows never sit on both sides, so the
//! test score measures generalisation to unseen recordings, not recall of a neighbour. The
//! physics prediction is computed on the whole record and then windowed, so windowing does
//! not add filter transients of its own.
//!
//! The crate reads no files (only `hxai-data` does) and prints nothing.
//!
//! # Example
//!
//! ```
//! use hxai_hybrid::CorrectionInfo;
//! use hxai_hybrid::records::{RecordInput, WindowConfig, record_hybrid};
//! use hxai_signal::PhysicsConfig;
//! # fn main() -> Result<(), hxai_hybrid::HybridError> {
//! let (fs, f, amp_um) = (2000.0, 20.0, 5.0);
//! let w = 2.0 * std::f64::consts::PI * f;
//! let t: Vec<f64> = (0..4000).map(|i| i as f64 / fs).collect();
//! // x = A sin(w t) um, so a = -A w^2 sin(w t) * 1e-6 m/s^2.
//! let accel: Vec<f64> = t.iter().map(|t| -amp_um * 1e-6 * w * w * (w * t).sin()).collect();
//! let probe: Vec<f64> = t.iter().map(|t| amp_um * (w * t).sin()).collect();
//! let hybrid = record_hybrid(&PhysicsConfig::default(), WindowConfig::default());
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

pub mod conformal;
mod correction;
pub mod dynamic;
mod error;
pub mod explain;
mod intervals;
pub mod records;
mod split;
pub mod tables;

pub use correction::CorrectionInfo;
pub use error::HybridError;
pub use hxai_eval::IntervalMethod;
pub use intervals::{DEFAULT_INTERVAL, IntervalReport, undefined_warning};
pub use split::{SplitInfo, WindowId};
