//! Least-squares sine fits (IEEE Std 1057 three- and four-parameter algorithms).

use std::f64::consts::PI;

use crate::SignalError;
use crate::error::{check_fs, check_signal};

/// A fitted sine `x(t) ~ offset + amplitude * sin(2 pi f t + phase)`, `t = i / fs`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SineFit {
    /// Amplitude, same unit as the signal, never negative.
    pub amplitude: f64,
    /// Phase in radians, in (-pi, pi].
    pub phase: f64,
    /// Constant offset, same unit as the signal.
    pub offset: f64,
}

/// Result of the four-parameter fit: the sine and the refined frequency.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SineFit4 {
    /// Amplitude, phase and offset at the refined frequency.
    pub fit: SineFit,
    /// Refined frequency, Hz (`frequency_hz` in files written before the rename).
    #[serde(alias = "freq_hz")]
    pub frequency_hz: f64,
    /// Gauss-Newton iterations used.
    pub iterations: usize,
}

fn check_inputs(x: &[f64], fs: f64, frequency_hz: f64, params: usize) -> Result<(), SignalError> {
    check_signal(x, "x")?;
    check_fs(fs)?;
    let nyquist = fs / 2.0;
    if !(frequency_hz.is_finite() && frequency_hz > 0.0 && frequency_hz < nyquist) {
        return Err(SignalError::InvalidFrequency {
            freq: frequency_hz,
            nyquist,
        });
    }
    if x.len() < params {
        return Err(SignalError::TooShort {
            len: x.len(),
            needed: params - 1,
            operation: "a sine fit",
        });
    }
    Ok(())
}

/// Solves the `N x N` normal equations `M u = r` (row-major `m`) by Gaussian elimination with
/// partial pivoting after scaling to unit diagonal. Returns `None` when singular.
#[allow(clippy::needless_range_loop)] // index notation mirrors the algebra
pub(crate) fn solve<const N: usize>(mut m: [[f64; N]; N], mut r: [f64; N]) -> Option<[f64; N]> {
    let mut d = [1.0; N];
    for i in 0..N {
        if m[i][i].is_nan() || m[i][i] <= 0.0 || !m[i][i].is_finite() {
            return None;
        }
        d[i] = 1.0 / m[i][i].sqrt();
    }
    for i in 0..N {
        for j in 0..N {
            m[i][j] *= d[i] * d[j];
        }
        r[i] *= d[i];
    }
    for col in 0..N {
        let piv = (col..N).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[piv][col].is_nan() || m[piv][col].abs() <= 1e-13 {
            return None;
        }
        m.swap(col, piv);
        r.swap(col, piv);
        for row in col + 1..N {
            let f = m[row][col] / m[col][col];
            for k in col..N {
                m[row][k] -= f * m[col][k];
            }
            r[row] -= f * r[col];
        }
    }
    let mut u = [0.0; N];
    for i in (0..N).rev() {
        let mut s = r[i];
        for k in i + 1..N {
            s -= m[i][k] * u[k];
        }
        u[i] = s / m[i][i];
    }
    for i in 0..N {
        u[i] *= d[i];
    }
    u.iter().all(|v| v.is_finite()).then_some(u)
}

/// Accumulates the normal equations of the rows `cols(i)` against `x`.
#[allow(clippy::needless_range_loop)] // index notation mirrors the algebra
fn normal<const N: usize>(
    x: &[f64],
    cols: impl Fn(usize) -> [f64; N],
) -> ([[f64; N]; N], [f64; N]) {
    let mut m = [[0.0; N]; N];
    let mut r = [0.0; N];
    for (i, &xi) in x.iter().enumerate() {
        let c = cols(i);
        for a in 0..N {
            r[a] += c[a] * xi;
            for b in a..N {
                m[a][b] += c[a] * c[b];
            }
        }
    }
    for a in 0..N {
        for b in 0..a {
            m[a][b] = m[b][a];
        }
    }
    (m, r)
}

