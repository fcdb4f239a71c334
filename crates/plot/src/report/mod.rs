//! One self-contained HTML page for a hybrid model (`hxai report`, issue 50), of either
//! workflow: a table hybrid ([`table_report`]), the recordings' tool model
//! ([`tool_report`]) or a dynamic hybrid ([`dynamic_report`]); what a person reads, in the order they ask it.
//!
//! 1. the model: the hybrid as one equation, the physics with its calibrated parameters
//!    (standard errors, 95 % intervals), the correction (factor by factor in the factor
//!    form, level by level with per-level constants);
//! 2. how good: train and test scores of physics and hybrid, the black boxes on the same
//!    split, and the table of `hxai hybrid compare --json` when given;
//! 3. how sure: how the correction was selected, the alternatives the data cannot tell
//!    apart, the stability shares, the response of the correction to each feature;
//! 4. where it holds: the training ranges, the warnings, the data read;
//! 5. how to reproduce: the command that refits the model, and the version.
//!
//! The tool page has the same sections: the hybrid `x_hat(t) = (A_phys + delta) sin(2 pi f
//! t + phi_phys)`, the signal chain's settings in place of calibrated physics, and, drawn on
//! the records of a data folder ([`tool_inputs`]), physics against hybrid on the test
//! records with the paired t-test and the intervals' coverage, and the training ranges of
//! the correction's features.
//!
//! Self-contained: inline CSS, figures as inline `<svg>` (each in a `role="img"` element
//! with an `aria-label`), equations as presentation MathML (which every current browser
//! renders without a script) with the plain text beside them to copy; no `http:` or
//! `https:` resource, no script, no font. A print stylesheet starts each section on a new
//! page; tables scroll sideways on a phone.
//!
//! Both pages are built from the same parts (the page frame, tables, equations, figures,
//! the correction with its constants, the comparison, the selection, the warnings and the
//! reproduction section, in this file); only what a workflow alone has (the table's
//! calibrated physics, the tool's signal chain and per-record evaluation) is written per
//! workflow, in `table` and `tool`.

mod dynamic;
mod table;
mod tool;

pub use dynamic::{DRAWN_RUNS, dynamic_card, dynamic_refit_command, dynamic_report};
pub use table::{correction_pictures, refit_command, table_card, table_report};
pub use tool::{
    ToolData, ToolInputs, tool_card, tool_inputs, tool_pictures, tool_refit_command, tool_report,
};

use crate::explain::Pictures;
use hxai_hybrid::CorrectionInfo;
use hxai_symreg::expr::xml_escape as esc;
use std::fmt::Write as _;

/// What the table hybrid's page shows beside the model.
#[derive(Debug, Default)]
pub struct ReportInputs<'a> {
    /// The pictures of the correction (`hxai explain`'s: response, predicted vs true,
    /// Pareto front), drawn on the data given.
    pub pictures: Option<&'a Pictures>,
    /// Rows of the data table read, and its name.
    pub data: Option<(&'a str, usize)>,
    /// The JSON of `hxai hybrid compare --json` on the same table, if given.
    pub compare: Option<&'a serde_json::Value>,
    /// The hxai version that wrote the page.
    pub version: &'a str,
}

const CSS: &str = "body{font-family:system-ui,sans-serif;max-width:60rem;margin:0 auto;\
padding:1rem;line-height:1.45;color:#1b1b1b}h1{font-size:1.6rem}h2{border-bottom:1px solid \
#ccc;margin-top:2rem}table{border-collapse:collapse;margin:.5rem 0}.scroll{overflow-x:auto}\
th,td{border:1px solid #ccc;padding:.25rem .5rem;text-align:left}td.n{text-align:right;\
font-variant-numeric:tabular-nums}code,pre{background:#f4f4f4;padding:.1rem .3rem}\
pre{white-space:pre-wrap;word-break:break-all;padding:.5rem}math{font-size:1.15rem}\
.eq{overflow-x:auto;padding:.5rem 0}figure{margin:1rem 0}figure svg{max-width:100%;\
height:auto}.warn{color:#8a4b00;overflow-wrap:anywhere}@media print{section{break-before:page}section:first-of-type\
{break-before:auto}.scroll{overflow:visible}}";

fn num(v: f64) -> String {
    hxai_symreg::expr::fmt_number(v, Some(4))
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_string(), num)
}

