//! Property tests of hxai-signal. Each test states its invariant in words first.
#![allow(clippy::unwrap_used)]

use std::f64::consts::PI;

use hxai_signal::{
    Band, PhysicsConfig, WelchConfig, butter, cumulative_trapezoid, detrend, fit_sine, fit_sine4,
    welch,
};
use proptest::prelude::*;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::SeedableRng;

fn band_strategy() -> impl Strategy<Value = (usize, Band)> {
    (1usize..=6, 0usize..3, 0.01f64..0.2, 0.25f64..0.45).prop_map(|(order, kind, lo, hi)| {
        // Frequencies as fractions of fs = 1 kHz.
        let band = match kind {
            0 => Band::Lowpass(hi * 1000.0),
            1 => Band::Highpass(lo * 1000.0),
            _ => Band::Bandpass(lo * 1000.0, hi * 1000.0),
        };
        (order, band)
    })
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    // Linearity of `filter`: filtering a*x + b*y equals a*filter(x) + b*filter(y), up to
    // rounding: 1e-9 times the largest magnitude involved.
    #[test]
    fn filter_is_linear(
        (order, band) in band_strategy(),
        x in prop::collection::vec(-10.0f64..10.0, 64),
        y in prop::collection::vec(-10.0f64..10.0, 64),
        a in -5.0f64..5.0,
        b in -5.0f64..5.0,
    ) {
        let sos = butter(order, band, 1000.0).unwrap();
        let mix: Vec<f64> = x.iter().zip(&y).map(|(p, q)| a * p + b * q).collect();
        let lhs = sos.filter(&mix);
        let (fx, fy) = (sos.filter(&x), sos.filter(&y));
        let scale = 1.0 + max_abs(&lhs) + a.abs() * max_abs(&fx) + b.abs() * max_abs(&fy);
        for i in 0..64 {
            prop_assert!((lhs[i] - (a * fx[i] + b * fy[i])).abs() <= 1e-9 * scale);
        }
    }

    // Time invariance of `filter`: delaying the input by k samples (zeros in front) delays
    // the output by k samples and changes nothing else (1e-12 relative: the arithmetic is the
    // same, only the state is zero for longer).
    #[test]
    fn filter_is_time_invariant(
        (order, band) in band_strategy(),
        x in prop::collection::vec(-10.0f64..10.0, 50),
        k in 1usize..30,
    ) {
        let sos = butter(order, band, 1000.0).unwrap();
        let mut delayed = vec![0.0; k];
        delayed.extend_from_slice(&x);
        let yd = sos.filter(&delayed);
        let y = sos.filter(&x);
        let scale = 1.0 + max_abs(&y);
        prop_assert!(yd[..k].iter().all(|v| *v == 0.0));
        for i in 0..x.len() {
            prop_assert!((yd[i + k] - y[i]).abs() <= 1e-12 * scale);
        }
    }

    // Zero phase of `filtfilt`: a sine inside the pass band of the 4th-order 5..200 Hz band-pass
    // comes out with the same phase (within 1e-4 rad) and amplitude (within 1 %) in the middle
    // half of the record, away from the edge transients.
    #[test]
    fn filtfilt_has_zero_phase_in_band(freq in 15.0f64..120.0, phase in -3.0f64..3.0, amp in 0.1f64..10.0) {
        let fs = 1000.0;
        let sos = butter(4, Band::Bandpass(5.0, 200.0), fs).unwrap();
        let x: Vec<f64> = (0..4000).map(|i| amp * (2.0 * PI * freq * i as f64 / fs + phase).sin()).collect();
        let y = sos.filtfilt(&x).unwrap();
        let fx = fit_sine(&x[1000..3000], fs, freq).unwrap();
        let fy = fit_sine(&y[1000..3000], fs, freq).unwrap();
        let dphi = (fy.phase - fx.phase + PI).rem_euclid(2.0 * PI) - PI;
        prop_assert!(dphi.abs() < 1e-4, "phase shift {dphi}");
        prop_assert!((fy.amplitude / fx.amplitude - 1.0).abs() < 0.01);
    }

    // DC rejection of the band-pass: a constant input gives (almost) zero output, |y| <= 1e-9 |c|
    // everywhere, because the odd extension of a constant is constant and the steady-state
    // initial condition of a band-pass for a step is its zero DC response.
    #[test]
    fn bandpass_rejects_dc(c in -100.0f64..100.0, order in 1usize..=6, n in 100usize..600) {
        let sos = butter(order, Band::Bandpass(5.0, 200.0), 1000.0).unwrap();
        prop_assume!(n > sos.padlen());
        let y = sos.filtfilt(&vec![c; n]).unwrap();
        prop_assert!(max_abs(&y) <= 1e-9 * c.abs().max(1e-300));
    }

    // The trapezoid rule is exact on straight lines: integrating a + b t from 0 gives
    // a t + b t^2 / 2 at every sample (1e-12 relative to the largest value).
    #[test]
    fn trapezoid_exact_on_lines(a in -10.0f64..10.0, b in -10.0f64..10.0, dx in 1e-4f64..1.0, n in 1usize..500) {
        let y: Vec<f64> = (0..n).map(|i| a + b * i as f64 * dx).collect();
        let got = cumulative_trapezoid(&y, dx);
        let want: Vec<f64> = (0..n).map(|i| { let t = i as f64 * dx; a * t + b * t * t / 2.0 }).collect();
        let scale = 1.0 + max_abs(&want);
        for i in 0..n {
            prop_assert!((got[i] - want[i]).abs() <= 1e-12 * scale);
        }
    }

    // The sine fit recovers amplitude and phase of a noisy sine. With N = 2000 samples and
    // uniform noise of standard deviation sigma = 0.05 A (half-width
    // 0.05 A * sqrt 3), the least-squares errors have standard deviation sigma * sqrt(2 / N)
    // (amplitude) and sigma / A * sqrt(2 / N) (phase), about 0.0016 A and 0.0016 rad; the
    // bounds are 0.01 A and 0.01 rad (over 6 standard deviations). The four-parameter fit,
    // started 0.2 % off, must find the frequency within 1e-3 relative.
    #[test]
    fn fit_sine_recovers_noisy_sine(
        amp in 0.1f64..10.0,
        phase in -3.1f64..3.1,
        offset in -5.0f64..5.0,
        freq in 2.0f64..100.0,
        seed in any::<u64>(),
    ) {
        let fs = 1000.0;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let half = 0.05 * amp * 3f64.sqrt();
        let x: Vec<f64> = (0..2000)
            .map(|i| offset + amp * (2.0 * PI * freq * i as f64 / fs + phase).sin() + rng.gen_range(-half..half))
            .collect();
        let fit = fit_sine(&x, fs, freq).unwrap();
        prop_assert!((fit.amplitude - amp).abs() < 0.01 * amp);
        let dphi = (fit.phase - phase + PI).rem_euclid(2.0 * PI) - PI;
        prop_assert!(dphi.abs() < 0.01);
        let f4 = fit_sine4(&x, fs, freq * 1.002).unwrap();
        prop_assert!((f4.frequency_hz / freq - 1.0).abs() < 1e-3);
        prop_assert!((f4.fit.amplitude - amp).abs() < 0.01 * amp);
    }

    // Parseval for the periodogram: sum(density) * df equals the variance (1/N) sum (x - mean)^2
    // exactly up to rounding (1e-9 relative), for any length, odd or even.
    #[test]
    fn periodogram_parseval(x in prop::collection::vec(-10.0f64..10.0, 8..400), fs in 1.0f64..5000.0) {
        let psd = welch(&x, fs, &WelchConfig::periodogram()).unwrap();
        let df = fs / x.len() as f64;
        let power: f64 = psd.density.iter().sum::<f64>() * df;
        let var = detrend(&x, hxai_signal::Detrend::Constant).iter().map(|v| v * v).sum::<f64>() / x.len() as f64;
        prop_assert!((power - var).abs() <= 1e-9 * var.max(1e-12));
    }

    // Parseval for Welch's default estimate of white noise: sum(density) * df estimates the
    // variance; with 8192 samples (63 half-overlapping Hann segments of 256) its relative
    // standard error is about 2 %, the bound is 10 %.
    #[test]
    fn welch_parseval_white_noise(seed in any::<u64>(), sd in 0.01f64..100.0) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let half = sd * 3f64.sqrt();
        let x: Vec<f64> = (0..8192).map(|_| rng.gen_range(-half..half)).collect();
        let psd = welch(&x, 1000.0, &WelchConfig::default()).unwrap();
        let power: f64 = psd.density.iter().sum::<f64>() * (1000.0 / 256.0);
        let mean = x.iter().sum::<f64>() / 8192.0;
        let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / 8192.0;
        prop_assert!((power / var - 1.0).abs() < 0.1, "ratio {}", power / var);
    }
}

