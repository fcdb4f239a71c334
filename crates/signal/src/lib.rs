//! Digital signal processing for hxai: Butterworth filters, zero-phase filtering,
//! integration, Welch PSD, sine fitting and the accelerometer physics model.
//!
//! The crate turns sampled signals into other sampled signals or into numbers. Its main types:
//!
//! - [`butter`] designs a Butterworth [`Sos`] (second-order sections) for a [`Band`];
//!   [`Sos::filter`], [`Sos::filter_with_state`], [`Sos::zi`] and [`Sos::filtfilt`] apply it.
//! - [`cumulative_trapezoid`] and [`detrend`] integrate and remove trends.
//! - [`welch`] estimates a power spectral density ([`Psd`]) with a [`WelchConfig`].
//! - [`fit_sine`] / [`fit_sine4`] fit a sine (IEEE 1057), giving a [`SineFit`].
//! - [`SlidingSine`] and [`SlidingWelch`] give the sine fit and the Welch PSD of the last
//!   `n` samples of a stream, one sample at a time, in bounded memory.
//! - [`displacement`] runs the physics model of the case study, configured by
//!   [`PhysicsConfig`] and checked once into a [`ValidPhysics`].
//!
//! Every fallible function returns [`SignalError`]; nothing panics on user input.
//!
//! # Design decision: filters written by hand, step for step like scipy
//!
//! The reference implementation of the method is Python/scipy, and the numbers this project
//! reports must be comparable with it. No Rust crate reproduces `scipy.signal.butter(...,
//! output='sos')` (its pole-zero pairing `'nearest'` and section order) together with
//! `sosfiltfilt`'s padding and initial conditions, and small differences there move filtered
//! edges and amplitudes. So the design follows scipy's own path (`buttap` -> `lp2*_zpk` ->
//! `bilinear_zpk` -> `zpk2sos`) with the same complex arithmetic, and the tests compare the
//! coefficients with stored scipy output to 1e-12.
//!
//! # Example
//! ```
//! use hxai_signal::{Band, PhysicsConfig, butter, displacement};
//!
//! let fs = 2000.0;
//! let sos = butter(4, Band::Bandpass(5.0, 200.0), fs)?;
//! assert_eq!(sos.sections().len(), 4);
//!
//! // A 20 Hz, 5 um sine motion has acceleration -(2 pi f)^2 * 5e-6 * sin(2 pi f t).
//! let w = 2.0 * std::f64::consts::PI * 20.0;
//! let accel: Vec<f64> = (0..4000)
//!     .map(|i| -w * w * 5e-6 * (w * i as f64 / fs).sin())
//!     .collect();
//! let d_um = displacement(&accel, fs, &PhysicsConfig::default())?;
//! let fit = hxai_signal::fit_sine(&d_um[1000..3000], fs, 20.0)?;
//! assert!((fit.amplitude - 5.0).abs() < 0.05);
//! # Ok::<(), hxai_signal::SignalError>(())
//! ```
#![deny(missing_docs)]

mod complex;
mod design;
mod error;
mod filter;
mod integrate;
mod physics;
mod sine;
mod sliding;
mod spectral;

pub use design::{Band, MAX_ORDER, butter};
pub use error::SignalError;
pub use filter::Sos;
pub use integrate::{Detrend, cumulative_trapezoid, detrend, detrend_in_place};
pub use physics::{Drift, Integrator, LengthUnit, PhysicsConfig, ValidPhysics, displacement};
pub use sine::{SineFit, SineFit4, fit_sine, fit_sine4, phase_lag_s};
pub use sliding::{SlidingSine, SlidingWelch};
pub use spectral::{Psd, Scaling, WelchConfig, Window, welch};
