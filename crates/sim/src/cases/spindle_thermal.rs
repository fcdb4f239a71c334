//! A spindle's thermal drift (issue 69): a dynamic process, one row per sample of several
//! runs, whose truth has a term the textbook ODE lacks.
//!
//! The engineer's physics is a lumped heat balance of the spindle housing: heat from the
//! bearings grows as the speed to the power 1.5 (Palmgren's friction torque times speed),
//! heat leaves through a constant conductance to the ambient air:
//!
//! ```text
//! C dT/dt = q n^1.5 - h (T - Ta)
//! ```
//!
//! The generator's truth adds **forced convection**: the rotating spindle stirs the air
//! around it, so the conductance grows with the speed, `h (1 + k n)`
//! ([`SpindleThermalConfig::forced_convection_per_krpm`]; 0 switches it off). The true
//! correction of the calibrated textbook ODE is the term `-h k n (T - Ta) / C` inside the
//! derivative: a function of the state `T` and the inputs `n` and `Ta` (documented in
//! `docs/cases.md`).
//!
//! Each run starts near the ambient temperature and runs a program of speed steps (held
//! between samples, with idle spells), under an ambient that drifts slowly. The measured
//! temperature has normal scatter ([`SpindleThermalConfig::noise_k`]). Columns: `run`
//! (1-based), `time_s` (from the run's start), `speed_krpm` and `ambient_C` (the inputs,
//! held from this sample to the next), `humidity_pct` (a distractor with no effect) and the
//! measured state `T_C`. Integrated by [`crate::ode::integrate`] from sample to sample.

use super::{normal, positive, range, rng_for, uniform};
use crate::SimError;
use crate::ode::{OdeSettings, integrate};
use hxai_table::Table;
use rand::Rng;
use serde::{Deserialize, Serialize};

/// Settings of the spindle's thermal drift. Defaults and their reasons: `docs/cases.md`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SpindleThermalConfig {
    /// Runs (one warm-up program each).
    pub n_runs: usize,
    /// Samples per run.
    pub samples_per_run: usize,
    /// Time between samples (s).
    pub dt_s: f64,
    /// Seed of every random draw (run `r` draws from stream `r + 1`).
    pub seed: u64,
    /// Heat capacity of the housing, `C` (J/K).
    pub heat_capacity_j_k: f64,
    /// Bearing heat at 1 krpm, `q` (W per krpm^1.5).
    pub heat_w_per_krpm15: f64,
    /// Conductance to the ambient at rest, `h` (W/K).
    pub conductance_w_k: f64,
    /// Growth of the conductance with the speed, `k` in `h (1 + k n)` (per krpm): the term
    /// the textbook ODE lacks. 0 switches it off.
    pub forced_convection_per_krpm: f64,
    /// Speed range of a step, uniform (krpm).
    pub speed_krpm: [f64; 2],
    /// Share of steps spent idle (speed 0).
    pub idle_share: f64,
    /// Samples a speed step lasts, uniform over this range.
    pub step_samples: [usize; 2],
    /// Ambient temperature at a run's start, uniform (deg C).
    pub ambient_c: [f64; 2],
    /// Peak-to-peak drift of the ambient over a run (K), a half sine.
    pub ambient_drift_k: f64,
    /// Standard deviation of the measured temperature's scatter (K).
    pub noise_k: f64,
}

impl Default for SpindleThermalConfig {
    fn default() -> Self {
        Self {
            n_runs: 12,
            samples_per_run: 240,
            dt_s: 30.0,
            seed: super::DEFAULT_SEED,
            heat_capacity_j_k: 20_000.0,
            heat_w_per_krpm15: 40.0,
            conductance_w_k: 10.0,
            forced_convection_per_krpm: 0.05,
            speed_krpm: [1.0, 8.0],
            idle_share: 0.2,
            step_samples: [10, 40],
            ambient_c: [18.0, 24.0],
            ambient_drift_k: 2.0,
            noise_k: 0.05,
        }
    }
}

