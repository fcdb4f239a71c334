//! `hxai hybrid fit | predict | evaluate | compare` end to end on a small CSV and Parquet
//! table with a known law, and one-line errors for bad input.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common;
use common::{evaluate_args, hxai, ok, s};

#[path = "../../../../hybrid/tests/it/common/mod.rs"]
mod hybrid_common;
use hybrid_common::COMPARE_MODELS;

type TestResult = Result<(), Box<dyn std::error::Error>>;

mod classes;
mod forms;
mod missing;
mod outputs;
mod reading;

/// A fresh scratch folder `name` holding `ra.csv`, a [`roughness_csv`] table of `n`
/// rows: the folder and the table's path.
fn scratch_table(name: &str, n: usize) -> Result<(common::Scratch, PathBuf), std::io::Error> {
    let dir = common::scratch("hxai-cli-hybrid-table", name)?;
    let csv = dir.join("ra.csv");
    std::fs::write(&csv, roughness_csv(n))?;
    Ok((dir, csv))
}

/// Turning-like table: Ra = 1.3 f^2/(32 r) + 2e-4 v, a distractor d, a text batch column.
fn roughness_csv(n: usize) -> String {
    let mut out = String::from("batch,f,r,v,d,Ra\n");
    for i in 0..n {
        let f = 0.05 + 0.25 * ((i * 7) % 23) as f64 / 22.0;
        let r = 0.4 + 1.2 * ((i * 5) % 13) as f64 / 12.0;
        let v = 50.0 + 250.0 * ((i * 11) % 29) as f64 / 28.0;
        let d = ((i * 3) % 7) as f64;
        let ra = 1.3 * f * f / (32.0 * r) + 2e-4 * v;
        out.push_str(&format!("b{},{f},{r},{v},{d},{ra}\n", i / 4));
    }
    out
}

const QUICK: [&str; 4] = ["--epochs", "2", "--max-complexity", "8"];

/// `hxai hybrid CMD` on `data` (target `Ra`) with the physics `physics`.
fn hybrid_args<'a>(cmd: &'a str, data: &'a str, physics: &'a str) -> Vec<&'a str> {
    vec![
        "hybrid",
        cmd,
        "--data",
        data,
        "--target",
        "Ra",
        "--physics",
        physics,
    ]
}

/// The kinematic roughness law, its factor `k` to calibrate ([`CALIBRATE_K`]).
const LAW: &str = "k*f^2/(32*r)";
const CALIBRATE_K: [&str; 2] = ["--calibrate", "k"];

/// `hxai hybrid fit` of [`LAW`] on `data`, quick, writing the model to `out`.
fn fit_args<'a>(data: &'a str, out: &'a str) -> Vec<&'a str> {
    let mut a = hybrid_args("fit", data, LAW);
    a.extend_from_slice(&CALIBRATE_K);
    a.extend_from_slice(&["--out", out]);
    a.extend_from_slice(&QUICK);
    a
}

/// `hxai hybrid predict` with `model` on `data`, writing `out`; callers append flags.
fn predict_args<'a>(model: &'a Path, data: &'a Path, out: &'a Path) -> Vec<&'a str> {
    vec![
        "hybrid",
        "predict",
        "--model",
        s(model),
        "--data",
        s(data),
        "--out",
        s(out),
    ]
}

/// `hxai hybrid design` with `model` over `space` for `n` runs, writing `out`; callers
/// append flags.
fn design_args<'a>(model: &'a Path, space: &'a str, n: &'a str, out: &'a Path) -> Vec<&'a str> {
    vec![
        "hybrid",
        "design",
        "--model",
        s(model),
        "--space",
        space,
        "--n",
        n,
        "--out",
        s(out),
    ]
}

