//! Power spectral density by Welch's method (and the periodogram as its one-segment case).

use std::f64::consts::PI;

use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use crate::SignalError;
use crate::error::{check_fs, check_signal};
use crate::integrate::{Detrend, detrend_in_place};

/// The window applied to each segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Window {
    /// Periodic Hann window (scipy's `get_window('hann', n)`), Welch's default.
    #[default]
    Hann,
    /// Rectangular window (scipy's `'boxcar'`), the periodogram's default.
    Boxcar,
}

impl Window {
    /// The window's `n` coefficients (periodic form, as scipy's `get_window(..., fftbins=True)`).
    pub fn coefficients(self, n: usize) -> Vec<f64> {
        match self {
            Window::Boxcar => vec![1.0; n],
            Window::Hann => {
                if n == 1 {
                    return vec![1.0];
                }
                // general_cosine(n + 1, [0.5, 0.5]) truncated to n samples.
                let step = 2.0 * PI / n as f64;
                (0..n)
                    .map(|i| {
                        let fac = i as f64 * step + (-PI);
                        0.5 + 0.5 * fac.cos()
                    })
                    .collect()
            }
        }
    }
}

/// Units of the estimate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum Scaling {
    /// Power spectral density, unit^2/Hz (scipy's `'density'`).
    #[default]
    Density,
    /// Power spectrum, unit^2 (scipy's `'spectrum'`).
    Spectrum,
}

/// Settings of [`welch`]. `Default` equals `scipy.signal.welch`'s defaults: periodic Hann
/// window, 256 samples per segment (cut to the signal length), half overlap, constant
/// detrend per segment, density scaling, one-sided spectrum, mean over segments.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WelchConfig {
    /// Samples per segment; cut to the signal length when longer (as scipy does).
    pub nperseg: usize,
    /// Samples shared by neighbouring segments; `None` means `nperseg / 2` (after the cut).
    pub noverlap: Option<usize>,
    /// Window applied to each segment.
    pub window: Window,
    /// Trend removed from each segment before windowing.
    pub detrend: Detrend,
    /// Density (per Hz) or spectrum.
    pub scaling: Scaling,
}

impl Default for WelchConfig {
    fn default() -> Self {
        Self {
            nperseg: 256,
            noverlap: None,
            window: Window::Hann,
            detrend: Detrend::Constant,
            scaling: Scaling::Density,
        }
    }
}

impl WelchConfig {
    /// The settings of `scipy.signal.periodogram` defaults: one segment spanning the whole
    /// signal, rectangular window, constant detrend, density scaling.
    pub fn periodogram() -> Self {
        Self {
            nperseg: usize::MAX,
            noverlap: Some(0),
            window: Window::Boxcar,
            detrend: Detrend::Constant,
            scaling: Scaling::Density,
        }
    }

    /// Segment length and overlap for a signal of `n` samples, validated.
    fn resolve(&self, n: usize) -> Result<(usize, usize), SignalError> {
        if self.nperseg == 0 {
            return Err(SignalError::InvalidConfig(
                "welch: nperseg must be at least 1".into(),
            ));
        }
        let nperseg = self.nperseg.min(n);
        let noverlap = self.noverlap.unwrap_or(nperseg / 2);
        if noverlap >= nperseg {
            return Err(SignalError::InvalidConfig(format!(
                "welch: noverlap ({noverlap}) must be less than nperseg ({nperseg})"
            )));
        }
        Ok((nperseg, noverlap))
    }
}

/// A one-sided spectrum estimate.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Psd {
    /// Frequencies in Hz, `0, fs/nperseg, ...` up to Nyquist.
    pub freqs: Vec<f64>,
    /// Density (unit^2/Hz) or spectrum (unit^2) at each frequency.
    pub density: Vec<f64>,
}

/// Welch's power spectral density estimate, equal to `scipy.signal.welch(x, fs, ...)` for the
/// settings in `cfg` (see [`WelchConfig`]).
///
/// # Errors
/// [`SignalError::Empty`], [`SignalError::NonFinite`], [`SignalError::InvalidSampleRate`],
/// [`SignalError::InvalidConfig`] (nperseg 0 or overlap not below nperseg).
pub fn welch(x: &[f64], fs: f64, cfg: &WelchConfig) -> Result<Psd, SignalError> {
    check_signal(x, "x")?;
    check_fs(fs)?;
    let (nperseg, noverlap) = cfg.resolve(x.len())?;
    let step = nperseg - noverlap;
    let nseg = (x.len() - nperseg) / step + 1;
    let win = cfg.window.coefficients(nperseg);
    let scale = match cfg.scaling {
        Scaling::Density => 1.0 / (fs * win.iter().map(|w| w * w).sum::<f64>()),
        Scaling::Spectrum => 1.0 / win.iter().sum::<f64>().powi(2),
    };
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(nperseg);
    let mut buf = fft.make_input_vec();
    let mut spec = fft.make_output_vec();
    let mut scratch = fft.make_scratch_vec();
    let nfreq = nperseg / 2 + 1;
    let mut acc = vec![0.0; nfreq];
    for s in 0..nseg {
        let seg = &x[s * step..s * step + nperseg];
        buf.copy_from_slice(seg);
        detrend_in_place(&mut buf, cfg.detrend);
        buf.iter_mut().zip(&win).for_each(|(b, w)| *b *= w);
        fft.process_with_scratch(&mut buf, &mut spec, &mut scratch)
            .map_err(|e| SignalError::InvalidConfig(format!("welch: FFT failed: {e}")))?;
        acc.iter_mut()
            .zip(&spec)
            .for_each(|(a, c): (&mut f64, &Complex<f64>)| *a += c.norm_sqr());
    }
    let last = if nperseg % 2 == 1 { nfreq } else { nfreq - 1 };
    let inv = 1.0 / nseg as f64;
    for (k, a) in acc.iter_mut().enumerate() {
        *a *= scale * inv;
        if k >= 1 && k < last {
            *a *= 2.0;
        }
    }
    let val = 1.0 / (nperseg as f64 * (1.0 / fs));
    let freqs = (0..nfreq).map(|k| k as f64 * val).collect();
    Ok(Psd {
        freqs,
        density: acc,
    })
}
