//! `hxai simulate --case NAME --out TABLE`: the process tables of docs/cases.md.

use hxai_data::read_table;
use hxai_sim::cases::{RoughnessConfig, roughness};
use std::path::PathBuf;
use std::process::Output;

mod common;
use common::{hxai, text};

type TestResult = Result<(), Box<dyn std::error::Error>>;

fn scratch(name: &str) -> Result<PathBuf, std::io::Error> {
    common::scratch("hxai-cli-case", name)
}

/// Runs `hxai simulate --case CASE --out OUT` with the `extra` flags.
fn simulate(case: &str, out: &str, extra: &[&str]) -> Result<Output, std::io::Error> {
    let mut args = vec!["simulate", "--case", case, "--out", out];
    args.extend_from_slice(extra);
    hxai(&args)
}

#[test]
fn writes_the_roughness_table_as_csv_and_parquet() -> TestResult {
    let dir = scratch("tables")?;
    let expected = roughness(&RoughnessConfig {
        n_rows: 25,
        seed: 7,
        ..RoughnessConfig::default()
    })?;
    for ext in ["csv", "parquet"] {
        let out = dir.join(format!("sub/roughness.{ext}"));
        let o = simulate(
            "roughness",
            out.to_str().ok_or("path")?,
            &["--rows", "25", "--seed", "7"],
        )?;
        assert!(o.status.success(), "{}", text(&o));
        let t = read_table(&out)?;
        assert_eq!(t.names(), expected.names());
        assert_eq!(t.n_rows(), 25);
        for (name, col) in expected.names().iter().zip(expected.columns()) {
            let got = t.column(name).ok_or("column")?;
            for (a, b) in got.iter().zip(col) {
                // CSV prints shortest round-trip decimals, Parquet stores the bits.
                assert!(
                    (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                    "{name}: {a} vs {b}"
                );
            }
        }
        // No temporary file is left beside the table.
        let left: Vec<_> = std::fs::read_dir(dir.join("sub"))?
            .filter_map(Result::ok)
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp."))
            .collect();
        assert!(left.is_empty());
    }
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

#[test]
fn refuses_to_overwrite_without_force() -> TestResult {
    let dir = scratch("force")?;
    let out = dir.join("force.csv");
    let path = out.to_str().ok_or("path")?;
    std::fs::write(&out, "keep me\n")?;
    let o = simulate("cutting_force", path, &["--rows", "10"])?;
    assert!(!o.status.success());
    assert!(text(&o).contains("--force"), "{}", text(&o));
    assert_eq!(std::fs::read_to_string(&out)?, "keep me\n");
    let o = simulate(
        "cutting_force",
        path,
        &["--rows", "10", "--force", "--json"],
    )?;
    assert!(o.status.success(), "{}", text(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout)?;
    assert_eq!(doc["rows"], 10);
    assert_eq!(doc["case"], "cutting_force");
    let t = read_table(&out)?;
    assert_eq!(t.n_rows(), 10);
    assert!(t.column("Fc_N").is_some());
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

#[test]
fn bad_case_options_are_refused() -> TestResult {
    let dir = scratch("bad")?;
    let csv = dir.join("t.csv");
    let csv = csv.to_str().ok_or("path")?;
    // Unknown case name: clap lists the known ones.
    let o = simulate("milling", csv, &[])?;
    assert!(!o.status.success());
    assert!(text(&o).contains("roughness"), "{}", text(&o));
    // Folder-mode options do not mix with --case.
    let o = simulate("roughness", csv, &["--repeats", "2"])?;
    assert!(!o.status.success());
    // An output that is not a table file.
    let txt = dir.join("t.txt");
    let o = simulate("roughness", txt.to_str().ok_or("path")?, &[])?;
    assert!(!o.status.success());
    assert!(text(&o).contains(".csv or .parquet"), "{}", text(&o));
    // Zero rows is a bad setting, named.
    let o = simulate("roughness", csv, &["--rows", "0"])?;
    assert!(!o.status.success());
    assert!(text(&o).contains("n_rows"), "{}", text(&o));
    assert!(!dir.join("t.csv").exists());
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}
