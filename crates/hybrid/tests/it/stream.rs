//! The streaming estimator (`hxai_hybrid::records::stream`): causal, the same in any chunking,
//! restartable, and as accurate as the offline prediction on simulated
//! records.

use hxai_hybrid::records::stream::{Estimator, Row};
use hxai_hybrid::records::{RecordInput, RecordModel};

fn model() -> RecordModel {
    RecordModel::from_json(include_str!("../../../../testdata/bad/good/model.json"))
        .expect("the test model loads")
}

/// One simulated record per amplitude and frequency.
fn simulate(
    seed: u64,
    amps: &[f64],
    freqs: &[f64],
    seconds: f64,
    fs: f64,
) -> Vec<hxai_sim::SimRecord> {
    let cfg = hxai_sim::SimConfig {
        seed,
        amplitudes_um: amps.to_vec(),
        frequencies_hz: freqs.to_vec(),
        repeats: 1,
        duration_s: seconds,
        fs_hz: fs,
        ..hxai_sim::SimConfig::default()
    };
    hxai_sim::simulate(&cfg).expect("simulate")
}

/// The test model with the uncertainty of its correction computed on the windows of a few
/// simulated records (the file predates stored uncertainties), for the interval rows.
fn model_with_uncertainty() -> RecordModel {
    let mut m = model();
    let hybrid = m.hybrid();
    let mut samples = Vec::new();
    for rec in simulate(5, &[4.0, 8.0], &[10.0, 20.0, 30.0, 40.0], 2.0, 2000.0) {
        let input = RecordInput {
            id: &rec.id,
            fs_hz: rec.fs_hz,
            frequency_hz: rec.frequency_hz,
            signal: &rec.accel_ms2,
            truth: Some(&rec.probe_um),
        };
        samples.extend(hybrid.samples(&input).expect("samples").windows);
    }
    let table = hybrid.feature_table(&samples).expect("features");
    let delta: Vec<f64> = samples.iter().map(|s| s.delta().expect("truth")).collect();
    let sym = m.correction.model.as_ref().expect("a symbolic correction");
    m.correction.uncertainty = Some(sym.uncertainty(&table, &delta).expect("uncertainty"));
    m
}

/// A noisy, harmonic, slowly modulated acceleration (m/s^2) of a motion at `f` Hz.
fn accel(n: usize, fs: f64, f: f64, seed: u64) -> Vec<f64> {
    use rand::Rng;
    use rand_chacha::rand_core::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let w = 2.0 * std::f64::consts::PI * f;
    (0..n)
        .map(|i| {
            let noise = rng.r#gen::<f64>() - 0.5;
            let t = i as f64 / fs;
            let amp = 6e-6 * (1.0 + 0.2 * (0.7 * t).sin());
            -amp * w * w * (w * t).sin() + 0.05 * (3.0 * w * t).sin() + 0.02 * noise
        })
        .collect()
}

fn run(est: &mut Estimator, x: &[f64], chunks: &[usize]) -> Vec<Row> {
    let mut rows = Vec::new();
    let mut at = 0;
    let mut k = 0;
    while at < x.len() {
        let n = chunks[k % chunks.len()].min(x.len() - at);
        est.push_into(&x[at..at + n], &mut rows).expect("push");
        at += n;
        k += 1;
    }
    rows
}

/// Invariant: one row per sample, whatever the chunking, and the same rows.
#[test]
fn chunking_changes_nothing() {
    let (fs, f) = (2000.0, 20.0);
    let x = accel(6000, fs, f, 1);
    let whole = Estimator::new(&model(), f, fs)
        .expect("estimator")
        .push(&x)
        .expect("push");
    assert_eq!(whole.len(), x.len());
    for chunks in [vec![1], vec![7, 300, 2, 1000], vec![4096]] {
        let mut est = Estimator::new(&model(), f, fs).expect("estimator");
        assert_eq!(run(&mut est, &x, &chunks), whole, "chunks {chunks:?}");
    }
    for (i, r) in whole.iter().enumerate() {
        assert_eq!(r.sample, i as u64);
    }
}

