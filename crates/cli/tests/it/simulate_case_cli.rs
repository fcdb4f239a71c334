//! `hxai simulate --case NAME --out TABLE`: the process tables of docs/cases.md.

use hxai_data::read_table;
use hxai_sim::cases::{CASE_NAMES, RoughnessConfig, generate_case, roughness};
use std::path::Path;
use std::process::Output;

use crate::common;
use common::{hxai, s, text};

type TestResult = Result<(), Box<dyn std::error::Error>>;

/// Runs `body` with a fresh scratch folder `name` and the path of `file` in it, and removes
/// the folder when `body` succeeds (a failed test leaves it to look at).
fn in_scratch(name: &str, file: &str, body: impl FnOnce(&Path, &Path) -> TestResult) -> TestResult {
    let dir = common::scratch("hxai-cli-case", name)?;
    body(&dir, &dir.join(file))?;
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

/// Runs `hxai simulate --case CASE --out OUT` with the `extra` flags.
fn simulate(case: &str, out: &Path, extra: &[&str]) -> Result<Output, std::io::Error> {
    let mut args = vec!["simulate", "--case", case, "--out", s(out)];
    args.extend_from_slice(extra);
    hxai(&args)
}

#[test]
fn writes_the_roughness_table_as_csv_and_parquet() -> TestResult {
    let expected = roughness(&RoughnessConfig {
        n_rows: 25,
        seed: 7,
        ..RoughnessConfig::default()
    })?;
    // `sub` does not exist yet: simulate makes it.
    in_scratch("tables", "sub", |_, sub| {
        for ext in ["csv", "parquet"] {
            let out = sub.join(format!("roughness.{ext}"));
            let o = simulate("roughness", &out, &["--rows", "25", "--seed", "7"])?;
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
            let left: Vec<_> = std::fs::read_dir(sub)?
                .filter_map(Result::ok)
                .filter(|e| e.file_name().to_string_lossy().contains(".tmp."))
                .collect();
            assert!(left.is_empty());
        }
        Ok(())
    })
}

/// Every case of the library is a `--case` value, and the table it writes is the library's
/// (tool_life, issue 23, included by name: its columns are the documented ones).
#[test]
fn every_library_case_is_a_case_value() -> TestResult {
    assert!(CASE_NAMES.contains(&"tool_life"));
    in_scratch("all", "t.parquet", |_, out| {
        for name in CASE_NAMES {
            let o = simulate(
                name,
                out,
                &["--rows", "12", "--seed", "3", "--force", "--json"],
            )?;
            assert!(o.status.success(), "{name}: {}", text(&o));
            let doc: serde_json::Value = serde_json::from_slice(&o.stdout)?;
            assert_eq!(doc["case"], name);
            assert_eq!(
                read_table(out)?,
                generate_case(name, Some(12), Some(3))?,
                "{name}"
            );
        }
        let o = simulate("tool_life", out, &["--rows", "12", "--force"])?;
        assert!(o.status.success(), "{}", text(&o));
        let t = read_table(out)?;
        assert_eq!(
            t.names(),
            [
                "cutting_speed_m_min",
                "feed_mm",
                "coolant_temp_C",
                "workpiece_diameter_mm",
                "tool",
                "tool_life_min"
            ]
        );
        Ok(())
    })
}

#[test]
fn refuses_to_overwrite_without_force() -> TestResult {
    in_scratch("force", "force.csv", |_, out| {
        std::fs::write(out, "keep me\n")?;
        let o = simulate("cutting_force", out, &["--rows", "10"])?;
        assert!(!o.status.success());
        assert!(text(&o).contains("--force"), "{}", text(&o));
        assert_eq!(std::fs::read_to_string(out)?, "keep me\n");
        let o = simulate("cutting_force", out, &["--rows", "10", "--force", "--json"])?;
        assert!(o.status.success(), "{}", text(&o));
        let doc: serde_json::Value = serde_json::from_slice(&o.stdout)?;
        assert_eq!(doc["rows"], 10);
        assert_eq!(doc["case"], "cutting_force");
        let t = read_table(out)?;
        assert_eq!(t.n_rows(), 10);
        assert!(t.column("Fc_N").is_some());
        Ok(())
    })
}

#[test]
fn bad_case_options_are_refused() -> TestResult {
    in_scratch("bad", "t.csv", |dir, csv| {
        // Unknown case name: clap lists the known ones.
        let o = simulate("milling", csv, &[])?;
        assert!(!o.status.success());
        assert!(text(&o).contains("roughness"), "{}", text(&o));
        // Folder-mode options do not mix with --case.
        let o = simulate("roughness", csv, &["--repeats", "2"])?;
        assert!(!o.status.success());
        // An output that is not a table file.
        let o = simulate("roughness", &dir.join("t.txt"), &[])?;
        assert!(!o.status.success());
        assert!(text(&o).contains(".csv or .parquet"), "{}", text(&o));
        // Zero rows is a bad setting, named.
        let o = simulate("roughness", csv, &["--rows", "0"])?;
        assert!(!o.status.success());
        assert!(text(&o).contains("n_rows"), "{}", text(&o));
        assert!(!csv.exists());
        Ok(())
    })
}
