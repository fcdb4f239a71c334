//! Property tests of the hybrid composer: each invariant in words, then the test.
#![allow(clippy::unwrap_used)]

use hxai_hybrid::records::{
    CorrectionKind, FeatureInfo, Latent, RecordInput, RecordModel, SCHEMA_VERSION, SplitKind,
    TrainingInfo, WindowConfig, WindowSample, corrected_latent, record_hybrid, split_samples,
};
use hxai_hybrid::{CorrectionInfo, HybridError, SplitInfo, WindowId};
use hxai_signal::PhysicsConfig;
use hxai_symreg::Strategy as SearchStrategy;
use proptest::prelude::*;
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// A clean 2 s record: displacement `amp sin(w t + ph)` um and its exact acceleration.
fn record(fs: f64, f: f64, amp: f64, ph: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    let w = 2.0 * PI * f;
    let accel = (0..n)
        .map(|i| -amp * 1e-6 * w * w * (w * i as f64 / fs + ph).sin())
        .collect();
    let probe = (0..n)
        .map(|i| amp * (w * i as f64 / fs + ph).sin() + 3.0)
        .collect();
    (accel, probe)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    // Invariant: reconstructing latent variables and decomposing the result at the same
    // frequency gives back the same amplitude and phase (the reconstruction keeps phase),
    // and a four-parameter fit finds the same frequency (it keeps frequency).
    // Tolerances: 1e-9 relative on amplitude, 1e-9 rad on phase, 1e-9 relative on frequency
    // (a noise-free least-squares fit is exact up to rounding).
    #[test]
    fn reconstruction_keeps_phase_and_frequency(
        amp in 0.1f64..20.0, phase in -3.1f64..3.1, fs in 500.0f64..5000.0,
        f in 5.0f64..60.0, periods in 3usize..10,
    ) {
        let n = (periods as f64 * fs / f).ceil() as usize;
        let lat = Latent { amplitude: amp, phase, offset: 0.0 };
        let x = lat.sine(fs, f, 0, n);
        let back = Latent::fit(&x, fs, f).unwrap();
        prop_assert!((back.amplitude - amp).abs() <= 1e-9 * amp);
        let dphi = (back.phase - phase + PI).rem_euclid(2.0 * PI) - PI;
        prop_assert!(dphi.abs() <= 1e-9, "phase {} vs {}", back.phase, phase);
        let f4 = hxai_signal::fit_sine4(&x, fs, f * 1.001).unwrap();
        prop_assert!((f4.frequency_hz - f).abs() <= 1e-9 * f, "{} vs {}", f4.frequency_hz, f);
    }

    // Invariant: A_corr = A_phys + delta_hat exactly (bit for bit), with the physics phase
    // and zero offset, both for the formula and through the composer on a record.
    #[test]
    fn corrected_amplitude_is_exact_sum(
        amp in 1.0f64..10.0, f in 10.0f64..40.0, ph in -3.0f64..3.0, c in -5.0f64..5.0,
    ) {
        let lat = Latent { amplitude: amp, phase: ph, offset: 0.7 };
        let k = corrected_latent(&lat, c);
        prop_assert_eq!(k.amplitude, amp + c);
        prop_assert_eq!(k.phase, ph);
        prop_assert_eq!(k.offset, 0.0);

        let fs = 2000.0;
        let (accel, probe) = record(fs, f, amp, ph, 4000);
        let h = record_hybrid(&PhysicsConfig::default(), WindowConfig::default());
        let rec = RecordInput { id: "r", fs_hz: fs, frequency_hz: f, signal: &accel, truth: Some(&probe) };
        // a constant correction, applied without a fitted model
        let samples = h.samples(&rec).unwrap();
        let pred = h.apply(&rec, samples, &[c; 3]);
        for (w, s) in pred.windows.iter().zip(&pred.samples) {
            prop_assert_eq!(w.corrected.amplitude, s.a_phys() + c);
            prop_assert_eq!(w.delta_hat, c);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    // Invariant: with the zero correction the hybrid prediction of every window equals the
    // physics model's sine representation A_phys sin(omega t + phi_phys) exactly.
    #[test]
    fn zero_correction_is_the_physics_sine(
        amp in 1.0f64..10.0, f in 10.0f64..40.0, ph in -3.0f64..3.0,
    ) {
        let fs = 2000.0;
        let (accel, probe) = record(fs, f, amp, ph, 4000);
        let h = record_hybrid(&PhysicsConfig::default(), WindowConfig::default());
        let rec = RecordInput { id: "r", fs_hz: fs, frequency_hz: f, signal: &accel, truth: Some(&probe) };
        let pred = h.predict(&rec, &CorrectionInfo::zero()).unwrap();
        prop_assert_eq!(pred.windows.len(), 3);
        for (w, s) in pred.windows.iter().zip(&pred.samples) {
            let sine = Latent { amplitude: s.a_phys(), phase: s.physics.phase, offset: 0.0 }
                .sine(fs, f, 0, s.range.len());
            prop_assert_eq!(&pred.hybrid[s.range.clone()], sine.as_slice());
            prop_assert_eq!(w.corrected.amplitude, s.a_phys());
        }
    }

    // Invariant: the grouped (record) split never puts windows of one record on both sides,
    // and every sample is on exactly one side; a split that would leave a side empty is a
    // clear error, never an empty side (found by CI: 2 records at a test fraction of 0.54).
    #[test]
    fn record_split_keeps_records_whole(
        windows_per_record in prop::collection::vec(1usize..8, 2..30),
        frac in 0.1f64..0.6, seed in any::<u64>(),
    ) {
        let samples: Vec<WindowSample> = windows_per_record.iter().enumerate().flat_map(|(r, &n)| {
            (0..n).map(move |w| WindowSample {
                record: format!("rec{r}"),
                window: w,
                range: 0..1,
                features: vec![],
                physics: Latent { amplitude: 1.0, phase: 0.0, offset: 0.0 },
                truth: None,
            })
        }).collect();
        // scikit-learn's rule: ceil(frac * groups) test groups; a side left empty is an error
        let groups = windows_per_record.len();
        let n_test = (frac * groups as f64).ceil() as usize;
        let split = split_samples(&samples, SplitKind::Record, frac, seed);
        if n_test >= groups {
            prop_assert!(split.is_err(), "{groups} groups at {frac} must be refused");
            return Ok(());
        }
        let is_test = split.unwrap();
        prop_assert_eq!(is_test.len(), samples.len());
        let mut side: BTreeMap<&str, bool> = BTreeMap::new();
        for (s, &t) in samples.iter().zip(&is_test) {
            if let Some(&prev) = side.get(s.record.as_str()) {
                prop_assert_eq!(prev, t, "record {} on both sides", s.record);
            }
            side.insert(&s.record, t);
        }
        prop_assert!(side.values().any(|&t| t) && side.values().any(|&t| !t));
    }
}

/// A small fitted symbolic model, made once.
fn symbolic_model() -> &'static hxai_symreg::Model {
    static MODEL: OnceLock<hxai_symreg::Model> = OnceLock::new();
    MODEL.get_or_init(|| {
        let x: Vec<f64> = (0..60).map(|i| 1.0 + i as f64 / 10.0).collect();
        let y: Vec<f64> = x.iter().map(|v| 2.0 * v + 1.0).collect();
        let data = hxai_symreg::Table::new(vec!["f2".into()], vec![x]).unwrap();
        let cfg = hxai_symreg::SearchConfig {
            epochs: 1,
            candidates_per_epoch: 50,
            ..hxai_symreg::SearchConfig::default()
        };
        hxai_symreg::search(&data, &y, &cfg, &mut |_| {})
            .unwrap()
            .best
    })
}

fn model_strategy() -> impl Strategy<Value = RecordModel> {
    (
        1.0f64..9.0,
        100.0f64..400.0,
        1usize..6,
        0.05f64..2.0,
        0.0f64..1.0,
        any::<bool>(),
        prop::collection::btree_set("[a-z0-9_]{1,8}", 2..8),
        any::<u64>(),
    )
        .prop_map(|(low, high, order, len, discard, zero, ids, seed)| {
            let ids: Vec<String> = ids.into_iter().collect();
            let (test, train) = ids.split_at(1);
            RecordModel {
                schema_version: SCHEMA_VERSION,
                physics: PhysicsConfig {
                    low_hz: low,
                    high_hz: high,
                    order,
                    ..PhysicsConfig::default()
                },
                features: FeatureInfo::default(),
                window: WindowConfig {
                    length_s: len,
                    discard_s: discard,
                },
                correction: if zero {
                    CorrectionInfo::zero()
                } else {
                    CorrectionInfo::symbolic(CorrectionKind::Symbolic, symbolic_model().clone())
                },
                split: SplitInfo {
                    kind: if zero {
                        SplitKind::Window
                    } else {
                        SplitKind::Record
                    },
                    seed: Some(seed),
                    test_fraction: Some(0.2),
                    train: train.to_vec(),
                    test: test.to_vec(),
                    test_windows: Some(vec![WindowId {
                        record: test[0].clone(),
                        window: 1,
                    }]),
                },
                training: TrainingInfo {
                    strategy: Some(SearchStrategy::Combined),
                    seed,
                    epochs: 10,
                    evaluations: 1234,
                    seconds: 1.5,
                    n_train_windows: 40,
                    n_test_windows: 10,
                    delta_train: None,
                    delta_test: Some(hxai_eval::Metrics {
                        rmse: 0.5,
                        r2: 0.9,
                        mae: 0.4,
                    }),
                },
                conformal: None,
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    // Invariant: a model written to JSON reads back equal, and carries the keys the
    // interface promises (schema_version, correction.{equation,sympy,latex,complexity,
    // features}, split.{train,test}).
    #[test]
    fn model_json_round_trip(m in model_strategy()) {
        let text = m.to_json().unwrap();
        let back = RecordModel::from_json(&text).unwrap();
        prop_assert_eq!(&back, &m);
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        prop_assert_eq!(v["schema_version"].as_u64(), Some(u64::from(SCHEMA_VERSION)));
        for k in ["equation", "sympy", "latex", "complexity", "features"] {
            prop_assert!(v["correction"].get(k).is_some(), "missing correction.{}", k);
        }
        prop_assert!(v["split"]["train"].is_array() && v["split"]["test"].is_array());
    }
}

#[test]
fn other_schema_version_is_a_clear_error() -> Result<(), Box<dyn std::error::Error>> {
    let mut v: serde_json::Value = serde_json::from_str(&model_zero().to_json()?)?;
    v["schema_version"] = serde_json::json!(SCHEMA_VERSION + 1);
    let err = RecordModel::from_json(&v.to_string())
        .err()
        .ok_or("expected an error")?;
    assert!(matches!(err, HybridError::SchemaVersion { .. }), "{err:?}");
    assert!(err.to_string().contains("refit"), "{err}");
    let err = RecordModel::from_json("{\"physics\": 1}")
        .err()
        .ok_or("expected an error")?;
    assert!(matches!(err, HybridError::ModelFormat(_)), "{err:?}");
    Ok(())
}

// A model file written before the strategy had serde names (`"engine": "qlattice"` or
// `"none"`) still loads, and the delta scores keep their `_um` keys both ways.
#[test]
fn model_files_with_the_old_engine_key_still_load() -> Result<(), Box<dyn std::error::Error>> {
    let mut v: serde_json::Value = serde_json::from_str(&model_zero().to_json()?)?;
    assert!(v["training"].get("strategy").is_some(), "{v}");
    let training = v["training"]
        .as_object_mut()
        .ok_or("training is an object")?;
    training.remove("strategy");
    training.insert("engine".into(), serde_json::json!("none"));
    assert_eq!(
        RecordModel::from_json(&v.to_string())?.training.strategy,
        None
    );
    v["training"]["engine"] = serde_json::json!("qlattice");
    v["training"]["delta_test"] = serde_json::json!({"rmse_um": 0.5, "r2": 0.9, "mae_um": 0.4});
    let back = RecordModel::from_json(&v.to_string())?;
    assert_eq!(back.training.strategy, Some(SearchStrategy::QLattice));
    assert_eq!(
        back.training.delta_test,
        Some(hxai_eval::Metrics {
            r2: 0.9,
            rmse: 0.5,
            mae: 0.4
        })
    );
    let again: serde_json::Value = serde_json::from_str(&back.to_json()?)?;
    assert_eq!(
        again["training"]["delta_test"]["rmse_um"].as_f64(),
        Some(0.5)
    );
    Ok(())
}

fn model_zero() -> RecordModel {
    RecordModel {
        schema_version: SCHEMA_VERSION,
        physics: PhysicsConfig::default(),
        features: FeatureInfo::default(),
        window: WindowConfig::default(),
        correction: CorrectionInfo::zero(),
        split: SplitInfo {
            kind: SplitKind::Record,
            seed: Some(1),
            test_fraction: Some(0.2),
            train: vec!["a".into()],
            test: vec!["b".into()],
            test_windows: Some(vec![]),
        },
        training: TrainingInfo {
            strategy: None,
            seed: 1,
            epochs: 0,
            evaluations: 0,
            seconds: 0.0,
            n_train_windows: 0,
            n_test_windows: 0,
            delta_train: None,
            delta_test: None,
        },
        conformal: None,
    }
}

#[test]
fn short_record_error_names_record_and_need() -> Result<(), Box<dyn std::error::Error>> {
    let h = record_hybrid(&PhysicsConfig::default(), WindowConfig::default());
    let (accel, _) = record(2000.0, 20.0, 5.0, 0.0, 1500); // 0.75 s < 1 s needed
    let rec = RecordInput {
        id: "short",
        fs_hz: 2000.0,
        frequency_hz: 20.0,
        signal: &accel,
        truth: None,
    };
    let err = h.samples(&rec).err().ok_or("expected an error")?;
    assert!(matches!(err, HybridError::RecordTooShort { .. }), "{err:?}");
    assert!(err.to_string().contains("short"), "{err}");
    Ok(())
}

// The samples table: `record`, `window`, `split`, the features, then `A_phys`, `A_true`
// and `delta = A_true - A_phys` (exact: the same subtraction as `WindowSample::delta`);
// a sample without truth is an error naming its record.
#[test]
fn samples_table_columns_and_missing_truth() -> Result<(), Box<dyn std::error::Error>> {
    let latent = |amplitude: f64| Latent {
        amplitude,
        phase: 0.1,
        offset: 0.0,
    };
    let sample = |record: &str, window: usize, truth: Option<f64>| WindowSample {
        record: record.into(),
        window,
        range: 0..10,
        features: vec![1.0, 2.0],
        physics: latent(4.0),
        truth: truth.map(latent),
    };
    let names = vec!["a".to_string(), "b".to_string()];
    let samples = [sample("r1", 0, Some(4.5)), sample("r2", 3, Some(3.75))];
    let t = hxai_hybrid::records::samples_table(&samples, &[false, true], &names)?;
    assert_eq!(
        t.names(),
        [
            "record", "window", "split", "a", "b", "A_phys", "A_true", "delta"
        ]
    );
    assert_eq!(t.record, ["r1", "r2"]);
    assert_eq!(t.window, [0, 3]);
    assert_eq!(t.split, ["train", "test"]);
    assert_eq!(t.values.column("delta"), Some(&[0.5, -0.25][..]));
    assert_eq!(t.values.column("A_phys"), Some(&[4.0, 4.0][..]));
    let err = hxai_hybrid::records::samples_table(&[sample("r3", 0, None)], &[false], &names)
        .err()
        .ok_or("expected an error")?;
    assert!(
        matches!(&err, HybridError::NoTruth { record } if record == "r3"),
        "{err:?}"
    );
    Ok(())
}

/// Cases of the fuzz properties: 256 in every test run, `HXAI_FUZZ_CASES` for a long run
/// (docs/bad-input.md).
fn fuzz_cases() -> u32 {
    std::env::var("HXAI_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: fuzz_cases(), ..ProptestConfig::default() })]

    /// Bounded fuzzing of the infix parser and the table-model loader (issue 52 item 7):
    /// arbitrary text is refused or accepted, never a panic.
    #[test]
    fn arbitrary_text_never_panics_the_parser_or_the_loader(
        text in "[a-z0-9_`+*/^().,\\-{}\\[\\]\": ]{0,60}",
    ) {
        let _ = hxai_symreg::infix::parse(&text);
        let _ = hxai_hybrid::tables::TableModel::from_json(&text);
    }
}
