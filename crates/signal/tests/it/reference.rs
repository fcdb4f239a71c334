//! Agreement with stored scipy output (testdata/signal, written by scripts/ref_signal.py).
//!
//! Tolerances: Butterworth SOS coefficients 1e-12 relative; `sosfilt`, `sosfilt_zi`,
//! `sosfiltfilt`, Welch and periodogram densities, `cumulative_trapezoid`, `detrend` and the
//! whole physics chain (both integrators) 1e-9 relative, with a floor of 1e-9 times the
//! largest reference value of the vector (each assertion says so again).
#![allow(clippy::unwrap_used)]

use hxai_signal::{
    Band, Detrend, Scaling, Sos, WelchConfig, Window, butter, cumulative_trapezoid, detrend, welch,
};
use serde_json::Value;

type TestResult = Result<(), Box<dyn std::error::Error>>;

fn load(name: &str) -> Result<Value, Box<dyn std::error::Error>> {
    let path = format!(
        "{}/../../testdata/signal/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    Ok(serde_json::from_str(&std::fs::read_to_string(path)?)?)
}

fn vecf(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn band(c: &Value) -> Band {
    let wn = vecf(&c["wn"]);
    match c["btype"].as_str().unwrap() {
        "lowpass" => Band::Lowpass(wn[0]),
        "highpass" => Band::Highpass(wn[0]),
        _ => Band::Bandpass(wn[0], wn[1]),
    }
}

/// Relative closeness with the tolerance `rel`, where the scale is the larger of the two
/// values and `floor` (the floor covers values that are zero up to rounding).
fn close(a: f64, b: f64, rel: f64, floor: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(floor)
}

/// Every value within `rel` relative of the reference, with the absolute floor `rel * max|ref|`
/// for entries that cross zero (signals are unit scale, so this floor is `rel` times about 1).
fn assert_vec_close(got: &[f64], want: &[f64], rel: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: length");
    let scale = want.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            close(*g, *w, rel, scale),
            "{what}[{i}]: got {g:e}, want {w:e} (rel {rel:e})"
        );
    }
}

#[test]
fn butter_sections_match_scipy() -> TestResult {
    // Tolerance: 1e-12 relative to the coefficient, with an absolute floor of 1e-12 times the
    // largest coefficient of the same polynomial (b0..b2 or a0..a2 of that section), because a
    // coefficient that is a sum of O(1) terms cancelling to ~0 carries absolute rounding error.
    let data = load("butter.json")?;
    let designs = data["designs"].as_array().unwrap();
    assert_eq!(designs.len(), 48);
    for d in designs {
        let order = d["order"].as_u64().unwrap() as usize;
        let fs = d["fs"].as_f64().unwrap();
        let sos = butter(order, band(d), fs)?;
        let want: Vec<Vec<f64>> = d["sos"].as_array().unwrap().iter().map(vecf).collect();
        assert_eq!(sos.sections().len(), want.len(), "sections of {d}");
        for (s, w) in sos.sections().iter().zip(&want) {
            for half in [0..3, 3..6] {
                let floor = w[half.clone()].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                for i in half {
                    assert!(
                        close(s[i], w[i], 1e-12, floor),
                        "order {order} {:?}: got {s:?}, want {w:?}",
                        band(d)
                    );
                }
            }
        }
    }
    Ok(())
}

#[test]
fn filter_zi_filtfilt_match_scipy() -> TestResult {
    // Tolerance 1e-9 relative (floor: 1e-9 times the largest |reference| of the vector).
    let data = load("filter.json")?;
    for c in data["cases"].as_array().unwrap() {
        let sos = butter(
            c["order"].as_u64().unwrap() as usize,
            band(c),
            c["fs"].as_f64().unwrap(),
        )?;
        let x = vecf(&c["x"]);
        assert_eq!(sos.padlen() as u64, c["padlen"].as_u64().unwrap());
        assert_vec_close(&sos.filter(&x), &vecf(&c["sosfilt"]), 1e-9, "sosfilt");
        let zi: Vec<f64> = sos.zi().iter().flatten().copied().collect();
        let want_zi: Vec<f64> = c["zi"].as_array().unwrap().iter().flat_map(vecf).collect();
        assert_vec_close(&zi, &want_zi, 1e-9, "sosfilt_zi");
        assert_vec_close(
            &sos.filtfilt(&x)?,
            &vecf(&c["sosfiltfilt"]),
            1e-9,
            "sosfiltfilt",
        );
        // One sample shorter than padlen + 1 must be refused, as scipy does.
        let short = &x[..sos.padlen()];
        assert!(matches!(
            sos.filtfilt(short),
            Err(hxai_signal::SignalError::TooShort { .. })
        ));
    }
    Ok(())
}

#[test]
fn filter_with_state_continues_a_split_signal() -> TestResult {
    // Filtering in two pieces, passing the final state on, equals filtering at once (1e-12).
    let data = load("filter.json")?;
    let c = &data["cases"][0];
    let sos = butter(4, band(c), 1000.0)?;
    let x = vecf(&c["x"]);
    let zero = vec![[0.0; 2]; sos.sections().len()];
    let (y1, z1) = sos.filter_with_state(&x[..150], &zero)?;
    let (y2, _) = sos.filter_with_state(&x[150..], &z1)?;
    let joined: Vec<f64> = y1.into_iter().chain(y2).collect();
    assert_vec_close(&joined, &sos.filter(&x), 1e-12, "split filter");
    Ok(())
}

