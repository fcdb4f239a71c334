//! The physics model of the case study: acceleration -> displacement by band-pass filtering
//! and double integration with drift removal (paper eq. 6-7), as a configurable chain.

use std::f64::consts::PI;

use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use crate::SignalError;
use crate::design::{Band, butter};
use crate::error::{check_fs, check_signal};
use crate::filter::Sos;
use crate::integrate::{Detrend, cumulative_trapezoid, detrend_in_place};

/// How drift is removed after each time-domain integration.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Drift {
    /// Keep the drift (for studying its effect).
    None,
    /// Subtract the least-squares line (removes the unknown integration constant and the ramp
    /// a small acceleration offset leaves behind).
    Linear,
    /// Zero-phase Butterworth high-pass (`filtfilt`) of the given order and cutoff (Hz).
    Highpass {
        /// Filter order (at least 1).
        order: usize,
        /// Cutoff in Hz; keep it well below the lowest command frequency.
        cutoff_hz: f64,
    },
}

/// How acceleration is integrated twice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Integrator {
    /// Band-pass filter (Butterworth, `filtfilt`), then cumulative trapezoid twice with drift
    /// removal after each step.
    Time,
    /// Divide the spectrum by `-omega^2` inside the band `[low_hz, high_hz]` and zero it
    /// outside (an ideal band-pass; the Butterworth filter and the drift step are not used).
    Frequency,
}

/// Unit of the returned displacement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum LengthUnit {
    /// Metres (the natural unit of integrating m/s^2 twice).
    Metres,
    /// Micrometres (the unit of the probe and of the hybrid model).
    Micrometres,
}

impl LengthUnit {
    fn factor(self) -> f64 {
        match self {
            LengthUnit::Metres => 1.0,
            LengthUnit::Micrometres => 1e6,
        }
    }
}

/// Settings of [`displacement`]. Check them once with [`PhysicsConfig::check`].
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PhysicsConfig {
    /// Lower band edge, Hz. Default 5 Hz: half the lowest command frequency (10 Hz), so a
    /// 4th-order edge costs 0.2 % amplitude at 10 Hz and under 1e-6 at 20-40 Hz (after `filtfilt`), while the
    /// accelerometer's low-frequency noise and offset, which double integration amplifies by
    /// 1/omega^2, are cut.
    pub low_hz: f64,
    /// Upper band edge, Hz. Default 200 Hz: five times the highest command frequency (40 Hz),
    /// keeping the first harmonics of the motion, removing high-frequency vibration and
    /// noise. Needs a sampling rate above 400 Hz.
    pub high_hz: f64,
    /// Butterworth order of the band-pass (default 4, as in common practice for accelerometer
    /// integration; `filtfilt` doubles the effective order and removes the phase shift, so the
    /// displacement stays aligned with the probe).
    pub order: usize,
    /// Time- or frequency-domain integration (default [`Integrator::Time`], the paper's
    /// eq. 6-7).
    pub integrator: Integrator,
    /// Drift removal after each integration (default [`Drift::Linear`]: the record is short
    /// and the band-pass already removed the offset, so a straight line is the whole drift).
    pub drift: Drift,
    /// Unit of the output (default micrometres, the hybrid model's unit).
    pub unit: LengthUnit,
}

impl Default for PhysicsConfig {
    fn default() -> Self {
        Self {
            low_hz: 5.0,
            high_hz: 200.0,
            order: 4,
            integrator: Integrator::Time,
            drift: Drift::Linear,
            unit: LengthUnit::Micrometres,
        }
    }
}

/// A checked [`PhysicsConfig`] for one sampling rate, with the filters designed. Reuse it for
/// many records of the same rate.
#[derive(Debug, Clone)]
pub struct ValidPhysics {
    cfg: PhysicsConfig,
    fs: f64,
    bandpass: Option<Sos>,
    drift: Option<Sos>,
}

impl PhysicsConfig {
    /// Validates the settings for sampling rate `fs` and designs the filters.
    ///
    /// # Errors
    /// [`SignalError::InvalidSampleRate`], [`SignalError::InvalidCutoff`],
    /// [`SignalError::InvalidBand`], [`SignalError::ZeroOrder`].
    pub fn check(&self, fs: f64) -> Result<ValidPhysics, SignalError> {
        check_fs(fs)?;
        let band = Band::Bandpass(self.low_hz, self.high_hz);
        band.check(fs)?;
        let (bandpass, drift) = match self.integrator {
            Integrator::Frequency => (None, None),
            Integrator::Time => {
                let bp = butter(self.order, band, fs)?;
                let drift = match self.drift {
                    Drift::Highpass { order, cutoff_hz } => {
                        Some(butter(order, Band::Highpass(cutoff_hz), fs)?)
                    }
                    Drift::None | Drift::Linear => None,
                };
                (Some(bp), drift)
            }
        };
        Ok(ValidPhysics {
            cfg: self.clone(),
            fs,
            bandpass,
            drift,
        })
    }
}

impl ValidPhysics {
    /// The settings this was checked from.
    pub fn config(&self) -> &PhysicsConfig {
        &self.cfg
    }

    /// Shortest record the chain accepts (the `filtfilt` padding), in samples.
    pub fn min_len(&self) -> usize {
        let a = self.bandpass.as_ref().map_or(1, |s| s.padlen() + 1);
        let b = self.drift.as_ref().map_or(1, |s| s.padlen() + 1);
        a.max(b).max(2)
    }

