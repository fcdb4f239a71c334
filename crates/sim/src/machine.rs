//! The machine: closed-loop Z slide with Stribeck friction, and the tool-holder mode outside
//! the loop, integrated with a fixed-step fourth-order Runge-Kutta method.
//!
//! Internal units are um, um/s and um/s^2 so that the states are of order one to a thousand.

use crate::config::SimConfig;
use std::f64::consts::PI;

/// Channels of the machine at the DAQ sample instants (before any sensor), um and um/s^2.
#[derive(Debug, Clone)]
pub(crate) struct MachineTrace {
    /// Command position (um).
    pub command: Vec<f64>,
    /// Tool-tip position relative to the frame, after the probe's own bandwidth (um).
    pub probe_lp: Vec<f64>,
    /// Slide position delayed by the encoder read-out delay (um).
    pub encoder: Vec<f64>,
    /// Acceleration at the accelerometer's mounting point (um/s^2).
    pub accel: Vec<f64>,
}

/// Model coefficients in internal units.
#[derive(Debug, Clone, Copy)]
struct Coeffs {
    wn2: f64,
    two_zwn: f64,
    wt2: f64,
    two_zwt: f64,
    coulomb: f64,
    stat_minus_coulomb: f64,
    inv_vs: f64,
    veps2: f64,
    wb2: f64,
    two_zwb: f64,
    mu: f64,
}

impl Coeffs {
    fn new(cfg: &SimConfig) -> Self {
        let wn = 2.0 * PI * cfg.servo.natural_hz;
        let wt = 2.0 * PI * cfg.tool.natural_hz;
        Self {
            wn2: wn * wn,
            two_zwn: 2.0 * cfg.servo.damping * wn,
            wt2: wt * wt,
            two_zwt: 2.0 * cfg.tool.damping * wt,
            coulomb: cfg.servo.coulomb_ms2 * 1e6,
            stat_minus_coulomb: (cfg.servo.static_ms2 - cfg.servo.coulomb_ms2) * 1e6,
            inv_vs: 1.0 / cfg.servo.stribeck_um_s,
            veps2: cfg.servo.smoothing_um_s * cfg.servo.smoothing_um_s,
            wb2: (2.0 * PI * cfg.base.natural_hz).powi(2),
            two_zwb: 2.0 * cfg.base.damping * 2.0 * PI * cfg.base.natural_hz,
            mu: cfg.base.mass_ratio,
        }
    }

    /// Friction deceleration of the slide (um/s^2): Coulomb level plus a Stribeck peak
    /// (Lorentzian in velocity), times a smoothed sign. Algebraic forms (no exp/tanh) keep the
    /// inner loop cheap; the shapes are standard alternatives of the exponential forms.
    #[inline]
    fn friction(&self, v: f64) -> f64 {
        let r = v * self.inv_vs;
        let level = self.coulomb + self.stat_minus_coulomb / (1.0 + r * r);
        level * v / (v * v + self.veps2).sqrt()
    }

    /// Slide, relative tool and frame accelerations for state (x, v, z, w, xb, vb) and command u.
    #[inline]
    fn accels(&self, s: [f64; 6], u: f64) -> (f64, f64, f64) {
        let a_slide = self.wn2 * (u - s[0]) - self.two_zwn * s[1] - self.friction(s[1]);
        let a_rel = -self.wt2 * s[2] - self.two_zwt * s[3] - a_slide;
        let a_base = -self.wb2 * s[4] - self.two_zwb * s[5] - self.mu * a_slide;
        (a_slide, a_rel, a_base)
    }

    #[inline]
    fn deriv(&self, s: [f64; 6], u: f64) -> [f64; 6] {
        let (a, b, c) = self.accels(s, u);
        [s[1], a, s[3], b, s[5], c]
    }
}

/// Complex multiply and divide on (re, im) pairs, enough for the steady-state start.
fn cmul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}
fn cdiv(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let d = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
}

