//! Property tests of hxai-features. Each test states its invariant in words first.
#![allow(clippy::unwrap_used)]

use hxai_features::{FeatureConfig, PsdEstimator, Sigma, extract, extract_with};
use proptest::prelude::*;

fn signal() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-10.0f64..10.0, 16..400).prop_filter("not (nearly) constant", |x| {
        let m = x.iter().sum::<f64>() / x.len() as f64;
        x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() > 1e-6
    })
}

fn scale() -> impl Strategy<Value = f64> {
    prop_oneof![-100.0f64..-0.01, 0.01f64..100.0]
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-300)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    // Scaling the acceleration by c scales MAV, RMS and peak by |c|, the variance and total
    // power by c^2 and flips the skewness's sign with c; kurtosis, crest, impulse and shape
    // factors and the mean frequency do not change. Tolerance 1e-9 relative (skewness:
    // 1e-9 absolute on top, as it may be near 0).
    #[test]
    fn scaling_laws(x in signal(), c in scale(), periodogram in any::<bool>(), unbiased in any::<bool>()) {
        let cfg = FeatureConfig {
            sigma: if unbiased { Sigma::Unbiased } else { Sigma::Biased },
            psd: if periodogram { PsdEstimator::Periodogram } else { PsdEstimator::default() },
        };
        let fs = 1000.0;
        let f = extract_with(&x, fs, 20.0, &cfg).unwrap();
        let y: Vec<f64> = x.iter().map(|v| c * v).collect();
        let g = extract_with(&y, fs, 20.0, &cfg).unwrap();
        let tol = 1e-9;
        prop_assert!(rel(g.mav, c.abs() * f.mav) < tol);
        prop_assert!(rel(g.rms, c.abs() * f.rms) < tol);
        prop_assert!(rel(g.peak, c.abs() * f.peak) < tol);
        prop_assert!(rel(g.variance, c * c * f.variance) < tol);
        prop_assert!(rel(g.total_power, c * c * f.total_power) < tol);
        prop_assert!(rel(g.kurtosis, f.kurtosis) < tol);
        prop_assert!(rel(g.crest, f.crest) < tol);
        prop_assert!(rel(g.impulse, f.impulse) < tol);
        prop_assert!(rel(g.shape, f.shape) < tol);
        prop_assert!(rel(g.mean_freq_hz, f.mean_freq_hz) < tol);
        prop_assert!((g.skewness - c.signum() * f.skewness).abs() <= tol * (1.0 + f.skewness.abs()));
        prop_assert_eq!(g.frequency_hz, 20.0);
    }

    // Orderings that hold for every signal: peak >= RMS >= MAV >= 0 (so crest, impulse and
    // shape factors are >= 1), kurtosis >= skewness^2 + 1 with biased sigma (Pearson's
    // inequality), and the mean frequency lies in [0, fs/2]. Slack 1e-12 relative for rounding.
    #[test]
    fn orderings(x in signal(), fs in 10.0f64..10_000.0) {
        let f = extract(&x, fs, 10.0).unwrap();
        let e = 1e-12;
        prop_assert!(f.peak >= f.rms * (1.0 - e) && f.rms >= f.mav * (1.0 - e) && f.mav > 0.0);
        prop_assert!(f.crest >= 1.0 - e && f.impulse >= 1.0 - e && f.shape >= 1.0 - e);
        prop_assert!(f.kurtosis >= (f.skewness * f.skewness + 1.0) * (1.0 - 1e-9));
        prop_assert!(f.mean_freq_hz >= 0.0 && f.mean_freq_hz <= fs / 2.0 * (1.0 + e));
    }

    // No panic on any input, finite or not: values or typed errors only.
    #[test]
    fn no_panic(
        x in prop::collection::vec(prop_oneof![-1e300f64..1e300, Just(f64::NAN), Just(f64::INFINITY), Just(0.0)], 0..64),
        fs in prop_oneof![-1.0f64..1e6, Just(f64::NAN), Just(0.0)],
        cmd in prop_oneof![-1.0f64..100.0, Just(f64::INFINITY)],
    ) {
        let _ = extract(&x, fs, cmd);
        let _ = extract_with(&x, fs, cmd, &FeatureConfig { sigma: Sigma::Unbiased, psd: PsdEstimator::Periodogram });
    }
}
