//! `hxai displacement`: the physics-model displacement (band-pass, double integration with
//! drift removal) of one record, written as a table `time_s,displacement_um`.
use std::path::PathBuf;

use anyhow::{Context, Result};
use hxai_signal::{Drift, Integrator, PhysicsConfig};

use crate::Global;
use crate::one_record::RecordArgs;

/// How the acceleration is integrated.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum IntegratorArg {
    /// Butterworth band-pass (filtfilt), then cumulative trapezoid twice with drift removal.
    Time,
    /// Divide the spectrum by -omega^2 inside the band, zero outside.
    Frequency,
}

/// How drift is removed after each time-domain integration.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum DriftArg {
    /// Subtract the least-squares line.
    Linear,
    /// Second-order Butterworth high-pass at half the lower band edge (filtfilt).
    Highpass,
    /// Keep the drift.
    None,
}

/// Arguments of `hxai displacement`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The record and its commanded frequency, which must lie inside the pass band; the
    /// command's amplitude and phase in the physics displacement are reported
    /// (least-squares sine fit).
    #[command(flatten)]
    pub input: RecordArgs,
    /// Output table (CSV or Parquet, by extension) with columns `time_s,displacement_um`.
    #[arg(long)]
    pub out: PathBuf,
    /// Lower edge of the band-pass, Hz.
    #[arg(long, default_value_t = PhysicsConfig::default().low_hz)]
    pub low_hz: f64,
    /// Upper edge of the band-pass, Hz.
    #[arg(long, default_value_t = PhysicsConfig::default().high_hz)]
    pub high_hz: f64,
    /// Butterworth order of the band-pass.
    #[arg(long, default_value_t = PhysicsConfig::default().order)]
    pub order: usize,
    /// Integrator.
    #[arg(long, value_enum, default_value = "time")]
    pub integrator: IntegratorArg,
    /// Drift removal after each integration (time-domain integrator only).
    #[arg(long, value_enum, default_value = "linear")]
    pub drift: DriftArg,
    /// Print one JSON document (summary) on stdout instead of a line of text.
    #[arg(long)]
    pub json: bool,
}

/// Runs `hxai displacement`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    let n = hxai_data::format_number;
    anyhow::ensure!(
        args.low_hz < args.high_hz,
        "--low-hz {} must be below --high-hz {}: the pass band runs from the low edge to the high one",
        n(args.low_hz),
        n(args.high_hz)
    );
    anyhow::ensure!(
        args.input.frequency_hz.is_finite()
            && args.input.frequency_hz >= args.low_hz
            && args.input.frequency_hz <= args.high_hz,
        "--frequency-hz {} lies outside the pass band {}..{} Hz; give the commanded frequency or widen the band with --low-hz/--high-hz",
        n(args.input.frequency_hz),
        n(args.low_hz),
        n(args.high_hz)
    );
    crate::safety::check_output(
        &args.out,
        &[crate::safety::input(
            &args.input.record,
            "the record (--record)",
        )],
    )?;
    crate::safety::check_table_path(&args.out)?;
    let rec = hxai_data::read_record(&args.input.record)
        .with_context(|| format!("reading record {}", args.input.record.display()))?;
    let warnings = args.input.warn(&rec);
    let fs = rec.fs_hz();
    let cfg = PhysicsConfig {
        low_hz: args.low_hz,
        high_hz: args.high_hz,
        order: args.order,
        integrator: match args.integrator {
            IntegratorArg::Time => Integrator::Time,
            IntegratorArg::Frequency => Integrator::Frequency,
        },
        drift: match args.drift {
            DriftArg::Linear => Drift::Linear,
            DriftArg::Highpass => Drift::Highpass {
                order: 2,
                cutoff_hz: args.low_hz / 2.0,
            },
            DriftArg::None => Drift::None,
        },
        ..PhysicsConfig::default()
    };
    let d_um = hxai_signal::displacement(&rec.accel_ms2, fs, &cfg)
        .with_context(|| format!("physics model on {}", args.input.record.display()))?;
    let fit = hxai_signal::fit_sine(&d_um, fs, args.input.frequency_hz)
        .context("fitting the commanded sine to the displacement")?;
    let table = hxai_data::Table::new(
        vec!["time_s".into(), "displacement_um".into()],
        vec![rec.time_s.clone(), d_um],
    )
    .context("the displacement is not a finite table")?;
    let cannot = || format!("writing {}", args.out.display());
    let staged = hxai_data::stage_table(&args.out, &table).with_context(cannot)?;
    let summary = serde_json::json!({
        "record": args.input.record.display().to_string(),
        "out": args.out.display().to_string(),
        "samples": rec.len(),
        "fs_hz": fs,
        "frequency_hz": args.input.frequency_hz,
        "amplitude_um": fit.amplitude,
        "phase_rad": fit.phase,
        "offset_um": fit.offset,
        "config": cfg,
        "warnings": warnings,
    });
    if args.json {
        // the document first: a full stdout then leaves an existing output as it was
        crate::safety::print_document(&summary.to_string())?;
        staged.commit().with_context(cannot)?;
    } else {
        staged.commit().with_context(cannot)?;
        crate::safety::emit(&format!(
            "wrote {} ({} samples at {:.1} Hz); physics amplitude at {} Hz: {:.4} um",
            args.out.display(),
            rec.len(),
            fs,
            args.input.frequency_hz,
            fit.amplitude
        ))?;
    }
    Ok(())
}
