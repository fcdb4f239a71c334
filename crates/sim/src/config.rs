//! Simulator parameters: one [`SimConfig`] with named groups, defaults and up-front validation.
//!
//! Every default and the reason for it is listed in `docs/simulator.md`.

use crate::SimError;
use hxai_table::Par;
use serde::{Deserialize, Serialize};

/// Closed-loop Z slide: second-order servo from command to slide position plus friction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ServoParams {
    /// Natural frequency of the closed position loop (Hz).
    pub natural_hz: f64,
    /// Damping ratio of the closed position loop (-).
    pub damping: f64,
    /// Coulomb (sliding) friction, as an acceleration of the slide (m/s^2).
    pub coulomb_ms2: f64,
    /// Static (breakaway) friction, as an acceleration (m/s^2); >= `coulomb_ms2`.
    pub static_ms2: f64,
    /// Stribeck velocity: how fast friction falls from static to Coulomb (um/s).
    pub stribeck_um_s: f64,
    /// Velocity over which the friction sign is smoothed at reversals (um/s).
    pub smoothing_um_s: f64,
}

impl Default for ServoParams {
    fn default() -> Self {
        Self {
            natural_hz: 110.0,
            damping: 0.45,
            coulomb_ms2: 0.06,
            static_ms2: 0.09,
            stribeck_um_s: 60.0,
            smoothing_um_s: 2.0,
        }
    }
}

/// Flexible tool holder outside the servo loop: the tool tip is a mass-spring-damper on the slide.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ToolParams {
    /// Natural frequency of the tool-holder mode (Hz).
    pub natural_hz: f64,
    /// Damping ratio of the tool-holder mode (-).
    pub damping: f64,
}

impl Default for ToolParams {
    fn default() -> Self {
        Self {
            natural_hz: 120.0,
            damping: 0.05,
        }
    }
}

/// Machine frame (base) mode excited by the reaction force of the slide. The probe and the
/// encoder measure relative to the frame and do not see it; the accelerometer is inertial
/// and does.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BaseParams {
    /// Natural frequency of the frame mode (Hz).
    pub natural_hz: f64,
    /// Damping ratio of the frame mode (-).
    pub damping: f64,
    /// Slide mass over the frame's modal mass (-).
    pub mass_ratio: f64,
}

impl Default for BaseParams {
    fn default() -> Self {
        Self {
            natural_hz: 20.0,
            damping: 0.15,
            mass_ratio: 0.03,
        }
    }
}

/// One spindle-synchronous vibration component seen by the accelerometer only.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Harmonic {
    /// Order: multiple of the spindle rotation frequency (1 = once per revolution).
    pub order: u32,
    /// Acceleration amplitude when the spindle turns at `AccelParams::spindle_ref_hz` (m/s^2);
    /// it scales with the square of the spindle frequency (unbalance-type forcing).
    pub amplitude_ms2: f64,
    /// Phase relative to the command sinusoid (rad); fixed because the Z motion is spindle-synchronous.
    pub phase_rad: f64,
}

/// ICP accelerometer and its DAQ channel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AccelParams {
    /// Relative sensitivity error (measured / true - 1), e.g. -0.03 reads 3 % low (-).
    pub sensitivity_error: f64,
    /// Ratio of the tool-holder mode shape at the accelerometer to that at the tool tip (-):
    /// 1 = mounted at the tip; the sensor sits near the TCP, on the holder body.
    pub mode_shape_ratio: f64,
    /// Corner of the ICP coupling high-pass (first order, Hz).
    pub highpass_hz: f64,
    /// Number of cascaded first-order high-pass stages (sensor discharge, conditioner coupling).
    pub highpass_stages: u32,
    /// White noise density of the sensor and its conditioning (m/s^2/sqrt(Hz)).
    pub noise_density: f64,
    /// Flicker (1/f) corner: below it the noise density rises as 1/sqrt(f) (Hz).
    pub flicker_corner_hz: f64,
    /// Mains frequency (Hz).
    pub mains_hz: f64,
    /// Mains pick-up amplitude (m/s^2 equivalent).
    pub mains_ms2: f64,
    /// Spindle rotation frequency as a fraction of the command frequency (1 = one Z cycle per revolution).
    pub spindle_per_command: f64,
    /// Spindle frequency at which the harmonic amplitudes are given (Hz).
    pub spindle_ref_hz: f64,
    /// Spindle-synchronous components.
    pub harmonics: Vec<Harmonic>,
    /// Sensor sensitivity (mV per m/s^2), sets the DAQ range in m/s^2.
    pub sensitivity_mv_per_ms2: f64,
    /// DAQ input range, +- this voltage (V).
    pub daq_range_v: f64,
    /// DAQ resolution (bits).
    pub adc_bits: u32,
}

