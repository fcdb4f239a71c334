//! Regression against `testdata/sim/records.json` (regenerate with
//! `cargo run -p hxai-sim --example regen_testdata`).
//!
//! Tolerance, per sample: time and command 1e-9 (pure arithmetic); the quantised channels
//! one quantisation step plus 1e-9 (probe 1 nm, encoder 5 nm, accelerometer one 16-bit DAQ
//! step), so that last-bit differences of `sin`/`sqrt` between platforms may flip a rounding
//! but any change of the model fails.

use hxai_sim::{SimConfig, SimRecord, simulate};
use serde::Deserialize;
use std::path::PathBuf;

#[derive(Deserialize)]
struct Stored {
    config: SimConfig,
    records: Vec<SimRecord>,
}

fn close(name: &str, id: &str, got: &[f64], want: &[f64], tol: f64) -> Result<(), String> {
    if got.len() != want.len() {
        return Err(format!(
            "{id} {name}: {} samples, stored {}",
            got.len(),
            want.len()
        ));
    }
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        if (g - w).abs() > tol {
            return Err(format!(
                "{id} {name}[{i}] = {g}, stored {w} (tolerance {tol})"
            ));
        }
    }
    Ok(())
}

#[test]
fn simulator_reproduces_stored_records() -> Result<(), Box<dyn std::error::Error>> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/sim/records.json");
    let stored: Stored = serde_json::from_str(&std::fs::read_to_string(&path)?)?;
    assert_eq!(stored.records.len(), 3);
    let cfg = &stored.config;
    let fresh = simulate(cfg)?;
    let adc_step = 2.0 * cfg.accel.daq_range_v * 1000.0
        / cfg.accel.sensitivity_mv_per_ms2
        / 2f64.powi(cfg.accel.adc_bits as i32);
    for want in &stored.records {
        let got = fresh
            .iter()
            .find(|r| r.id == want.id)
            .ok_or_else(|| format!("record {} no longer simulated", want.id))?;
        assert_eq!(got.amplitude_um, want.amplitude_um);
        assert_eq!(got.frequency_hz, want.frequency_hz);
        assert_eq!(got.repeat, want.repeat);
        let id = &want.id;
        close("time_s", id, &got.time_s, &want.time_s, 1e-9)?;
        close("command_um", id, &got.command_um, &want.command_um, 1e-9)?;
        let probe_tol = cfg.probe.resolution_nm * 1e-3 + 1e-9;
        close("probe_um", id, &got.probe_um, &want.probe_um, probe_tol)?;
        let enc_tol = cfg.encoder.resolution_nm * 1e-3 + 1e-9;
        close("encoder_um", id, &got.encoder_um, &want.encoder_um, enc_tol)?;
        close(
            "accel_ms2",
            id,
            &got.accel_ms2,
            &want.accel_ms2,
            adc_step + 1e-9,
        )?;
    }
    Ok(())
}
