//! `hxai fit`, `hxai predict` and `hxai evaluate` end to end on a tiny data folder written
//! by the test (analytic signals: the accelerometer sees the commanded amplitude, the probe
//! an amplitude that grows with frequency, so there is a correction to learn).

use hxai_data::{Format, ManifestEntry, Record, read_table, write_folder};
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::path::Path;

use crate::common;
use common::{evaluate_args, hxai, hxai_ok, predict_args, s};

type TestResult = Result<(), Box<dyn std::error::Error>>;

fn scratch(name: &str) -> Result<common::Scratch, std::io::Error> {
    common::scratch("hxai-cli-hybrid", name)
}

fn write_data(dir: &Path, format: Format) -> Result<(), Box<dyn std::error::Error>> {
    let fs = 1000.0;
    let n = 2000;
    let mut items = Vec::new();
    for a in [4.0, 7.0, 10.0] {
        for f in [10.0, 20.0, 30.0, 40.0] {
            let w = 2.0 * PI * f;
            let a_true = a * (1.0 + 0.012 * f);
            let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
            // Small deterministic disturbance so the data are not perfectly clean.
            let wobble = |i: usize| 0.01 * ((i * 7919 % 1000) as f64 / 1000.0 - 0.5);
            let rec = Record {
                accel_ms2: t
                    .iter()
                    .enumerate()
                    .map(|(i, t)| -a * 1e-6 * w * w * (w * t).sin() + 0.01 * wobble(i))
                    .collect(),
                probe_um: Some(
                    t.iter()
                        .enumerate()
                        .map(|(i, t)| a_true * (w * t).sin() + wobble(i))
                        .collect(),
                ),
                command_um: Some(t.iter().map(|t| a * (w * t).sin()).collect()),
                encoder_um: None,
                time_s: t,
            };
            items.push((
                ManifestEntry {
                    record: format!("a{a}_f{f}"),
                    file: String::new(),
                    amplitude_um: a,
                    frequency_hz: f,
                    repeat: Some(1),
                    extra: BTreeMap::new(),
                },
                rec,
            ));
        }
    }
    write_folder(dir, &items, format)?;
    Ok(())
}

#[test]
fn fit_evaluate_predict() -> TestResult {
    let dir = scratch("ok")?;
    let data = dir.join("data");
    write_data(&data, Format::Parquet)?;
    let model = dir.join("model.json");
    let samples = dir.join("samples.csv");
    let out = hxai_ok(
        &[
            "fit",
            "--data",
            s(&data),
            "--out",
            s(&model),
            "--seed",
            "3",
            "--epochs",
            "3",
            "--samples",
            s(&samples),
            "--json",
        ],
        "fit failed",
    )?;
    let fit_json: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    assert!(fit_json["correction"]["equation"].is_string());
    // the correction's constants and selection, as the library reports them (FittedReport)
    let c = &fit_json["correction"];
    assert!(c["template"].is_string() && c["params"].is_object(), "{c}");
    assert!(c["selection"]["method"].is_string(), "{c}");

    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model)?)?;
    assert_eq!(m["schema_version"], 1);
    for k in ["equation", "sympy", "latex", "complexity", "features"] {
        assert!(m["correction"].get(k).is_some(), "correction.{k} missing");
    }
    // 12 records, ceil(0.2 * 12) = 3 held out.
    assert_eq!(m["split"]["test"].as_array().map(Vec::len), Some(3));
    assert_eq!(m["split"]["train"].as_array().map(Vec::len), Some(9));

    // samples.csv: one row per window (12 records x 3 windows) with the promised columns.
    let st = hxai_data::read_mixed_table(&samples)?;
    for c in [
        "record", "window", "split", "f1", "f12", "A_phys", "A_true", "delta",
    ] {
        assert!(
            st.names.iter().any(|n| n == c),
            "samples column {c} missing"
        );
    }
    assert_eq!(st.columns[0].len(), 36);

    let out = hxai_ok(
        &evaluate_args(s(&model), s(&data), &["--json"]),
        "evaluate failed",
    )?;
    let ev: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    for path in [
        ["physics", "rmse_um"],
        ["physics", "r2"],
        ["hybrid", "rmse_um"],
        ["hybrid", "r2"],
        ["t_test", "p_value"],
    ] {
        assert!(
            ev[path[0]][path[1]].is_number(),
            "{}.{} missing in {ev}",
            path[0],
            path[1]
        );
    }
    assert!(ev["improvement_pct"].is_number());
    // 3 test records x 3 windows x 500 samples.
    assert_eq!(ev["n_samples"], 4500);
    // The correction must help on unseen records (the construction leaves a delta of up to
    // 48 % of the amplitude for the physics model); threshold: hybrid RMSE below physics RMSE.
    let (p, h) = (
        ev["physics"]["rmse_um"].as_f64(),
        ev["hybrid"]["rmse_um"].as_f64(),
    );
    assert!(h < p, "hybrid {h:?} vs physics {p:?}");

    let out = hxai(&evaluate_args(s(&model), s(&data), &["--all", "--json"]))?;
    assert!(out.status.success());
    let ev_all: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    assert_eq!(ev_all["n_samples"], 18000);

    let pred = dir.join("pred.csv");
    let rec = data.join("a7_f20.parquet");
    hxai_ok(
        &predict_args(s(&model), s(&rec), "20", s(&pred)),
        "predict failed",
    )?;
    let t = read_table(&pred)?;
    assert_eq!(t.names(), ["time_s", "physics_um", "hybrid_um"]);
    assert_eq!(t.n_rows(), 2000);

    // issue 15: the interval of the corrected amplitude, and its coverage on test windows
    let iv = &ev["interval"];
    assert_eq!(iv["nominal"], 0.95, "{ev}");
    let cov = iv["coverage"].as_f64().ok_or("coverage")?;
    assert!((0.0..=1.0).contains(&cov), "{iv}");
    assert_eq!(iv["n"], 9, "3 test records x 3 windows");
    let pred_iv = dir.join("pred_iv.csv");
    let mut args = predict_args(s(&model), s(&rec), "20", s(&pred_iv));
    args.extend_from_slice(&["--interval", "0.9"]);
    hxai_ok(&args, "predict --interval failed")?;
    let t = read_table(&pred_iv)?;
    assert_eq!(
        t.names(),
        [
            "time_s",
            "physics_um",
            "hybrid_um",
            "hybrid_lo_um",
            "hybrid_hi_um"
        ]
    );
    let (h, lo, hi) = (
        t.require("hybrid_um")?,
        t.require("hybrid_lo_um")?,
        t.require("hybrid_hi_um")?,
    );
    for i in 0..t.n_rows() {
        assert!(lo[i] <= h[i] + 1e-12 && h[i] <= hi[i] + 1e-12, "row {i}");
    }
    Ok(())
}

