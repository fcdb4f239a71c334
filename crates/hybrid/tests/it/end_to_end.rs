//! End to end on a tiny synthetic data set: fit, predict, evaluate.
//!
//! The data are analytic: the tool moves `A_true sin(w t)` with `A_true = A (1 + 0.012 f)`
//! (an overshoot growing with frequency, as the paper reports), the probe sees that plus
//! noise, and the accelerometer sees the acceleration of the *commanded* amplitude `A` plus
//! noise. The physics model therefore under-reads by `delta = 0.012 A f`, which the
//! features can explain (f1 is f; f2, the mean absolute acceleration, is proportional to
//! `A f^2`), so a correct pipeline must cut the error substantially on unseen records.

use hxai_hybrid::records::{RecordConfig, RecordInput, RecordModel, SplitKind, fit};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::PI;

struct Rec {
    id: String,
    f: f64,
    accel: Vec<f64>,
    probe: Vec<f64>,
}

fn data() -> Result<Vec<Rec>, Box<dyn std::error::Error>> {
    let fs = 1000.0;
    let n = 2000; // 2 s -> three 0.5 s windows after discarding 0.25 s at each end
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let noise_probe = Normal::new(0.0, 0.02)?; // um
    let noise_acc = Normal::new(0.0, 0.002)?; // m/s^2
    let mut out = Vec::new();
    for (ai, a) in [4.0, 6.0, 8.0, 10.0].into_iter().enumerate() {
        for (fi, f) in [10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0]
            .into_iter()
            .enumerate()
        {
            let w = 2.0 * PI * f;
            let a_true = a * (1.0 + 0.012 * f);
            let ph = 0.3 * (ai + fi) as f64;
            let probe = (0..n)
                .map(|i| {
                    a_true * (w * i as f64 / fs + ph).sin() + 1.0 + noise_probe.sample(&mut rng)
                })
                .collect();
            let accel = (0..n)
                .map(|i| {
                    -a * 1e-6 * w * w * (w * i as f64 / fs + ph).sin() + noise_acc.sample(&mut rng)
                })
                .collect();
            out.push(Rec {
                id: format!("a{a}_f{f}"),
                f,
                accel,
                probe,
            });
        }
    }
    Ok(out)
}

/// The records as the library takes them (1 kHz, with the probe as the truth).
fn inputs_of(recs: &[Rec]) -> Vec<RecordInput<'_>> {
    recs.iter()
        .map(|r| RecordInput {
            id: &r.id,
            fs_hz: 1000.0,
            frequency_hz: r.f,
            signal: &r.accel,
            truth: Some(&r.probe),
        })
        .collect()
}

#[test]
fn fit_predict_evaluate_on_synthetic_records() -> Result<(), Box<dyn std::error::Error>> {
    let recs = data()?;
    let inputs = inputs_of(&recs);
    let cfg = RecordConfig {
        search: hxai_symreg::SearchConfig {
            epochs: 4,
            candidates_per_epoch: 300,
            ..hxai_symreg::SearchConfig::default()
        },
        ..RecordConfig::default()
    };
    let out = fit(&inputs, &cfg, &mut |_| {})?;
    let m = &out.model;
    // 28 records, 20 % of them (ceil(5.6) = 6) held out, three windows each.
    assert_eq!(m.split.test.len(), 6);
    assert_eq!(m.split.train.len(), 22);
    assert_eq!(m.training.n_test_windows, 18);
    assert_eq!(out.samples.len(), 84);

    // The model survives its file format and predicts the same afterwards.
    let loaded = RecordModel::from_json(&m.to_json()?)?;
    assert_eq!(&loaded, m);

    let ev = loaded.evaluate(&inputs, false)?;
    assert_eq!(ev.n_records, 6);
    assert_eq!(ev.n_windows, 18);
    assert_eq!(ev.records, m.split.test);
    // Goal: the correction explains delta on unseen records. Thresholds (chosen before
    // running, from the construction): delta R^2 above 0.9 on the test windows, hybrid RMSE
    // at most half the physics RMSE, and a significant paired t-test (p < 0.01).
    let delta = ev.delta.ok_or("delta not scored")?;
    assert!(delta.r2 > 0.9, "delta R^2 {}", delta.r2);
    assert!(ev.hybrid.rmse < 0.5 * ev.physics.rmse, "{ev:?}");
    assert!(ev.improvement_pct > 50.0, "{ev:?}");
    let t = ev.t_test.ok_or("no t-test")?;
    assert!(t.p_value < 0.01, "{t:?}");
    assert_eq!(t.pairs, 18);

    // Prediction of one record without truth gives full-length signals.
    let r = &recs[0];
    let pred = loaded.predict(&RecordInput {
        id: &r.id,
        fs_hz: 1000.0,
        frequency_hz: r.f,
        signal: &r.accel,
        truth: None,
    })?;
    assert_eq!(pred.physics.len(), r.accel.len());
    assert_eq!(pred.hybrid.len(), r.accel.len());

    // A window split gives a different, per-window test set on the same data.
    let cfg_w = RecordConfig {
        split: SplitKind::Window,
        ..cfg
    };
    let out_w = fit(&inputs, &cfg_w, &mut |_| {})?;
    assert_eq!(
        out_w.model.split.test_windows.as_ref().map_or(0, Vec::len),
        17
    ); // ceil(0.2 * 84)
    let ev_w = out_w.model.evaluate(&inputs, false)?;
    assert_eq!(ev_w.n_windows, 17);
    Ok(())
}