#[test]
fn fit_predict_evaluate_follow_the_contract() -> TestResult {
    let (dir, data) = scratch_table("contract", 160)?;
    let model = dir.join("model.json");
    let mut args = fit_args(s(&data), s(&model));
    args.extend_from_slice(&["--group", "batch", "--json"]);
    let out = hxai(&args)?;
    ok(&out, "fit");
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    let file: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model)?)?;
    assert_eq!(doc, file, "--json prints the model file");
    for key in [
        "/schema_version",
        "/physics/equation",
        "/physics/parameters/k",
        "/physics/standard_errors/k",
        "/correction/kind",
        "/correction/equation",
        "/correction/sympy",
        "/correction/latex",
        "/correction/complexity",
        "/correction/features",
        "/hybrid/equation",
        "/hybrid/sympy",
        "/hybrid/latex",
        "/target",
        "/split/train",
        "/split/test",
    ] {
        assert!(doc.pointer(key).is_some(), "missing {key}");
    }
    assert_eq!(doc["correction"]["kind"], "additive");
    assert_eq!(doc["target"], "Ra");
    // groups of four rows never straddle the split
    let test: Vec<u64> = doc["split"]["test"]
        .as_array()
        .ok_or("test")?
        .iter()
        .filter_map(serde_json::Value::as_u64)
        .collect();
    for i in &test {
        let g = i / 4;
        assert!((g * 4..g * 4 + 4).all(|j| test.contains(&j)));
    }

    // predict: one row per input row, with the group column; the target is not needed
    let no_target = dir.join("new.csv");
    let text: String = roughness_csv(160)
        .lines()
        .map(|l| l.rsplit_once(',').map_or(l, |(a, _)| a).to_string() + "\n")
        .collect();
    std::fs::write(&no_target, text)?;
    let pred = dir.join("pred.csv");
    let out = hxai(&predict_args(&model, &no_target, &pred))?;
    ok(&out, "predict");
    let written = std::fs::read_to_string(&pred)?;
    let mut lines = written.lines();
    assert_eq!(
        lines.next(),
        Some("batch,physics,correction,hybrid,outside_training")
    );
    assert_eq!(lines.count(), 160);

    // evaluate
    let mut args = vec!["hybrid"];
    args.extend(evaluate_args(s(&model), s(&data), &["--json"]));
    let out = hxai(&args)?;
    ok(&out, "evaluate");
    let ev: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    for key in [
        "/physics/rmse",
        "/physics/r2",
        "/hybrid/rmse",
        "/hybrid/r2",
        "/improvement_pct",
        "/t_test/p_value",
        "/n_samples",
    ] {
        assert!(ev.pointer(key).is_some(), "missing {key}");
    }
    assert_eq!(ev["n_samples"], 160);
    // the hybrid improves on the calibrated law, which misses the speed term
    assert!(ev["improvement_pct"].as_f64().ok_or("pct")? > 50.0, "{ev}");
    // issue 15: calibrated parameters with intervals, templates, interval coverage
    for key in [
        "/physics/params/k/std_error",
        "/physics/params/k/ci95",
        "/correction/uncertainty/template",
        "/correction/uncertainty/params",
        "/hybrid/uncertainty/template",
        "/hybrid/uncertainty/params/k",
        "/hybrid/uncertainty/covariance",
    ] {
        assert!(doc.pointer(key).is_some(), "missing {key}");
    }
    assert_eq!(ev["interval"]["nominal"], 0.95, "{ev}");
    assert!(
        ev["interval"]["coverage"].as_f64().ok_or("coverage")? > 0.5,
        "{ev}"
    );
    let pred_iv = dir.join("pred_iv.csv");
    let mut args = predict_args(&model, &no_target, &pred_iv);
    args.extend_from_slice(&["--interval", "0.95"]);
    let out = hxai(&args)?;
    ok(&out, "predict --interval");
    let written = std::fs::read_to_string(&pred_iv)?;
    let mut lines = written.lines();
    assert_eq!(
        lines.next(),
        Some("batch,physics,correction,hybrid,hybrid_lo,hybrid_hi,outside_training")
    );
    for line in lines {
        let v: Vec<f64> = line
            .split(',')
            .skip(1)
            .filter_map(|x| x.parse().ok())
            .collect();
        assert!(v[3] <= v[2] && v[2] <= v[4], "{line}");
    }
    // predict refuses to write over its input
    let out = hxai(&predict_args(&model, &data, &data))?;
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("input"));
    Ok(())
}

