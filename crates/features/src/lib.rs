//! The twelve acceleration-signal features of the hxai case study (paper Table 2).
//!
//! The hybrid model corrects the physics model's amplitude with an equation of a few
//! features of the raw acceleration record. This crate computes them: [`extract`] (default
//! settings) and [`extract_with`] (a [`FeatureConfig`]) return a [`Features`] value with the
//! twelve numbers `f1`..`f12`; [`Features::NAMES`], [`Features::LONG_NAMES`],
//! [`Features::to_vec`] and [`Features::from_slice`] move them in and out of tables. Errors
//! are [`FeatureError`].
//!
//! # Design decision: the paper's formulas, with its silent choices made explicit
//!
//! The paper does not say whether sigma in kurtosis and skewness is the biased (1/N) or
//! unbiased (1/(N-1)) deviation, nor how the power spectral density is estimated. Defaults
//! here: biased sigma (what `scipy.stats.kurtosis(fisher=False)` and `skew` compute, the most
//! likely tool of the authors), Welch's PSD with scipy's defaults, and total power as the plain
//! sum `sum_k P(f_k)` exactly as the paper writes it (not the integral `sum_k P(f_k) df`; the
//! two differ by the constant factor `df = fs / nperseg`). Both choices are fields of
//! [`FeatureConfig`]. Kurtosis is the plain fourth standardised moment (3 for a Gaussian), not
//! the excess kurtosis.
//!
//! # Example
//! ```
//! let fs = 1000.0;
//! let accel: Vec<f64> = (0..2000)
//!     .map(|i| (2.0 * std::f64::consts::PI * 25.0 * i as f64 / fs).sin())
//!     .collect();
//! let f = hxai_features::extract(&accel, fs, 25.0)?;
//! // 40 samples per period, 50 whole periods: a sine's kurtosis is 3/2, its crest factor sqrt 2.
//! assert!((f.kurtosis - 1.5).abs() < 1e-9);
//! assert!((f.crest - 2f64.sqrt()).abs() < 1e-9);
//! assert_eq!(hxai_features::Features::NAMES[0], "f1");
//! # Ok::<(), hxai_features::FeatureError>(())
//! ```
#![deny(missing_docs)]

mod sliding;
pub use sliding::SlidingFeatures;

use hxai_signal::{SignalError, WelchConfig, welch};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Everything that can go wrong computing features.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum FeatureError {
    /// The acceleration record holds fewer than two samples.
    #[error("the acceleration record has {len} samples; features need at least 2")]
    TooShort {
        /// Samples given.
        len: usize,
    },
    /// A sample is NaN or infinite.
    #[error("acceleration sample {index} is NaN or infinite; clean the record first")]
    NonFinite {
        /// Index of the first bad sample.
        index: usize,
    },
    /// The sampling rate is not positive and finite.
    #[error("the sampling rate must be a positive finite number of Hz, got {}", hxai_table::format_number(*.0))]
    InvalidSampleRate(f64),
    /// The command frequency is not positive and finite.
    #[error("the command frequency must be a positive finite number of Hz, got {}", hxai_table::format_number(*.0))]
    InvalidCommandFrequency(f64),
    /// The record is constant, so sigma is 0 and kurtosis, skewness (and, for an all-zero
    /// record, the crest, impulse and shape factors and mean frequency) are undefined.
    #[error(
        "the acceleration record is constant (standard deviation 0); kurtosis, skewness and the spectral features are undefined for it"
    )]
    ConstantSignal,
    /// Sums of powers of the samples overflow f64 (values around 1e77 or larger).
    #[error(
        "the acceleration values are too large: their fourth powers overflow; rescale the record"
    )]
    Overflow,
    /// [`Features::from_slice`] got the wrong number of values.
    #[error("expected 12 feature values (f1..f12), got {0}")]
    WrongLength(usize),
    /// The spectrum estimate failed.
    #[error("power spectral density: {0}")]
    Signal(#[from] SignalError),
    /// The record is shorter than one period of the command frequency
    /// ([`check_covers_one_period`]).
    #[error(
        "the record has {len} samples but one period of {} Hz at {} Hz needs at least {need}",
        hxai_table::format_number(*.frequency_hz),
        hxai_table::format_number(*.fs)
    )]
    ShorterThanOnePeriod {
        /// Samples given.
        len: usize,
        /// Samples one period needs (`ceil(fs / frequency_hz) + 1`).
        need: usize,
        /// Command frequency, Hz.
        frequency_hz: f64,
        /// Sampling rate, Hz.
        fs: f64,
    },
}

