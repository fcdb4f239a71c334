//! Shared evaluation of simulated records, the way the hybrid crate evaluates them: physics
//! displacement on the whole record, then windows (0.5 s after discarding 0.25 s at each
//! end); R^2 pooled over all windows' samples of (probe - window mean) vs physics.
#![allow(dead_code)]

use hxai_signal::{PhysicsConfig, displacement, fit_sine};
use hxai_sim::SimRecord;

/// Window length (s).
pub const WINDOW_S: f64 = 0.5;
/// Discarded at each record end (s).
pub const EDGE_S: f64 = 0.25;

/// One window's latent variables.
#[derive(Debug, Clone)]
pub struct WindowStats {
    pub amplitude_um: f64,
    pub frequency_hz: f64,
    /// fit_sine amplitude of the probe window.
    pub a_true: f64,
    /// fit_sine amplitude of the physics displacement window.
    pub a_phys: f64,
    /// fit_sine amplitude of the command window.
    pub a_cmd: f64,
    /// fit_sine amplitude of the encoder window.
    pub a_enc: f64,
    /// Phase of probe minus phase of encoder (rad, wrapped to (-pi, pi]); > 0: encoder lags.
    pub probe_minus_encoder_phase: f64,
}

impl WindowStats {
    pub fn delta(&self) -> f64 {
        self.a_true - self.a_phys
    }
}

/// Everything the calibration targets are checked on.
#[derive(Debug, Clone)]
pub struct Evaluation {
    pub r2: f64,
    pub rmse_um: f64,
    pub windows: Vec<WindowStats>,
}

fn wrap(p: f64) -> f64 {
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut x = p % two_pi;
    if x > std::f64::consts::PI {
        x -= two_pi;
    } else if x <= -std::f64::consts::PI {
        x += two_pi;
    }
    x
}

pub fn evaluate(records: &[SimRecord]) -> Result<Evaluation, Box<dyn std::error::Error>> {
    let cfg = PhysicsConfig::default();
    let (mut sse, mut n) = (0.0, 0usize);
    let mut ys: Vec<f64> = Vec::new();
    let mut windows = Vec::new();
    for r in records {
        let fs = r.fs_hz;
        let phys = displacement(&r.accel_ms2, fs, &cfg)?;
        let edge = (EDGE_S * fs).round() as usize;
        let win = (WINDOW_S * fs).round() as usize;
        let mut start = edge;
        while start + win + edge <= r.probe_um.len() {
            let rng = start..start + win;
            let p = &r.probe_um[rng.clone()];
            let x = &phys[rng.clone()];
            let mean = p.iter().sum::<f64>() / win as f64;
            for (pi, xi) in p.iter().zip(x) {
                let y = pi - mean;
                sse += (y - xi).powi(2);
                ys.push(y);
                n += 1;
            }
            let f = r.frequency_hz;
            let ft = fit_sine(p, fs, f)?;
            let fp = fit_sine(x, fs, f)?;
            let fc = fit_sine(&r.command_um[rng.clone()], fs, f)?;
            let fe = fit_sine(&r.encoder_um[rng], fs, f)?;
            windows.push(WindowStats {
                amplitude_um: r.amplitude_um,
                frequency_hz: f,
                a_true: ft.amplitude,
                a_phys: fp.amplitude,
                a_cmd: fc.amplitude,
                a_enc: fe.amplitude,
                probe_minus_encoder_phase: wrap(ft.phase - fe.phase),
            });
            start += win;
        }
    }
    let ybar = ys.iter().sum::<f64>() / ys.len() as f64;
    let sst: f64 = ys.iter().map(|y| (y - ybar).powi(2)).sum();
    Ok(Evaluation {
        r2: 1.0 - sse / sst,
        rmse_um: (sse / n as f64).sqrt(),
        windows,
    })
}

/// Mean of `value` over the windows whose key equals `key`, for every distinct key (sorted).
pub fn grouped(
    windows: &[WindowStats],
    key: impl Fn(&WindowStats) -> f64,
    value: impl Fn(&WindowStats) -> f64,
) -> Vec<(f64, f64)> {
    let mut keys: Vec<f64> = windows.iter().map(&key).collect();
    keys.sort_by(f64::total_cmp);
    keys.dedup();
    keys.into_iter()
        .map(|k| {
            let sel: Vec<f64> = windows.iter().filter(|w| key(w) == k).map(&value).collect();
            (k, sel.iter().sum::<f64>() / sel.len() as f64)
        })
        .collect()
}
