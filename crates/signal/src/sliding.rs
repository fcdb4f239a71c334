//! Estimates over a sliding window, updated one sample at a time: the sine fit and the Welch
//! PSD of the last `n` samples of a stream, for the streaming estimator of the tool position
//! (`hxai_hybrid::records::stream`).
//!
//! Both keep memory bounded by the window (never by the stream's length) and cost O(1) per
//! sample, amortised:
//! - [`SlidingSine`] keeps the sums of the three-parameter least-squares normal equations
//!   (offset, sine, cosine at the known frequency) over the window, adding the new sample and
//!   subtracting the one that leaves. Sums updated this way drift by rounding as the stream
//!   goes on, so every `n` samples they are recomputed from the stored window, which bounds
//!   the drift to what one window's worth of updates can accumulate.
//! - [`SlidingWelch`] computes each Welch segment's power once, when its last sample arrives,
//!   and keeps the powers of the window's segments. When the window ends on the segment grid
//!   (every `step` samples) the PSD of the window is the average of those powers, summed in
//!   the same order as [`crate::welch`] sums them: the result equals `welch` of the window to
//!   the last bit, at the cost of one FFT of `nperseg` samples per `step` samples.

use std::collections::VecDeque;
use std::f64::consts::PI;

use crate::SignalError;
use crate::spectral::{Psd, Segments, WelchConfig};

/// Least-squares fit of `offset + p sin(theta_k) + q cos(theta_k)`, `theta_k = 2 pi f k /
/// fs` counted from the first sample pushed, over the last `n` samples of a stream.
///
/// After at least `n` samples, [`SlidingSine::fit`] gives what [`crate::fit_sine`] gives on
/// the last `n` samples (the same model; its phase counted from the stream's first sample
/// instead of the window's), up to the rounding of the running sums.
#[derive(Debug, Clone)]
pub struct SlidingSine {
    n: usize,
    radians_per_sample: f64,
    /// The window: sample, sine and cosine of each of the last `n` samples.
    ring: Vec<[f64; 3]>,
    head: usize,
    count: u64,
    since_refresh: usize,
    /// Sums over the window: x, s, c, ss, cc, sc, xs, xc.
    sums: [f64; 8],
}

fn terms(x: f64, s: f64, c: f64) -> [f64; 8] {
    [x, s, c, s * s, c * c, s * c, x * s, x * c]
}

impl SlidingSine {
    /// A fit over windows of `n` samples of a sine of `frequency_hz` sampled at `fs`.
    ///
    /// # Errors
    /// [`SignalError::InvalidSampleRate`], [`SignalError::InvalidFrequency`] (outside (0,
    /// fs/2)), [`SignalError::TooShort`] for a window of fewer than 3 samples.
    pub fn new(n: usize, fs: f64, frequency_hz: f64) -> Result<Self, SignalError> {
        crate::error::check_fs(fs)?;
        let nyquist = fs / 2.0;
        if !(frequency_hz.is_finite() && frequency_hz > 0.0 && frequency_hz < nyquist) {
            return Err(SignalError::InvalidFrequency {
                freq: frequency_hz,
                nyquist,
            });
        }
        if n < 3 {
            return Err(SignalError::TooShort {
                len: n,
                needed: 2,
                operation: "a sliding sine fit",
            });
        }
        Ok(Self {
            n,
            radians_per_sample: 2.0 * PI * frequency_hz / fs,
            ring: vec![[0.0; 3]; n],
            head: 0,
            count: 0,
            since_refresh: 0,
            sums: [0.0; 8],
        })
    }

    /// The window length, samples.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Always false: a window holds at least 3 samples.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Samples pushed so far.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Adds one sample (the caller checks that it is finite).
    pub fn push(&mut self, x: f64) {
        // Exact for any stream shorter than 2^53 samples (28,000 years at 10 kHz).
        let (s, c) = (self.count as f64 * self.radians_per_sample).sin_cos();
        if self.count >= self.n as u64 {
            let [ox, os, oc] = self.ring[self.head];
            for (sum, t) in self.sums.iter_mut().zip(terms(ox, os, oc)) {
                *sum -= t;
            }
        }
        for (sum, t) in self.sums.iter_mut().zip(terms(x, s, c)) {
            *sum += t;
        }
        self.ring[self.head] = [x, s, c];
        self.head = (self.head + 1) % self.n;
        self.count += 1;
        self.since_refresh += 1;
        if self.since_refresh >= self.n {
            self.refresh();
        }
    }

