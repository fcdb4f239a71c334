//! `hxai simulate`: write a simulated data folder (manifest + one record file per record).
use crate::Global;
use anyhow::{Context, Result};
use hxai_data::{Format, ManifestEntry, Record, write_folder};
use hxai_sim::{SimConfig, SimRecord, simulate_with_progress};
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Record file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FormatArg {
    /// Comma-separated text (about 2 MB per default record).
    Csv,
    /// Apache Parquet (compact, fast).
    Parquet,
}

/// Arguments of `hxai simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Folder to write (created if needed): manifest.csv and one file per record.
    #[arg(long)]
    pub out: PathBuf,
    /// Seed of every random choice (noise, mains phase); same seed, same data.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Record file format (Parquet by default: the default data set is about 340 MB as CSV).
    #[arg(long, value_enum, default_value_t = FormatArg::Parquet)]
    pub format: FormatArg,
    /// Repeats of each (amplitude, frequency) condition [default: 3].
    #[arg(long)]
    pub repeats: Option<usize>,
    /// Record length in seconds [default: 2].
    #[arg(long)]
    pub duration_s: Option<f64>,
    /// Sampling rate in Hz [default: 10000].
    #[arg(long)]
    pub fs: Option<f64>,
    /// Commanded amplitudes in um, comma-separated [default: 4,5,...,11].
    #[arg(long, value_delimiter = ',', num_args = 1..)]
    pub amplitudes: Option<Vec<f64>>,
    /// Commanded frequencies in Hz, comma-separated [default: 10,15,...,40].
    #[arg(long, value_delimiter = ',', num_args = 1..)]
    pub frequencies: Option<Vec<f64>>,
    /// JSON file with simulator parameters (any subset of hxai_sim::SimConfig's fields;
    /// see docs/simulator.md). Command-line options override it.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Print a JSON summary on stdout instead of the one-line message.
    #[arg(long)]
    pub json: bool,
    /// Write into --out even if it already holds files (same-named records and the
    /// manifest are replaced; other files stay).
    #[arg(long)]
    pub force: bool,
}

fn to_entry_and_record(r: SimRecord) -> (ManifestEntry, Record) {
    let entry = ManifestEntry {
        record: r.id,
        file: String::new(),
        amplitude_um: r.amplitude_um,
        frequency_hz: r.frequency_hz,
        repeat: u32::try_from(r.repeat).ok(),
        extra: BTreeMap::new(),
    };
    let rec = Record {
        time_s: r.time_s,
        accel_ms2: r.accel_ms2,
        probe_um: Some(r.probe_um),
        command_um: Some(r.command_um),
        encoder_um: Some(r.encoder_um),
    };
    (entry, rec)
}

/// Runs `hxai simulate`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    crate::safety::check_empty_folder(&args.out, args.force)?;
    let mut cfg = match &args.config {
        Some(path) => {
            let text = hxai_data::read_text(path)
                .with_context(|| format!("cannot read --config {}", path.display()))?;
            serde_json::from_str::<SimConfig>(&text).with_context(|| {
                format!(
                    "--config {} is not a valid simulator configuration",
                    path.display()
                )
            })?
        }
        None => SimConfig::default(),
    };
    if let Some(s) = args.seed {
        cfg.seed = s;
    }
    if let Some(r) = args.repeats {
        cfg.repeats = r;
    }
    if let Some(d) = args.duration_s {
        cfg.duration_s = d;
    }
    if let Some(fs) = args.fs {
        cfg.fs_hz = fs;
    }
    if let Some(a) = args.amplitudes {
        cfg.amplitudes_um = a;
    }
    if let Some(f) = args.frequencies {
        cfg.frequencies_hz = f;
    }
    cfg.validate().context("invalid simulation settings")?;

    let n = cfg.n_records();
    let bar = ProgressBar::new(n as u64);
    bar.set_style(
        ProgressStyle::with_template("{msg:>10} [{bar:40}] {pos}/{len} records ({elapsed})")
            .context("progress bar template")?
            .progress_chars("=> "),
    );
    bar.set_message("simulating");
    let records = simulate_with_progress(&cfg, &|| bar.inc(1)).context("simulation failed")?;
    bar.set_message("writing");
    let samples = records.first().map_or(0, |r| r.time_s.len());
    let items: Vec<(ManifestEntry, Record)> =
        records.into_iter().map(to_entry_and_record).collect();
    let format = match args.format {
        FormatArg::Csv => Format::Csv,
        FormatArg::Parquet => Format::Parquet,
    };
    write_folder(&args.out, &items, format)
        .with_context(|| format!("cannot write the data folder {}", args.out.display()))?;
    bar.finish_and_clear();

    #[allow(clippy::print_stdout)]
    if args.json {
        let doc = serde_json::json!({
            "out": args.out.display().to_string(),
            "records": n,
            "samples_per_record": samples,
            "fs_hz": cfg.fs_hz,
            "seed": cfg.seed,
            "format": format.extension(),
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&doc).context("cannot format JSON")?
        );
    } else {
        println!(
            "wrote {n} records ({samples} samples each at {} Hz, seed {}) to {}",
            cfg.fs_hz,
            cfg.seed,
            args.out.display()
        );
    }
    Ok(())
}