/// Invariant (causality): the row of sample `i` depends on samples `0..=i + D` only.
/// Changing every sample after `i + D` leaves the rows up to `i` bit for bit as they were.
#[test]
fn rows_depend_on_past_samples_only() {
    let (fs, f) = (2000.0, 25.0);
    let x = accel(5000, fs, f, 2);
    let est = Estimator::new(&model(), f, fs).expect("estimator");
    let d = est.delay_samples();
    let base = Estimator::new(&model(), f, fs)
        .expect("estimator")
        .push(&x)
        .expect("push");
    for i in [999, 1000, 1500, 2047, 3333, 4998] {
        let mut y = x.clone();
        for (k, v) in y.iter_mut().enumerate().skip(i + d + 1) {
            *v = 0.3 * (k as f64).cos() + 5.0;
        }
        let other = Estimator::new(&model(), f, fs)
            .expect("estimator")
            .push(&y)
            .expect("push");
        assert_eq!(
            other[..=i],
            base[..=i],
            "a change after sample {} moved an earlier row",
            i + d
        );
        assert_ne!(
            other[i + d + 1..],
            base[i + d + 1..],
            "the changed samples must matter"
        );
    }
}

/// Warm-up: the first `W - 1` rows are empty, every later one has values; after a restart
/// the estimator behaves as a new one on the samples that follow.
#[test]
fn warm_up_and_restart() {
    let (fs, f) = (2000.0, 20.0);
    let x = accel(4000, fs, f, 3);
    let m = model_with_uncertainty();
    let mut est = Estimator::new(&m, f, fs)
        .expect("estimator")
        .with_interval(0.95)
        .expect("interval");
    let w = est.warmup_samples();
    assert_eq!(w, 999);
    let rows = est.push(&x[..2500]).expect("push");
    assert!(
        rows[..w]
            .iter()
            .all(|r| r.physics_um.is_none() && r.hybrid_um.is_none())
    );
    for r in &rows[w..] {
        let (h, (lo, hi)) = (
            r.hybrid_um.expect("hybrid after the warm-up"),
            r.interval_um.expect("interval"),
        );
        assert!(r.physics_um.is_some());
        assert!(lo <= h && h <= hi, "{lo} <= {h} <= {hi}");
    }
    est.restart();
    let after = est.push(&x[2500..]).expect("push");
    let fresh = Estimator::new(&m, f, fs)
        .expect("estimator")
        .with_interval(0.95)
        .expect("interval")
        .push(&x[2500..])
        .expect("push");
    assert_eq!(after, fresh);
}

#[test]
fn bad_input_is_refused() {
    let m = model();
    assert!(
        Estimator::new(&m, 1000.0, 10_000.0).is_err(),
        "frequency above the band"
    );
    assert!(
        Estimator::new(&m, 20.0, 300.0).is_err(),
        "band above Nyquist"
    );
    assert!(Estimator::new(&m, 20.0, f64::NAN).is_err());
    let est = Estimator::new(&m, 20.0, 2000.0).expect("estimator");
    assert!(est.with_interval(1.5).is_err());
    let mut est = Estimator::new(&m, 20.0, 2000.0).expect("estimator");
    let mut rows = Vec::new();
    let err = est
        .push_into(&[0.1, 0.2, f64::NAN, 0.3], &mut rows)
        .expect_err("NaN is refused");
    assert!(err.to_string().contains("sample 2"), "{err}");
    assert_eq!(rows.len(), 2, "the rows before the bad sample are kept");
    assert_eq!(est.samples(), 2);
}

/// Accuracy against the offline prediction (`RecordModel::predict`, what `hxai predict`
/// runs) on simulated records at the test matrix's frequencies: after the warm-up, the
/// streaming hybrid's RMSE against the probe is at most 1.1 times the offline one on the
/// same samples.
#[test]
fn as_accurate_as_the_offline_prediction() {
    let m = model();
    for rec in simulate(11, &[5.0, 9.0], &[10.0, 25.0, 40.0], 2.5, 5000.0) {
        let input = RecordInput {
            id: &rec.id,
            fs_hz: rec.fs_hz,
            frequency_hz: rec.frequency_hz,
            signal: &rec.accel_ms2,
            truth: None,
        };
        let offline = m.predict(&input).expect("offline");
        let rows = Estimator::new(&m, rec.frequency_hz, rec.fs_hz)
            .expect("estimator")
            .push(&rec.accel_ms2)
            .expect("stream");
        let (mut se_stream, mut se_offline, mut n) = (0.0, 0.0, 0);
        for (i, r) in rows.iter().enumerate() {
            if let Some(h) = r.hybrid_um {
                se_stream += (h - rec.probe_um[i]).powi(2);
                se_offline += (offline.hybrid[i] - rec.probe_um[i]).powi(2);
                n += 1;
            }
        }
        assert!(n > rows.len() / 2);
        let (rs, ro) = (
            (se_stream / n as f64).sqrt(),
            (se_offline / n as f64).sqrt(),
        );
        assert!(
            rs <= 1.1 * ro,
            "{}: streaming RMSE {rs} vs offline {ro}",
            rec.id
        );
    }
}
