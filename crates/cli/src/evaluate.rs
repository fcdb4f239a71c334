//! `hxai evaluate`: physics vs hybrid on the records of a data folder.
use crate::Global;
use anyhow::{Context, Result};
use std::path::PathBuf;

/// Arguments of `hxai evaluate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Model written by `hxai fit`.
    #[arg(long)]
    pub model: PathBuf,
    /// Data folder (records need `probe_um`).
    #[arg(long)]
    pub data: PathBuf,
    /// Evaluate every record of the folder, not only the model's test records.
    #[arg(long)]
    pub all: bool,
    /// Nominal level of the prediction intervals of the corrected amplitude whose
    /// coverage is reported (JSON `interval`).
    #[arg(long, default_value_t = hxai_hybrid::DEFAULT_INTERVAL)]
    pub interval: f64,
    /// How the intervals are made: `conformal` (CV+, the default where the model file
    /// stores its calibration), `split` (split conformal) or `delta` (the delta method,
    /// the default for older files).
    #[arg(long, value_enum)]
    pub interval_method: Option<crate::strategy::IntervalMethodArg>,
    /// Print one JSON document on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Runs `hxai evaluate`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    crate::safety::check_level(args.interval, "--interval")?;
    let model = crate::predict::load_model(&args.model)?;
    let folder = hxai_data::read_folder(&args.data)
        .with_context(|| format!("cannot read the data folder {}", args.data.display()))?;
    // Only the records that will be evaluated are read.
    let wanted: Vec<&hxai_data::ManifestEntry> = folder
        .entries
        .iter()
        .filter(|e| args.all || model.split.test.contains(&e.record))
        .collect();
    anyhow::ensure!(
        !wanted.is_empty(),
        "none of the {} records of {} is a test record of this model (test records: {}); \
         use --all to evaluate every record",
        folder.entries.len(),
        args.data.display(),
        model.split.test.join(", ")
    );
    let pb = crate::progress::bar(wanted.len() as u64);
    let recs = crate::records::read_with_truth(&folder, &wanted, "evaluating", &pb)?;
    let inputs = crate::records::inputs(&wanted, &recs);
    let method = crate::strategy::interval_method(
        args.interval_method,
        model.default_interval_method(args.interval),
    );
    let mut ev = model
        .evaluate_with(&inputs, args.all, args.interval, method)
        .context("evaluation failed")?;
    ev.warnings
        .extend(crate::records::amplitude_warnings(&wanted, &inputs));
    crate::safety::warn(&ev.warnings);
    if args.json {
        let mut doc = serde_json::to_value(&ev).context("cannot format JSON")?;
        if let Some(obj) = doc.as_object_mut() {
            obj.insert("warnings".into(), serde_json::json!(ev.warnings));
        }
        let text = serde_json::to_string_pretty(&doc).context("cannot format JSON")?;
        crate::safety::emit(&text)?;
        return Ok(());
    }
    #[allow(clippy::print_stdout)]
    {
        println!(
            "{} records, {} windows, {} samples ({})",
            ev.n_records,
            ev.n_windows,
            ev.n_samples,
            if args.all { "all records" } else { "test set" }
        );
        println!(
            "{:<16} {:>10} {:>8} {:>10}",
            "model", "RMSE um", "R^2", "MAE um"
        );
        for (name, s) in [
            ("physics", ev.physics),
            ("physics sine", ev.physics_sine),
            ("hybrid", ev.hybrid),
        ] {
            println!("{name:<16} {:>10.4} {:>8.4} {:>10.4}", s.rmse, s.r2, s.mae);
        }
        println!(
            "improvement {:.2} % (vs physics sine {:.2} %)",
            ev.improvement_pct, ev.improvement_vs_sine_pct
        );
        if let Some(iv) = ev.interval {
            println!(
                "prediction intervals of the amplitude at {:.1} %: coverage {:.1} % of {} windows",
                100.0 * iv.nominal,
                100.0 * iv.coverage,
                iv.n
            );
        }
        match ev.t_test {
            Some(t) => println!(
                "paired t-test on per-window MSE: t = {:.3}, df = {}, p = {:.3e}",
                t.statistic, t.df, t.p_value
            ),
            None => println!("paired t-test: not enough windows"),
        }
    }
    Ok(())
}