impl Default for AccelParams {
    fn default() -> Self {
        Self {
            sensitivity_error: -0.04,
            mode_shape_ratio: 0.7,
            highpass_hz: 0.5,
            highpass_stages: 2,
            noise_density: 4.0e-4,
            flicker_corner_hz: 10.0,
            mains_hz: 50.0,
            mains_ms2: 0.02,
            spindle_per_command: 1.0,
            spindle_ref_hz: 40.0,
            harmonics: vec![
                Harmonic {
                    order: 2,
                    amplitude_ms2: 0.02,
                    phase_rad: 0.4,
                },
                Harmonic {
                    order: 3,
                    amplitude_ms2: 0.01,
                    phase_rad: 1.3,
                },
            ],
            sensitivity_mv_per_ms2: 10.2,
            daq_range_v: 1.0,
            adc_bits: 16,
        }
    }
}

/// Capacitance probe (the ground truth channel).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ProbeParams {
    /// Bandwidth (first-order low-pass corner, Hz).
    pub bandwidth_hz: f64,
    /// White noise, RMS (nm).
    pub noise_nm: f64,
    /// Resolution, the quantisation step (nm).
    pub resolution_nm: f64,
}

impl Default for ProbeParams {
    fn default() -> Self {
        Self {
            bandwidth_hz: 1000.0,
            noise_nm: 2.0,
            resolution_nm: 1.0,
        }
    }
}

/// Linear encoder of the Z slide as read by the DAQ.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EncoderParams {
    /// Resolution, the quantisation step (nm).
    pub resolution_nm: f64,
    /// Transport delay of the position read-out (controller cycle and interpolation, s).
    pub delay_s: f64,
}

impl Default for EncoderParams {
    fn default() -> Self {
        Self {
            resolution_nm: 5.0,
            delay_s: 0.5e-3,
        }
    }
}

/// Everything the simulator needs: test matrix, sampling, and the machine and sensor models.
///
/// Build it with `SimConfig::default()` and change fields; [`SimConfig::check`] (called by
/// [`crate::simulate`]) rejects bad values before any work starts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimConfig {
    /// Seed of every random choice.
    pub seed: u64,
    /// Commanded amplitudes (um).
    pub amplitudes_um: Vec<f64>,
    /// Commanded frequencies (Hz).
    pub frequencies_hz: Vec<f64>,
    /// Repeats of each (amplitude, frequency) condition.
    pub repeats: usize,
    /// Record length (s).
    pub duration_s: f64,
    /// DAQ sampling rate (Hz).
    pub fs_hz: f64,
    /// Minimum internal integration steps per output sample (RK4).
    pub oversample: usize,
    /// Motion simulated before the record starts, so the record is in steady state (s).
    pub warmup_s: f64,
    /// Servo-controlled slide.
    pub servo: ServoParams,
    /// Tool-holder mode.
    pub tool: ToolParams,
    /// Machine frame mode.
    pub base: BaseParams,
    /// Accelerometer channel.
    pub accel: AccelParams,
    /// Capacitance probe channel.
    pub probe: ProbeParams,
    /// Encoder channel.
    pub encoder: EncoderParams,
    /// Threads that simulate the records (default [`Par::Current`], the caller's pool).
    /// Not part of any file (`serde(skip)`): the records do not depend on it.
    #[serde(skip)]
    pub par: Par,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            seed: 42,
            amplitudes_um: (4..=11).map(f64::from).collect(),
            frequencies_hz: (0..7).map(|i| 10.0 + 5.0 * f64::from(i)).collect(),
            repeats: 3,
            duration_s: 2.0,
            fs_hz: 10_000.0,
            oversample: 4,
            warmup_s: 0.5,
            servo: ServoParams::default(),
            tool: ToolParams::default(),
            base: BaseParams::default(),
            accel: AccelParams::default(),
            probe: ProbeParams::default(),
            encoder: EncoderParams::default(),
            par: Par::Current,
        }
    }
}