    /// Forgets every sample, as if new.
    pub fn reset(&mut self) {
        self.head = 0;
        self.count = 0;
        self.since_refresh = 0;
        self.sums = [0.0; 8];
    }

    /// Recomputes the sums from the stored window, oldest sample first.
    fn refresh(&mut self) {
        let mut sums = [0.0; 8];
        let filled = (self.count.min(self.n as u64)) as usize;
        for k in 0..filled {
            let [x, s, c] = self.ring[(self.head + self.n - filled + k) % self.n];
            for (sum, t) in sums.iter_mut().zip(terms(x, s, c)) {
                *sum += t;
            }
        }
        self.sums = sums;
        self.since_refresh = 0;
    }

    /// The sine and cosine of the newest sample's phase, `(sin theta_k, cos theta_k)`.
    pub fn basis(&self) -> (f64, f64) {
        let [_, s, c] = self.ring[(self.head + self.n - 1) % self.n];
        (s, c)
    }

    /// `[p, q, offset]` of the last `n` samples, once `n` have been pushed; `None` before
    /// that or when the window does not determine them (a window far shorter than a period).
    pub fn fit(&self) -> Option<[f64; 3]> {
        if self.count < self.n as u64 {
            return None;
        }
        let [x, s, c, ss, cc, sc, xs, xc] = self.sums;
        let m = [[ss, sc, s], [sc, cc, c], [s, c, self.n as f64]];
        crate::sine::solve(m, [xs, xc, x])
    }
}

/// Welch's PSD of the last `n` samples of a stream, equal to [`crate::welch`] of those
/// samples whenever the window ends on the segment grid ([`SlidingWelch::aligned`]).
#[derive(Debug)]
pub struct SlidingWelch {
    n: usize,
    segments: Segments,
    /// The last `nperseg` samples, in arrival order from `head`.
    recent: Vec<f64>,
    head: usize,
    ordered: Vec<f64>,
    count: u64,
    /// Powers of the last `nseg` complete segments, oldest first.
    powers: VecDeque<Vec<f64>>,
}

impl SlidingWelch {
    /// Welch's method with `cfg` over windows of `n` samples at rate `fs`.
    ///
    /// # Errors
    /// As [`crate::welch`] for a signal of `n` samples.
    pub fn new(cfg: &WelchConfig, fs: f64, n: usize) -> Result<Self, SignalError> {
        let segments = Segments::new(cfg, fs, n)?;
        let nperseg = segments.nperseg;
        let nseg = segments.nseg;
        Ok(Self {
            n,
            segments,
            recent: vec![0.0; nperseg],
            head: 0,
            ordered: vec![0.0; nperseg],
            count: 0,
            powers: VecDeque::with_capacity(nseg + 1),
        })
    }

    /// Samples between two windows that end on the segment grid (Welch's step,
    /// `nperseg - noverlap`).
    pub fn step(&self) -> usize {
        self.segments.step
    }

    /// Adds one sample; computes a segment's power when the sample completes one.
    ///
    /// # Errors
    /// [`SignalError::InvalidConfig`] if the FFT fails (it does not for the sizes `new`
    /// accepts).
    pub fn push(&mut self, x: f64) -> Result<(), SignalError> {
        let nperseg = self.segments.nperseg;
        self.recent[self.head] = x;
        self.head = (self.head + 1) % nperseg;
        self.count += 1;
        // Segment j covers samples [j step, j step + nperseg) of the stream.
        if self.count >= nperseg as u64
            && (self.count - nperseg as u64).is_multiple_of(self.segments.step as u64)
        {
            for k in 0..nperseg {
                self.ordered[k] = self.recent[(self.head + k) % nperseg];
            }
            let nseg = self.segments.nseg;
            let power = self.segments.power(&self.ordered)?;
            let mut slot = if self.powers.len() == nseg {
                self.powers.pop_front().unwrap_or_default()
            } else {
                Vec::new()
            };
            slot.clear();
            slot.extend_from_slice(power);
            self.powers.push_back(slot);
        }
        Ok(())
    }

