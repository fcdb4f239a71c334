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
    pub(crate) fn resolve(&self, n: usize) -> Result<(usize, usize), SignalError> {
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
    let mut seg = Segments::new(cfg, fs, x.len())?;
    let mut acc = vec![0.0; seg.nfreq()];
    for s in 0..seg.nseg {
        let power = seg.power(&x[s * seg.step..s * seg.step + seg.nperseg])?;
        acc.iter_mut().zip(power).for_each(|(a, p)| *a += p);
    }
    Ok(seg.finish(acc))
}

/// The per-segment work of Welch's method for signals of `n` samples: the segment length,
/// step and count, the window and its scale, and the FFT. [`welch`] and the sliding
/// estimator ([`crate::SlidingWelch`]) share it, so both compute each segment's power the
/// same way, to the last bit.
pub(crate) struct Segments {
    pub nperseg: usize,
    pub step: usize,
    pub nseg: usize,
    fs: f64,
    detrend: Detrend,
    win: Vec<f64>,
    scale: f64,
    fft: std::sync::Arc<dyn realfft::RealToComplex<f64>>,
    buf: Vec<f64>,
    spec: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
    power: Vec<f64>,
}

impl std::fmt::Debug for Segments {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Segments")
            .field("nperseg", &self.nperseg)
            .field("step", &self.step)
            .field("nseg", &self.nseg)
            .finish_non_exhaustive()
    }
}

impl Segments {
    pub fn new(cfg: &WelchConfig, fs: f64, n: usize) -> Result<Self, SignalError> {
        check_fs(fs)?;
        if n == 0 {
            return Err(SignalError::Empty { what: "x" });
        }
        let (nperseg, noverlap) = cfg.resolve(n)?;
        let step = nperseg - noverlap;
        let nseg = (n - nperseg) / step + 1;
        let win = cfg.window.coefficients(nperseg);
        let scale = match cfg.scaling {
            Scaling::Density => 1.0 / (fs * win.iter().map(|w| w * w).sum::<f64>()),
            Scaling::Spectrum => 1.0 / win.iter().sum::<f64>().powi(2),
        };
        let mut planner = RealFftPlanner::<f64>::new();
        let fft = planner.plan_fft_forward(nperseg);
        let buf = fft.make_input_vec();
        let spec = fft.make_output_vec();
        let scratch = fft.make_scratch_vec();
        let power = vec![0.0; nperseg / 2 + 1];
        Ok(Self {
            nperseg,
            step,
            nseg,
            fs,
            detrend: cfg.detrend,
            win,
            scale,
            fft,
            buf,
            spec,
            scratch,
            power,
        })
    }

    /// Frequencies of the one-sided spectrum.
    pub fn nfreq(&self) -> usize {
        self.nperseg / 2 + 1
    }

    /// `|FFT(window * detrend(segment))|^2` of one segment of `nperseg` samples.
    pub fn power(&mut self, segment: &[f64]) -> Result<&[f64], SignalError> {
        self.buf.copy_from_slice(segment);
        detrend_in_place(&mut self.buf, self.detrend);
        self.buf
            .iter_mut()
            .zip(&self.win)
            .for_each(|(b, w)| *b *= w);
        self.fft
            .process_with_scratch(&mut self.buf, &mut self.spec, &mut self.scratch)
            .map_err(|e| SignalError::InvalidConfig(format!("welch: FFT failed: {e}")))?;
        self.power
            .iter_mut()
            .zip(&self.spec)
            .for_each(|(p, c): (&mut f64, &Complex<f64>)| *p = c.norm_sqr());
        Ok(&self.power)
    }

    /// The PSD from the sum of the `nseg` segments' powers: averaged, scaled, one-sided.
    pub fn finish(&self, mut acc: Vec<f64>) -> Psd {
        let nfreq = self.nfreq();
        let last = if self.nperseg % 2 == 1 {
            nfreq
        } else {
            nfreq - 1
        };
        let inv = 1.0 / self.nseg as f64;
        for (k, a) in acc.iter_mut().enumerate() {
            *a *= self.scale * inv;
            if k >= 1 && k < last {
                *a *= 2.0;
            }
        }
        let val = 1.0 / (self.nperseg as f64 * (1.0 / self.fs));
        let freqs = (0..nfreq).map(|k| k as f64 * val).collect();
        Psd {
            freqs,
            density: acc,
        }
    }
}
