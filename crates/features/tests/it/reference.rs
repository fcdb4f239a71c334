//! Agreement with stored numpy/scipy output (testdata/features, written by scripts/ref_signal.py).
#![allow(clippy::unwrap_used)]

use hxai_features::{FeatureConfig, Features, PsdEstimator, Sigma, extract, extract_with};
use serde_json::Value;

type TestResult = Result<(), Box<dyn std::error::Error>>;

/// Relative tolerance for every feature: 1e-9 (the signals are unit scale; skewness can be
/// near zero, so its floor is 1e-9 absolute, i.e. relative to a scale of 1).
const REL: f64 = 1e-9;

fn check(got: f64, want: f64, what: &str) {
    let floor = if what == "f7" { 1.0 } else { 0.0 };
    let scale = got.abs().max(want.abs()).max(floor);
    assert!(
        (got - want).abs() <= REL * scale,
        "{what}: got {got:e}, want {want:e}"
    );
}

fn load() -> Result<Value, Box<dyn std::error::Error>> {
    let path = format!(
        "{}/../../testdata/features/features.json",
        env!("CARGO_MANIFEST_DIR")
    );
    Ok(serde_json::from_str(&std::fs::read_to_string(path)?)?)
}

/// The accelerometer samples of one case.
fn accel(case: &Value) -> Vec<f64> {
    case["accel"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

#[test]
fn features_match_numpy_scipy() -> TestResult {
    let data = load()?;
    for c in data["cases"].as_array().unwrap() {
        let a = accel(c);
        let fs = c["fs"].as_f64().unwrap();
        let cmd = c["command_hz"].as_f64().unwrap();
        let g = |k: &str| c[k].as_f64().unwrap();

        let f = extract(&a, fs, cmd)?;
        for (name, got, key) in [
            ("f1", f.frequency_hz, "f1"),
            ("f2", f.mav, "f2"),
            ("f3", f.variance, "f3"),
            ("f4", f.peak, "f4"),
            ("f5", f.rms, "f5"),
            ("f6", f.kurtosis, "f6_biased"),
            ("f7", f.skewness, "f7_biased"),
            ("f8", f.crest, "f8"),
            ("f9", f.impulse, "f9"),
            ("f10", f.shape, "f10"),
        ] {
            check(got, g(key), name);
        }
        check(f.mean_freq_hz, c["welch"]["f11"].as_f64().unwrap(), "f11");
        check(f.total_power, c["welch"]["f12"].as_f64().unwrap(), "f12");

        let cfg = FeatureConfig {
            sigma: Sigma::Unbiased,
            psd: PsdEstimator::Periodogram,
        };
        let u = extract_with(&a, fs, cmd, &cfg)?;
        check(u.kurtosis, g("f6_unbiased_sigma"), "f6");
        check(u.skewness, g("f7_unbiased_sigma"), "f7");
        check(
            u.mean_freq_hz,
            c["periodogram"]["f11"].as_f64().unwrap(),
            "f11",
        );
        check(
            u.total_power,
            c["periodogram"]["f12"].as_f64().unwrap(),
            "f12",
        );
    }
    Ok(())
}

#[test]
fn names_vec_slice_and_json_round_trip() -> TestResult {
    let data = load()?;
    let c = &data["cases"][0];
    let a = accel(c);
    let f = extract(&a, 1000.0, 20.0)?;
    assert_eq!(Features::NAMES.len(), 12);
    assert_eq!(Features::NAMES[11], "f12");
    assert_eq!(Features::from_slice(&f.to_vec())?, f);
    assert!(Features::from_slice(&[1.0; 11]).is_err());
    let json = serde_json::to_value(f)?;
    for (i, name) in Features::NAMES.iter().enumerate() {
        assert_eq!(json[name].as_f64(), Some(f.to_vec()[i]));
    }
    let back: Features = serde_json::from_value(json)?;
    assert_eq!(back, f);
    Ok(())
}

#[test]
fn bad_input_gives_typed_errors() {
    use hxai_features::FeatureError as E;
    assert!(matches!(
        extract(&[], 100.0, 10.0),
        Err(E::TooShort { len: 0 })
    ));
    assert!(matches!(
        extract(&[1.0, f64::NAN], 100.0, 10.0),
        Err(E::NonFinite { index: 1 })
    ));
    assert!(matches!(
        extract(&[1.0, 2.0], 0.0, 10.0),
        Err(E::InvalidSampleRate(_))
    ));
    assert!(matches!(
        extract(&[1.0, 2.0], 100.0, -1.0),
        Err(E::InvalidCommandFrequency(_))
    ));
    assert!(matches!(
        extract(&[3.0; 50], 100.0, 10.0),
        Err(E::ConstantSignal)
    ));
    assert!(matches!(
        extract(&[0.0; 50], 100.0, 10.0),
        Err(E::ConstantSignal)
    ));
}