fn wild() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1e6f64..1e6,
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(1e308),
        Just(f64::MIN_POSITIVE),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    // No panic on any input: arbitrary finite and non-finite samples, rates, cutoffs and
    // orders only ever produce values or typed errors.
    #[test]
    fn no_panic_on_any_input(
        x in prop::collection::vec(wild(), 0..80),
        fs in wild(),
        f1 in wild(),
        f2 in wild(),
        order in 0usize..9,
        nperseg in 0usize..100,
    ) {
        for band in [Band::Lowpass(f1), Band::Highpass(f1), Band::Bandpass(f1, f2)] {
            if let Ok(sos) = butter(order, band, fs) {
                let _ = sos.filter(&x);
                let _ = sos.filtfilt(&x);
                let _ = sos.zi();
            }
        }
        let _ = cumulative_trapezoid(&x, fs);
        let _ = detrend(&x, hxai_signal::Detrend::Linear);
        let cfg = WelchConfig { nperseg, ..WelchConfig::default() };
        let _ = welch(&x, fs, &cfg);
        let _ = welch(&x, fs, &WelchConfig::periodogram());
        let _ = fit_sine(&x, fs, f1);
        let _ = fit_sine4(&x, fs, f1);
        let phys = PhysicsConfig { low_hz: f1, high_hz: f2, order, ..PhysicsConfig::default() };
        let _ = hxai_signal::displacement(&x, fs, &phys);
        let freq = PhysicsConfig { integrator: hxai_signal::Integrator::Frequency, ..phys };
        let _ = hxai_signal::displacement(&x, fs, &freq);
    }
}

// `phase_lag_s`: the phase difference over 2 pi f, wrapped to (-pi, pi] first, so a lag of
// nearly a full period reads as a small lead. Tolerance 1e-12 s (a few ulps of the inputs).
#[test]
fn phase_lag_wraps_to_half_a_period() {
    use hxai_signal::{SineFit, phase_lag_s};
    let sine = |phase: f64| SineFit {
        amplitude: 1.0,
        phase,
        offset: 0.0,
    };
    let f = 10.0;
    let lag = phase_lag_s(&sine(0.3), &sine(0.1), f);
    assert!((lag - 0.2 / (2.0 * PI * f)).abs() < 1e-12, "{lag}");
    let lead = phase_lag_s(&sine(3.0), &sine(-3.0), f);
    assert!(
        (lead - (6.0 - 2.0 * PI) / (2.0 * PI * f)).abs() < 1e-12,
        "{lead}"
    );
    assert!(lead < 0.0);
}