/// An element id from its parts: joined by `-`, every character but ASCII letters, digits,
/// `_`, `.` and `-` replaced by `_` (so a name with spaces or brackets makes a valid id).
fn slug(parts: &[&str]) -> String {
    parts
        .iter()
        .map(|p| {
            p.chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-') {
                        c
                    } else {
                        '_'
                    }
                })
                .collect::<String>()
        })
        .collect::<Vec<_>>()
        .join("-")
}

/// `v` as shown (four significant digits) in a `<data>` element whose `id` is the slug of
/// `id` and whose `value` is `v` in full (the shortest text that reads back as the same
/// `f64`), so a reader or a test can take every number of the page back exactly.
fn val(id: &[&str], v: f64) -> String {
    format!(
        "<data id=\"{}\" value=\"{v}\">{}</data>",
        esc(&slug(id)),
        num(v)
    )
}

/// [`val`] of `v`, or `-` when there is none.
fn opt_val(id: &[&str], v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_string(), |v| val(id, v))
}

/// [`interval`] with each end a [`val`] (`id` then `ci-lo`, `ci-hi`).
fn interval_val(id: &[&str], ci: Option<[f64; 2]>) -> String {
    ci.map_or_else(
        || "-".into(),
        |[lo, hi]| {
            let end = |which: &str, v: f64| {
                let mut parts = id.to_vec();
                parts.push(which);
                val(&parts, v)
            };
            format!("{} to {}", end("ci-lo", lo), end("ci-hi", hi))
        },
    )
}

/// A table with `head` and `rows` (cells already HTML), scrolling sideways when narrow.
fn table(caption: &str, head: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!(
        "<div class=\"scroll\"><table><caption>{}</caption><thead><tr>",
        esc(caption)
    );
    for h in head {
        let _ = write!(s, "<th scope=\"col\">{}</th>", esc(h));
    }
    s.push_str("</tr></thead><tbody>");
    for r in rows {
        s.push_str("<tr>");
        for (i, c) in r.iter().enumerate() {
            if i == 0 {
                let _ = write!(s, "<th scope=\"row\">{c}</th>");
            } else {
                let _ = write!(s, "<td class=\"n\">{c}</td>");
            }
        }
        s.push_str("</tr>");
    }
    s.push_str("</tbody></table></div>");
    s
}

/// A display equation: MathML (with `id` when given) and its plain text to copy.
fn equation(id: Option<&str>, lhs: Option<&str>, mathml: &str, text: &str) -> String {
    let id = id.map(|i| format!(" id=\"{i}\"")).unwrap_or_default();
    let lhs = lhs
        .map(|l| format!("<mi mathvariant=\"normal\">{}</mi><mo>=</mo>", esc(l)))
        .unwrap_or_default();
    format!(
        "<div class=\"eq\"><math display=\"block\"{id}><mrow>{lhs}{mathml}</mrow></math></div>\
         <pre>{}</pre>",
        esc(text)
    )
}

/// An SVG drawn by this crate, inlined (its XML declaration dropped) in an element that
/// screen readers announce with `label`.
fn figure(svg: &str, label: &str) -> String {
    let body = match svg.find("<svg") {
        Some(i) => &svg[i..],
        None => svg,
    };
    // inline SVG in HTML needs no namespace: without it the page names no address at all
    let body = strip_namespaces(body);
    format!(
        "<figure><div role=\"img\" aria-label=\"{l}\">{body}</div><figcaption>{l}</figcaption>\
         </figure>",
        l = esc(label)
    )
}

/// `svg` without its `xmlns` and `xmlns:*` attributes.
fn strip_namespaces(svg: &str) -> String {
    let mut out = String::with_capacity(svg.len());
    let mut rest = svg;
    while let Some(i) = rest.find(" xmlns") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        // skip `xmlns[:name]="..."`
        match after
            .find('"')
            .and_then(|q| after[q + 1..].find('"').map(|e| q + 1 + e + 1))
        {
            Some(end) => rest = &after[end..],
            None => {
                rest = after;
                out.push(' ');
            }
        }
    }
    out.push_str(rest);
    out
}

/// The page frame: the document head (title, viewport, style sheet), the `h1` heading
/// (HTML), then `body` (the sections).
fn page(title: &str, heading: &str, body: &str) -> String {
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <title>{}</title><style>{CSS}</style></head><body><h1>{heading}</h1>{body}</body>\
         </html>\n",
        esc(title)
    )
}