fn to_fit(s: f64, c: f64, offset: f64) -> SineFit {
    // s sin(wt) + c cos(wt) = R sin(wt + phi) with R cos(phi) = s, R sin(phi) = c.
    SineFit {
        amplitude: s.hypot(c),
        phase: c.atan2(s),
        offset,
    }
}

/// How far the sine `later` lags the sine `reference` (both fitted at `frequency_hz`), in
/// seconds: their phase difference wrapped to (-pi, pi], over `2 pi frequency_hz`.
/// Positive when `later` comes later.
pub fn phase_lag_s(reference: &SineFit, later: &SineFit, frequency_hz: f64) -> f64 {
    let mut dphi = reference.phase - later.phase;
    while dphi > PI {
        dphi -= 2.0 * PI;
    }
    while dphi <= -PI {
        dphi += 2.0 * PI;
    }
    dphi / (2.0 * PI * frequency_hz)
}

/// Three-parameter least-squares sine fit at a known frequency (IEEE 1057): solves for
/// `x ~ s sin(w t) + c cos(w t) + offset` and returns amplitude `hypot(s, c)` and phase
/// `atan2(c, s)`.
///
/// # Errors
/// [`SignalError::Empty`], [`SignalError::NonFinite`], [`SignalError::InvalidSampleRate`],
/// [`SignalError::InvalidFrequency`] (outside (0, fs/2)), [`SignalError::TooShort`] (fewer than
/// 3 samples), [`SignalError::Singular`] (the three columns are not independent, e.g. far less
/// than a period).
pub fn fit_sine(x: &[f64], fs: f64, frequency_hz: f64) -> Result<SineFit, SignalError> {
    check_inputs(x, fs, frequency_hz, 3)?;
    let w = 2.0 * PI * frequency_hz / fs;
    let (m, r) = normal(x, |i| {
        let (s, c) = (w * i as f64).sin_cos();
        [s, c, 1.0]
    });
    let u = solve(m, r).ok_or(SignalError::Singular("sine, cosine and constant columns"))?;
    Ok(to_fit(u[0], u[1], u[2]))
}

/// Four-parameter sine fit (IEEE 1057): starts from [`fit_sine`] at `frequency_hz` and refines the
/// frequency by Gauss-Newton until the relative frequency step is below 1e-12 (at most 100
/// iterations).
///
/// # Errors
/// As [`fit_sine`] (at least 4 samples), plus [`SignalError::NoConvergence`] when the
/// frequency leaves (0, fs/2) or does not settle.
pub fn fit_sine4(x: &[f64], fs: f64, frequency_hz: f64) -> Result<SineFit4, SignalError> {
    check_inputs(x, fs, frequency_hz, 4)?;
    let start = fit_sine(x, fs, frequency_hz)?;
    let mut w = 2.0 * PI * frequency_hz / fs; // radians per sample
    let (mut s, mut c) = (
        start.amplitude * start.phase.cos(),
        start.amplitude * start.phase.sin(),
    );
    const MAX_ITER: usize = 100;
    for it in 1..=MAX_ITER {
        let (m, r) = normal(x, |i| {
            let t = i as f64;
            let (sn, cs) = (w * t).sin_cos();
            [sn, cs, 1.0, t * (s * cs - c * sn)]
        });
        let u = solve(m, r).ok_or(SignalError::Singular("four-parameter sine fit"))?;
        s = u[0];
        c = u[1];
        let dw = u[3];
        w += dw;
        if !(w > 0.0 && w < PI) {
            return Err(SignalError::NoConvergence {
                what: "the four-parameter sine fit (frequency left (0, fs/2))",
                iterations: it,
            });
        }
        if dw.abs() <= 1e-12 * w {
            // Final amplitude/phase/offset at the converged frequency.
            let fit = fit_sine(x, fs, w * fs / (2.0 * PI))?;
            return Ok(SineFit4 {
                fit,
                frequency_hz: w * fs / (2.0 * PI),
                iterations: it,
            });
        }
    }
    Err(SignalError::NoConvergence {
        what: "the four-parameter sine fit",
        iterations: MAX_ITER,
    })
}
