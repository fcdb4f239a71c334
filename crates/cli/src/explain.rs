//! `hxai explain`: pictures (SVG) of a fitted model's correction.
use crate::Global;
use anyhow::{Context, Result};
use hxai_data::Column;
use hxai_hybrid::explain::ExplainData;
use std::path::{Path, PathBuf};

/// Arguments of `hxai explain`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Model written by `hxai fit`.
    #[arg(long)]
    pub model: PathBuf,
    /// Folder the pictures are written into (created if missing): response.svg,
    /// predicted_vs_true.svg, pareto.svg.
    #[arg(long)]
    pub out: PathBuf,
    /// The samples the model was fitted on: the table `hxai fit --samples` wrote (CSV or
    /// Parquet; the model's feature columns, `delta`, and `split` = train/test if present).
    /// Without it only the Pareto front is drawn.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Level of the prediction intervals drawn.
    #[arg(long, default_value_t = hxai_hybrid::DEFAULT_INTERVAL)]
    pub interval: f64,
}

/// The numeric columns of a samples table and its split flags (`split` = `test`).
fn read_samples(path: &Path) -> Result<(hxai_table::Table, Vec<f64>, Vec<bool>)> {
    let mixed = hxai_data::read_mixed_table(path)
        .with_context(|| format!("cannot read the samples {}", path.display()))?;
    let (table, _) = mixed
        .numeric()
        .with_context(|| format!("{}: no usable numeric columns", path.display()))?;
    let delta = table
        .require("delta")
        .with_context(|| {
            format!(
                "{}: no numeric column `delta`; pass the table `hxai fit --samples` wrote",
                path.display()
            )
        })?
        .to_vec();
    let is_test = match mixed.names.iter().position(|n| n == "split") {
        None => vec![false; delta.len()],
        Some(i) => match &mixed.columns[i] {
            Column::Text(v) => v
                .iter()
                .enumerate()
                .map(|(row, s)| match s.as_str() {
                    "train" => Ok(false),
                    "test" => Ok(true),
                    other => Err(anyhow::anyhow!(
                        "{}: row {}: `split` must be train or test, got `{}`",
                        path.display(),
                        row + 1,
                        other.chars().take(20).collect::<String>()
                    )),
                })
                .collect::<Result<Vec<bool>>>()?,
            Column::Number(_) => anyhow::bail!(
                "{}: `split` must be text (train or test), found numbers",
                path.display()
            ),
        },
    };
    Ok((table, delta, is_test))
}

/// Runs `hxai explain`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    if args.out.exists() && !args.out.is_dir() {
        anyhow::bail!(
            "{}: --out must be a folder (the pictures are written into it), and this is a file",
            args.out.display()
        );
    }
    anyhow::ensure!(
        args.interval > 0.0 && args.interval < 1.0,
        "--interval must lie strictly between 0 and 1, got {}",
        hxai_data::format_number(args.interval)
    );
    let model = crate::predict::load_model(&args.model)?;
    let mut inputs = vec![crate::safety::input(&args.model, "the model (--model)")];
    let samples = match &args.data {
        Some(path) => {
            inputs.push(crate::safety::input(path, "the samples (--data)"));
            Some(read_samples(path)?)
        }
        None => None,
    };
    let data = samples.as_ref().map(|(t, d, s)| ExplainData {
        features: t,
        target: d,
        is_test: s,
    });
    let explanation = model
        .explain(data.as_ref(), args.interval)
        .with_context(|| format!("cannot explain the model {}", args.model.display()))?;
    let pictures = hxai_plot::explain::pictures(&explanation, hxai_plot::explain::DELTA_AXIS, "")
        .context("cannot draw the pictures")?;
    if pictures.files.is_empty() {
        let reasons: Vec<String> = pictures
            .skipped
            .iter()
            .map(|(f, why)| format!("{f} {why}"))
            .collect();
        anyhow::bail!("nothing to draw: {}", reasons.join("; "));
    }
    // Every output is checked before anything is written.
    let paths: Vec<PathBuf> = pictures
        .files
        .iter()
        .map(|(name, _)| args.out.join(name))
        .collect();
    for p in &paths {
        crate::safety::check_output(p, &inputs)?;
    }
    for (p, (_, svg)) in paths.iter().zip(&pictures.files) {
        hxai_data::write_text(p, svg).with_context(|| format!("cannot write {}", p.display()))?;
    }
    let mut lines: Vec<String> = paths
        .iter()
        .map(|p| format!("wrote {}", p.display()))
        .collect();
    lines.extend(
        pictures
            .skipped
            .iter()
            .map(|(f, why)| format!("not drawn: {f} {why}")),
    );
    crate::safety::emit(&lines.join("\n"))
}
