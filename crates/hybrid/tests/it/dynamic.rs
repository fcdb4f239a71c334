//! `hxai dynamic` (issue 69) on the simulated spindle: the calibration recovers a known
//! ODE's constants within their 95 % intervals, the correction of the textbook ODE names
//! the state and the speed and beats the calibrated physics and the NARX boosting on
//! held-out runs, the conformal band and bad settings behave.
#![allow(clippy::unwrap_used)]

use hxai_hybrid::HybridError;
use hxai_hybrid::dynamic::{DynamicConfig, DynamicModel, TestSplit, compare, fit};
use hxai_hybrid::tables::Form;
use hxai_sim::cases::{SpindleThermalConfig, spindle_thermal};
use std::collections::BTreeMap;

const ODE: &str = "T_C' = (q*speed_krpm^1.5 - h*(T_C - ambient_C))/C";

fn table(forced: f64, runs: usize) -> hxai_symreg::Table {
    let c = SpindleThermalConfig {
        forced_convection_per_krpm: forced,
        n_runs: runs,
        ..SpindleThermalConfig::default()
    };
    spindle_thermal(&c, None).unwrap()
}

fn config(form: Form) -> DynamicConfig {
    DynamicConfig {
        time: "time_s".into(),
        run: Some("run".into()),
        states: vec!["T_C".into()],
        inputs: vec![
            "speed_krpm".into(),
            "ambient_C".into(),
            "humidity_pct".into(),
        ],
        ode: ODE.into(),
        calibrate: vec!["q".into(), "h".into()],
        init: BTreeMap::from([("q".into(), 30.0), ("h".into(), 8.0)]),
        set: BTreeMap::from([("C".into(), 20_000.0)]),
        form,
        conformal_folds: 0,
        ..DynamicConfig::default()
    }
}

/// With the textbook ODE as the truth (no forced convection), the calibration through the
/// trajectories finds `q` = 40 and `h` = 10 inside their 95 % intervals, from starting
/// values 25 % and 20 % off.
#[test]
fn calibration_recovers_a_known_odes_constants_within_their_intervals() {
    let mut cfg = config(Form::None);
    // the first reading carries the measurement's scatter: estimated, it does not bias
    cfg.initial = hxai_hybrid::dynamic::Initial::Estimate;
    let m = fit(&table(0.0, 6), &cfg, &mut |_| {}).unwrap();
    for (p, truth) in [("q", 40.0), ("h", 10.0)] {
        let e = &m.physics_calibrated[p];
        let [lo, hi] = e.ci95.unwrap();
        assert!(
            lo <= truth && truth <= hi,
            "{p} = {} with 95 % interval [{lo}, {hi}] misses {truth}",
            e.value
        );
        assert!(
            hi - lo < 0.05 * truth,
            "{p}: interval [{lo}, {hi}] too wide"
        );
    }
    assert_eq!(m.corrections[0].form, Form::None);
    // the calibrated physics follows the truth to about the measurement noise (0.05 K)
    assert!(
        m.train_rmse["physics_calibrated"] < 0.07,
        "{:?}",
        m.train_rmse
    );
}

/// With forced convection, the default correction names `T_C` and `speed_krpm` (not the
/// humidity), and on held-out runs the hybrid's free run is at most half the calibrated
/// physics' error and below the NARX boosting's.
#[test]
fn the_spindles_correction_is_found_and_beats_its_peers_on_held_out_runs() {
    let c = compare(
        &table(0.05, 12),
        &config(Form::Auto),
        &TestSplit::default(),
        &mut |_| {},
    )
    .unwrap();
    let rmse = |n: &str| {
        c.models
            .iter()
            .find(|m| m.name == n)
            .and_then(|m| m.rmse)
            .unwrap()
    };
    let names: Vec<&str> = c.models.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        ["physics", "physics_calibrated", "hybrid", "narx_boosting"]
    );
    assert!(
        rmse("hybrid") <= 0.5 * rmse("physics_calibrated"),
        "hybrid {} against calibrated physics {}",
        rmse("hybrid"),
        rmse("physics_calibrated")
    );
    assert!(rmse("hybrid") < rmse("narx_boosting"));
    let f = &c.hybrid.correction.features;
    assert!(
        f.iter().any(|x| x == "T_C") && f.iter().any(|x| x == "speed_krpm"),
        "{f:?}"
    );
    assert!(
        !f.iter().any(|x| x == "humidity_pct"),
        "{f:?} {:?}",
        c.hybrid
    );
    assert_eq!(c.test_runs.len(), 3);
}

/// The model file reads back equal, its predictions start at each run's first reading, and
/// the conformal band at 0.9 holds the hybrid inside it; without scores an interval is
/// refused.
#[test]
fn the_model_file_predicts_with_a_band_over_runs() {
    let t = table(0.05, 5);
    let mut cfg = config(Form::Factors);
    cfg.conformal_folds = 5;
    let m = fit(&t, &cfg, &mut |_| {}).unwrap();
    let back = DynamicModel::from_json(&m.to_json()).unwrap();
    assert_eq!(back, m);
    let p = back.predict(&t, Some(0.8)).unwrap();
    let measured = t.column("T_C").unwrap();
    assert_eq!(p.hybrid[0][0], measured[0]);
    let (lo, hi) = (p.lower.unwrap(), p.upper.unwrap());
    assert!(lo[0][5] < p.hybrid[0][5] && p.hybrid[0][5] < hi[0][5]);
    // 5 runs: a 0.9 band needs the 6th of 5 scores: empty, with a warning
    let p9 = back.predict(&t, Some(0.9)).unwrap();
    assert!(p9.lower.unwrap()[0][3].is_nan());
    assert!(!p9.warnings.is_empty());
    let mut none = back.clone();
    none.conformal = None;
    assert!(matches!(
        none.predict(&t, Some(0.8)),
        Err(HybridError::InvalidConfig(_))
    ));
}

/// Bad systems and settings are refused with messages, never a panic.
#[test]
fn bad_systems_are_refused() {
    let t = table(0.05, 3);
    let bad = |edit: &dyn Fn(&mut DynamicConfig), says: &str| {
        let mut c = config(Form::None);
        edit(&mut c);
        let e = fit(&t, &c, &mut |_| {}).err().map(|e| e.to_string());
        let e = e.unwrap_or_default();
        assert!(e.contains(says), "expected {says:?} in {e:?}");
    };
    bad(&|c| c.ode = "T_C = 1".into(), "not a derivative");
    bad(&|c| c.ode = "P' = 1".into(), "not among --state");
    bad(
        &|c| c.ode = "T_C' = (q*speed_krpm - k*T_C)/C".into(),
        "k in",
    );
    bad(&|c| c.ode = "T_C' = (q*".into(), "character 4");
    bad(&|c| c.time = "nope".into(), "nope");
    bad(
        &|c| c.set.insert("q".into(), 1.0).map_or((), |_| ()),
        "both calibrated",
    );
    bad(&|c| c.smooth = 2, "--smooth");
    bad(
        &|c| {
            c.init.insert("q".into(), 1e9);
        },
        "",
    );
}