#[test]
fn parquet_tables_and_compare_work() -> TestResult {
    let (dir, csv) = scratch_table("parquet", 120)?;
    // convert with hxai itself: predict writes Parquet; here write the input via hxai-data
    let table = hxai_data::read_mixed_table(&csv)?;
    let pq = dir.join("ra.parquet");
    hxai_data::write_mixed_table(&pq, &table)?;
    let model = dir.join("m.json");
    let out = hxai(&fit_args(s(&pq), s(&model)))?;
    ok(&out, "fit parquet");
    let pred = dir.join("p.parquet");
    let out = hxai(&predict_args(&model, &pq, &pred))?;
    ok(&out, "predict parquet");
    let back = hxai_data::read_mixed_table(&pred)?;
    assert_eq!(
        back.names,
        ["physics", "correction", "hybrid", "outside_training"]
    );

    let mut args = hybrid_args("compare", s(&csv), LAW);
    args.extend_from_slice(&CALIBRATE_K);
    args.extend_from_slice(&[
        "--init",
        "k=1.1",
        "--extrapolate",
        "v",
        "--folds",
        "3",
        "--json",
    ]);
    args.extend_from_slice(&QUICK);
    let out = hxai(&args)?;
    ok(&out, "compare");
    let c: serde_json::Value = serde_json::from_slice(&out.stdout)?;
    let names: Vec<&str> = c["models"]
        .as_array()
        .ok_or("models")?
        .iter()
        .filter_map(|m| m["name"].as_str())
        .collect();
    assert_eq!(names, COMPARE_MODELS);
    for m in c["models"].as_array().ok_or("models")? {
        for k in ["r2", "rmse", "mae"] {
            assert!(m[k].is_number(), "{m}");
        }
    }
    // the best black box and the hybrid's ratio to it (issue 48)
    let best = c["best_black_box"]["name"]
        .as_str()
        .ok_or("best_black_box")?;
    assert!(["physics_forest", "boosting"].contains(&best), "{best}");
    let rmse_of = |n: &str| {
        c["models"]
            .as_array()
            .and_then(|v| v.iter().find(|m| m["name"] == n))
            .and_then(|m| m["rmse"].as_f64())
    };
    let ratio = c["hybrid_over_best_black_box"].as_f64().ok_or("ratio")?;
    let want = rmse_of("hybrid").ok_or("hybrid")?
        / rmse_of("physics_forest")
            .ok_or("forest")?
            .min(rmse_of("boosting").ok_or("boosting")?);
    assert!((ratio - want).abs() <= 1e-12 * want, "{ratio} vs {want}");
    let cv = c["cv"].as_array().ok_or("cv")?;
    assert_eq!(cv.len(), COMPARE_MODELS.len());
    for s in cv {
        for k in ["name", "r2_mean", "r2_sd", "r2_ci"] {
            assert!(!s[k].is_null(), "{s}");
        }
    }
    assert_eq!(c["split"], "extrapolate");
    assert!(c["t_test"]["p_value"].is_number());
    Ok(())
}

/// Runs `hybrid fit` with `extra` replacing defaults; requires failure with one stderr
/// line that contains every needle.
fn refused(data: &Path, physics: &str, extra: &[&str], needles: &[&str]) -> TestResult {
    let dir = data.parent().ok_or("dir")?;
    let model = dir.join("never.json");
    let mut args = hybrid_args("fit", s(data), physics);
    args.extend_from_slice(&["--out", s(&model)]);
    args.extend_from_slice(extra);
    args.extend_from_slice(&QUICK);
    let out = hxai(&args)?;
    assert!(!out.status.success(), "{physics} {extra:?} should fail");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    for n in needles {
        assert!(err.contains(n), "{physics} {extra:?}: `{n}` not in {err}");
    }
    assert!(!model.exists());
    Ok(())
}

#[test]
fn bad_input_gives_one_line_naming_it() -> TestResult {
    let (_dir, data) = scratch_table("bad", 60)?;
    let cal = ["--calibrate", "k"];
    // neither a column nor a parameter
    refused(&data, "k*f^2/(32*rr)", &cal, &["`rr`", "character 11"])?;
    // a parameter that is also a column
    refused(
        &data,
        "k*f^2/(32*r)",
        &["--calibrate", "k,r"],
        &["`r`", "column"],
    )?;
    // a calibrated parameter that does not appear
    refused(
        &data,
        "k*f^2/(32*r)",
        &["--calibrate", "k,n"],
        &["`n`", "does not appear"],
    )?;
    // a syntax error
    refused(&data, "k*f^2/(32*r", &cal, &["character 12", "`)`"])?;
    // an empty feature set
    refused(
        &data,
        "k*f^2/(32*r)",
        &["--calibrate", "k", "--exclude", "f,r,v,d"],
        &["no feature column"],
    )?;
    // the target in the physics
    refused(&data, "k*f^2/(32*r) + 0*Ra", &cal, &["target", "`Ra`"])?;
    // a text column where numbers are needed
    refused(&data, "k*f^2/(32*r) + 0*batch", &cal, &["`batch`", "text"])?;
    // an operator the search does not know
    refused(
        &data,
        "k*f^2/(32*r)",
        &["--calibrate", "k", "--operators", "add,pow3"],
        &["`pow3`"],
    )?;
    // a malformed --set
    refused(
        &data,
        "k*f^2/(32*r)",
        &["--set", "k"],
        &["--set", "NAME=VALUE"],
    )?;
    Ok(())
}

