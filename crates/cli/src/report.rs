//! `hxai report`: one self-contained HTML page of a table hybrid (issue 50): the model, how
//! good, how sure, where it holds, how to reproduce (`hxai_plot::report`).
use crate::Global;
use anyhow::{Context, Result};
use std::path::PathBuf;

/// Arguments of `hxai report`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Model written by `hxai hybrid fit`.
    #[arg(long)]
    pub model: PathBuf,
    /// The table to draw the figures on (the table it was fitted on, with the target).
    /// Without it the page has no response or parity figure.
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// The HTML file to write.
    #[arg(long)]
    pub out: PathBuf,
    /// The JSON of `hxai hybrid compare --json` on the same table, shown as a table.
    #[arg(long)]
    pub compare: Option<PathBuf>,
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
    let model = match crate::explain::load(&args.model)? {
        crate::explain::Model::Process(m) => m,
        crate::explain::Model::Tool(_) => anyhow::bail!(
            "{}: a report of the recordings' tool model (`hxai fit`) is not built yet; \
             `hxai report` reads models of `hxai hybrid fit` (use `hxai explain` for its \
             pictures)",
            args.model.display()
        ),
    };
    let compare = match &args.compare {
        Some(p) => {
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
            Some(v)
        }
        None => None,
    };
    let mut notes = Vec::new();
    let (pictures, rows) = match &args.data {
        Some(path) => {
            let mut view = crate::hybrid::read_for(path, &model, true)?;
            crate::hybrid::add_levels(&model, &mut view)?;
            let rows = view.table.n_rows();
            match hxai_plot::report::correction_pictures(&model, &view.table) {
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
        &model,
        &hxai_plot::report::ReportInputs {
            pictures: pictures.as_ref(),
            data: data_name.as_deref().zip(rows),
            compare: compare.as_ref(),
            version: env!("CARGO_PKG_VERSION"),
        },
    );
    hxai_data::write_text(&args.out, &html)
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    crate::safety::warn(&notes);
    crate::safety::emit(&format!("wrote {}", args.out.display()))
}
