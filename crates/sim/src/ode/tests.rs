//! The integrator against scipy's `solve_ivp` (`DOP853`, rtol 1e-13) on three ODEs, to 1e-8
//! (vectors from `scripts/ref_ode.py`), and its refusals: a stiff system, a blow-up, bad
//! arguments.
#![allow(clippy::unwrap_used, clippy::expect_used)]
use super::*;

fn reference() -> serde_json::Value {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/ode/solve_ivp.json"
    );
    serde_json::from_str(&std::fs::read_to_string(path).expect("the vectors")).expect("json")
}

fn floats(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

fn tight() -> OdeSettings {
    OdeSettings {
        rtol: 1e-11,
        atol: 1e-13,
        ..OdeSettings::default()
    }
}

/// Every state within 1e-8 of scipy's (relative to the value's size where it is above 1).
fn close(got: &[Vec<f64>], want: &serde_json::Value, name: &str) {
    let want: Vec<Vec<f64>> = want
        .as_array()
        .expect("states")
        .iter()
        .map(floats)
        .collect();
    assert_eq!(got.len(), want.len(), "{name}");
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        for (a, b) in g.iter().zip(w) {
            assert!(
                (a - b).abs() <= 1e-8 * b.abs().max(1.0),
                "{name} at output {k}: {a} against scipy's {b}"
            );
        }
    }
}

#[test]
fn van_der_pol_and_lotka_volterra_match_scipy() {
    let r = reference();
    type Fun = fn(f64, &[f64], &mut [f64]);
    let cases: [(&str, Fun); 2] = [
        ("van_der_pol", |_, y, d| {
            d[0] = y[1];
            d[1] = (1.0 - y[0] * y[0]) * y[1] - y[0];
        }),
        ("lotka_volterra", |_, y, d| {
            d[0] = 1.5 * y[0] - y[0] * y[1];
            d[1] = -3.0 * y[1] + y[0] * y[1];
        }),
    ];
    for (name, rhs) in cases {
        let c = &r[name];
        let mut f = |t: f64, y: &[f64], d: &mut [f64]| rhs(t, y, d);
        let got = integrate(
            &mut f,
            c["t0"].as_f64().unwrap(),
            &floats(&c["y0"]),
            &floats(&c["times"]),
            &tight(),
        )
        .unwrap();
        close(&got, &c["states"], name);
    }
}

#[test]
fn an_input_held_between_samples_matches_scipy() {
    let r = reference();
    let c = &r["thermal_held"];
    let u = floats(&c["inputs"]);
    let (q, h, ta, cap) = (2.0, 0.5, 20.0, 10.0);
    let mut y = floats(&c["y0"]);
    let mut got = Vec::new();
    for (k, &uk) in u.iter().enumerate() {
        let mut f = |_: f64, s: &[f64], d: &mut [f64]| {
            d[0] = (q * uk.powf(1.5) - h * (s[0] - ta)) / cap;
        };
        let t0 = k as f64;
        let out = integrate(&mut f, t0, &y, &[t0 + 1.0], &tight()).unwrap();
        y.clone_from(&out[0]);
        got.push(y.clone());
    }
    close(&got, &c["states"], "thermal_held");
}

#[test]
fn the_default_tolerances_are_within_their_order_of_scipy() {
    // y' = -2 y, y(3) = exp(-6): the defaults (rtol 1e-8) land within 1e-7 of the truth
    let mut f = |_: f64, y: &[f64], d: &mut [f64]| d[0] = -2.0 * y[0];
    let got = integrate(&mut f, 0.0, &[1.0], &[1.0, 3.0], &OdeSettings::default()).unwrap();
    assert!((got[1][0] - (-6.0f64).exp()).abs() < 1e-7 * (-6.0f64).exp().max(1e-3));
    // an output at the start is the start
    let got = integrate(&mut f, 0.0, &[1.0], &[0.0], &OdeSettings::default()).unwrap();
    assert_eq!(got, vec![vec![1.0]]);
}

#[test]
fn a_stiff_system_is_refused_with_a_message() {
    let mut f = |t: f64, y: &[f64], d: &mut [f64]| d[0] = -1e6 * (y[0] - t.cos());
    let e = integrate(&mut f, 0.0, &[0.0], &[10.0], &OdeSettings::default()).unwrap_err();
    assert!(matches!(e, OdeError::Stiff { .. }), "{e}");
    assert!(e.to_string().contains("stiff"));
}

#[test]
fn a_blow_up_and_bad_arguments_are_errors_not_panics() {
    // y' = y^2 from 1 reaches infinity at t = 1
    let mut f = |_: f64, y: &[f64], d: &mut [f64]| d[0] = y[0] * y[0];
    let e = integrate(&mut f, 0.0, &[1.0], &[2.0], &OdeSettings::default()).unwrap_err();
    assert!(
        matches!(
            e,
            OdeError::NotFinite { .. } | OdeError::StepTooSmall { .. } | OdeError::TooManySteps(_)
        ),
        "{e}"
    );
    let mut g = |_: f64, y: &[f64], d: &mut [f64]| d[0] = -y[0];
    for (y0, times, s) in [
        (vec![], vec![1.0], OdeSettings::default()),
        (vec![1.0], vec![2.0, 1.0], OdeSettings::default()),
        (vec![1.0], vec![-1.0], OdeSettings::default()),
        (
            vec![1.0],
            vec![1.0],
            OdeSettings {
                rtol: 0.0,
                ..OdeSettings::default()
            },
        ),
    ] {
        let e = integrate(&mut g, 0.0, &y0, &times, &s).unwrap_err();
        assert!(matches!(e, OdeError::Invalid(_)), "{e}");
    }
    let e = integrate(&mut g, 0.0, &[f64::NAN], &[1.0], &OdeSettings::default()).unwrap_err();
    assert!(matches!(e, OdeError::NotFinite { .. }));
}
