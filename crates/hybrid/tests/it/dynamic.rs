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

/// With forced convection, the default correction names `T_C`, `speed_krpm` and
/// `ambient_C` (the true term is `-h k n (T - Ta)/C`; not the humidity), and on held-out runs the hybrid's free run is at most half the calibrated
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
    for c in ["T_C", "speed_krpm", "ambient_C"] {
        assert!(f.iter().any(|x| x == c), "{c} not in {f:?}");
    }
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
    // a blow-up at the starting values is named, with the values
    bad(
        &|c| {
            c.ode = "T_C' = q*T_C^2".into();
            c.calibrate = vec!["q".into()];
            c.init = BTreeMap::from([("q".into(), 1.0)]);
            c.set.clear();
        },
        "cannot be integrated from the starting values (q = 1)",
    );
}

/// `n` runs of a driven mass-spring-damper `x' = v; v' = (u - k x - c v)/m` (k = 4, c = 0.6,
/// m = 1) with the force `u` stepping between runs' levels, `x` and `v` measured with
/// scatter 0.002: a table of two states.
fn oscillator(runs: usize) -> hxai_symreg::Table {
    use hxai_sim::ode::{OdeSettings, integrate};
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let noise = Normal::new(0.0, 0.002).unwrap();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 5];
    for r in 0..runs {
        let mut y = vec![0.1 * r as f64, 0.0];
        for k in 0..150u32 {
            let t = 0.1 * f64::from(k);
            let u = if (k as usize / 30 + r).is_multiple_of(2) {
                1.0
            } else {
                -0.5
            };
            cols[0].push(r as f64 + 1.0);
            cols[1].push(t);
            cols[2].push(u);
            cols[3].push(y[0] + noise.sample(&mut rng));
            cols[4].push(y[1] + noise.sample(&mut rng));
            let mut f = |_t: f64, s: &[f64], d: &mut [f64]| {
                d[0] = s[1];
                d[1] = u - 4.0 * s[0] - 0.6 * s[1];
            };
            y = integrate(&mut f, t, &y, &[t + 0.1], &OdeSettings::default()).unwrap()[0].clone();
        }
    }
    let names = ["run", "t", "u", "x", "v"].map(String::from).to_vec();
    hxai_symreg::Table::new(names, cols).unwrap()
}

/// Two states: the calibration recovers `k` and `c` of a mass-spring-damper within their
/// 95 % intervals, and the prediction of both states follows the measurements.
#[test]
fn a_system_of_two_states_is_calibrated() {
    let t = oscillator(3);
    let cfg = DynamicConfig {
        time: "t".into(),
        run: Some("run".into()),
        states: vec!["x".into(), "v".into()],
        inputs: vec!["u".into()],
        ode: "x' = v; v' = (u - k*x - c*v)/m".into(),
        calibrate: vec!["k".into(), "c".into()],
        init: BTreeMap::from([("k".into(), 3.0), ("c".into(), 1.0)]),
        set: BTreeMap::from([("m".into(), 1.0)]),
        form: Form::None,
        initial: hxai_hybrid::dynamic::Initial::Estimate,
        conformal_folds: 0,
        ..DynamicConfig::default()
    };
    let m = fit(&t, &cfg, &mut |_| {}).unwrap();
    for (p, truth) in [("k", 4.0), ("c", 0.6)] {
        let [lo, hi] = m.physics_calibrated[p].ci95.unwrap();
        assert!(
            lo <= truth && truth <= hi,
            "{p}: [{lo}, {hi}] misses {truth}"
        );
    }
    let p = m.predict(&t, None).unwrap();
    for (j, s) in ["x", "v"].iter().enumerate() {
        let y = t.column(s).unwrap();
        let rmse = (p.hybrid[j]
            .iter()
            .zip(y)
            .map(|(a, b)| (a - b).powi(2))
            .sum::<f64>()
            / y.len() as f64)
            .sqrt();
        assert!(rmse < 0.01, "{s}: free-run RMSE {rmse}");
    }
}

/// Every fit saves: a run too short to search a correction on gives the calibrated physics,
/// with a warning that says why, not an error.
#[test]
fn a_run_too_short_for_a_correction_still_saves_its_physics() {
    let c = SpindleThermalConfig {
        n_runs: 1,
        samples_per_run: 8,
        ..SpindleThermalConfig::default()
    };
    let t = spindle_thermal(&c, None).unwrap();
    let m = fit(&t, &config(Form::Auto), &mut |_| {}).unwrap();
    assert_eq!(m.corrections[0].form, Form::None);
    assert!(
        m.warnings
            .iter()
            .any(|w| w.contains("no correction could be searched")),
        "{:?}",
        m.warnings
    );
    assert!(m.physics_calibrated["q"].value.is_finite());
}