/// Simulates one record: `n_warm` warm-up samples then `n` record samples, at rate `fs` with
/// `m` RK4 steps per sample. Returns all `n_warm + n` samples (the caller drops the warm-up).
pub(crate) fn run(cfg: &SimConfig, amplitude_um: f64, frequency_hz: f64) -> MachineTrace {
    let fs = cfg.fs_hz;
    let n = cfg.samples_per_record();
    let n_warm = (cfg.warmup_s * fs).round() as usize;
    let m = cfg.substeps();
    let h = 1.0 / (fs * m as f64);
    let c = Coeffs::new(cfg);
    let w = 2.0 * PI * frequency_hz;
    let t0 = -(n_warm as f64) / fs;

    // Start on the linear steady state so that only friction transients need the warm-up.
    let hs = cdiv((c.wn2, 0.0), (c.wn2 - w * w, c.two_zwn * w));
    let ps = (amplitude_um * hs.0, amplitude_um * hs.1);
    let pz = cdiv((w * w * ps.0, w * w * ps.1), (c.wt2 - w * w, c.two_zwt * w));
    let e0 = ((w * t0).cos(), (w * t0).sin());
    let at = |p: (f64, f64)| cmul(p, e0).1;
    let dt = |p: (f64, f64)| cmul(cmul(p, (0.0, w)), e0).1;
    let wb2 = c.wb2;
    let pb = cdiv(
        (c.mu * w * w * ps.0, c.mu * w * w * ps.1),
        (wb2 - w * w, c.two_zwb * w),
    );
    let mut s = [at(ps), dt(ps), at(pz), dt(pz), at(pb), dt(pb)];

    // Command phasor advanced by rotation (half steps), renormalised every sample.
    let (sh, ch) = ((w * h / 2.0).sin(), (w * h / 2.0).cos());
    let mut rot = e0; // (cos, sin) of w t

    // Probe bandwidth: exact first-order low-pass at the internal rate.
    let beta = 1.0 - (-2.0 * PI * cfg.probe.bandwidth_hz * h).exp();
    let mut probe = s[0] + s[2];

    // Encoder delay as a ring of past slide positions.
    let delay_steps = cfg.encoder.delay_s / h;
    let q = delay_steps.floor() as usize;
    let frac = delay_steps - q as f64;
    let ring_len = q + 2;
    let mut ring = vec![s[0]; ring_len];

    let mut out = MachineTrace {
        command: Vec::with_capacity(n_warm + n),
        probe_lp: Vec::with_capacity(n_warm + n),
        encoder: Vec::with_capacity(n_warm + n),
        accel: Vec::with_capacity(n_warm + n),
    };
    let kappa = cfg.accel.mode_shape_ratio;
    let total = n_warm + n;
    let mut step: usize = 0;
    for _ in 0..total {
        {
            let u = amplitude_um * rot.1;
            let (a_s, a_r, a_b) = c.accels(s, u);
            // Slide positions q and q+1 internal steps back.
            let back_q = ring[(step + ring_len - q) % ring_len];
            let back_q1 = ring[(step + ring_len - q - 1) % ring_len];
            out.command.push(u);
            out.probe_lp.push(probe);
            out.encoder.push((1.0 - frac) * back_q + frac * back_q1);
            // Inertial acceleration at the sensor: frame + slide + holder (mode shape kappa).
            out.accel.push(a_b + a_s + kappa * a_r);
        }
        for _ in 0..m {
            let u0 = amplitude_um * rot.1;
            let mid = (rot.0 * ch - rot.1 * sh, rot.1 * ch + rot.0 * sh);
            let u1 = amplitude_um * mid.1;
            let end = (mid.0 * ch - mid.1 * sh, mid.1 * ch + mid.0 * sh);
            let u2 = amplitude_um * end.1;
            let k1 = c.deriv(s, u0);
            let s2 = add(s, k1, h / 2.0);
            let k2 = c.deriv(s2, u1);
            let s3 = add(s, k2, h / 2.0);
            let k3 = c.deriv(s3, u1);
            let s4 = add(s, k3, h);
            let k4 = c.deriv(s4, u2);
            for i in 0..6 {
                s[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            rot = end;
            probe += beta * (s[0] + s[2] - probe);
            step += 1;
            ring[step % ring_len] = s[0];
        }
        let norm = (rot.0 * rot.0 + rot.1 * rot.1).sqrt();
        rot = (rot.0 / norm, rot.1 / norm);
    }
    out
}

#[inline]
fn add(s: [f64; 6], k: [f64; 6], f: f64) -> [f64; 6] {
    let mut o = s;
    for i in 0..6 {
        o[i] += f * k[i];
    }
    o
}