/// `lo to hi`, or `-`.
fn interval(ci: Option<[f64; 2]>) -> String {
    ci.map_or_else(
        || "-".into(),
        |[lo, hi]| format!("{} to {}", num(lo), num(hi)),
    )
}

/// A share in per cent, or `-`.
fn share(v: Option<f64>) -> String {
    v.map_or_else(|| "-".into(), |v| format!("{:.0} %", 100.0 * v))
}

/// The correction `c` of either workflow: its equation (`lhs = ...`, MathML and text), the
/// table of its constants with standard errors and 95 % intervals, and its factors in the
/// factor form. `kind` names the correction (`multiplicative`, `symbolic`).
fn correction_part<K>(c: &CorrectionInfo<K>, kind: &str, lhs: &str) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "<h3>Correction</h3><p>{} correction, complexity {}, on {}.</p>",
        esc(kind),
        c.forms.complexity,
        esc(&if c.forms.features.is_empty() {
            "no feature".to_string()
        } else {
            c.forms.features.join(", ")
        })
    );
    let mathml = c
        .model
        .as_ref()
        .map_or_else(|| "<mn>0</mn>".to_string(), |m| m.expr().to_mathml(4));
    s.push_str(&equation(None, Some(lhs), &mathml, &c.forms.equation));
    if let Some(u) = &c.uncertainty {
        let rows: Vec<Vec<String>> = u
            .params
            .iter()
            .map(|(name, p)| {
                vec![
                    format!("<code>{}</code>", esc(name)),
                    val(&["correction", name, "value"], p.value),
                    opt_val(&["correction", name, "se"], p.std_error),
                    interval_val(&["correction", name], p.ci95),
                ]
            })
            .collect();
        if !rows.is_empty() {
            let _ = write!(
                s,
                "<p>Its constants in the template <code>{}</code>:</p>",
                esc(&hxai_symreg::expr::readable_names(&u.template))
            );
            s.push_str(&table(
                "The correction's constants",
                &["constant", "value", "standard error", "95 % interval"],
                &rows,
            ));
        }
    }
    if let Some(factors) = &c.factors {
        let rows: Vec<Vec<String>> = factors
            .iter()
            .map(|f| {
                let on = f
                    .column
                    .clone()
                    .or_else(|| f.columns.as_ref().map(|c| c.join(" × ")))
                    .unwrap_or_default();
                vec![
                    esc(&on),
                    esc(f.shape.name()),
                    format!("<code>{}</code>", esc(&f.equation)),
                    f.complexity.to_string(),
                ]
            })
            .collect();
        s.push_str(&table(
            "The correction factor by factor",
            &["column", "shape", "factor", "complexity"],
            &rows,
        ));
    }
    s
}

/// The tables of a comparison JSON (`hxai hybrid compare --json` or `hxai compare
/// --json`): every model's test scores, the hybrid against the best black box, the
/// cross-validation and the interval coverage, each where the JSON has it.
fn compare_part(c: &serde_json::Value) -> String {
    let mut s = String::new();
    let models = c["models"].as_array().cloned().unwrap_or_default();
    let rows: Vec<Vec<String>> = models
        .iter()
        .map(|m| {
            let name = m["name"].as_str().unwrap_or("");
            vec![
                esc(name),
                opt_val(&["compare", name, "rmse"], m["rmse"].as_f64()),
                opt_val(&["compare", name, "r2"], m["r2"].as_f64()),
                opt_val(&["compare", name, "mae"], m["mae"].as_f64()),
            ]
        })
        .collect();
    let caption = match c["split"].as_str() {
        Some(split) => format!("The comparison: every model on the {split} split's test rows"),
        None => "The comparison: every model on the test rows".to_string(),
    };
    s.push_str(&table(
        &caption,
        &["model", "test RMSE", "test R²", "test MAE"],
        &rows,
    ));
    if let Some(r) = c["hybrid_over_best_black_box"].as_f64() {
        let _ = write!(
            s,
            "<p>The hybrid has <strong>{} times the best black box's test RMSE</strong> \
             ({}).</p>",
            val(&["compare", "hybrid_over_best_black_box"], r),
            esc(c["best_black_box"]["name"].as_str().unwrap_or(""))
        );
    }
    let cv: Vec<Vec<String>> = c["cv"]
        .as_array()
        .cloned()
        .unwrap_or_default()
        .iter()
        .map(|m| {
            let name = m["name"].as_str().unwrap_or("");
            vec![
                esc(name),
                opt_val(&["cv", name, "r2_mean"], m["r2_mean"].as_f64()),
                opt_val(&["cv", name, "r2_sd"], m["r2_sd"].as_f64()),
                opt_val(&["cv", name, "rmse_mean"], m["rmse_mean"].as_f64()),
            ]
        })
        .collect();
    if !cv.is_empty() {
        s.push_str(&table(
            &format!("{}-fold cross-validation", c["folds"].as_u64().unwrap_or(0)),
            &["model", "mean R²", "R² sd", "mean RMSE"],
            &cv,
        ));
    }
    if let Some(iv) = c.get("interval").filter(|v| !v.is_null()) {
        let _ = write!(
            s,
            "<p>Prediction intervals on the test rows: nominal {}, coverage {} ({}).</p>",
            opt_val(&["compare", "interval", "nominal"], iv["nominal"].as_f64()),
            opt_val(
                &["compare", "interval", "coverage"],
                iv["coverage"].as_f64()
            ),
            esc(iv["method"].as_str().unwrap_or(""))
        );
    }
    s
}