/// Largest number of internal integration steps per record.
pub const MAX_INTERNAL_STEPS: u64 = 50_000_000;

fn bad(name: &'static str, value: impl std::fmt::Display, reason: &str) -> SimError {
    SimError::InvalidParameter {
        name,
        value: value.to_string(),
        reason: reason.to_string(),
    }
}

fn positive(name: &'static str, v: f64) -> Result<(), SimError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(bad(name, v, "must be a finite number greater than 0"))
    }
}

fn non_negative(name: &'static str, v: f64) -> Result<(), SimError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(bad(name, v, "must be a finite number >= 0"))
    }
}

fn finite(name: &'static str, v: f64) -> Result<(), SimError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(bad(name, v, "must be a finite number"))
    }
}

impl SimConfig {
    /// Number of records the configuration describes.
    pub fn n_records(&self) -> usize {
        self.amplitudes_um.len() * self.frequencies_hz.len() * self.repeats
    }

    /// Samples per record at the DAQ rate.
    pub fn samples_per_record(&self) -> usize {
        // Validated configs keep this well inside usize.
        (self.duration_s * self.fs_hz).round() as usize
    }

    /// Internal integration steps per output sample: at least `oversample`, and enough that
    /// the stiffest part of the model (modes, friction smoothing) stays well inside RK4's
    /// stability region (h * lambda_max <= 1).
    pub fn substeps(&self) -> usize {
        let lambda = self.stiffest_rate();
        let needed = (lambda / self.fs_hz).ceil();
        let needed = if needed.is_finite() && needed >= 1.0 {
            needed as usize
        } else {
            1
        };
        self.oversample.max(needed)
    }

    /// Largest eigenvalue magnitude (1/s) of the model's linearisation, an upper bound.
    fn stiffest_rate(&self) -> f64 {
        let wn = 2.0 * std::f64::consts::PI * self.servo.natural_hz;
        let wt = 2.0 * std::f64::consts::PI * self.tool.natural_hz;
        let fric =
            self.servo.static_ms2.max(self.servo.coulomb_ms2) * 1e6 / self.servo.smoothing_um_s;
        // Modes: |lambda| = omega; damping terms add at most 2 zeta omega.
        let slide = wn * (1.0 + 2.0 * self.servo.damping) + fric;
        let tool = wt * (1.0 + 2.0 * self.tool.damping) + slide;
        let wb = 2.0 * std::f64::consts::PI * self.base.natural_hz;
        let base = wb * (1.0 + 2.0 * self.base.damping) + self.base.mass_ratio * slide;
        slide.max(tool).max(base)
    }