    /// Forgets every sample, as if new.
    pub fn reset(&mut self) {
        self.head = 0;
        self.count = 0;
        self.powers.clear();
    }

    /// True when the last `n` samples end on the segment grid: their segments are exactly
    /// the ones held, and [`SlidingWelch::psd`] is their Welch PSD.
    pub fn aligned(&self) -> bool {
        self.count >= self.n as u64
            && (self.count - self.n as u64).is_multiple_of(self.step() as u64)
    }

    /// The Welch PSD of the last `n` samples when [`SlidingWelch::aligned`], else `None`.
    pub fn psd(&self) -> Option<Psd> {
        if !self.aligned() || self.powers.len() != self.segments.nseg {
            return None;
        }
        let mut acc = vec![0.0; self.segments.nfreq()];
        for p in &self.powers {
            acc.iter_mut().zip(p).for_each(|(a, v)| *a += v);
        }
        Some(self.segments.finish(acc))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signal(n: usize) -> Vec<f64> {
        // A sine, a harmonic, an offset and seeded noise.
        use rand::Rng;
        use rand_chacha::rand_core::SeedableRng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12345);
        (0..n)
            .map(|i| {
                let noise = rng.r#gen::<f64>() - 0.5;
                let t = i as f64 / 2000.0;
                0.3 + 2.0 * (2.0 * PI * 25.0 * t + 0.4).sin()
                    + 0.2 * (2.0 * PI * 75.0 * t).sin()
                    + 0.1 * noise
            })
            .collect()
    }

    /// Invariant: at every aligned window end, the sliding PSD is `welch` of the window, bit
    /// for bit (the same segments, summed in the same order).
    #[test]
    fn sliding_welch_is_welch_of_the_window() {
        let x = signal(6000);
        let n = 1000;
        let cfg = WelchConfig::default();
        let mut sw = SlidingWelch::new(&cfg, 2000.0, n).expect("config");
        let mut checked = 0;
        for (i, &v) in x.iter().enumerate() {
            sw.push(v).expect("push");
            if let Some(psd) = sw.psd() {
                let want = crate::welch(&x[i + 1 - n..=i], 2000.0, &cfg).expect("welch");
                assert_eq!(psd, want, "window ending at sample {i}");
                checked += 1;
            }
        }
        // Windows end on the grid every 128 samples from sample 999 on.
        assert_eq!(checked, (6000 - 1000) / 128 + 1);
    }

    /// The periodogram (one segment the size of the window) is the same mechanism with a
    /// step of the whole window.
    #[test]
    fn sliding_periodogram_is_welch_of_the_window() {
        let x = signal(3000);
        let n = 700;
        let cfg = WelchConfig::periodogram();
        let mut sw = SlidingWelch::new(&cfg, 2000.0, n).expect("config");
        assert_eq!(sw.step(), n);
        let mut checked = 0;
        for (i, &v) in x.iter().enumerate() {
            sw.push(v).expect("push");
            if let Some(psd) = sw.psd() {
                let want = crate::welch(&x[i + 1 - n..=i], 2000.0, &cfg).expect("welch");
                assert_eq!(psd, want);
                checked += 1;
            }
        }
        assert_eq!(checked, 4);
    }

    /// Invariant: after `n` samples, the sliding fit equals `fit_sine` of the last `n`
    /// samples, whose phase counts from the window's first sample (tolerance 1e-9 relative
    /// on the amplitude and offset, 1e-9 rad on the phase), over a stream many windows long
    /// (so the refresh of the sums is exercised).
    #[test]
    fn sliding_sine_is_fit_sine_of_the_window() {
        let (fs, f) = (2000.0, 25.0);
        let x = signal(20_000);
        let n = 333; // not a whole number of periods
        let mut ss = SlidingSine::new(n, fs, f).expect("config");
        for (i, &v) in x.iter().enumerate() {
            ss.push(v);
            if i + 1 < n {
                assert!(ss.fit().is_none());
                continue;
            }
            if i % 97 != 0 {
                continue;
            }
            let [p, q, offset] = ss.fit().expect("fit");
            let want = crate::fit_sine(&x[i + 1 - n..=i], fs, f).expect("fit_sine");
            // Shift the phase from the stream's origin to the window's first sample.
            let start = (i + 1 - n) as f64 * 2.0 * PI * f / fs;
            let amp = p.hypot(q);
            let phase = q.atan2(p) + start;
            let dphase = (phase - want.phase).sin().abs();
            assert!(
                (amp - want.amplitude).abs() <= 1e-9 * want.amplitude,
                "amplitude at {i}"
            );
            assert!(dphase <= 1e-9, "phase at {i}: {phase} vs {}", want.phase);
            assert!(
                (offset - want.offset).abs() <= 1e-9 * want.amplitude,
                "offset at {i}"
            );
        }
    }

