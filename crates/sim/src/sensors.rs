//! Sensor models applied at the DAQ rate: ICP accelerometer chain, capacitance probe, encoder.

use crate::SimError;
use crate::config::{AccelParams, SimConfig};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use realfft::RealFftPlanner;
use realfft::num_complex::Complex;
use std::f64::consts::PI;

/// Rounds `x` to the nearest multiple of `step` (no-op for `step == 0`).
#[inline]
pub(crate) fn quantise(x: f64, step: f64) -> f64 {
    if step > 0.0 {
        (x / step).round() * step
    } else {
        x
    }
}

/// Gaussian noise of one-sided density `density^2 * (1 + corner / f)` (unit^2/Hz), `n` samples
/// at rate `fs`, shaped in the frequency domain (exact PSD, no filter transients).
pub(crate) fn colored_noise(
    n: usize,
    fs: f64,
    density: f64,
    corner_hz: f64,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<f64>, SimError> {
    if density == 0.0 || n < 2 {
        return Ok(vec![0.0; n]);
    }
    let mut planner = RealFftPlanner::<f64>::new();
    let ifft = planner.plan_fft_inverse(n);
    let mut spec: Vec<Complex<f64>> = ifft.make_input_vec();
    let nb = spec.len();
    for (k, bin) in spec.iter_mut().enumerate() {
        if k == 0 {
            continue;
        }
        let f = k as f64 * fs / n as f64;
        let psd = density * density * (1.0 + corner_hz / f);
        let nyquist = n.is_multiple_of(2) && k == nb - 1;
        let g1: f64 = rng.sample(StandardNormal);
        if nyquist {
            *bin = Complex::new((psd * fs * n as f64 / 2.0).sqrt() * g1, 0.0);
        } else {
            let g2: f64 = rng.sample(StandardNormal);
            let s = (psd * fs * n as f64 / 4.0).sqrt();
            *bin = Complex::new(s * g1, s * g2);
        }
    }
    let mut out = ifft.make_output_vec();
    ifft.process(&mut spec, &mut out)
        .map_err(|e| SimError::Noise(e.to_string()))?;
    let scale = 1.0 / n as f64;
    out.iter_mut().for_each(|x| *x *= scale);
    Ok(out)
}

/// First-order high-pass (bilinear transform), started in the state of a long-running
/// channel: the first output equals the first input.
fn highpass_in_place(x: &mut [f64], corner_hz: f64, fs: f64) {
    if corner_hz <= 0.0 || x.is_empty() {
        return;
    }
    let k = 2.0 * fs;
    let wc = 2.0 * PI * corner_hz;
    let b = k / (k + wc);
    let a = (k - wc) / (k + wc);
    let mut x_prev = x[0];
    let mut y_prev = x[0];
    for v in x.iter_mut() {
        let y = b * (*v - x_prev) + a * y_prev;
        x_prev = *v;
        y_prev = y;
        *v = y;
    }
}

/// The accelerometer channel: `accel_um_s2` is the true acceleration at the mounting point
/// (um/s^2) over warm-up plus record; returns m/s^2 as the DAQ records it.
pub(crate) fn accelerometer(
    accel_um_s2: &[f64],
    t0: f64,
    fs: f64,
    frequency_hz: f64,
    p: &AccelParams,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<f64>, SimError> {
    let n = accel_um_s2.len();
    let spindle = frequency_hz * p.spindle_per_command;
    let scale = (spindle / p.spindle_ref_hz).powi(2);
    let w = 2.0 * PI * frequency_hz;
    let gain = 1.0 + p.sensitivity_error;
    let noise = colored_noise(n, fs, p.noise_density, p.flicker_corner_hz, rng)?;
    // Mechanical vibration at the sensor (motion + spindle-synchronous), then sensor noise,
    // all seen through the sensor's sensitivity and the ICP coupling.
    let mut x: Vec<f64> = accel_um_s2
        .iter()
        .zip(&noise)
        .enumerate()
        .map(|(i, (&a, &e))| {
            let t = t0 + i as f64 / fs;
            let mut mech = a * 1e-6;
            for hm in &p.harmonics {
                let order = f64::from(hm.order);
                mech += hm.amplitude_ms2
                    * scale
                    * (order * w * p.spindle_per_command * t + hm.phase_rad).sin();
            }
            gain * mech + e
        })
        .collect();
    for _ in 0..p.highpass_stages {
        highpass_in_place(&mut x, p.highpass_hz, fs);
    }
    // Mains pick-up in the cable and DAQ, then 16-bit conversion over the input range.
    let mains_phase: f64 = rng.r#gen::<f64>() * 2.0 * PI;
    let range = p.daq_range_v * 1000.0 / p.sensitivity_mv_per_ms2;
    let levels = 2f64.powi(p.adc_bits as i32);
    let step = 2.0 * range / levels;
    let (lo, hi) = (-levels / 2.0, levels / 2.0 - 1.0);
    for (i, v) in x.iter_mut().enumerate() {
        let t = t0 + i as f64 / fs;
        let y = *v + p.mains_ms2 * (2.0 * PI * p.mains_hz * t + mains_phase).sin();
        *v = (y / step).round().clamp(lo, hi) * step;
    }
    Ok(x)
}

/// Probe channel: band-limited tip position plus white noise, quantised to the resolution (um).
pub(crate) fn probe(lp_um: &[f64], cfg: &SimConfig, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let sd = cfg.probe.noise_nm * 1e-3;
    let step = cfg.probe.resolution_nm * 1e-3;
    lp_um
        .iter()
        .map(|&x| {
            let g: f64 = rng.sample(StandardNormal);
            quantise(x + sd * g, step)
        })
        .collect()
}