/// Refuses a record of `len` samples at `fs` Hz that does not cover one period of
/// `frequency_hz` (`ceil(fs / frequency_hz) + 1` samples): the least a feature of the commanded
/// motion can describe. [`extract`] itself accepts any record of two or more samples (a
/// window of a long record is the caller's choice); front ends that take a whole record from
/// a user call this first.
///
/// # Errors
/// [`FeatureError::InvalidSampleRate`], [`FeatureError::InvalidCommandFrequency`],
/// [`FeatureError::ShorterThanOnePeriod`].
pub fn check_covers_one_period(len: usize, fs: f64, frequency_hz: f64) -> Result<(), FeatureError> {
    if !(fs.is_finite() && fs > 0.0) {
        return Err(FeatureError::InvalidSampleRate(fs));
    }
    if !(frequency_hz.is_finite() && frequency_hz > 0.0) {
        return Err(FeatureError::InvalidCommandFrequency(frequency_hz));
    }
    let need = (fs / frequency_hz).ceil() + 1.0;
    if (len as f64) < need {
        return Err(FeatureError::ShorterThanOnePeriod {
            len,
            // Saturating: a period longer than usize::MAX samples is refused all the same.
            need: if need >= usize::MAX as f64 {
                usize::MAX
            } else {
                need as usize
            },
            frequency_hz,
            fs,
        });
    }
    Ok(())
}

/// How sigma in kurtosis and skewness is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Sigma {
    /// `sqrt((1/N) sum (a_i - mean)^2)` (scipy.stats `bias=True`), the default.
    #[default]
    Biased,
    /// `sqrt(1/(N-1) sum (a_i - mean)^2)`, the same deviation as in f3.
    Unbiased,
}

/// How the power spectral density of f11 and f12 is estimated.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum PsdEstimator {
    /// Welch's method with these settings (default: scipy.signal.welch defaults).
    Welch(WelchConfig),
    /// One-segment periodogram (scipy.signal.periodogram defaults: boxcar window, constant
    /// detrend, density).
    Periodogram,
}

impl Default for PsdEstimator {
    fn default() -> Self {
        PsdEstimator::Welch(WelchConfig::default())
    }
}

/// Settings of [`extract_with`]; `Default` is what [`extract`] uses.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FeatureConfig {
    /// Sigma of kurtosis and skewness (default biased).
    pub sigma: Sigma,
    /// PSD estimator of f11 and f12 (default Welch with scipy's defaults).
    pub psd: PsdEstimator,
}