#[test]
fn conformal_intervals_of_the_corrected_amplitude() -> Result<(), Box<dyn std::error::Error>> {
    use hxai_hybrid::IntervalMethod;
    let recs = data()?;
    let inputs = inputs_of(&recs);
    let search = hxai_symreg::SearchConfig {
        epochs: 4,
        candidates_per_epoch: 300,
        ..hxai_symreg::SearchConfig::default()
    };
    let cfg = RecordConfig {
        search: search.clone(),
        ..RecordConfig::default()
    };
    let out = fit(&inputs, &cfg, &mut |_| {})?;
    let m = &out.model;
    let conf = m.conformal.as_ref().ok_or("no conformal calibration")?;
    assert_eq!(conf.folds, 5);
    assert_eq!(conf.fold_params.len(), 5);
    assert_eq!(conf.scores.len(), m.training.n_train_windows);
    // The folds are grouped by record: every training window of a record has one fold.
    let train: Vec<&str> = out
        .samples
        .iter()
        .zip(&out.is_test)
        .filter(|(_, t)| !**t)
        .map(|(s, _)| s.record.as_str())
        .collect();
    for (i, r) in train.iter().enumerate() {
        for (j, q) in train.iter().enumerate() {
            if r == q {
                assert_eq!(
                    conf.fold_of[i], conf.fold_of[j],
                    "record {r} split over folds"
                );
            }
        }
    }
    let loaded = RecordModel::from_json(&m.to_json()?)?;
    assert_eq!(
        loaded.default_interval_method(0.95),
        Some(IntervalMethod::Conformal)
    );
    // 66 training windows cannot give a finite CV+ interval at 99 % (it needs 99 scores):
    // the default falls back to the delta method there
    assert_eq!(
        loaded.default_interval_method(0.99),
        Some(IntervalMethod::Delta)
    );
    assert!(loaded.evaluate_at(&inputs, false, 0.99).is_ok());
    let ev = loaded.evaluate(&inputs, false)?;
    let iv = ev.interval.ok_or("no interval report")?;
    assert_eq!(iv.method, IntervalMethod::Conformal);
    assert_eq!(iv.n, 18);
    // Each method's interval holds the corrected amplitude; the conformal ones are CV+'s
    // order statistics of the fold models' predictions, so they hold every fold model's
    // prediction shifted by the smallest score, at least.
    let test: Vec<_> = out
        .samples
        .iter()
        .zip(&out.is_test)
        .filter(|(_, t)| **t)
        .map(|(s, _)| s.clone())
        .collect();
    let table = loaded.hybrid().feature_table(&test)?;
    let a_corr: Vec<f64> = {
        let d = loaded
            .correction
            .model
            .as_ref()
            .ok_or("no model")?
            .predict(&table)?;
        test.iter().zip(d).map(|(s, d)| s.a_phys() + d).collect()
    };
    for method in [
        IntervalMethod::Conformal,
        IntervalMethod::Split,
        IntervalMethod::Delta,
    ] {
        let b = loaded.amplitude_intervals_with(&test, 0.8, method)?;
        for (a, (lo, hi)) in a_corr.iter().zip(&b) {
            assert!(
                lo.is_finite() && hi.is_finite() && lo < hi,
                "{method:?}: ({lo}, {hi})"
            );
            if method != IntervalMethod::Conformal {
                // split and delta are centred on their model: the full model's prediction
                // for delta, the first fold's for split (close to it)
                assert!(lo < a && a < hi, "{method:?}: {a} outside ({lo}, {hi})");
            }
        }
        // a higher level never narrows an interval
        let wide = loaded.amplitude_intervals_with(&test, 0.9, method)?;
        for (n, w) in b.iter().zip(&wide) {
            assert!(
                w.0 <= n.0 + 1e-12 && w.1 >= n.1 - 1e-12,
                "{method:?}: {n:?} vs {w:?}"
            );
        }
    }

    // Without folds: no calibration, the delta method by default, conformal refused by name.
    let plain = fit(
        &inputs,
        &RecordConfig {
            search,
            conformal_folds: 0,
            ..RecordConfig::default()
        },
        &mut |_| {},
    )?
    .model;
    assert!(plain.conformal.is_none());
    assert_eq!(
        plain.default_interval_method(0.95),
        Some(IntervalMethod::Delta)
    );
    let err = plain
        .amplitude_intervals_with(&test, 0.95, IntervalMethod::Conformal)
        .err()
        .ok_or("conformal accepted without calibration")?;
    assert!(err.to_string().contains("--conformal-folds 0"), "{err}");

    // A tampered calibration is refused when the file is read.
    let mut doc: serde_json::Value = serde_json::from_str(&m.to_json()?)?;
    doc["conformal"]["scores"]
        .as_array_mut()
        .ok_or("no scores")?
        .pop();
    let err = RecordModel::from_json(&doc.to_string())
        .err()
        .ok_or("tampered calibration accepted")?;
    assert!(err.to_string().contains("conformal"), "{err}");
    Ok(())
}
