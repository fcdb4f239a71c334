//! The tool position in real time: the hybrid model of `hxai fit` applied sample by sample,
//! causally, in bounded memory.
//!
//! `hxai predict` needs the whole record: a zero-phase band-pass (`filtfilt`), double
//! integration with drift removal, then a sine fit per window. None of that is causal. The
//! [`Estimator`] computes the same latent variables from a trailing window instead:
//!
//! 1. **Physics by demodulation at the known frequency.** The physics model is linear, so
//!    its displacement at the command frequency `f` is the acceleration's sine at `f` times
//!    the chain's gain there ([`hxai_signal::ValidPhysics::gain_at`]: the band-pass's
//!    `|H(f)|^2`, the trapezoid rule's `1 / w^2` up to `(w T)^2 / 12`, the unit) with the
//!    sign of a double integral. The acceleration's sine is a least-squares fit of offset,
//!    sine and cosine at `f` over the whole periods of the last `W` samples
//!    ([`hxai_signal::SlidingSine`], running sums, O(1) per sample), `W` being the model's
//!    window length (0.5 s by default), re-solved at every sample. Over whole periods the
//!    harmonics of `f` are orthogonal to the fit, so they do not leak into the amplitude. `A_phys` is its amplitude, the row's `physics_um`
//!    the fitted sine's value at the newest sample.
//! 2. **Features on the same trailing window** ([`hxai_features::SlidingFeatures`]): the
//!    moments and the peak updated per sample, the Welch PSD one segment FFT per Welch step,
//!    reported every step (128 samples at the default settings, 12.8 ms at 10 kHz). They
//!    equal the offline features of that window.
//! 3. **The correction** `delta_hat = f(features)` is evaluated at each report, and, with an
//!    interval level, its prediction interval; each row uses the latest report:
//!    `hybrid_um = (A_phys + delta_hat) / A_phys * physics_um` (eq. 10-11: the corrected
//!    amplitude, the physics phase).
//!
//! # Delay and warm-up
//!
//! The row of sample `i` uses samples `i - W + 1 ..= i` only, so the delay `D` (samples
//! after `i` that its row depends on) is **0**: a row is complete when its sample arrives.
//! The first `W - 1` rows are the warm-up (no values): the window is not yet full. What a
//! trailing window costs is not delay but response time: the amplitude is the average over
//! the last `W` samples, so after a change of the motion the estimate settles within `W`
//! samples; a stationary motion is estimated without lag, its phase included.
//!
//! # What differs from `hxai predict`
//!
//! The offline physics signal (`physics_um` of `hxai predict`) is the whole band-passed
//! double integral, harmonics and noise included; the streaming `physics_um` is its
//! component at the command frequency (the latent variable of eq. 8), which the hybrid
//! corrects in both. The offline fit is on the displacement after linear drift removal and
//! on fixed windows; the streaming one is on the acceleration over the trailing window.
//! docs/benchmarks.md measures both against the probe.
//!
//! # Example
//! ```
//! use hxai_hybrid::records::stream::Estimator;
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let model = hxai_hybrid::records::RecordModel::from_json(include_str!(
//!     "../../../../testdata/bad/good/model.json"
//! ))?;
//! let (fs, f, amp_um) = (2000.0, 20.0, 6.0);
//! let w = 2.0 * std::f64::consts::PI * f;
//! let accel: Vec<f64> = (0..3000)
//!     .map(|i| -amp_um * 1e-6 * w * w * (w * i as f64 / fs).sin())
//!     .collect();
//! let mut est = Estimator::new(&model, f, fs)?;
//! let rows = est.push(&accel)?;
//! assert_eq!(rows.len(), 3000); // delay 0: one row per sample pushed
//! assert_eq!(est.warmup_samples(), 999); // a 0.5 s window at 2 kHz
//! assert!(rows[998].physics_um.is_none());
//! let last = rows.last().and_then(|r| r.physics_um).unwrap_or(f64::NAN);
//! let want = amp_um * (w * 2999.0 / fs).sin();
//! assert!((last - want).abs() < 0.01 * amp_um);
//! # Ok(())
//! # }
//! ```

use crate::records::CorrectionKind;
use crate::records::model::{RecordModel, check_band_hz};
use crate::{CorrectionInfo, HybridError};
use hxai_features::SlidingFeatures;
use hxai_signal::SlidingSine;
use hxai_table::Table;
use serde::{Deserialize, Serialize};

/// One output row: the estimates at one input sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Index of the sample since the estimator started (or last restarted), from 0.
    pub sample: u64,
    /// Time of the sample since the estimator started (or last restarted), s: `sample / fs`.
    pub time_s: f64,
    /// Physics displacement at the command frequency, um; `None` during the warm-up.
    pub physics_um: Option<f64>,
    /// Hybrid displacement, um; `None` during the warm-up and while the correction is
    /// undefined (a window whose features are undefined, such as a constant signal).
    pub hybrid_um: Option<f64>,
    /// Lower and upper bound of the hybrid displacement at the interval level, when one was
    /// asked for ([`Estimator::with_interval`]).
    pub interval_um: Option<(f64, f64)>,
}

/// Most samples one window may hold in a stream (each estimate keeps a few copies of the
/// window): 1e7, 80 MB per copy, a 10 s window at 1 MHz. A rate far above any accelerometer's
/// (`--fs-hz 1e9`) is refused before anything is allocated.
pub const MAX_WINDOW_SAMPLES: usize = 10_000_000;

/// Columns of the streaming output, in order (`hxai stream`'s CSV header).
pub const COLUMNS: [&str; 3] = ["time_s", "physics_um", "hybrid_um"];

/// Columns added with an interval.
pub const INTERVAL_COLUMNS: [&str; 2] = ["hybrid_lo_um", "hybrid_hi_um"];

/// What a streaming run reports at its end (`hxai stream --summary`): the contract's keys
/// first, then the estimator's settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// The delay `D`, samples: the row of sample `i` depends on samples up to `i + D`.
    pub delay_samples: usize,
    /// Rows without values at the start and after each restart.
    pub warmup_samples: usize,
    /// Samples read (= rows written).
    pub samples: u64,
    /// Wall time of the run, s.
    pub seconds: f64,
    /// Restarts of the estimator after a gap or a jump back in time.
    pub restarts: u64,
    /// The commanded frequency, Hz.
    pub frequency_hz: f64,
    /// The sampling rate, Hz (`None` when the stream ended before it was known).
    pub fs_hz: Option<f64>,
    /// The window the estimates are made over, samples.
    pub window_samples: usize,
    /// Samples between two updates of the correction.
    pub update_step_samples: usize,
    /// Updates whose features were undefined (a constant window): the hybrid stayed empty.
    pub undefined_reports: u64,
}