    /// The chain's gain on a sine of `frequency_hz`: the displacement amplitude (in the configured
    /// unit) that [`ValidPhysics::displacement`] makes of an acceleration sine of amplitude 1
    /// m/s^2, away from the record's ends. Its sign is the phase: the displacement of
    /// `sin(w t)` is `-gain * sin(w t)`.
    ///
    /// Time integration: the zero-phase band-pass passes `|H(f)|^2`, each cumulative
    /// trapezoid integrates a sampled sine with gain `(T / 2) cot(w T / 2)` (`1 / w` less a
    /// relative `(w T)^2 / 12`) and a phase of exactly -90 degrees, and a high-pass drift
    /// filter passes `|H_d(f)|^2` after each integration. A linear drift removal is a
    /// projection that leaves a sine of whole periods unchanged and is taken as 1. Frequency
    /// integration: `1 / w^2` inside the band, 0 outside. The streaming estimator
    /// (`hxai_hybrid::records::stream`) uses this to turn the acceleration's sine at the command
    /// frequency into the physics model's displacement without integrating.
    pub fn gain_at(&self, frequency_hz: f64) -> f64 {
        let w = 2.0 * PI * frequency_hz;
        let unit = self.cfg.unit.factor();
        match (&self.bandpass, self.cfg.integrator) {
            (Some(bp), Integrator::Time) => {
                let dt = 1.0 / self.fs;
                let half = w * dt / 2.0;
                let integrate = dt / 2.0 / half.tan();
                let drift = self
                    .drift
                    .as_ref()
                    .map_or(1.0, |hp| hp.gain(frequency_hz, self.fs).powi(4));
                unit * bp.gain(frequency_hz, self.fs).powi(2) * integrate * integrate * drift
            }
            _ => {
                if frequency_hz >= self.cfg.low_hz && frequency_hz <= self.cfg.high_hz {
                    unit / (w * w)
                } else {
                    0.0
                }
            }
        }
    }

    /// Displacement from acceleration in m/s^2, in the configured unit.
    ///
    /// # Errors
    /// [`SignalError::Empty`], [`SignalError::NonFinite`], [`SignalError::TooShort`].
    pub fn displacement(&self, accel_ms2: &[f64]) -> Result<Vec<f64>, SignalError> {
        check_signal(accel_ms2, "accel_ms2")?;
        if accel_ms2.len() < self.min_len() {
            return Err(SignalError::TooShort {
                len: accel_ms2.len(),
                needed: self.min_len() - 1,
                operation: "the physics model (filter padding)",
            });
        }
        let dt = 1.0 / self.fs;
        let mut d = match (&self.bandpass, self.cfg.integrator) {
            (Some(bp), Integrator::Time) => {
                let af = bp.filtfilt(accel_ms2)?;
                let mut v = cumulative_trapezoid(&af, dt);
                self.remove_drift(&mut v)?;
                let mut d = cumulative_trapezoid(&v, dt);
                self.remove_drift(&mut d)?;
                d
            }
            _ => self.frequency_domain(accel_ms2)?,
        };
        let f = self.cfg.unit.factor();
        d.iter_mut().for_each(|v| *v *= f);
        Ok(d)
    }

    fn remove_drift(&self, x: &mut Vec<f64>) -> Result<(), SignalError> {
        match (self.cfg.drift, &self.drift) {
            (Drift::Highpass { .. }, Some(hp)) => *x = hp.filtfilt(x)?,
            (Drift::Linear, _) => detrend_in_place(x, Detrend::Linear),
            _ => {}
        }
        Ok(())
    }

    fn frequency_domain(&self, a: &[f64]) -> Result<Vec<f64>, SignalError> {
        let n = a.len();
        let mut planner = RealFftPlanner::<f64>::new();
        let fwd = planner.plan_fft_forward(n);
        let inv = planner.plan_fft_inverse(n);
        let mut buf = a.to_vec();
        let mut spec = fwd.make_output_vec();
        let fft_err = |e: realfft::FftError| SignalError::InvalidConfig(format!("FFT failed: {e}"));
        fwd.process(&mut buf, &mut spec).map_err(fft_err)?;
        let df = self.fs / n as f64;
        for (k, c) in spec.iter_mut().enumerate() {
            let f = k as f64 * df;
            if f >= self.cfg.low_hz && f <= self.cfg.high_hz {
                let w = 2.0 * PI * f;
                *c /= -(w * w) * n as f64;
            } else {
                *c = Complex::new(0.0, 0.0);
            }
        }
        // The inverse of a real signal's spectrum needs real DC and Nyquist bins.
        if let Some(c) = spec.last_mut()
            && n.is_multiple_of(2)
        {
            c.im = 0.0;
        }
        let mut out = inv.make_output_vec();
        inv.process(&mut spec, &mut out).map_err(fft_err)?;
        Ok(out)
    }
}

/// Displacement from acceleration (m/s^2, sampled at `fs` Hz) by the physics chain `cfg`;
/// the unit of the result is `cfg.unit` (micrometres by default). Equivalent to
/// `cfg.check(fs)?.displacement(accel_ms2)`.
///
/// # Errors
/// Those of [`PhysicsConfig::check`] and [`ValidPhysics::displacement`].
pub fn displacement(
    accel_ms2: &[f64],
    fs: f64,
    cfg: &PhysicsConfig,
) -> Result<Vec<f64>, SignalError> {
    cfg.check(fs)?.displacement(accel_ms2)
}