/// The twelve features of paper Table 2 for one acceleration record `a_i`, `i = 1..N`
/// (acceleration unit written `u`, m/s^2 in this project). Serialised with keys `f1`..`f12`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Features {
    /// f1, command frequency: the programmed sinusoid's frequency, Hz (an input, copied).
    #[serde(rename = "f1")]
    pub frequency_hz: f64,
    /// f2, mean absolute value `(1/N) sum |a_i|`, u.
    #[serde(rename = "f2")]
    pub mav: f64,
    /// f3, variance `1/(N-1) sum (a_i - mean)^2` (unbiased), u^2.
    #[serde(rename = "f3")]
    pub variance: f64,
    /// f4, peak amplitude `max |a_i|`, u.
    #[serde(rename = "f4")]
    pub peak: f64,
    /// f5, root mean square `sqrt((1/N) sum a_i^2)` (not centred), u.
    #[serde(rename = "f5")]
    pub rms: f64,
    /// f6, kurtosis `(1/N) sum ((a_i - mean)/sigma)^4`, dimensionless; the plain fourth
    /// standardised moment (3 for Gaussian noise), NOT the excess; sigma per [`Sigma`].
    #[serde(rename = "f6")]
    pub kurtosis: f64,
    /// f7, skewness `(1/N) sum ((a_i - mean)/sigma)^3`, dimensionless; sigma per [`Sigma`].
    #[serde(rename = "f7")]
    pub skewness: f64,
    /// f8, crest factor `peak / RMS` (f4 / f5), dimensionless.
    #[serde(rename = "f8")]
    pub crest: f64,
    /// f9, impulse factor `peak / MAV` (f4 / f2), dimensionless.
    #[serde(rename = "f9")]
    pub impulse: f64,
    /// f10, shape factor `RMS / MAV` (f5 / f2), dimensionless.
    #[serde(rename = "f10")]
    pub shape: f64,
    /// f11, mean frequency `sum f_k P(f_k) / sum P(f_k)` over the one-sided PSD, Hz.
    #[serde(rename = "f11")]
    pub mean_freq_hz: f64,
    /// f12, total power `sum_k P(f_k)`, the plain sum as in the paper (not multiplied by the
    /// bin width), u^2/Hz with the default density scaling.
    #[serde(rename = "f12")]
    pub total_power: f64,
}

impl Features {
    /// Short names in order, as used for table columns and JSON keys.
    pub const NAMES: [&'static str; 12] = [
        "f1", "f2", "f3", "f4", "f5", "f6", "f7", "f8", "f9", "f10", "f11", "f12",
    ];

    /// Human-readable names in the same order.
    pub const LONG_NAMES: [&'static str; 12] = [
        "command frequency",
        "mean absolute value",
        "variance",
        "peak amplitude",
        "root mean square",
        "kurtosis",
        "skewness",
        "crest factor",
        "impulse factor",
        "shape factor",
        "mean frequency",
        "total power",
    ];

    /// The values in the order of [`Features::NAMES`].
    pub fn to_vec(&self) -> Vec<f64> {
        self.to_array().to_vec()
    }

    /// The values in the order of [`Features::NAMES`], as an array.
    pub fn to_array(&self) -> [f64; 12] {
        [
            self.frequency_hz,
            self.mav,
            self.variance,
            self.peak,
            self.rms,
            self.kurtosis,
            self.skewness,
            self.crest,
            self.impulse,
            self.shape,
            self.mean_freq_hz,
            self.total_power,
        ]
    }

    /// Builds features from twelve values in the order of [`Features::NAMES`].
    ///
    /// # Errors
    /// [`FeatureError::WrongLength`] unless `v.len() == 12`.
    pub fn from_slice(v: &[f64]) -> Result<Self, FeatureError> {
        let a: [f64; 12] = v
            .try_into()
            .map_err(|_| FeatureError::WrongLength(v.len()))?;
        Ok(Self {
            frequency_hz: a[0],
            mav: a[1],
            variance: a[2],
            peak: a[3],
            rms: a[4],
            kurtosis: a[5],
            skewness: a[6],
            crest: a[7],
            impulse: a[8],
            shape: a[9],
            mean_freq_hz: a[10],
            total_power: a[11],
        })
    }
}

/// The twelve features with the default [`FeatureConfig`].
///
/// # Errors
/// See [`extract_with`].
pub fn extract(accel: &[f64], fs: f64, frequency_hz: f64) -> Result<Features, FeatureError> {
    extract_with(accel, fs, frequency_hz, &FeatureConfig::default())
}

