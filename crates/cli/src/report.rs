//! `hxai report`: one self-contained HTML page of a model of either workflow (issue 50): a
//! table hybrid of `hxai hybrid fit` on its table, or the recordings' tool model of `hxai
//! fit` on its data folder; the model, how good, how sure, where it holds, how to reproduce
//! (`hxai_plot::report`).
use crate::Global;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};

/// Arguments of `hxai report`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Model written by `hxai hybrid fit` (a table hybrid) or `hxai fit` (the tool model);
    /// the kind is read from the file.
    #[arg(long)]
    pub model: PathBuf,
    /// The data to draw the figures and scores on: for a table hybrid the table it was
    /// fitted on (with the target), for the tool model its data folder (records with
    /// `probe_um`). Without it the page has no response or parity figure.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// The HTML file to write.
    #[arg(long)]
    pub out: PathBuf,
    /// The JSON of `hxai hybrid compare --json` (or, for the tool model, `hxai compare
    /// --json`) on the same data, shown as a table.
    #[arg(long)]
    pub compare: Option<PathBuf>,
}

/// Reads the comparison JSON: a document with a `models` list.
fn read_compare(p: &Path) -> Result<serde_json::Value> {
    let text = hxai_data::read_text(p)
        .with_context(|| format!("cannot read the comparison {}", p.display()))?;
    let v: serde_json::Value = serde_json::from_str(&text).with_context(|| {
        format!(
            "{}: not JSON; give the output of `hxai hybrid compare --json`",
            p.display()
        )
    })?;
    anyhow::ensure!(
        v.get("models").is_some_and(serde_json::Value::is_array),
        "{}: no `models` list; give the output of `hxai hybrid compare --json`",
        p.display()
    );
    Ok(v)
}

/// Runs `hxai report`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    let mut inputs = vec![crate::safety::input(&args.model, "the model (--model)")];
    if let Some(p) = &args.data {
        inputs.push(crate::safety::input(p, "the data (--data)"));
    }
    if let Some(p) = &args.compare {
        inputs.push(crate::safety::input(p, "the comparison (--compare)"));
    }
    crate::safety::check_output(&args.out, &inputs)?;
    let compare = args.compare.as_deref().map(read_compare).transpose()?;
    if let Some(model) = dynamic_model(&args.model)? {
        anyhow::ensure!(
            compare.is_none(),
            "--compare takes `hxai hybrid compare --json`; a dynamic model's comparison is              `hxai dynamic compare`, which the page does not show yet"
        );
        let view = args
            .data
            .as_deref()
            .map(|p| crate::hybrid::read(p, model.run.as_deref()))
            .transpose()?;
        let name = args.data.as_ref().map(|p| p.display().to_string());
        let html = hxai_plot::report::dynamic_report(
            &model,
            name.as_deref().zip(view.as_ref().map(|v| &v.table)),
            env!("CARGO_PKG_VERSION"),
        );
        hxai_data::write_text(&args.out, &html)
            .with_context(|| format!("cannot write {}", args.out.display()))?;
        return crate::safety::emit(&format!("wrote {}", args.out.display()));
    }
    let (html, notes) = match crate::explain::load(&args.model)? {
        crate::explain::Model::Process(model) => table_page(&args, &model, compare.as_ref())?,
        crate::explain::Model::Tool(model) => {
            (tool_page(&args, &model, compare.as_ref())?, Vec::new())
        }
    };
    hxai_data::write_text(&args.out, &html)
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    crate::safety::warn(&notes);
    crate::safety::emit(&format!("wrote {}", args.out.display()))
}

/// The page of a table hybrid, with notes for the terminal (figures that could not be
/// drawn).
/// The model file at `path` when it is a dynamic model's (`hxai dynamic fit`: keys `ode`
/// and `corrections`).
fn dynamic_model(path: &Path) -> Result<Option<hxai_hybrid::dynamic::DynamicModel>> {
    let text = hxai_data::read_text(path)
        .with_context(|| format!("cannot read the model {}", path.display()))?;
    let is_dynamic = serde_json::from_str::<serde_json::Value>(&text)
        .ok()
        .is_some_and(|v| v.get("ode").is_some() && v.get("corrections").is_some());
    if !is_dynamic {
        return Ok(None);
    }
    hxai_hybrid::dynamic::DynamicModel::from_json(&text)
        .map(Some)
        .with_context(|| format!("cannot load the model {}", path.display()))
}

fn table_page(
    args: &Args,
    model: &hxai_hybrid::tables::TableModel,
    compare: Option<&serde_json::Value>,
) -> Result<(String, Vec<String>)> {
    let mut notes = Vec::new();
    let (pictures, rows) = match &args.data {
        Some(path) => {
            let mut view = crate::hybrid::read_for(path, model, true)?;
            crate::hybrid::add_levels(model, &mut view)?;
            let rows = view.table.n_rows();
            match hxai_plot::report::correction_pictures(model, &view.table) {
                Ok(p) => (Some(p), Some(rows)),
                Err(e) => {
                    notes.push(format!("no figures: {e}"));
                    (None, Some(rows))
                }
            }
        }
        None => (None, None),
    };
    let data_name = args.data.as_ref().map(|p| p.display().to_string());
    let html = hxai_plot::report::table_report(
        model,
        &hxai_plot::report::ReportInputs {
            pictures: pictures.as_ref(),
            data: data_name.as_deref().zip(rows),
            compare,
            version: env!("CARGO_PKG_VERSION"),
        },
    );
    Ok((html, notes))
}

/// The page of the tool model, drawn on every record of the data folder `--data` (each
/// with its truth).
fn tool_page(
    args: &Args,
    model: &hxai_hybrid::records::RecordModel,
    compare: Option<&serde_json::Value>,
) -> Result<String> {
    let version = env!("CARGO_PKG_VERSION");
    let Some(dir) = &args.data else {
        let inputs = hxai_plot::report::tool_inputs(model, None, compare, version)?;
        return Ok(hxai_plot::report::tool_report(model, &inputs));
    };
    anyhow::ensure!(
        dir.is_dir(),
        "{}: --data of a tool model (`hxai fit`) is its data folder (manifest.csv and the \
         records), and this is not a folder",
        dir.display()
    );
    let folder = hxai_data::read_folder(dir)
        .with_context(|| format!("cannot read the data folder {}", dir.display()))?;
    let entries: Vec<&hxai_data::ManifestEntry> = folder.entries.iter().collect();
    let pb = crate::progress::bar(entries.len() as u64);
    let recs = crate::records::read_with_truth(&folder, &entries, "the report", &pb)?;
    let records = crate::records::inputs(&entries, &recs);
    let name = dir.display().to_string();
    let data = hxai_plot::report::ToolData {
        name: &name,
        records: &records,
        warnings: crate::records::amplitude_warnings(&entries, &records),
    };
    let inputs = hxai_plot::report::tool_inputs(model, Some(&data), compare, version)
        .with_context(|| {
            format!(
                "cannot apply the model {} to the data folder {}",
                args.model.display(),
                dir.display()
            )
        })?;
    Ok(hxai_plot::report::tool_report(model, &inputs))
}