impl SpindleThermalConfig {
    /// Checks every setting.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] naming the setting.
    pub fn check(&self) -> Result<(), SimError> {
        if self.n_runs == 0 || self.samples_per_run == 0 {
            return Err(super::bad(
                "n_runs",
                format!("{} x {}", self.n_runs, self.samples_per_run),
                "give at least one run of at least one sample",
            ));
        }
        positive("dt_s", self.dt_s)?;
        positive("heat_capacity_j_k", self.heat_capacity_j_k)?;
        positive("conductance_w_k", self.conductance_w_k)?;
        super::non_negative("heat_w_per_krpm15", self.heat_w_per_krpm15)?;
        super::non_negative(
            "forced_convection_per_krpm",
            self.forced_convection_per_krpm,
        )?;
        super::non_negative("ambient_drift_k", self.ambient_drift_k)?;
        super::non_negative("noise_k", self.noise_k)?;
        range("speed_krpm", self.speed_krpm, false)?;
        range("ambient_c", self.ambient_c, false)?;
        if self.speed_krpm[0] < 0.0 {
            return Err(super::bad(
                "speed_krpm",
                self.speed_krpm[0],
                "a speed is >= 0",
            ));
        }
        if !(0.0..1.0).contains(&self.idle_share) {
            return Err(super::bad(
                "idle_share",
                self.idle_share,
                "a share in [0, 1)",
            ));
        }
        if self.step_samples[0] == 0 || self.step_samples[1] < self.step_samples[0] {
            return Err(super::bad(
                "step_samples",
                format!("{:?}", self.step_samples),
                "give [lo, hi] with 1 <= lo <= hi",
            ));
        }
        Ok(())
    }
}

/// The table of `cfg` (see the module docs); with `rows`, exactly that many rows: runs of
/// `samples_per_run` samples, the last one cut short.
///
/// # Errors
/// A bad configuration ([`SpindleThermalConfig::check`]), an integration that fails (a
/// configuration far outside the physical), or more rows than [`super::MAX_ROWS`].
pub fn spindle_thermal(cfg: &SpindleThermalConfig, rows: Option<usize>) -> Result<Table, SimError> {
    cfg.check()?;
    let total = rows.unwrap_or(cfg.n_runs * cfg.samples_per_run);
    super::rows(total)?;
    let names = [
        "run",
        "time_s",
        "speed_krpm",
        "ambient_C",
        "humidity_pct",
        "T_C",
    ];
    let mut cols: Vec<Vec<f64>> = vec![Vec::with_capacity(total); names.len()];
    let mut run = 0usize;
    while cols[0].len() < total {
        let n = cfg.samples_per_run.min(total - cols[0].len());
        for row in one_run(cfg, run, n)? {
            for (c, v) in cols.iter_mut().zip(row) {
                c.push(v);
            }
        }
        run += 1;
    }
    Ok(Table::new(
        names.iter().map(|s| s.to_string()).collect(),
        cols,
    )?)
}

/// The `n` samples of run `run` (0-based).
fn one_run(cfg: &SpindleThermalConfig, run: usize, n: usize) -> Result<Vec<[f64; 6]>, SimError> {
    let mut rng = rng_for(cfg.seed, Some(run));
    let ta0 = uniform(&mut rng, cfg.ambient_c);
    let phase = uniform(&mut rng, [0.0, std::f64::consts::PI]);
    let span = (cfg.samples_per_run as f64 * cfg.dt_s).max(cfg.dt_s);
    let ambient =
        |t: f64| ta0 + 0.5 * cfg.ambient_drift_k * (phase + std::f64::consts::PI * t / span).sin();
    let mut temp = ambient(0.0) + uniform(&mut rng, [0.0, 3.0]);
    let (mut speed, mut left) = (0.0, 0usize);
    let mut out = Vec::with_capacity(n);
    let (c, q, h, k) = (
        cfg.heat_capacity_j_k,
        cfg.heat_w_per_krpm15,
        cfg.conductance_w_k,
        cfg.forced_convection_per_krpm,
    );
    for i in 0..n {
        if left == 0 {
            speed = if rng.r#gen::<f64>() < cfg.idle_share {
                0.0
            } else {
                uniform(&mut rng, cfg.speed_krpm)
            };
            left = rng.gen_range(cfg.step_samples[0]..=cfg.step_samples[1]);
        }
        left -= 1;
        let t = i as f64 * cfg.dt_s;
        let ta = ambient(t);
        let humidity = uniform(&mut rng, [30.0, 60.0]);
        let measured = temp + cfg.noise_k * normal(&mut rng);
        out.push([(run + 1) as f64, t, speed, ta, humidity, measured]);
        // the inputs of this sample held until the next
        let mut rhs = |_: f64, y: &[f64], d: &mut [f64]| {
            d[0] = (q * speed.powf(1.5) - h * (1.0 + k * speed) * (y[0] - ta)) / c;
        };
        let next = integrate(
            &mut rhs,
            t,
            &[temp],
            &[t + cfg.dt_s],
            &OdeSettings::default(),
        )
        .map_err(|e| {
            super::bad(
                "spindle_thermal",
                e,
                "the heat balance cannot be integrated",
            )
        })?;
        temp = next[0][0];
    }
    Ok(out)
}
