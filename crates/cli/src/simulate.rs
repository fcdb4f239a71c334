//! `hxai simulate`: write a simulated data folder (manifest + one record file per record),
//! or, with `--case`, one table of a simulated manufacturing process (docs/cases.md).
use crate::Global;
use anyhow::{Context, Result, bail};
use hxai_data::{Format, ManifestEntry, Record, write_folder};
use hxai_sim::{SimConfig, SimRecord, simulate_with_progress};
use indicatif::ProgressStyle;
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

/// A process table generator of `hxai_sim::cases` (docs/cases.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CaseArg {
    /// Finish-turning surface roughness: kinematic law f^2/(32 r) plus ploughing, wear,
    /// built-up edge, vibration and scatter.
    #[value(name = "roughness")]
    Roughness,
    /// Main cutting force: Kienzle's law plus rake-angle, speed and wear factors and scatter.
    #[value(name = "cutting_force")]
    CuttingForce,
    /// Tool life in turning: Taylor's law (C/vc)^(1/n) times the feed's power law of the
    /// extended Taylor law, and scatter.
    #[value(name = "tool_life")]
    ToolLife,
    /// A spindle's thermal drift (a dynamic process, one row per sample of 12 runs): the heat
    /// balance C T' = q n^1.5 - h (T - Ta) plus forced convection that grows with the speed.
    #[value(name = "spindle_thermal")]
    SpindleThermal,
}

impl CaseArg {
    fn name(self) -> &'static str {
        match self {
            CaseArg::Roughness => "roughness",
            CaseArg::CuttingForce => "cutting_force",
            CaseArg::ToolLife => "tool_life",
            CaseArg::SpindleThermal => "spindle_thermal",
        }
    }
}

/// Arguments of `hxai simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Folder to write (created if needed): manifest.csv and one file per record. With
    /// `--case`: the table file to write (.csv or .parquet).
    #[arg(long)]
    pub out: PathBuf,
    /// Write one table of a simulated manufacturing process instead of a data folder.
    #[arg(long, value_enum, conflicts_with_all = ["format", "repeats", "duration_s", "fs_hz", "amplitudes", "frequencies", "config"])]
    pub case: Option<CaseArg>,
    /// Rows of the `--case` table [default: 400; spindle_thermal: 12 runs of 240 samples,
    /// and with --rows N exactly N rows, the last run cut short].
    #[arg(long, requires = "case")]
    pub rows: Option<usize>,
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
    #[arg(long, alias = "fs")]
    pub fs_hz: Option<f64>,
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
    /// manifest are replaced; other files stay); with `--case`, replace the table file.
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

/// `hxai simulate --case NAME --out TABLE`.
fn run_case(case: CaseArg, args: &Args) -> Result<()> {
    hxai_data::Format::from_path(&args.out)
        .with_context(|| format!("--out {}: give a .csv or .parquet file", args.out.display()))?;
    if args.out.is_dir() {
        bail!(
            "--out {} is a folder; with --case give a table file (.csv or .parquet)",
            args.out.display()
        );
    }
    if args.out.exists() && !args.force {
        bail!("{} exists; pass --force to replace it", args.out.display());
    }
    let table = hxai_sim::cases::generate_case(case.name(), args.rows, args.seed)
        .with_context(|| format!("cannot generate the {} table", case.name()))?;
    let seed = args.seed.unwrap_or(hxai_sim::cases::DEFAULT_SEED);
    let (rows, cols) = (table.n_rows(), table.n_cols());
    let names = table.names().to_vec();
    if let Some(parent) = args.out.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create the folder {}", parent.display()))?;
    }
    let cannot = || format!("cannot write {}", args.out.display());
    let staged = hxai_data::stage_table(&args.out, &table).with_context(cannot)?;
    let doc = serde_json::json!({
        "out": args.out.display().to_string(),
        "case": case.name(),
        "rows": rows,
        "columns": names,
        "seed": seed,
    });
    let line = format!(
        "wrote the {} table ({rows} rows x {cols} columns, seed {}) to {}",
        case.name(),
        seed,
        args.out.display()
    );
    if args.json {
        // the document first: a full stdout then leaves an existing table as it was
        let text = serde_json::to_string_pretty(&doc).context("cannot format JSON")?;
        crate::safety::print_document(&text)?;
        return staged.commit().with_context(cannot);
    }
    staged.commit().with_context(cannot)?;
    print_summary(false, &doc, &line)
}

/// Prints what was written: `doc` as pretty JSON with `--json`, else the one `line`.
#[allow(clippy::print_stdout)]
fn print_summary(json: bool, doc: &serde_json::Value, line: &str) -> Result<()> {
    if json {
        println!(
            "{}",
            serde_json::to_string_pretty(doc).context("cannot format JSON")?
        );
    } else {
        println!("{line}");
    }
    Ok(())
}

/// Runs `hxai simulate`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    if let Some(case) = args.case {
        return run_case(case, &args);
    }
    crate::safety::check_empty_folder(&args.out, args.force)?;
    let mut cfg = match &args.config {
        Some(path) => {
            let text = hxai_data::read_text(path)
                .with_context(|| format!("cannot read --config {}", path.display()))?;
            serde_json::from_str::<SimConfig>(&text).map_err(|e| {
                anyhow::anyhow!(
                    "--config {} is not a valid simulator configuration: {}",
                    path.display(),
                    hxai_table::plain_json_error(&e.to_string())
                )
            })?
        }
        None => SimConfig::default(),
    };
    // Each flag given replaces the configuration's value.
    cfg.seed = args.seed.unwrap_or(cfg.seed);
    cfg.repeats = args.repeats.unwrap_or(cfg.repeats);
    cfg.duration_s = args.duration_s.unwrap_or(cfg.duration_s);
    cfg.fs_hz = args.fs_hz.unwrap_or(cfg.fs_hz);
    cfg.amplitudes_um = args.amplitudes.unwrap_or(cfg.amplitudes_um);
    cfg.frequencies_hz = args.frequencies.unwrap_or(cfg.frequencies_hz);
    cfg.check().context("invalid simulation settings")?;

    let n = cfg.n_records();
    let bar = crate::progress::bar(n as u64);
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

    let doc = serde_json::json!({
        "out": args.out.display().to_string(),
        "records": n,
        "samples_per_record": samples,
        "fs_hz": cfg.fs_hz,
        "seed": cfg.seed,
        "format": format.extension(),
    });
    let line = format!(
        "wrote {n} records ({samples} samples each at {} Hz, seed {}) to {}",
        cfg.fs_hz,
        cfg.seed,
        args.out.display()
    );
    print_summary(args.json, &doc, &line)
}
