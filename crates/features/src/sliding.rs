//! The twelve features of the last `n` samples of a stream, updated one sample at a time.
//!
//! What is updated per sample and what is recomputed, and why:
//! - `f2`, `f3`, `f5`-`f10` (moments): running sums of `|a|` and of the first four powers of
//!   `a - K`, adding the new sample and subtracting the one that leaves; the central moments
//!   follow from them by the binomial expansion. `K` is the window's mean at the last
//!   refresh, so the expansion does not subtract large numbers when the signal has an
//!   offset. Every `n` samples the sums are recomputed from the stored window (and `K`
//!   re-centred), so rounding cannot accumulate over a long stream.
//! - `f4` (peak): a monotone queue of the window's samples in decreasing `|a|`; each sample
//!   enters and leaves it once, O(1) amortised.
//! - `f11`, `f12` (spectral): Welch's PSD by [`hxai_signal::SlidingWelch`], one FFT per
//!   Welch step, exact when the window ends on the segment grid. This is why features are
//!   *reported* every `step` samples ([`SlidingFeatures::step`], 128 at the default Welch
//!   settings) rather than every sample: between two grid points the spectral features are
//!   not defined by the offline formula without recomputing every segment.
//! - `f1` is the commanded frequency, given.

use std::collections::VecDeque;

use hxai_signal::SlidingWelch;

use crate::{FeatureConfig, FeatureError, Features, Sums, assemble, welch_config};

/// The features of the trailing window of `n` samples, equal to [`crate::extract_with`] of
/// that window (up to the rounding of running sums: 1e-9 relative in the tests) every
/// [`SlidingFeatures::step`] samples. Memory is O(n), whatever the stream's length.
#[derive(Debug)]
pub struct SlidingFeatures {
    n: usize,
    frequency_hz: f64,
    cfg: FeatureConfig,
    ring: Vec<f64>,
    head: usize,
    count: u64,
    since_refresh: usize,
    /// The shift `K` of the power sums.
    shift: f64,
    /// Sums of `(a - K)^1..4` over the window.
    powers: [f64; 4],
    sum_abs: f64,
    /// `(index, |a|)`, strictly decreasing in `|a|`, indices increasing.
    peaks: VecDeque<(u64, f64)>,
    welch: SlidingWelch,
}

impl SlidingFeatures {
    /// Features of windows of `n` samples at rate `fs`, `f1 = frequency_hz`.
    ///
    /// # Errors
    /// [`FeatureError::TooShort`] for `n < 2`, [`FeatureError::InvalidSampleRate`],
    /// [`FeatureError::InvalidCommandFrequency`], [`FeatureError::Signal`] for PSD settings
    /// that do not fit the window.
    pub fn new(
        n: usize,
        fs: f64,
        frequency_hz: f64,
        cfg: &FeatureConfig,
    ) -> Result<Self, FeatureError> {
        if n < 2 {
            return Err(FeatureError::TooShort { len: n });
        }
        if !(fs.is_finite() && fs > 0.0) {
            return Err(FeatureError::InvalidSampleRate(fs));
        }
        if !(frequency_hz.is_finite() && frequency_hz > 0.0) {
            return Err(FeatureError::InvalidCommandFrequency(frequency_hz));
        }
        let welch = SlidingWelch::new(&welch_config(cfg), fs, n)?;
        Ok(Self {
            n,
            frequency_hz,
            cfg: cfg.clone(),
            ring: vec![0.0; n],
            head: 0,
            count: 0,
            since_refresh: 0,
            shift: 0.0,
            powers: [0.0; 4],
            sum_abs: 0.0,
            peaks: VecDeque::new(),
            welch,
        })
    }

    /// Samples between two reports (the Welch step).
    pub fn step(&self) -> usize {
        self.welch.step()
    }

    /// Adds one sample. Returns the features of the last `n` samples when the window ends on
    /// a report point (after `n` samples, then every [`SlidingFeatures::step`]), else
    /// `None`. A window whose features are undefined (a constant signal) is an error for
    /// that report only: the stream goes on.
    ///
    /// # Errors
    /// [`FeatureError::NonFinite`] for a NaN or infinite sample (it is not added), and the
    /// errors of [`crate::extract_with`] for the window at a report point.
    pub fn push(&mut self, a: f64) -> Result<Option<Features>, FeatureError> {
        if !a.is_finite() {
            return Err(FeatureError::NonFinite {
                index: usize::try_from(self.count).unwrap_or(usize::MAX),
            });
        }
        if self.count == 0 {
            self.shift = a;
        }
        if self.count >= self.n as u64 {
            let old = self.ring[self.head];
            self.add(old, -1.0);
        }
        self.add(a, 1.0);
        self.ring[self.head] = a;
        self.head = (self.head + 1) % self.n;
        let index = self.count;
        self.count += 1;
        let abs = a.abs();
        while self.peaks.back().is_some_and(|&(_, v)| v <= abs) {
            self.peaks.pop_back();
        }
        self.peaks.push_back((index, abs));
        while self
            .peaks
            .front()
            .is_some_and(|&(i, _)| i + (self.n as u64) <= index)
        {
            self.peaks.pop_front();
        }
        self.welch.push(a)?;
        self.since_refresh += 1;
        if self.since_refresh >= self.n {
            self.refresh();
        }
        if !self.welch.aligned() {
            return Ok(None);
        }
        let Some(psd) = self.welch.psd() else {
            return Ok(None);
        };
        let nf = self.n as f64;
        let [s1, s2, s3, s4] = self.powers;
        let mu = s1 / nf;
        let k = self.shift;
        let sums = Sums {
            n: nf,
            sum_abs: self.sum_abs,
            sum_sq: s2 + 2.0 * k * s1 + nf * k * k,
            m2: s2 - s1 * mu,
            m3: s3 - 3.0 * mu * s2 + 2.0 * nf * mu.powi(3),
            m4: s4 - 4.0 * mu * s3 + 6.0 * mu * mu * s2 - 3.0 * nf * mu.powi(4),
            peak: self.peaks.front().map_or(0.0, |&(_, v)| v),
        };
        assemble(self.frequency_hz, &sums, &psd, &self.cfg).map(Some)
    }

