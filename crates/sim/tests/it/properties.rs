//! Property tests of the simulator.
#![allow(clippy::unwrap_used)]

use hxai_signal::fit_sine;
use hxai_sim::{SimConfig, SimError, simulate};
use proptest::prelude::*;

/// A short single-record configuration, fast enough for property tests.
fn short(seed: u64, a: f64, f: f64) -> SimConfig {
    SimConfig {
        seed,
        amplitudes_um: vec![a],
        frequencies_hz: vec![f],
        repeats: 1,
        duration_s: 0.4,
        fs_hz: 5_000.0,
        warmup_s: 0.3,
        ..SimConfig::default()
    }
}

fn wrap(p: f64) -> f64 {
    let two_pi = 2.0 * std::f64::consts::PI;
    (p + std::f64::consts::PI).rem_euclid(two_pi) - std::f64::consts::PI
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    // Invariant: the output is a pure function of the configuration: the same seed gives
    // bit-identical records, whether the records are computed on one thread or several.
    #[test]
    fn deterministic_for_a_seed_whatever_the_threads(seed in any::<u64>(), a in 2.0..15.0f64, f in 5.0..50.0f64) {
        let mut cfg = short(seed, a, f);
        cfg.repeats = 3;
        let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let r1 = one.install(|| simulate(&cfg)).unwrap();
        let r2 = two.install(|| simulate(&cfg)).unwrap();
        prop_assert_eq!(&r1, &r2);
        // Repeats differ (independent noise streams per record).
        prop_assert_ne!(&r1[0].accel_ms2, &r1[1].accel_ms2);
    }

    // Invariant: at low frequency (2-8 Hz, far below the servo, tool and frame modes) the
    // probe tracks the command: fitted amplitudes agree within 2 % + 0.15 um (the 0.15 um
    // allows for the Coulomb friction offset coulomb / omega_n^2 = 0.13 um of the default).
    #[test]
    fn probe_tracks_command_at_low_frequency(seed in any::<u64>(), a in 2.0..20.0f64, f in 2.0..8.0f64) {
        let mut cfg = short(seed, a, f);
        cfg.duration_s = 1.0;
        let r = &simulate(&cfg).unwrap()[0];
        let p = fit_sine(&r.probe_um, r.fs_hz, f).unwrap().amplitude;
        let c = fit_sine(&r.command_um, r.fs_hz, f).unwrap().amplitude;
        prop_assert!((p - c).abs() <= 0.02 * c + 0.15, "probe {} vs command {}", p, c);
    }

    // Invariant: the encoder lags the probe (its phase is behind) at every amplitude and
    // frequency of the machine's working range.
    #[test]
    fn encoder_lags_probe(seed in any::<u64>(), a in 2.0..20.0f64, f in 5.0..60.0f64) {
        let r = &simulate(&short(seed, a, f)).unwrap()[0];
        let p = fit_sine(&r.probe_um, r.fs_hz, f).unwrap();
        let e = fit_sine(&r.encoder_um, r.fs_hz, f).unwrap();
        let lag = wrap(p.phase - e.phase);
        prop_assert!(lag > 0.0, "lag {} rad at A = {}, f = {}", lag, a, f);
    }

    // Invariant: any configuration that validates produces finite samples on every channel.
    #[test]
    fn no_nan_for_valid_configs(
        seed in any::<u64>(),
        a in 0.01..1000.0f64,
        f in 0.5..200.0f64,
        fs in 2_000.0..20_000.0f64,
        duration in 0.01..0.3f64,
        noise in 0.0..0.1f64,
        coulomb in 0.0..0.5f64,
        servo_damping in 0.01..3.0f64,
        tool_hz in 20.0..2_000.0f64,
        sens in -0.9..1.0f64,
    ) {
        let mut cfg = short(seed, a, f);
        cfg.fs_hz = fs;
        cfg.duration_s = duration;
        cfg.accel.noise_density = noise;
        cfg.servo.coulomb_ms2 = coulomb;
        cfg.servo.static_ms2 = coulomb * 1.5;
        cfg.servo.damping = servo_damping;
        cfg.tool.natural_hz = tool_hz;
        cfg.accel.sensitivity_error = sens;
        if cfg.check().is_ok() {
            let recs = simulate(&cfg).unwrap();
            for r in &recs {
                for ch in [&r.time_s, &r.accel_ms2, &r.probe_um, &r.command_um, &r.encoder_um] {
                    prop_assert!(ch.iter().all(|v| v.is_finite()));
                    prop_assert_eq!(ch.len(), cfg.samples_per_record());
                }
            }
        }
    }

    // Invariant: a configuration with one bad value is rejected with an error naming it,
    // before any simulation.
    #[test]
    fn invalid_configs_give_errors(which in 0usize..8, bad in prop_oneof![Just(f64::NAN), Just(-1.0), Just(0.0), Just(f64::INFINITY)]) {
        let mut cfg = SimConfig::default();
        let name = match which {
            0 => { cfg.amplitudes_um = vec![5.0, bad]; "amplitudes_um" }
            1 => { cfg.frequencies_hz = vec![bad]; "frequencies_hz" }
            2 => { cfg.duration_s = bad; "duration_s" }
            3 => { cfg.fs_hz = bad; "fs_hz" }
            4 => { cfg.servo.natural_hz = bad; "servo.natural_hz" }
            5 => { cfg.tool.damping = bad; "tool.damping" }
            6 => { cfg.probe.bandwidth_hz = bad; "probe.bandwidth_hz" }
            _ => { cfg.accel.daq_range_v = bad; "accel.daq_range_v" }
        };
        match simulate(&cfg) {
            Err(SimError::InvalidParameter { name: got, .. }) => prop_assert_eq!(got, name),
            other => prop_assert!(false, "expected an InvalidParameter error for {}, got {:?}", name, other.map(|r| r.len())),
        }
    }
}

#[test]
fn structural_errors() {
    let empty = SimConfig {
        amplitudes_um: vec![],
        ..SimConfig::default()
    };
    assert_eq!(
        empty.check(),
        Err(SimError::EmptyList {
            name: "amplitudes_um"
        })
    );
    let huge = SimConfig {
        duration_s: 1.0e6,
        ..SimConfig::default()
    };
    assert!(matches!(huge.check(), Err(SimError::TooLarge { .. })));
    // One bad structural setting each, and the parameter the error names.
    for (cfg, name) in [
        (
            SimConfig {
                repeats: 0,
                ..SimConfig::default()
            },
            "repeats",
        ),
        (
            SimConfig {
                frequencies_hz: vec![2_000.0],
                ..SimConfig::default()
            },
            "frequencies_hz",
        ),
        (
            SimConfig {
                warmup_s: 0.0,
                ..SimConfig::default()
            },
            "encoder.delay_s",
        ),
    ] {
        assert!(
            matches!(cfg.check(), Err(SimError::InvalidParameter { name: got, .. }) if got == name),
            "{name}: {:?}",
            cfg.check()
        );
    }
    let msg = SimError::EmptyList {
        name: "frequencies_hz",
    }
    .to_string();
    assert!(msg.contains("give at least one value"));
}