/// Outputs are checked before any work: `hybrid fit --out` naming the table is refused
/// before the search (the table untouched), `hybrid predict --out` with an unknown
/// extension is refused naming that path (not a temporary one), and nothing is left behind.
#[test]
fn outputs_are_checked_before_any_work() -> TestResult {
    let (dir, csv) = scratch_table("outputs-first", 60)?;
    let before = std::fs::read(&csv)?;
    let o = hxai(&fit_args(s(&csv), s(&csv)))?;
    assert_eq!(o.status.code(), Some(1));
    let err = common::stderr(&o);
    assert!(err.contains("the table (--data)"), "{err}");
    assert!(!err.contains("epoch"), "{err}");
    assert_eq!(std::fs::read(&csv)?, before);
    let model = dir.join("m.json");
    ok(&hxai(&fit_args(s(&csv), s(&model)))?, "fit");
    let out = dir.join("p.txt");
    let o = hxai(&predict_args(&model, &csv, &out))?;
    assert_eq!(o.status.code(), Some(1));
    let err = common::stderr(&o);
    assert!(err.contains("p.txt") && !err.contains(".tmp"), "{err}");
    common::assert_no_temporary_files(&dir);
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

/// No physics equation aborts the process: nesting 10,000 deep and flat chains of 60,000
/// terms (which overflowed the stack) exit 1 with one short line naming the limit.
#[test]
fn deep_and_long_physics_equations_are_refused() -> TestResult {
    let (dir, csv) = scratch_table("deep-physics", 40)?;
    let out = dir.join("m.json");
    for physics in [
        format!("{}f{}", "(".repeat(10_000), ")".repeat(10_000)),
        format!("{}f{}", "abs(".repeat(10_000), ")".repeat(10_000)),
        vec!["f"; 60_000].join("+"),
        vec!["f"; 1_500].join("*"),
    ] {
        let mut args = hybrid_args("fit", s(&csv), &physics);
        args.extend(["--out", s(&out)]);
        let o = hxai(&args)?;
        assert_eq!(o.status.code(), Some(1), "{}...", &physics[..12]);
        let err = common::stderr(&o);
        assert!(err.lines().count() == 1 && err.len() < 400, "{err}");
        assert!(err.contains("tokens") || err.contains("nests"), "{err}");
    }
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

/// A model of the other workflow is refused by name, with the command it belongs to:
/// `hxai fit`'s model given to `hybrid predict`, `hybrid fit`'s given to `predict`.
#[test]
fn models_of_the_other_kind_are_named() -> TestResult {
    let (dir, csv) = scratch_table("other-kind", 60)?;
    let tool_model = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/bad/good/model.json"
    );
    let out = dir.join("p.csv");
    let o = hxai(&predict_args(Path::new(tool_model), &csv, &out))?;
    assert_eq!(o.status.code(), Some(1));
    let err = common::stderr(&o);
    assert!(
        err.contains("model of `hxai fit`") && err.contains("`hxai predict`"),
        "{err}"
    );
    let model = dir.join("m.json");
    ok(&hxai(&fit_args(s(&csv), s(&model)))?, "fit");
    let record = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../testdata/bad/good/r1.parquet"
    );
    let o = hxai(&common::predict_args(s(&model), record, "20", s(&out)))?;
    assert_eq!(o.status.code(), Some(1));
    let err = common::stderr(&o);
    assert!(err.contains("`hxai hybrid predict`"), "{err}");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

// Empty cells by the user's choice (issue 48): refused by default with the count and the two
// other choices; `drop` fits on the complete rows; `impute` fills a feature's gaps with its
// training median, stores the medians in the model file and fills a new row the same way at
// predict; the physics' gaps and a model without medians are refused, nothing written.

// A data logger's `-9999` (issue 52): without `--missing-codes` it is a number, named by the
// fit's warning with the flag to give; with `--missing-codes=-9999` those cells are empty,
// so `--missing` decides: refused by default (after a note naming the cells), and under
// `drop` the very model of the same file with the cells left empty. `hxai sr` reads the
// codes the same way (its JSON's warnings name them); a code that is not a number is refused.