/// How the correction was selected, with the alternatives the data cannot tell apart.
fn selection_part(sel: &hxai_symreg::SelectionReport) -> String {
    let mut s = String::new();
    let given_back = match (sel.share, sel.runs) {
        (Some(v), Some(r)) => format!(", given back by {:.0} % of {r} resamples", 100.0 * v),
        _ => String::new(),
    };
    let _ = write!(
        s,
        "<p>The correction was selected by {}; its structure <code>{}</code>{given_back}.</p>",
        esc(&sel.method),
        esc(&hxai_symreg::expr::readable_names(&sel.structure))
    );
    if !sel.alternatives.is_empty() {
        let rows: Vec<Vec<String>> = sel
            .alternatives
            .iter()
            .map(|a| {
                vec![
                    format!("<code>{}</code>", esc(&a.equation)),
                    a.complexity.to_string(),
                    share(a.share),
                ]
            })
            .collect();
        s.push_str(&table(
            "Alternatives the data cannot tell apart (within one standard error)",
            &["correction", "complexity", "share of resamples"],
            &rows,
        ));
    }
    s
}

/// The pictures of the correction as figures, each with its accessible name, and those not
/// drawn with their reason.
fn pictures_part(p: &Pictures) -> String {
    let mut s = String::new();
    for (file, svg) in &p.files {
        let label = match file.as_str() {
            crate::explain::RESPONSE_FILE => {
                "The correction's response to each feature, the others at their medians, with its band"
            }
            crate::explain::PARITY_FILE => "Predicted against true on the data given",
            crate::explain::PARETO_FILE => "The Pareto front the correction was chosen from",
            other => other,
        };
        s.push_str(&figure(svg, label));
    }
    for (file, why) in &p.skipped {
        let _ = write!(s, "<p>Not drawn: {} ({}).</p>", esc(file), esc(why));
    }
    s
}

/// The warnings as a list, or `none` (a sentence) when there are none.
fn warnings_part(warnings: &[String], none: &str) -> String {
    if warnings.is_empty() {
        return format!("<p>{}</p>", esc(none));
    }
    let mut s = String::from("<h3>Warnings</h3><ul>");
    for w in warnings {
        let _ = write!(s, "<li class=\"warn\">{}</li>", esc(w));
    }
    s.push_str("</ul>");
    s
}

/// The last section: the command that refits the model, and who wrote the page.
fn reproduce_section(command: &str, version: &str, schema_version: u32) -> String {
    format!(
        "<section id=\"reproduce\"><h2>How to reproduce</h2><p>Refit (the search settings \
         not stored in the model file at their defaults):</p><pre>{}</pre><p>Written by hxai \
         {} from a model file of schema version {schema_version}.</p></section>",
        esc(command),
        esc(version)
    )
}

/// A shell word: `s` in single quotes.
fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn namespaces_are_taken_off_inline_svg() {
        let svg = r#"<svg width="10" xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink" height="5"><rect/></svg>"#;
        assert_eq!(
            strip_namespaces(svg),
            r#"<svg width="10" height="5"><rect/></svg>"#
        );
        assert!(!figure(svg, "a <b>").contains("http"));
        assert!(figure(svg, "a <b>").contains("aria-label=\"a &lt;b&gt;\""));
    }
}