/// The latest report of the correction.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Report {
    delta_hat: f64,
    interval: Option<(f64, f64)>,
}

/// The longest span of whole periods of `frequency_hz` within `window` samples (rounded to
/// samples; `window` itself when not even one period fits). Over whole periods every
/// harmonic of the command frequency is orthogonal to its sine and cosine, so harmonics of
/// the motion and of the mains at twice a 25 Hz command do not leak into the amplitude, and
/// the estimate does not wobble as the window slides.
fn whole_periods(window: usize, fs_hz: f64, frequency_hz: f64) -> usize {
    let period = fs_hz / frequency_hz;
    let periods = (window as f64 / period).floor();
    if periods >= 1.0 {
        ((periods * period).round() as usize).clamp(3, window)
    } else {
        window
    }
}

/// Checks what can be checked of a model and a frequency before the sampling rate is known:
/// the frequency lies in the model's physics band, and the model is complete.
///
/// # Errors
/// [`HybridError::FrequencyOutOfBand`], and the model's correction errors.
pub fn check_frequency(model: &RecordModel, frequency_hz: f64) -> Result<(), HybridError> {
    check_band_hz(&model.physics, "stream", frequency_hz)?;
    model.correction().map(|_| ())
}

/// The causal streaming estimator of the tool position (see the module docs).
#[derive(Debug)]
pub struct Estimator {
    frequency_hz: f64,
    fs_hz: f64,
    window: usize,
    gain: f64,
    level: Option<f64>,
    model: RecordModel,
    correction: CorrectionInfo<CorrectionKind>,
    names: Vec<String>,
    sine: SlidingSine,
    features: SlidingFeatures,
    report: Option<Report>,
    samples: u64,
    undefined_reports: u64,
}

