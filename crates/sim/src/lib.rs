//! Simulator of the slow-tool-servo (STS) Z axis of an ultra-precision diamond-turning
//! machine, with the four channels the paper recorded: command, encoder, capacitance probe
//! (ground truth) and an ICP accelerometer near the tool-centre point.
//!
//! The paper's recordings are not reachable, so this crate stands in for the machine. It is
//! calibrated so that the published *magnitudes* come out of physics, not of fudge terms
//! (targets and every parameter with its reason: `docs/simulator.md`):
//!
//! * the slide follows the command through a closed position loop (second order, slightly
//!   under-damped) disturbed by Stribeck friction, so it overshoots the command more at
//!   higher frequency and, relative to friction, at higher amplitude;
//! * the tool tip sits on a flexible tool holder *outside* the servo loop (a mass-spring-damper
//!   driven by slide acceleration), so the probe exceeds the encoder, more at high frequency;
//! * the encoder reads the slide through a read-out delay, so it lags and under-reads the probe;
//! * the accelerometer sees the holder near (not at) the tip, through a sensitivity error, the
//!   ICP coupling high-pass, 1/f and white noise, mains pick-up, spindle-synchronous
//!   vibration and 16-bit conversion; double integration of it (the physics model) therefore
//!   misses the true amplitude in a frequency-dependent way.
//!
//! Main types: [`SimConfig`] (all parameters, [`SimConfig::check`]), [`SimRecord`] (one
//! record in memory), [`SimError`]. Entry points: [`simulate`], [`simulate_with_progress`],
//! [`record_plan`].
//!
//! Design decision: every record draws its randomness from its own `ChaCha8Rng` seeded by
//! `(seed, record index)` (the index selects the ChaCha stream), so the records are
//! independent, can be computed in parallel with rayon, and the result is bit-identical for a
//! seed whatever the thread count. The crate does not touch files (only `hxai-data` does).
//!
//! ```
//! use hxai_sim::{SimConfig, simulate};
//! let cfg = SimConfig {
//!     amplitudes_um: vec![5.0],
//!     frequencies_hz: vec![20.0],
//!     repeats: 1,
//!     duration_s: 0.2,
//!     fs_hz: 2_000.0,
//!     ..SimConfig::default()
//! };
//! let records = simulate(&cfg)?;
//! assert_eq!(records.len(), 1);
//! assert_eq!(records[0].probe_um.len(), 400);
//! # Ok::<(), hxai_sim::SimError>(())
//! ```
#![deny(missing_docs)]

pub mod cases;
mod config;
mod error;
mod machine;
pub mod ode;
mod sensors;

pub use config::{
    AccelParams, BaseParams, EncoderParams, Harmonic, MAX_INTERNAL_STEPS, ProbeParams, ServoParams,
    SimConfig, ToolParams,
};
pub use error::SimError;
pub use hxai_table::Par;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One simulated record: all channels sampled at `fs` Hz, `time_s[i] = i / fs`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SimRecord {
    /// Unique id, e.g. `a4um_f10hz_r1`.
    pub id: String,
    /// Commanded amplitude (um).
    pub amplitude_um: f64,
    /// Commanded frequency (Hz).
    pub frequency_hz: f64,
    /// Repeat number, starting at 1.
    pub repeat: usize,
    /// Sampling rate (Hz); files written before the rename call it `fs`.
    #[serde(alias = "fs")]
    pub fs_hz: f64,
    /// Sample times (s).
    pub time_s: Vec<f64>,
    /// Accelerometer, Z, as recorded (m/s^2).
    pub accel_ms2: Vec<f64>,
    /// Capacitance probe: true tool position (um).
    pub probe_um: Vec<f64>,
    /// Command (um).
    pub command_um: Vec<f64>,
    /// Encoder: slide position as read out (um).
    pub encoder_um: Vec<f64>,
}

/// Which condition a record index stands for.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordSpec {
    /// Index in [`simulate`]'s output (amplitude-major, then frequency, then repeat).
    pub index: usize,
    /// Record id.
    pub id: String,
    /// Commanded amplitude (um).
    pub amplitude_um: f64,
    /// Commanded frequency (Hz).
    pub frequency_hz: f64,
    /// Repeat number, starting at 1.
    pub repeat: usize,
}

/// The records a configuration describes, in output order (no simulation is run).
pub fn record_plan(cfg: &SimConfig) -> Vec<RecordSpec> {
    let mut out = Vec::with_capacity(cfg.n_records());
    for &a in &cfg.amplitudes_um {
        for &f in &cfg.frequencies_hz {
            for r in 1..=cfg.repeats {
                out.push(RecordSpec {
                    index: out.len(),
                    id: format!("a{a}um_f{f}hz_r{r}"),
                    amplitude_um: a,
                    frequency_hz: f,
                    repeat: r,
                });
            }
        }
    }
    out
}

/// Simulates every record of the configuration (see [`simulate_with_progress`]).
pub fn simulate(cfg: &SimConfig) -> Result<Vec<SimRecord>, SimError> {
    simulate_with_progress(cfg, &|| {})
}

/// Simulates every record, in parallel on the threads `cfg.par` chooses, calling `progress` once per finished record (from
/// any thread). The result depends on the configuration only, never on the thread count.
pub fn simulate_with_progress(
    cfg: &SimConfig,
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<SimRecord>, SimError> {
    cfg.check()?;
    let plan = record_plan(cfg);
    cfg.par.run(|| {
        plan.into_par_iter()
            .map(|spec| {
                let rec = simulate_one(cfg, &spec);
                progress();
                rec
            })
            .collect()
    })
}

/// Simulates a single record of the plan (validates the configuration first).
pub fn simulate_record(cfg: &SimConfig, spec: &RecordSpec) -> Result<SimRecord, SimError> {
    cfg.check()?;
    simulate_one(cfg, spec)
}

fn simulate_one(cfg: &SimConfig, spec: &RecordSpec) -> Result<SimRecord, SimError> {
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed);
    rng.set_stream(spec.index as u64);
    let fs = cfg.fs_hz;
    let trace = machine::run(cfg, spec.amplitude_um, spec.frequency_hz);
    let n = cfg.samples_per_record();
    let n_warm = trace.accel.len() - n;
    let t0 = -(n_warm as f64) / fs;
    let accel = sensors::accelerometer(
        &trace.accel,
        t0,
        fs,
        spec.frequency_hz,
        &cfg.accel,
        &mut rng,
    )?;
    let probe = sensors::probe(&trace.probe_lp[n_warm..], cfg, &mut rng);
    let enc_step = cfg.encoder.resolution_nm * 1e-3;
    let encoder = trace.encoder[n_warm..]
        .iter()
        .map(|&x| sensors::quantise(x, enc_step))
        .collect();
    Ok(SimRecord {
        id: spec.id.clone(),
        amplitude_um: spec.amplitude_um,
        frequency_hz: spec.frequency_hz,
        repeat: spec.repeat,
        fs_hz: fs,
        time_s: (0..n).map(|i| i as f64 / fs).collect(),
        accel_ms2: accel[n_warm..].to_vec(),
        probe_um: probe,
        command_um: trace.command[n_warm..].to_vec(),
        encoder_um: encoder,
    })
}