/// The twelve features of `accel` (sampled at `fs` Hz, commanded at `frequency_hz` Hz) with the
/// settings `cfg`.
///
/// # Errors
/// [`FeatureError::TooShort`] (fewer than 2 samples), [`FeatureError::NonFinite`],
/// [`FeatureError::InvalidSampleRate`], [`FeatureError::InvalidCommandFrequency`],
/// [`FeatureError::ConstantSignal`], [`FeatureError::Overflow`], [`FeatureError::Signal`] (an invalid Welch setting).
pub fn extract_with(
    accel: &[f64],
    fs: f64,
    frequency_hz: f64,
    cfg: &FeatureConfig,
) -> Result<Features, FeatureError> {
    let n = accel.len();
    if n < 2 {
        return Err(FeatureError::TooShort { len: n });
    }
    if let Some(index) = accel.iter().position(|v| !v.is_finite()) {
        return Err(FeatureError::NonFinite { index });
    }
    if !(fs.is_finite() && fs > 0.0) {
        return Err(FeatureError::InvalidSampleRate(fs));
    }
    if !(frequency_hz.is_finite() && frequency_hz > 0.0) {
        return Err(FeatureError::InvalidCommandFrequency(frequency_hz));
    }
    let nf = n as f64;
    let mut sum = 0.0;
    let mut sum_abs = 0.0;
    let mut sum_sq = 0.0;
    let mut peak = 0.0_f64;
    for &a in accel {
        sum += a;
        sum_abs += a.abs();
        sum_sq += a * a;
        peak = peak.max(a.abs());
    }
    let mean = sum / nf;
    let (mut m2, mut m3, mut m4) = (0.0, 0.0, 0.0);
    for &a in accel {
        let d = a - mean;
        let d2 = d * d;
        m2 += d2;
        m3 += d2 * d;
        m4 += d2 * d2;
    }
    let wcfg = welch_config(cfg);
    let psd = welch(accel, fs, &wcfg)?;
    assemble(
        frequency_hz,
        &Sums {
            n: nf,
            sum_abs,
            sum_sq,
            m2,
            m3,
            m4,
            peak,
        },
        &psd,
        cfg,
    )
}

/// The Welch settings of a PSD estimator.
fn welch_config(cfg: &FeatureConfig) -> WelchConfig {
    match &cfg.psd {
        PsdEstimator::Welch(w) => w.clone(),
        PsdEstimator::Periodogram => WelchConfig::periodogram(),
    }
}

/// What the twelve features are made of: over `n` samples, the sums of `|a|` and `a^2`, the
/// sums of the 2nd, 3rd and 4th powers of `a - mean`, and the largest `|a|`.
pub(crate) struct Sums {
    pub n: f64,
    pub sum_abs: f64,
    pub sum_sq: f64,
    pub m2: f64,
    pub m3: f64,
    pub m4: f64,
    pub peak: f64,
}

/// The features from the sums and the PSD ([`extract_with`] and [`SlidingFeatures`] share
/// it, so both define each feature once).
pub(crate) fn assemble(
    frequency_hz: f64,
    sums: &Sums,
    psd: &hxai_signal::Psd,
    cfg: &FeatureConfig,
) -> Result<Features, FeatureError> {
    let (nf, sum_abs, sum_sq, peak) = (sums.n, sums.sum_abs, sums.sum_sq, sums.peak);
    let (m2, m3, m4) = (sums.m2, sums.m3, sums.m4);
    if !(m4.is_finite() && sum_sq.is_finite() && sum_abs.is_finite()) {
        return Err(FeatureError::Overflow);
    }
    if m2 <= 0.0 {
        return Err(FeatureError::ConstantSignal);
    }
    let var_b = m2 / nf;
    let var_u = m2 / (nf - 1.0);
    let var_sigma = match cfg.sigma {
        Sigma::Biased => var_b,
        Sigma::Unbiased => var_u,
    };
    let kurtosis = (m4 / nf) / (var_sigma * var_sigma);
    let skewness = (m3 / nf) / (var_sigma * var_sigma.sqrt());
    let mav = sum_abs / nf;
    let rms = (sum_sq / nf).sqrt();
    let total_power: f64 = psd.density.iter().sum();
    if total_power <= 0.0 || !total_power.is_finite() {
        return Err(FeatureError::ConstantSignal);
    }
    let mean_freq_hz = psd
        .freqs
        .iter()
        .zip(&psd.density)
        .map(|(f, p)| f * p)
        .sum::<f64>()
        / total_power;

    Ok(Features {
        frequency_hz,
        mav,
        variance: var_u,
        peak,
        rms,
        kurtosis,
        skewness,
        crest: peak / rms,
        impulse: peak / mav,
        shape: rms / mav,
        mean_freq_hz,
        total_power,
    })
}