impl Estimator {
    /// An estimator for `model` (from `hxai fit`), a commanded frequency and a sampling rate.
    ///
    /// # Errors
    /// [`HybridError::FrequencyOutOfBand`] for a frequency outside the model's physics band,
    /// [`HybridError::Signal`] / [`HybridError::Features`] for a sampling rate the physics
    /// chain or the features cannot use (a band above Nyquist, a window shorter than a
    /// period), [`HybridError::RecordTooShort`]-like config errors for the window.
    pub fn new(model: &RecordModel, frequency_hz: f64, fs_hz: f64) -> Result<Self, HybridError> {
        check_band_hz(&model.physics, "stream", frequency_hz)?;
        let physics = model.physics.check(fs_hz)?;
        model.window.check()?;
        let window = model.window.length_samples(fs_hz);
        if window > MAX_WINDOW_SAMPLES {
            return Err(HybridError::InvalidConfig(format!(
                "one model window of {} s at {} Hz is {window} samples, more than the {} a \
                 stream holds; is the sampling rate right (time_s in seconds)?",
                crate::error::num(model.window.length_s),
                crate::error::num(fs_hz),
                MAX_WINDOW_SAMPLES
            )));
        }
        hxai_features::check_covers_one_period(window, fs_hz, frequency_hz)?;
        let sine = SlidingSine::new(
            whole_periods(window, fs_hz, frequency_hz),
            fs_hz,
            frequency_hz,
        )?;
        let features = SlidingFeatures::new(window, fs_hz, frequency_hz, &model.features.config)?;
        Ok(Self {
            frequency_hz,
            fs_hz,
            window,
            gain: physics.gain_at(frequency_hz),
            level: None,
            model: model.clone(),
            correction: model.correction()?.clone(),
            names: model.features.names.clone(),
            sine,
            features,
            report: None,
            samples: 0,
            undefined_reports: 0,
        })
    }

    /// Adds prediction bounds at `level` (e.g. 0.95) to every row: the interval of the
    /// corrected amplitude (as `hxai predict --interval`: the model's default method,
    /// conformal when the file stores its calibration), applied to the row's sine.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] for a level outside (0, 1) or a model that stores no
    /// uncertainty of its correction.
    pub fn with_interval(mut self, level: f64) -> Result<Self, HybridError> {
        if !(level > 0.0 && level < 1.0) {
            return Err(HybridError::InvalidConfig(format!(
                "the interval level must lie between 0 and 1 (e.g. 0.95), got {}",
                crate::error::num(level)
            )));
        }
        if self.model.correction.model.is_none() || self.model.correction.uncertainty.is_none() {
            return Err(HybridError::InvalidConfig(
                "this model stores no uncertainty of its correction (a zero correction, or a \
                 file written before prediction intervals existed): refit it with `hxai fit` \
                 or stream without an interval"
                    .into(),
            ));
        }
        self.level = Some(level);
        Ok(self)
    }

    /// The delay `D`: the row of sample `i` depends on samples up to `i + D`. Always 0.
    pub fn delay_samples(&self) -> usize {
        0
    }

    /// Rows at the start (and after each restart) that have no values: `W - 1`.
    pub fn warmup_samples(&self) -> usize {
        self.window - 1
    }

    /// Samples between two updates of the correction (the Welch step of the features).
    pub fn update_step(&self) -> usize {
        self.features.step()
    }

    /// The window length `W`, samples.
    pub fn window_samples(&self) -> usize {
        self.window
    }

    /// Samples pushed since the start or the last restart.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// Reports whose features were undefined (the hybrid was left empty until the next).
    pub fn undefined_reports(&self) -> u64 {
        self.undefined_reports
    }

    /// The commanded frequency, Hz.
    pub fn frequency_hz(&self) -> f64 {
        self.frequency_hz
    }

    /// The sampling rate, Hz.
    pub fn fs_hz(&self) -> f64 {
        self.fs_hz
    }

    /// The run's summary, given what the caller counted: samples read over the whole run
    /// (restarts included), its wall time and the restarts.
    pub fn summary(&self, samples: u64, seconds: f64, restarts: u64) -> Summary {
        Summary {
            delay_samples: self.delay_samples(),
            warmup_samples: self.warmup_samples(),
            samples,
            seconds,
            restarts,
            frequency_hz: self.frequency_hz,
            fs_hz: Some(self.fs_hz),
            window_samples: self.window,
            update_step_samples: self.update_step(),
            undefined_reports: self.undefined_reports,
        }
    }

