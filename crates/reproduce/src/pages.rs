//! The report pages of the results (issue 50): `report_tool.html` for the paper's tool
//! model and `report_<case>.html` for each table case, the pages `hxai report` writes for
//! the same model, data and comparison, so the results folder shows what a user's report
//! looks like on every case the reproduction runs.

use crate::ReproduceError;
use crate::pipeline::{Computed, input};
use hxai_hybrid::records::RecordInput;
use hxai_hybrid::tables::Comparison;
use hxai_table::Table;

/// The hxai version written on each page (the workspace's, as the command line's).
const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The name the pages give the paper's simulated data folder (`hxai simulate`'s
/// default settings at the run's seed make the same records).
const TOOL_DATA: &str = "paper_data";

fn pipeline_error(what: &str, e: impl std::fmt::Display) -> ReproduceError {
    ReproduceError::Pipeline(format!("{what}: {e}"))
}

/// File name of a table case's page.
pub fn table_file(case: &str) -> String {
    format!("report_{case}.html")
}

/// File name of the tool model's page.
pub const TOOL_FILE: &str = "report_tool.html";

/// The page of the paper's tool model on every simulated record, with Table 3 as its
/// comparison and the selection's stability over the run's resamples.
///
/// # Errors
/// The model cannot be applied to the records (it was fitted on them, so this is a bug).
pub fn tool(c: &Computed) -> Result<(String, String), ReproduceError> {
    let inputs: Vec<RecordInput<'_>> = c.records.iter().map(input).collect();
    let mut model = c.fit.model.clone();
    model.correction.selection = Some(c.results.symbolic.selection.clone());
    let compare = serde_json::json!({
        "models": c.results.table3.iter().map(|m| serde_json::json!({
            "name": m.name,
            "rmse": m.test.rmse,
            "r2": m.test.r2,
            "mae": m.test.mae,
        })).collect::<Vec<_>>(),
        "target": "delta",
    });
    let data = hxai_plot::report::ToolData {
        name: TOOL_DATA,
        records: &inputs,
        warnings: Vec::new(),
    };
    let page_inputs = hxai_plot::report::tool_inputs(&model, Some(&data), Some(&compare), VERSION)
        .map_err(|e| pipeline_error("the tool model's page", e))?;
    Ok((
        TOOL_FILE.to_string(),
        hxai_plot::report::tool_report(&model, &page_inputs),
    ))
}

/// The page of a table case's hybrid (the random split's, `c.hybrid`) on its whole
/// simulated `table`, with the comparison `c` beside it. `data` names the table on the page.
///
/// # Errors
/// The comparison cannot be written as JSON, or the pictures cannot be drawn.
pub fn table(
    case: &str,
    data: &str,
    c: &Comparison,
    table: &Table,
) -> Result<(String, String), ReproduceError> {
    let compare = serde_json::to_value(c)?;
    let pictures = hxai_plot::report::correction_pictures(&c.hybrid, table)
        .map_err(|e| pipeline_error(&format!("the {case} page's figures"), e))?;
    let html = hxai_plot::report::table_report(
        &c.hybrid,
        &hxai_plot::report::ReportInputs {
            pictures: Some(&pictures),
            data: Some((data, table.n_rows())),
            compare: Some(&compare),
            version: VERSION,
        },
    );
    Ok((table_file(case), html))
}

/// The results page's section naming the report pages (`names`: the table cases, in
/// order).
pub fn markdown(names: &[&str]) -> String {
    let mut s = String::from(
        "\n## Report pages (`hxai report`)\n\nThe page `hxai report` writes for each model of \
         this run, one self-contained HTML file each (open it in a browser; every number is \
         a `<data>` element whose `value` holds it in full):\n\n",
    );
    s.push_str(&format!(
        "- [{TOOL_FILE}]({TOOL_FILE}): the paper's tool model on every simulated record, \
         with Table 3 as its comparison;\n"
    ));
    for n in names {
        let f = table_file(n);
        s.push_str(&format!(
            "- [{f}]({f}): the {n} case's hybrid of the random split on its {n}.csv (`hxai \
             simulate --case {n}` at the run's rows and seed), with its comparison;\n"
        ));
    }
    s
}