#[test]
fn bad_inputs_fail_with_one_line() -> TestResult {
    let dir = scratch("bad")?;
    // `fit` takes the search strategy as `--strategy`, like `sr`, and still accepts the
    // old spelling `--engine` (a hidden alias, for old scripts): with either, the run fails
    // only on the folder.
    for strategy in [
        &[][..],
        &["--strategy", "genetic"],
        &["--engine", "genetic"],
    ] {
        let (data, model) = (dir.join("nope"), dir.join("m.json"));
        let mut args = vec!["fit", "--data", s(&data), "--out", s(&model)];
        args.extend_from_slice(strategy);
        let out = hxai(&args)?;
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{strategy:?}: {err}");
        assert!(err.contains("nope"), "{strategy:?}: {err}");
        assert!(out.stdout.is_empty());
    }

    let model = dir.join("m.json");
    std::fs::write(&model, "{\"schema_version\": 99}")?;
    let (rec, pred) = (dir.join("r.csv"), dir.join("o.csv"));
    let out = hxai(&predict_args(s(&model), s(&rec), "10", s(&pred)))?;
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("schema_version"), "{err}");
    Ok(())
}

/// All or nothing: `--stability 0` is refused before any work, and a samples path that
/// cannot be written (its folder is a file) fails before the model file is replaced: an
/// existing model stays byte for byte, and no temporary file is left.
#[test]
fn fit_writes_all_outputs_or_none() -> TestResult {
    let dir = scratch("all-or-nothing")?;
    let data = dir.join("data");
    write_data(&data, Format::Parquet)?;
    let model = dir.join("model.json");
    std::fs::write(&model, "the old model\n")?;
    let blocker = dir.join("not_a_folder");
    std::fs::write(&blocker, "a file")?;
    let bad_samples = blocker.join("s.csv");
    let (data_s, model_s) = (s(&data), s(&model));
    let fit = |extra: &[&str]| {
        let mut args = vec!["fit", "--epochs", "2", "--data", data_s, "--out", model_s];
        args.extend_from_slice(extra);
        hxai(&args)
    };
    let o = fit(&["--stability", "0"])?;
    assert_eq!(o.status.code(), Some(1));
    assert!(common::stderr(&o).contains("--stability must be at least 1"));
    let o = fit(&["--samples", s(&bad_samples)])?;
    assert_eq!(o.status.code(), Some(1), "{}", common::stderr(&o));
    assert_eq!(std::fs::read_to_string(&model)?, "the old model\n");
    common::assert_no_temporary_files(&dir);
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}
