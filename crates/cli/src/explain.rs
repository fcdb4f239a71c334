//! `hxai explain`: pictures (SVG) of a fitted model's correction.
use crate::Global;
use anyhow::{Context, Result};
use hxai_hybrid::explain::ExplainData;
use std::path::{Path, PathBuf};

/// Arguments of `hxai explain`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Model written by `hxai fit` or `hxai hybrid fit`.
    #[arg(long)]
    pub model: PathBuf,
    /// Folder the pictures are written into (created if missing): response.svg,
    /// predicted_vs_true.svg, pareto.svg.
    #[arg(long)]
    pub out: PathBuf,
    /// The rows the model was fitted on: for a model of `hxai fit`, the table `hxai fit
    /// --samples` wrote (CSV or Parquet; the model's feature columns, `delta`, and `split` =
    /// train/test if present); for one of `hxai hybrid fit`, the table it was fitted on.
    /// Without it only the Pareto front is drawn.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Level of the prediction intervals drawn.
    #[arg(long, default_value_t = hxai_hybrid::DEFAULT_INTERVAL)]
    pub interval: f64,
    /// Method of the prediction intervals drawn (default: the model file's, conformal where
    /// it stores the calibration, as `predict` and `evaluate` use).
    #[arg(long, value_enum)]
    pub interval_method: Option<crate::strategy::IntervalMethodArg>,
}

/// A model file of either kind.
pub(crate) enum Model {
    /// `hxai fit`.
    Tool(Box<hxai_hybrid::records::RecordModel>),
    /// `hxai hybrid fit`.
    Process(Box<hxai_hybrid::tables::TableModel>),
}

/// Reads a model file of `hxai fit` or `hxai hybrid fit` (told apart by the process model's
/// `target` and `hybrid` keys and the tool model's `features` and `window`); a JSON
/// document with neither pair is refused as no model, naming both.
pub(crate) fn load(path: &Path) -> Result<Model> {
    let text = hxai_data::read_text(path)
        .with_context(|| format!("cannot read the model {}", path.display()))?;
    let value = serde_json::from_str::<serde_json::Value>(&text).ok();
    let has = |a: &str, b: &str| {
        value
            .as_ref()
            .is_some_and(|v| v.get(a).is_some() && v.get(b).is_some())
    };
    let is_process = has("target", "hybrid");
    anyhow::ensure!(
        !has("ode", "corrections"),
        "{}: a dynamic model (`hxai dynamic fit`) has no pictures of its own here; its page \
         is `hxai report --model {} --data TABLE --out PAGE.html`",
        path.display(),
        path.display()
    );
    anyhow::ensure!(
        value.is_none() || is_process || has("features", "window"),
        "cannot load the model {}: it is JSON but no model file, neither of `hxai hybrid \
         fit` (keys `target`, `hybrid`) nor of `hxai fit` (keys `features`, `window`); give \
         the file their --out wrote",
        path.display()
    );
    let loaded = if is_process {
        hxai_hybrid::tables::TableModel::from_json(&text).map(|m| Model::Process(Box::new(m)))
    } else {
        hxai_hybrid::records::RecordModel::from_json(&text).map(|m| Model::Tool(Box::new(m)))
    };
    loaded.with_context(|| format!("cannot load the model {}", path.display()))
}

/// The numeric columns of a samples table and its split flags (`split` = `test`).
fn read_samples(path: &Path) -> Result<(hxai_table::Table, Vec<f64>, Vec<bool>)> {
    let view = hxai_data::read_mixed_table(path)
        .with_context(|| format!("cannot read the samples {}", path.display()))?
        .numeric_view(None)
        .with_context(|| format!("{}: no usable numeric columns", path.display()))?;
    let split = view
        .text
        .iter()
        .find(|(n, _)| n == "split")
        .map(|(_, cells)| cells.as_slice());
    hxai_hybrid::records::SamplesTable::read_back(view.table, split)
        .with_context(|| path.display().to_string())
}

/// Runs `hxai explain`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    if args.out.exists() && !args.out.is_dir() {
        anyhow::bail!(
            "{}: --out must be a folder (the pictures are written into it), and this is a file",
            args.out.display()
        );
    }
    crate::safety::check_level(args.interval, "--interval")?;
    let mut inputs = vec![crate::safety::input(&args.model, "the model (--model)")];
    if let Some(path) = &args.data {
        inputs.push(crate::safety::input(path, "the data (--data)"));
    }
    let method = args.interval_method.map(hxai_hybrid::IntervalMethod::from);
    let (explanation, label, selection) = match load(&args.model)? {
        Model::Tool(model) => {
            let samples = args.data.as_deref().map(read_samples).transpose()?;
            let data = samples.as_ref().map(|(t, d, s)| ExplainData {
                features: t,
                target: d,
                is_test: s,
            });
            let e = model.explain(data.as_ref(), args.interval, method);
            let sel = model.correction.selection.clone();
            (e, hxai_plot::explain::DELTA_AXIS.to_owned(), sel)
        }
        Model::Process(model) => {
            let table = match &args.data {
                Some(path) => {
                    let mut view = crate::hybrid::read_for(path, &model, true)?;
                    crate::hybrid::add_levels(&model, &mut view)?;
                    Some(view.table)
                }
                None => None,
            };
            let e = model.explain(table.as_ref(), args.interval, method);
            let label = format!(
                "δ ({} correction of {})",
                model.correction.kind.name(),
                model.target
            );
            (e, label, model.correction.selection.clone())
        }
    };
    let explanation = explanation.with_context(|| match &args.data {
        Some(d) => format!(
            "cannot explain the model {} with --data {}",
            args.model.display(),
            d.display()
        ),
        None => format!("cannot explain the model {}", args.model.display()),
    })?;
    let pictures = hxai_plot::explain::pictures(&explanation, &label, "")
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
    let mut lines = vec![format!("correction: delta = {}", explanation.equation)];
    // its share over resamples and the alternatives the data cannot tell apart (issue 23)
    if let Some(sel) = &selection {
        lines.extend(crate::sr::selection_lines(sel));
    }
    if let Some(m) = explanation.method {
        lines.push(format!(
            "prediction intervals: {} %, {}",
            explanation.level * 100.0,
            m.name()
        ));
    }
    lines.extend(paths.iter().map(|p| format!("wrote {}", p.display())));
    lines.extend(
        pictures
            .skipped
            .iter()
            .map(|(f, why)| format!("not drawn: {f} {why}")),
    );
    crate::safety::emit(&lines.join("\n"))
}
