//! Regenerates `testdata/sim/records.json`: three short records and the configuration that
//! produced them. The `regression` test checks that the simulator still produces them.
//!
//! Run: `cargo run -p hxai-sim --example regen_testdata`
#![allow(clippy::print_stdout)]

use hxai_sim::{SimConfig, SimRecord, simulate};
use serde::Serialize;
use std::path::PathBuf;

/// The stored regression case.
#[derive(Serialize)]
struct Stored {
    /// How the file was made.
    note: &'static str,
    config: SimConfig,
    records: Vec<SimRecord>,
}

/// The small configuration of the regression case: three conditions across the test matrix,
/// 0.25 s at 2 kHz each (the file stays near 120 KB).
fn config() -> SimConfig {
    SimConfig {
        seed: 7,
        amplitudes_um: vec![4.0, 11.0],
        frequencies_hz: vec![10.0, 40.0],
        repeats: 1,
        duration_s: 0.25,
        fs_hz: 2_000.0,
        ..SimConfig::default()
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cfg = config();
    // Keep three of the four conditions (drop 4 um at 40 Hz) to stay small.
    let records: Vec<SimRecord> = simulate(&cfg)?
        .into_iter()
        .filter(|r| !(r.amplitude_um == 4.0 && r.frequency_hz == 40.0))
        .collect();
    let stored = Stored {
        note: "written by `cargo run -p hxai-sim --example regen_testdata`; checked by crates/sim/tests/it/regression.rs",
        config: cfg,
        records,
    };
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/sim");
    std::fs::create_dir_all(&dir)?;
    let path = dir.join("records.json");
    std::fs::write(&path, serde_json::to_string(&stored)?)?;
    println!("wrote {}", path.display());
    Ok(())
}