#[test]
fn welch_matches_scipy() -> TestResult {
    // Tolerance 1e-9 relative (floor: 1e-9 times the largest density of the case).
    let data = load("welch.json")?;
    for c in data["cases"].as_array().unwrap() {
        let kw = &c["kwargs"];
        let mut cfg = if kw.get("periodogram").is_some() {
            WelchConfig::periodogram()
        } else {
            WelchConfig::default()
        };
        if let Some(v) = kw.get("nperseg") {
            cfg.nperseg = v.as_u64().unwrap() as usize;
        }
        if let Some(v) = kw.get("noverlap") {
            cfg.noverlap = Some(v.as_u64().unwrap() as usize);
        }
        match kw.get("detrend") {
            Some(Value::String(s)) if s == "linear" => cfg.detrend = Detrend::Linear,
            Some(Value::Bool(false)) => cfg.detrend = Detrend::None,
            _ => {}
        }
        if kw.get("scaling").is_some() {
            cfg.scaling = Scaling::Spectrum;
        }
        if kw.get("window").is_some() {
            cfg.window = Window::Boxcar;
        }
        let psd = welch(&vecf(&c["x"]), c["fs"].as_f64().unwrap(), &cfg)?;
        assert_vec_close(&psd.freqs, &vecf(&c["freqs"]), 1e-12, "freqs");
        assert_vec_close(&psd.density, &vecf(&c["density"]), 1e-9, "density");
    }
    Ok(())
}

#[test]
fn integration_and_detrend_match_scipy() -> TestResult {
    // Tolerance 1e-9 relative (floor: 1e-9 times the largest |reference|).
    let data = load("integrate.json")?;
    let y = vecf(&data["y"]);
    let got = cumulative_trapezoid(&y, data["dx"].as_f64().unwrap());
    assert_eq!(got[0], 0.0);
    assert_vec_close(&got, &vecf(&data["cumulative_trapezoid"]), 1e-9, "cumtrapz");
    assert_vec_close(
        &detrend(&y, Detrend::Linear),
        &vecf(&data["detrend_linear"]),
        1e-9,
        "linear",
    );
    assert_vec_close(
        &detrend(&y, Detrend::Constant),
        &vecf(&data["detrend_constant"]),
        1e-9,
        "constant",
    );
    Ok(())
}

#[test]
fn from_sections_normalises_and_rejects() {
    let s = Sos::from_sections(vec![[2.0, 0.0, 0.0, 2.0, -1.0, 0.0]]).unwrap();
    assert_eq!(s.sections()[0], [1.0, 0.0, 0.0, 1.0, -0.5, 0.0]);
    assert!(Sos::from_sections(vec![]).is_err());
    assert!(Sos::from_sections(vec![[1.0, 0.0, 0.0, 0.0, 0.0, 0.0]]).is_err());
    assert!(Sos::from_sections(vec![[f64::NAN, 0.0, 0.0, 1.0, 0.0, 0.0]]).is_err());
}

#[test]
fn long_cascades_equal_their_halves() -> TestResult {
    // More than 8 sections take the section-by-section path; it must equal filtering by the
    // first and then the second half of the cascade (both on the fused kernel), to 1e-12.
    let data = load("filter.json")?;
    let x = vecf(&data["cases"][0]["x"]);
    let sos = butter(10, Band::Bandpass(5.0, 200.0), 1000.0)?;
    assert_eq!(sos.sections().len(), 10);
    let (a, b) = sos.sections().split_at(5);
    let first = Sos::from_sections(a.to_vec())?;
    let second = Sos::from_sections(b.to_vec())?;
    assert_vec_close(
        &sos.filter(&x),
        &second.filter(&first.filter(&x)),
        1e-12,
        "cascade",
    );
    Ok(())
}

#[test]
fn physics_chain_matches_scipy_composition() -> TestResult {
    // The default chain equals butter + sosfiltfilt + (cumulative_trapezoid, detrend linear)
    // twice, and the frequency integrator equals rfft / -omega^2 in band / irfft (numpy), to
    // 1e-9 relative (floor: 1e-9 times the largest |displacement|).
    use hxai_signal::{Integrator, PhysicsConfig, displacement};
    let data = load("physics.json")?;
    for c in data["cases"].as_array().unwrap() {
        let a = vecf(&c["accel"]);
        let fs = c["fs"].as_f64().unwrap();
        let d = displacement(&a, fs, &PhysicsConfig::default())?;
        assert_vec_close(&d, &vecf(&c["time"]), 1e-9, "time-domain chain");
        let cfg = PhysicsConfig {
            integrator: Integrator::Frequency,
            ..PhysicsConfig::default()
        };
        let d = displacement(&a, fs, &cfg)?;
        assert_vec_close(
            &d,
            &vecf(&c["frequency"]),
            1e-9,
            "frequency-domain integrator",
        );
    }
    Ok(())
}
