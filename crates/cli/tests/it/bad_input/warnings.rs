//! Input that is legal but implausible (a probe in mm where the manifest says µm, a 10 Hz
//! sampling rate) gives warnings, not errors.

use super::*;

/// Runs the command and requires success with a warning on stderr containing `expect`;
/// returns the JSON document it printed.
fn warned(args: &[&str], expect: &str) -> serde_json::Value {
    let out = hxai(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains(expect), "{stderr}");
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn implausible_input_gives_warnings_not_errors() {
    // The probe is about 6 um where the manifest commands 4000-10000 um: a unit slip.
    let doc = warned(
        &evaluate_args(
            &corpus("good/model.json"),
            &corpus("folders/probe_in_mm"),
            &["--all", "--json"],
        ),
        "warning: record `r1`: the probe amplitude",
    );
    let w = doc["warnings"].as_array().unwrap();
    assert_eq!(w.len(), 4, "{w:?}");
    // A 10 Hz sampling rate is legal but implausible.
    let dir = scratch("warn");
    let rec = dir.join("slow.csv");
    let mut text = String::from("time_s,accel_ms2\n");
    for i in 0..400 {
        let t = i as f64 / 10.0;
        text.push_str(&format!(
            "{t},{}\n",
            (2.0 * std::f64::consts::PI * 0.5 * t).sin()
        ));
    }
    std::fs::write(&rec, text).unwrap();
    let doc = warned(
        &[
            "features",
            "--record",
            rec.to_str().unwrap(),
            "--frequency-hz",
            "0.5",
            "--json",
        ],
        "sampling rate 10 Hz is outside",
    );
    assert_eq!(doc["warnings"].as_array().map(Vec::len), Some(1));
}
