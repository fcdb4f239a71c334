//! `hxai predict`: apply a fitted hybrid model to one record.
use crate::Global;
use crate::one_record::RecordArgs;
use anyhow::{Context, Result};
use hxai_hybrid::records::{RecordInput, RecordModel};
use std::path::PathBuf;

/// Arguments of `hxai predict`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Model written by `hxai fit`.
    #[arg(long)]
    pub model: PathBuf,
    /// The record and its commanded frequency.
    #[command(flatten)]
    pub input: RecordArgs,
    /// Output table (CSV or Parquet): `time_s,physics_um,hybrid_um` (and
    /// `hybrid_lo_um,hybrid_hi_um` with --interval).
    #[arg(long)]
    pub out: PathBuf,
    /// Add bounds of the displacement from the prediction interval of each window's
    /// corrected amplitude at this level (e.g. 0.95): columns hybrid_lo_um, hybrid_hi_um.
    #[arg(long)]
    pub interval: Option<f64>,
    /// How the intervals are made with --interval: `conformal` (CV+, the default where the
    /// model file stores its calibration), `split` or `delta`.
    #[arg(long, value_enum, requires = "interval")]
    pub interval_method: Option<crate::strategy::IntervalMethodArg>,
    /// Print the per-window corrections as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Reads a model file written by `hxai fit`.
pub fn load_model(path: &std::path::Path) -> Result<RecordModel> {
    let text = hxai_data::read_text(path)
        .with_context(|| format!("cannot read the model {}", path.display()))?;
    RecordModel::from_json(&text)
        .with_context(|| format!("cannot load the model {}", path.display()))
}

/// Runs `hxai predict`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    anyhow::ensure!(
        args.input.frequency_hz.is_finite() && args.input.frequency_hz > 0.0,
        "--frequency-hz must be a positive number of Hz, got {}",
        hxai_data::format_number(args.input.frequency_hz)
    );
    crate::safety::check_output(
        &args.out,
        &[
            crate::safety::input(&args.input.record, "the record (--record)"),
            crate::safety::input(&args.model, "the model (--model)"),
        ],
    )?;
    crate::safety::check_table_path(&args.out)?;
    if let Some(level) = args.interval {
        crate::safety::check_level(level, "--interval")?;
    }
    let model = load_model(&args.model)?;
    let rec = hxai_data::read_record(&args.input.record)
        .with_context(|| format!("cannot read the record {}", args.input.record.display()))?;
    let id = args
        .input
        .record
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("record")
        .to_owned();
    let input = RecordInput {
        id: &id,
        fs_hz: rec.fs_hz(),
        frequency_hz: args.input.frequency_hz,
        signal: &rec.accel_ms2,
        truth: None,
    };
    let (pred, bounds) = match args.interval {
        Some(level) => {
            let method = crate::strategy::interval_method(
                args.interval_method,
                model.default_interval_method(level),
            );
            let (p, lo, hi) = model
                .predict_with_intervals_by(&input, level, method)
                .context("prediction failed")?;
            (p, Some((lo, hi)))
        }
        None => (model.predict(&input).context("prediction failed")?, None),
    };
    let warnings: Vec<String> = pred.warnings.iter().map(ToString::to_string).collect();
    crate::safety::warn(&warnings);
    let mut names: Vec<String> = vec!["time_s".into(), "physics_um".into(), "hybrid_um".into()];
    let mut columns = vec![
        rec.time_s.clone(),
        pred.physics.clone(),
        pred.hybrid.clone(),
    ];
    if let Some((lo, hi)) = bounds {
        names.extend(["hybrid_lo_um".into(), "hybrid_hi_um".into()]);
        columns.extend([lo, hi]);
    }
    let table =
        hxai_data::Table::new(names, columns).context("the prediction is not a finite table")?;
    let cannot = || format!("cannot write {}", args.out.display());
    let staged = hxai_data::stage_table(&args.out, &table).with_context(cannot)?;
    if args.json {
        let doc = serde_json::json!({
            "out": crate::safety::path_text(&args.out),
            "equation": model.correction.forms.equation,
            "windows": pred.window_rows(Some(&rec.time_s), rec.fs_hz(), None),
            "warnings": warnings,
        });
        let text = serde_json::to_string_pretty(&doc).context("cannot format JSON")?;
        // the document first: a full stdout then leaves an existing output as it was
        crate::safety::print_document(&text)?;
        staged.commit().with_context(cannot)?;
    } else {
        staged.commit().with_context(cannot)?;
        crate::safety::emit(&format!(
            "wrote {} ({} samples, {} windows corrected)",
            args.out.display(),
            rec.len(),
            pred.windows.len()
        ))?;
    }
    Ok(())
}