    /// Forgets every sample, as if new.
    pub fn reset(&mut self) {
        self.head = 0;
        self.count = 0;
        self.since_refresh = 0;
        self.shift = 0.0;
        self.powers = [0.0; 4];
        self.sum_abs = 0.0;
        self.peaks.clear();
        self.welch.reset();
    }

    fn add(&mut self, a: f64, sign: f64) {
        let y = a - self.shift;
        let y2 = y * y;
        self.powers[0] += sign * y;
        self.powers[1] += sign * y2;
        self.powers[2] += sign * y2 * y;
        self.powers[3] += sign * y2 * y2;
        self.sum_abs += sign * a.abs();
    }

    /// Recomputes the sums from the stored window, re-centred on its mean.
    fn refresh(&mut self) {
        let filled = self.count.min(self.n as u64) as usize;
        let window = || (0..filled).map(|k| self.ring[(self.head + self.n - filled + k) % self.n]);
        let mean = window().sum::<f64>() / filled as f64;
        let (mut powers, mut sum_abs) = ([0.0; 4], 0.0);
        for a in window() {
            let y = a - mean;
            let y2 = y * y;
            powers[0] += y;
            powers[1] += y2;
            powers[2] += y2 * y;
            powers[3] += y2 * y2;
            sum_abs += a.abs();
        }
        self.shift = mean;
        self.powers = powers;
        self.sum_abs = sum_abs;
        self.since_refresh = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{PsdEstimator, Sigma, extract_with};

    fn signal(n: usize, offset: f64) -> Vec<f64> {
        use rand::Rng;
        use rand_chacha::rand_core::SeedableRng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(99);
        (0..n)
            .map(|i| {
                let noise = rng.r#gen::<f64>() - 0.5;
                let t = i as f64 / 5000.0;
                // The amplitude drifts, so windows differ.
                offset
                    + (1.0 + 0.5 * (0.3 * t).sin()) * (2.0 * std::f64::consts::PI * 30.0 * t).sin()
                    + 0.3 * noise
            })
            .collect()
    }

    /// 1e-9 relative; for skewness (index 6), dimensionless and often near 0, 1e-9 absolute.
    fn close(k: usize, a: f64, b: f64) -> bool {
        let scale = if k == 6 { 1.0 } else { a.abs().max(b.abs()) };
        (a - b).abs() <= 1e-9 * scale
    }

    /// Invariant: at every report point the features equal `extract_with` of the trailing
    /// window, within 1e-9 relative (skewness 1e-9 absolute; moments from running sums), the spectral ones exactly,
    /// for both sigma conventions, both PSD estimators, with and without an offset, over a
    /// stream of many windows (refreshes exercised).
    #[test]
    fn equals_extract_of_the_window() {
        let fs = 5000.0;
        let n = 2500;
        for (cfg, offset) in [
            (FeatureConfig::default(), 0.0),
            (FeatureConfig::default(), 40.0),
            (
                FeatureConfig {
                    sigma: Sigma::Unbiased,
                    psd: PsdEstimator::Periodogram,
                },
                -3.0,
            ),
        ] {
            let x = signal(30_000, offset);
            let mut sf = SlidingFeatures::new(n, fs, 30.0, &cfg).expect("config");
            let mut reports = 0;
            for (i, &a) in x.iter().enumerate() {
                if let Some(f) = sf.push(a).expect("push") {
                    let want = extract_with(&x[i + 1 - n..=i], fs, 30.0, &cfg).expect("extract");
                    for (k, (got, exp)) in f.to_array().iter().zip(want.to_array()).enumerate() {
                        assert!(
                            close(k, *got, exp),
                            "f{} at {i} (offset {offset}): {got} vs {exp}",
                            k + 1
                        );
                    }
                    assert_eq!(f.total_power, want.total_power);
                    assert_eq!(f.mean_freq_hz, want.mean_freq_hz);
                    reports += 1;
                }
            }
            assert_eq!(reports, (30_000 - n) / sf.step() + 1);
        }
    }

    #[test]
    fn a_constant_window_is_an_error_and_the_stream_goes_on() {
        let mut sf =
            SlidingFeatures::new(256, 1000.0, 10.0, &FeatureConfig::default()).expect("config");
        let mut errors = 0;
        for _ in 0..256 {
            if sf.push(1.0).is_err() {
                errors += 1;
            }
        }
        assert_eq!(errors, 1);
        assert!(matches!(
            sf.push(f64::NAN),
            Err(FeatureError::NonFinite { index: 256 })
        ));
        let mut reported = false;
        for i in 0..512 {
            if let Ok(Some(_)) = sf.push((i as f64).sin()) {
                reported = true;
            }
        }
        assert!(reported);
    }
}