    /// Checks every parameter; returns the first problem found, with how to mend it.
    pub fn check(&self) -> Result<(), SimError> {
        if self.amplitudes_um.is_empty() {
            return Err(SimError::EmptyList {
                name: "amplitudes_um",
            });
        }
        if self.frequencies_hz.is_empty() {
            return Err(SimError::EmptyList {
                name: "frequencies_hz",
            });
        }
        for &a in &self.amplitudes_um {
            positive("amplitudes_um", a)?;
            if a > 1000.0 {
                return Err(bad(
                    "amplitudes_um",
                    a,
                    "must be at most 1000 um (a slow-tool-servo stroke)",
                ));
            }
        }
        positive("fs_hz", self.fs_hz)?;
        for &f in &self.frequencies_hz {
            positive("frequencies_hz", f)?;
            if f > self.fs_hz / 10.0 {
                return Err(bad(
                    "frequencies_hz",
                    f,
                    "must be at most fs_hz / 10 (ten samples per period): raise fs_hz or lower the frequency",
                ));
            }
        }
        if self.repeats == 0 {
            return Err(bad("repeats", self.repeats, "must be at least 1"));
        }
        positive("duration_s", self.duration_s)?;
        if self.duration_s * self.fs_hz < 16.0 {
            return Err(bad(
                "duration_s",
                self.duration_s,
                "the record must hold at least 16 samples: raise duration_s or fs_hz",
            ));
        }
        if self.oversample == 0 || self.oversample > 1000 {
            return Err(bad(
                "oversample",
                self.oversample,
                "must be between 1 and 1000",
            ));
        }
        non_negative("warmup_s", self.warmup_s)?;
        let s = &self.servo;
        positive("servo.natural_hz", s.natural_hz)?;
        positive("servo.damping", s.damping)?;
        non_negative("servo.coulomb_ms2", s.coulomb_ms2)?;
        non_negative("servo.static_ms2", s.static_ms2)?;
        if s.static_ms2 < s.coulomb_ms2 {
            return Err(bad(
                "servo.static_ms2",
                s.static_ms2,
                "static friction must be >= servo.coulomb_ms2",
            ));
        }
        positive("servo.stribeck_um_s", s.stribeck_um_s)?;
        positive("servo.smoothing_um_s", s.smoothing_um_s)?;
        positive("tool.natural_hz", self.tool.natural_hz)?;
        positive("tool.damping", self.tool.damping)?;
        positive("base.natural_hz", self.base.natural_hz)?;
        positive("base.damping", self.base.damping)?;
        non_negative("base.mass_ratio", self.base.mass_ratio)?;
        if self.base.mass_ratio > 1.0 {
            return Err(bad(
                "base.mass_ratio",
                self.base.mass_ratio,
                "must be at most 1 (the slide is lighter than the frame)",
            ));
        }
        let a = &self.accel;
        finite("accel.sensitivity_error", a.sensitivity_error)?;
        if a.sensitivity_error <= -1.0 {
            return Err(bad(
                "accel.sensitivity_error",
                a.sensitivity_error,
                "must be greater than -1 (the sensor must read something)",
            ));
        }
        non_negative("accel.mode_shape_ratio", a.mode_shape_ratio)?;
        non_negative("accel.highpass_hz", a.highpass_hz)?;
        if a.highpass_stages > 8 {
            return Err(bad(
                "accel.highpass_stages",
                a.highpass_stages,
                "must be at most 8",
            ));
        }
        if a.highpass_hz >= self.fs_hz / 4.0 {
            return Err(bad(
                "accel.highpass_hz",
                a.highpass_hz,
                "must be below fs_hz / 4",
            ));
        }
        non_negative("accel.noise_density", a.noise_density)?;
        non_negative("accel.flicker_corner_hz", a.flicker_corner_hz)?;
        positive("accel.mains_hz", a.mains_hz)?;
        non_negative("accel.mains_ms2", a.mains_ms2)?;
        positive("accel.spindle_per_command", a.spindle_per_command)?;
        positive("accel.spindle_ref_hz", a.spindle_ref_hz)?;
        for h in &a.harmonics {
            if h.order == 0 {
                return Err(bad("accel.harmonics.order", h.order, "must be at least 1"));
            }
            non_negative("accel.harmonics.amplitude_ms2", h.amplitude_ms2)?;
            finite("accel.harmonics.phase_rad", h.phase_rad)?;
        }
        positive("accel.sensitivity_mv_per_ms2", a.sensitivity_mv_per_ms2)?;
        positive("accel.daq_range_v", a.daq_range_v)?;
        if !(2..=32).contains(&a.adc_bits) {
            return Err(bad(
                "accel.adc_bits",
                a.adc_bits,
                "must be between 2 and 32",
            ));
        }
        positive("probe.bandwidth_hz", self.probe.bandwidth_hz)?;
        non_negative("probe.noise_nm", self.probe.noise_nm)?;
        non_negative("probe.resolution_nm", self.probe.resolution_nm)?;
        non_negative("encoder.resolution_nm", self.encoder.resolution_nm)?;
        non_negative("encoder.delay_s", self.encoder.delay_s)?;
        if self.encoder.delay_s > self.warmup_s {
            return Err(bad(
                "encoder.delay_s",
                self.encoder.delay_s,
                "must not exceed warmup_s (the delayed read-out needs simulated history)",
            ));
        }
        let steps = (self.duration_s + self.warmup_s) * self.fs_hz * self.substeps() as f64;
        if steps.is_nan() || steps > MAX_INTERNAL_STEPS as f64 {
            return Err(SimError::TooLarge {
                samples: if steps.is_finite() {
                    steps as u64
                } else {
                    u64::MAX
                },
                limit: MAX_INTERNAL_STEPS,
            });
        }
        Ok(())
    }
}