    #[test]
    fn bad_settings_are_refused() {
        assert!(SlidingSine::new(2, 1000.0, 10.0).is_err());
        assert!(SlidingSine::new(100, 1000.0, 600.0).is_err());
        assert!(SlidingSine::new(100, 0.0, 10.0).is_err());
        assert!(SlidingWelch::new(&WelchConfig::default(), f64::NAN, 100).is_err());
        assert!(SlidingWelch::new(&WelchConfig::default(), 1000.0, 0).is_err());
    }

    /// A 3-parameter gain check: `Sos::gain` against the response of the filter to a long
    /// sine (the steady-state amplitude after the transient), 1e-6 relative.
    #[test]
    fn sos_gain_is_the_steady_state_amplitude() {
        let fs = 2000.0;
        let sos = crate::butter(4, crate::Band::Bandpass(5.0, 200.0), fs).expect("design");
        for f in [3.0, 10.0, 40.0, 150.0, 400.0] {
            let x: Vec<f64> = (0..40_000)
                .map(|i| (2.0 * PI * f * i as f64 / fs).sin())
                .collect();
            let y = sos.filter(&x);
            let fit = crate::fit_sine(&y[20_000..], fs, f).expect("fit");
            let g = sos.gain(f, fs);
            assert!(
                (fit.amplitude - g).abs() <= 1e-6 * g.max(1e-3),
                "{f} Hz: {} vs {g}",
                fit.amplitude
            );
        }
    }

    /// `ValidPhysics::gain_at` is what the chain does to a sine: the amplitude of
    /// `displacement` of a 1 m/s^2 sine over whole periods of a 4 s record, fitted on its
    /// middle half. Tolerances, relative: frequency integration 1e-12 (exact); time
    /// integration with a high-pass drift filter 1e-4 (fine enough to catch a missing
    /// `|H|^2`, 2e-3 at 10 Hz, or trapezoid factor, 4e-4 at 40 Hz); time integration with the
    /// default linear drift removal, which `gain_at` takes as 1, 4e-3 (measured: it moves a
    /// 4 s record's amplitude by 1.4e-4 at 10 Hz, 7.2e-4 at 40 Hz, 2.9e-3 at 150 Hz).
    #[test]
    fn physics_gain_is_the_chain_on_a_sine() {
        let fs = 5000.0;
        let configs = [
            (crate::PhysicsConfig::default(), 4e-3),
            (
                crate::PhysicsConfig {
                    integrator: crate::Integrator::Frequency,
                    ..crate::PhysicsConfig::default()
                },
                1e-12,
            ),
            (
                crate::PhysicsConfig {
                    drift: crate::Drift::Highpass {
                        order: 2,
                        cutoff_hz: 2.0,
                    },
                    ..crate::PhysicsConfig::default()
                },
                1e-4,
            ),
        ];
        for (cfg, tol) in configs {
            let chain = cfg.check(fs).expect("config");
            for f in [10.0, 25.0, 40.0, 150.0] {
                let n = (fs * 4.0) as usize; // whole periods of every f
                let x: Vec<f64> = (0..n)
                    .map(|i| (2.0 * PI * f * i as f64 / fs).sin())
                    .collect();
                let d = chain.displacement(&x).expect("displacement");
                let fit = crate::fit_sine(&d[n / 4..3 * n / 4], fs, f).expect("fit");
                let g = chain.gain_at(f);
                assert!(
                    (fit.amplitude - g).abs() <= tol * g,
                    "{cfg:?} at {f} Hz: {} vs {g}",
                    fit.amplitude
                );
            }
        }
    }
}