    /// Forgets every sample: the next one starts a new warm-up (after a gap in time).
    pub fn restart(&mut self) {
        self.sine.reset();
        self.features.reset();
        self.report = None;
        self.samples = 0;
    }

    /// Pushes samples of acceleration (m/s^2) and returns the rows they complete: one per
    /// sample, in order (the delay is 0).
    ///
    /// # Errors
    /// As [`Estimator::push_into`]; the rows completed before the error are lost with this
    /// form, use `push_into` to keep them.
    pub fn push(&mut self, accel_ms2: &[f64]) -> Result<Vec<Row>, HybridError> {
        let mut rows = Vec::with_capacity(accel_ms2.len());
        self.push_into(accel_ms2, &mut rows)?;
        Ok(rows)
    }

    /// [`Estimator::push`] appending to `rows`, which keeps the rows of the samples before
    /// an error.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] for a NaN or infinite sample (naming its index; the
    /// sample is not used and the estimator stays as it was before it), and the correction's
    /// errors.
    pub fn push_into(&mut self, accel_ms2: &[f64], rows: &mut Vec<Row>) -> Result<(), HybridError> {
        rows.reserve(accel_ms2.len());
        for &a in accel_ms2 {
            rows.push(self.push_one(a)?);
        }
        Ok(())
    }

    fn push_one(&mut self, a: f64) -> Result<Row, HybridError> {
        if !a.is_finite() {
            return Err(HybridError::InvalidConfig(format!(
                "acceleration sample {} is NaN or infinite; the stream needs finite numbers",
                self.samples
            )));
        }
        self.sine.push(a);
        match self.features.push(a) {
            Ok(None) => {}
            Ok(Some(f)) => self.report = Some(self.correct(&f.to_array())?),
            Err(_) => {
                // Undefined features (a constant window): no correction until the next report.
                self.report = None;
                self.undefined_reports += 1;
            }
        }
        let sample = self.samples;
        self.samples += 1;
        // The sine's window (whole periods) may fill before the features' window: every row
        // of the warm-up stays empty all the same, so a row has both values or neither.
        let fit = if self.samples < self.window as u64 {
            None
        } else {
            self.sine.fit()
        };
        let Some([p, q, _]) = fit else {
            return Ok(Row {
                sample,
                time_s: sample as f64 / self.fs_hz,
                physics_um: None,
                hybrid_um: None,
                interval_um: None,
            });
        };
        let (s, c) = self.sine.basis();
        let amp_a = p.hypot(q);
        // The displacement of the acceleration's sine is -gain times it (a double integral).
        let unit = if amp_a > 0.0 {
            -(p * s + q * c) / amp_a
        } else {
            -s
        };
        let a_phys = self.gain * amp_a;
        let physics = a_phys * unit;
        let (hybrid, interval) = match self.report {
            None => (None, None),
            Some(r) => (
                Some((a_phys + r.delta_hat) * unit),
                r.interval.map(|(lo, hi)| {
                    let (x, y) = ((a_phys + lo) * unit, (a_phys + hi) * unit);
                    (x.min(y), x.max(y))
                }),
            ),
        };
        Ok(Row {
            sample,
            time_s: sample as f64 / self.fs_hz,
            physics_um: Some(physics),
            hybrid_um: hybrid,
            interval_um: interval,
        })
    }

    /// The correction (and its interval) for one feature vector.
    fn correct(&self, features: &[f64]) -> Result<Report, HybridError> {
        let columns = features.iter().map(|v| vec![*v]).collect();
        let table = Table::new(self.names.clone(), columns)?;
        let delta_hat = self.correction.predict(&table)?[0];
        let interval = match self.level {
            Some(level) => {
                let method = self
                    .model
                    .default_interval_method(level)
                    .unwrap_or(crate::IntervalMethod::Delta);
                self.model
                    .correction_intervals(&table, level, method)?
                    .first()
                    .copied()
            }
            None => None,
        };
        Ok(Report {
            delta_hat,
            interval,
        })
    }
}
