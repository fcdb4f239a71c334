//! `hxai dynamic fit | predict | compare` and `hxai report` of a dynamic model (issue 69),
//! on a short simulated spindle: the files, their columns, the page, the JSON names of
//! docs/interfaces.md, and an input never written over.

use crate::common;
use common::{hxai, s, text};

type TestResult = Result<(), Box<dyn std::error::Error>>;

const ODE: &str = "T_C' = (q*speed_krpm^1.5 - h*(T_C - ambient_C))/C";

#[test]
fn fit_predict_compare_and_report_a_dynamic_model() -> TestResult {
    let dir = common::scratch("hxai-cli-dynamic", "all")?;
    let data = dir.join("spindle.csv");
    let o = hxai(&[
        "simulate",
        "--case",
        "spindle_thermal",
        "--rows",
        "720",
        "--out",
        s(&data),
    ])?;
    assert!(o.status.success(), "{}", text(&o));
    let common_flags = [
        "--data",
        s(&data),
        "--time",
        "time_s",
        "--run",
        "run",
        "--state",
        "T_C",
        "--inputs",
        "speed_krpm,ambient_C,humidity_pct",
        "--ode",
        ODE,
        "--calibrate",
        "q,h",
        "--init",
        "q=30,h=8",
        "--set",
        "C=20000",
        "--form",
        "factors",
    ];
    let model = dir.join("m.json");
    let mut fit = vec!["dynamic", "fit"];
    fit.extend_from_slice(&common_flags);
    fit.extend_from_slice(&["--conformal-folds", "3", "--out", s(&model)]);
    let o = hxai(&fit)?;
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("model written"), "{}", text(&o));
    let m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&model)?)?;
    assert_eq!(m["corrections"][0]["state"], "T_C");
    // predict: each run from its first reading, the band's columns with --interval
    let pred = dir.join("p.csv");
    let o = hxai(&[
        "dynamic",
        "predict",
        "--model",
        s(&model),
        "--data",
        s(&data),
        "--interval",
        "0.5",
        "--out",
        s(&pred),
    ])?;
    assert!(o.status.success(), "{}", text(&o));
    let p = hxai_data::read_table(&pred)?;
    for c in [
        "run",
        "time_s",
        "T_C_physics",
        "T_C_hybrid",
        "T_C_lo",
        "T_C_hi",
    ] {
        assert!(p.column(c).is_some(), "no column {c}: {:?}", p.names());
    }
    assert_eq!(p.n_rows(), 720);
    // never over an input
    let o = hxai(&[
        "dynamic",
        "predict",
        "--model",
        s(&model),
        "--data",
        s(&data),
        "--out",
        s(&data),
    ])?;
    assert!(!o.status.success());
    assert!(text(&o).contains("refusing to write over"), "{}", text(&o));
    // compare: the four names, the correction's equation and features
    let mut cmp = vec!["dynamic", "compare"];
    cmp.extend_from_slice(&common_flags);
    cmp.extend_from_slice(&["--test-runs", "3", "--json"]);
    let o = hxai(&cmp)?;
    assert!(o.status.success(), "{}", text(&o));
    let c: serde_json::Value = serde_json::from_slice(&o.stdout)?;
    let names: Vec<&str> = c["models"]
        .as_array()
        .ok_or("models")?
        .iter()
        .filter_map(|m| m["name"].as_str())
        .collect();
    assert_eq!(
        names,
        ["physics", "physics_calibrated", "hybrid", "narx_boosting"]
    );
    assert!(c["hybrid"]["correction"]["equation"].is_string());
    assert!(c["hybrid"]["correction"]["features"].is_array());
    assert_eq!(c["test_runs"], serde_json::json!([3.0]));
    // the report: self-contained, the equation's id, the runs drawn
    let page = dir.join("r.html");
    let o = hxai(&[
        "report",
        "--model",
        s(&model),
        "--data",
        s(&data),
        "--out",
        s(&page),
    ])?;
    assert!(o.status.success(), "{}", text(&o));
    let html = std::fs::read_to_string(&page)?;
    assert!(common::assert_self_contained_page(&html) >= 1);
    assert!(html.contains("id=\"hybrid-equation\""));
    assert!(html.contains("hxai dynamic fit --data"));
    Ok(())
}
