//! One self-contained HTML page for a hybrid model (`hxai report`, issue 50), of either
//! workflow: a table hybrid ([`table_report`]) or the recordings' tool model
//! ([`tool_report`]); what a person reads, in the order they ask it.
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
//! reproduction section); only what a workflow alone has (the table's calibrated physics,
//! the tool's signal chain and per-record evaluation) is written per workflow.

use crate::explain::Pictures;
use hxai_hybrid::CorrectionInfo;
use hxai_hybrid::records::{RecordInput, RecordModel, SamplesTable};
use hxai_hybrid::tables::TableModel;
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
height:auto}.warn{color:#8a4b00}@media print{section{break-before:page}section:first-of-type\
{break-before:auto}.scroll{overflow:visible}}";

fn num(v: f64) -> String {
    hxai_symreg::expr::fmt_number(v, Some(4))
}

fn opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_string(), num)
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
                    num(p.value),
                    opt(p.std_error),
                    interval(p.ci95),
                ]
            })
            .collect();
        if !rows.is_empty() {
            let _ = write!(
                s,
                "<p>Its constants in the template <code>{}</code>:</p>",
                esc(&u.template)
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
            vec![
                esc(m["name"].as_str().unwrap_or("")),
                opt(m["rmse"].as_f64()),
                opt(m["r2"].as_f64()),
                opt(m["mae"].as_f64()),
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
            num(r),
            esc(c["best_black_box"]["name"].as_str().unwrap_or(""))
        );
    }
    let cv: Vec<Vec<String>> = c["cv"]
        .as_array()
        .cloned()
        .unwrap_or_default()
        .iter()
        .map(|m| {
            vec![
                esc(m["name"].as_str().unwrap_or("")),
                opt(m["r2_mean"].as_f64()),
                opt(m["r2_sd"].as_f64()),
                opt(m["rmse_mean"].as_f64()),
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
            opt(iv["nominal"].as_f64()),
            opt(iv["coverage"].as_f64()),
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
        esc(&sel.structure)
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

fn model_section(m: &TableModel) -> String {
    let mut s = String::from("<section id=\"model\"><h2>The model</h2>");
    let hybrid_mathml = m.hybrid_expr().map(|e| e.to_mathml(4));
    s.push_str("<h3>The hybrid as one equation</h3>");
    match hybrid_mathml {
        Ok(mm) => s.push_str(&equation(
            Some("hybrid-equation"),
            Some(&m.target),
            &mm,
            &format!("{} = {}", m.target, m.hybrid.equation),
        )),
        Err(_) => {
            let _ = write!(
                s,
                "<pre id=\"hybrid-equation\">{} = {}</pre>",
                esc(&m.target),
                esc(&m.hybrid.equation)
            );
        }
    }
    s.push_str("<h3>Physics</h3>");
    if let Ok(p) = hxai_symreg::infix::parse(&m.physics.equation) {
        s.push_str(&equation(
            None,
            None,
            &p.expr.to_mathml(4),
            &m.physics.equation,
        ));
    }
    let rows: Vec<Vec<String>> = m
        .physics
        .parameters
        .iter()
        .map(|(name, v)| {
            let se = m.physics.standard_errors.get(name).copied().flatten();
            let ci = m.physics.params.get(name).and_then(|p| p.ci95);
            vec![
                format!("<code>{}</code>", esc(name)),
                num(*v),
                opt(se),
                interval(ci),
                if m.physics.calibrated.contains(name) {
                    "calibrated".into()
                } else {
                    "set".into()
                },
            ]
        })
        .collect();
    if !rows.is_empty() {
        s.push_str(&table(
            "Physics parameters",
            &[
                "parameter",
                "value",
                "standard error",
                "95 % interval",
                "how",
            ],
            &rows,
        ));
    }
    s.push_str(&correction_part(
        &m.correction,
        m.correction.kind.name(),
        "δ",
    ));
    if let Some(cp) = &m.correction_per {
        let rows: Vec<Vec<String>> = cp
            .levels
            .iter()
            .map(|l| {
                vec![
                    esc(l),
                    cp.rows.get(l).copied().unwrap_or(0).to_string(),
                    format!(
                        "<code>{}</code>",
                        esc(cp.equations.get(l).map_or("", String::as_str))
                    ),
                ]
            })
            .collect();
        s.push_str(&table(
            &format!("The correction's constants per level of {}", cp.column),
            &["level", "training rows", "correction"],
            &rows,
        ));
    }
    s.push_str("</section>");
    s
}

fn scores_section(m: &TableModel, compare: Option<&serde_json::Value>) -> String {
    let mut s = String::from("<section id=\"scores\"><h2>How good</h2>");
    let pair = |name: &str, p: &hxai_hybrid::tables::PairScores| {
        vec![
            esc(name),
            num(p.physics.rmse),
            num(p.physics.r2),
            num(p.hybrid.rmse),
            num(p.hybrid.r2),
        ]
    };
    let mut rows = vec![pair(
        &format!("training rows ({})", m.split.train.len()),
        &m.scores.train,
    )];
    if let Some(t) = &m.scores.test {
        rows.push(pair(&format!("test rows ({})", m.split.test.len()), t));
    }
    s.push_str(&table(
        "Physics and hybrid on the fitting table's split",
        &[
            "rows",
            "physics RMSE",
            "physics R²",
            "hybrid RMSE",
            "hybrid R²",
        ],
        &rows,
    ));
    if let Some(bb) = &m.scores.black_boxes {
        let _ = write!(
            s,
            "<p>Black boxes on the same split: physics + forest RMSE {}, gradient boosting \
             RMSE {}; the hybrid has <strong>{} times the best black box's test RMSE</strong> \
             ({}).</p>",
            num(bb.physics_forest),
            num(bb.boosting),
            num(bb.hybrid_over_best_black_box),
            esc(&bb.best_black_box.name)
        );
    }
    if let Some(c) = compare {
        s.push_str(&compare_part(c));
    }
    s.push_str("</section>");
    s
}

fn sure_section(m: &TableModel, pictures: Option<&Pictures>) -> String {
    let mut s = String::from("<section id=\"sure\"><h2>How sure</h2>");
    if let Some(sel) = &m.correction.selection {
        s.push_str(&selection_part(sel));
    }
    if let Some(st) = &m.stability {
        let rows: Vec<Vec<String>> = st
            .structures
            .iter()
            .take(8)
            .map(|x| {
                vec![
                    format!("<code>{}</code>", esc(&x.template)),
                    share(Some(x.share)),
                ]
            })
            .collect();
        s.push_str(&table(
            &format!("Structures over {} bootstrap resamples", st.runs),
            &["structure", "share"],
            &rows,
        ));
    }
    if let Some(p) = pictures {
        s.push_str(&pictures_part(p));
    }
    s.push_str("</section>");
    s
}

fn holds_section(m: &TableModel, data: Option<(&str, usize)>) -> String {
    let mut s = String::from("<section id=\"holds\"><h2>Where it holds</h2>");
    if let Some(w) = m.conformal.as_ref().and_then(|c| c.widening.as_ref()) {
        let rows: Vec<Vec<String>> = w
            .columns
            .iter()
            .zip(w.lo.iter().zip(&w.hi))
            .map(|(c, (lo, hi))| vec![format!("<code>{}</code>", esc(c)), num(*lo), num(*hi)])
            .collect();
        s.push_str(&table(
            "Training ranges of the inputs",
            &["column", "lowest", "highest"],
            &rows,
        ));
    }
    s.push_str(&warnings_part(&m.warnings, "The fit gave no warning."));
    let _ = write!(
        s,
        "<p>Fitted on {} training and {} test rows ({} split",
        m.split.train.len(),
        m.split.test.len(),
        esc(&format!("{:?}", m.split.kind).to_lowercase())
    );
    if let Some(mi) = &m.missing {
        let _ = write!(
            s,
            "; empty cells: <code>--missing {}</code>",
            esc(&mi.policy)
        );
    }
    s.push_str(").");
    if let Some((name, rows)) = data {
        let _ = write!(
            s,
            " This page was drawn on {rows} rows of <code>{}</code>.",
            esc(name)
        );
    }
    s.push_str("</p></section>");
    s
}

/// The `hxai hybrid fit` command line that refits `m` (from what its file stores: the
/// search settings beyond these are the defaults of its version).
pub fn refit_command(m: &TableModel, data: &str) -> String {
    let q = quote;
    let mut c = format!(
        "hxai hybrid fit --data {} --target {} --physics {}",
        q(data),
        q(&m.target),
        q(&m.physics.equation)
    );
    if !m.physics.calibrated.is_empty() {
        let plain: Vec<&str> = m
            .physics
            .calibrated
            .iter()
            .filter(|p| !p.contains('['))
            .map(String::as_str)
            .collect();
        if !plain.is_empty() {
            let _ = write!(c, " --calibrate {}", q(&plain.join(",")));
        }
    }
    if let Some(pc) = &m.per_class {
        let _ = write!(
            c,
            " --calibrate-per {}",
            q(&format!("{}={}", pc.column, pc.parameters.join(",")))
        );
    }
    if let Some(cp) = &m.correction_per {
        let _ = write!(c, " --correction-per {}", q(&cp.column));
    }
    let _ = write!(c, " --correction {}", m.correction.kind.name());
    if let Some(form) = &m.correction.form {
        let _ = write!(c, " --form {form}");
    }
    if let Some(g) = &m.group {
        let _ = write!(c, " --group {}", q(g));
    }
    if let Some(seed) = m.split.seed {
        let _ = write!(c, " --seed {seed}");
    }
    if let Some(f) = m.split.test_fraction {
        let _ = write!(c, " --test-fraction {}", num(f));
    }
    if m.joint.is_some() {
        c.push_str(" --joint");
    }
    c.push_str(" --out model.json");
    c
}

/// The correction's pictures (response, predicted vs true, Pareto front) of `m` drawn on
/// `table` (its input columns and target) at the default interval level and method: the
/// figures of the page, for `hxai report` and Python's `report` alike.
///
/// # Errors
/// The explanation's (a column missing from `table`) or the drawing's.
pub fn correction_pictures(
    m: &TableModel,
    table: &hxai_symreg::Table,
) -> Result<Pictures, Box<dyn std::error::Error + Send + Sync>> {
    let label = format!(
        "δ ({} correction of {})",
        m.correction.kind.name(),
        m.target
    );
    let e = m.explain(Some(table), hxai_hybrid::DEFAULT_INTERVAL, None)?;
    Ok(crate::explain::pictures(&e, &label, "")?)
}

/// The whole page for the table hybrid `m`.
pub fn table_report(m: &TableModel, inputs: &ReportInputs<'_>) -> String {
    let data = inputs.data.map_or("TABLE.csv", |(n, _)| n);
    let body = [
        model_section(m),
        scores_section(m, inputs.compare),
        sure_section(m, inputs.pictures),
        holds_section(m, inputs.data),
        reproduce_section(&refit_command(m, data), inputs.version, m.schema_version),
    ]
    .concat();
    page(
        &format!("hxai report: {}", m.target),
        &format!("Hybrid model of <code>{}</code>", esc(&m.target)),
        &body,
    )
}

/// A compact card of `m` for a notebook (`_repr_html_` of the Python estimator): the hybrid
/// as MathML with its text, the calibrated parameters with their 95 % intervals, and the
/// scores. No figure, no style sheet (the notebook's own applies).
pub fn table_card(m: &TableModel) -> String {
    let mut s = String::from("<div class=\"hxai-card\">");
    let mm = m
        .hybrid_expr()
        .map(|e| e.to_mathml(4))
        .unwrap_or_else(|_| format!("<mtext>{}</mtext>", esc(&m.hybrid.equation)));
    s.push_str(&equation(
        None,
        Some(&m.target),
        &mm,
        &format!("{} = {}", m.target, m.hybrid.equation),
    ));
    let params: Vec<String> = m
        .physics
        .calibrated
        .iter()
        .map(|p| {
            let v = m.physics.parameters.get(p).copied().unwrap_or(f64::NAN);
            match m.physics.params.get(p).and_then(|e| e.ci95) {
                Some([lo, hi]) => {
                    format!("{} = {} (95 % {} to {})", esc(p), num(v), num(lo), num(hi))
                }
                None => format!("{} = {}", esc(p), num(v)),
            }
        })
        .collect();
    if !params.is_empty() {
        let _ = write!(s, "<p>Calibrated: {}.</p>", params.join("; "));
    }
    let _ = write!(
        s,
        "<p>{} correction, complexity {}; training RMSE {} (physics alone {})",
        esc(m.correction.kind.name()),
        m.correction.forms.complexity,
        num(m.scores.train.hybrid.rmse),
        num(m.scores.train.physics.rmse)
    );
    if let Some(t) = &m.scores.test {
        let _ = write!(s, ", test RMSE {}", num(t.hybrid.rmse));
    }
    s.push_str(".</p></div>");
    s
}

/// The recordings a tool model's page is drawn on: every record with its truth (the data
/// folder the model was fitted on, or more of the same machine).
#[derive(Debug)]
pub struct ToolData<'a> {
    /// What the records are called on the page (the data folder's path).
    pub name: &'a str,
    /// The records, each with its `probe_um` truth.
    pub records: &'a [RecordInput<'a>],
    /// Warnings about the records found while reading them (a probe amplitude far from the
    /// manifest's, say); the page adds those of the records' signals.
    pub warnings: Vec<String>,
}

/// What a tool model's page holds beyond the model file: computed from [`ToolData`] by
/// [`tool_inputs`], so the command line and Python draw the same page.
#[derive(Debug)]
pub struct ToolInputs<'a> {
    /// The data's name, records and windows.
    pub data: Option<(&'a str, usize, usize)>,
    /// The window samples of the data, labelled `train`/`test` by the model's split.
    pub samples: Option<SamplesTable>,
    /// Physics against hybrid on the data's test records (or on every record, when none of
    /// them is a test record: then `true`).
    pub evaluation: Option<(hxai_hybrid::records::Evaluation, bool)>,
    /// The correction's pictures drawn on the samples, or why they are not drawn.
    pub pictures: Option<Result<Pictures, String>>,
    /// The warnings of the data.
    pub warnings: Vec<String>,
    /// The JSON of `hxai compare --json` on the model's samples, if given.
    pub compare: Option<&'a serde_json::Value>,
    /// The hxai version that writes the page.
    pub version: &'a str,
}

/// The page's numbers and pictures of the tool model `m` on `data`: the labelled window
/// samples, the evaluation on the test records (on every record when the data holds none),
/// the correction's pictures, the warnings.
///
/// # Errors
/// A record without truth, out of the model's band or too short for one window (the
/// samples' errors), and the evaluation's.
pub fn tool_inputs<'a>(
    m: &RecordModel,
    data: Option<&'a ToolData<'a>>,
    compare: Option<&'a serde_json::Value>,
    version: &'a str,
) -> Result<ToolInputs<'a>, hxai_hybrid::HybridError> {
    let Some(d) = data else {
        return Ok(ToolInputs {
            data: None,
            samples: None,
            evaluation: None,
            pictures: None,
            warnings: Vec::new(),
            compare,
            version,
        });
    };
    let samples = m.samples_of(d.records)?;
    let level = hxai_hybrid::DEFAULT_INTERVAL;
    let method = m
        .default_interval_method(level)
        .unwrap_or(hxai_hybrid::IntervalMethod::Delta);
    let has_test = samples.split.contains(&"test");
    let mut ev = m.evaluate_with(d.records, !has_test, level, method)?;
    let mut warnings = d.warnings.clone();
    warnings.append(&mut ev.warnings);
    let pictures = Some(tool_pictures(m, &samples).map_err(|e| e.to_string()));
    Ok(ToolInputs {
        data: Some((d.name, d.records.len(), samples.record.len())),
        samples: Some(samples),
        evaluation: Some((ev, !has_test)),
        pictures,
        warnings,
        compare,
        version,
    })
}

/// The correction's pictures (response, predicted vs true, Pareto front) of the tool model
/// `m` drawn on its labelled window `samples` ([`RecordModel::samples_of`]) at the default
/// interval level and the model's interval method.
///
/// # Errors
/// The explanation's (a zero correction has nothing to explain) or the drawing's.
pub fn tool_pictures(
    m: &RecordModel,
    samples: &SamplesTable,
) -> Result<Pictures, Box<dyn std::error::Error + Send + Sync>> {
    let delta = samples
        .values
        .column("delta")
        .ok_or("the samples have no column `delta`")?;
    let is_test: Vec<bool> = samples.split.iter().map(|s| *s == "test").collect();
    let data = hxai_hybrid::explain::ExplainData {
        features: &samples.values,
        target: delta,
        is_test: &is_test,
    };
    let e = m.explain(Some(&data), hxai_hybrid::DEFAULT_INTERVAL, None)?;
    Ok(crate::explain::pictures(
        &e,
        crate::explain::DELTA_AXIS,
        "",
    )?)
}

fn tool_kind(m: &RecordModel) -> &'static str {
    match m.correction.kind {
        hxai_hybrid::records::CorrectionKind::Symbolic => "symbolic (added to the amplitude)",
        hxai_hybrid::records::CorrectionKind::Zero => "zero",
    }
}

/// The tool hybrid as one equation: MathML (without the outer `<math>`) and its text.
fn tool_equation(m: &RecordModel) -> (String, String) {
    let a_phys = "<msub><mi>A</mi><mtext>phys</mtext></msub>";
    let phi = "<msub><mi>φ</mi><mtext>phys</mtext></msub>";
    let (amp, amp_text) = match &m.correction.model {
        Some(c) => (
            format!(
                "<mrow><mo>(</mo>{a_phys}<mo>+</mo><mrow><mo>(</mo>{}<mo>)</mo></mrow>\
                 <mo>)</mo></mrow>",
                c.expr().to_mathml(4)
            ),
            format!("(A_phys + ({}))", m.correction.forms.equation),
        ),
        None => (a_phys.to_string(), "A_phys".to_string()),
    };
    (
        format!(
            "<mover accent=\"true\"><mi>x</mi><mo>^</mo></mover><mo>(</mo><mi>t</mi><mo>)</mo><mo>=</mo>\
             {amp}<mo>\u{2062}</mo><mi>sin</mi><mo>\u{2061}</mo><mrow><mo>(</mo><mn>2</mn>\
             <mi>π</mi><mi>f</mi><mi>t</mi><mo>+</mo>{phi}<mo>)</mo></mrow>"
        ),
        format!("x_hat(t) = {amp_text} * sin(2*pi*f*t + phi_phys)"),
    )
}

fn tool_model_section(m: &RecordModel) -> String {
    let mut s =
        String::from("<section id=\"model\"><h2>The model</h2><h3>The hybrid as one equation</h3>");
    let (mathml, text) = tool_equation(m);
    s.push_str(&equation(Some("hybrid-equation"), None, &mathml, &text));
    let _ = write!(
        s,
        "<p>In each window of {} s: <i>A</i><sub>phys</sub> and <i>φ</i><sub>phys</sub> are \
         the amplitude and phase of the sine fitted to the physics displacement, <i>f</i> the \
         commanded frequency; the correction δ of the amplitude is learned from the \
         window's features ({}).</p>",
        num(m.window.length_s),
        esc(&m.features.names.join(", "))
    );
    let p = &m.physics;
    let rows = vec![
        vec![
            "band-pass".into(),
            format!(
                "{} to {} Hz, Butterworth order {}",
                num(p.low_hz),
                num(p.high_hz),
                p.order
            ),
        ],
        vec!["integration".into(), esc(&format!("{:?}", p.integrator))],
        vec!["drift removal".into(), esc(&format!("{:?}", p.drift))],
        vec![
            "windows".into(),
            format!(
                "{} s, {} s discarded at each record end",
                num(m.window.length_s),
                num(m.window.discard_s)
            ),
        ],
    ];
    s.push_str(
        "<h3>Physics</h3><p>Double integration of the acceleration (no constant \
                calibrated):</p>",
    );
    s.push_str(&table(
        "The physics model's settings",
        &["step", "setting"],
        &rows,
    ));
    s.push_str(&correction_part(&m.correction, tool_kind(m), "δ"));
    s.push_str("</section>");
    s
}

fn tool_scores_section(m: &RecordModel, inputs: &ToolInputs<'_>) -> String {
    let mut s = String::from("<section id=\"scores\"><h2>How good</h2>");
    let t = &m.training;
    let mut rows = Vec::new();
    for (name, n, metrics) in [
        ("training windows", t.n_train_windows, &t.delta_train),
        ("test windows", t.n_test_windows, &t.delta_test),
    ] {
        if let Some(x) = metrics {
            rows.push(vec![
                format!("{name} ({n})"),
                num(x.rmse),
                num(x.r2),
                num(x.mae),
            ]);
        }
    }
    if !rows.is_empty() {
        s.push_str(&table(
            "The correction δ against the truth at the fit (µm)",
            &["windows", "RMSE", "R²", "MAE"],
            &rows,
        ));
    }
    if let Some((ev, all)) = &inputs.evaluation {
        let rows: Vec<Vec<String>> = [
            ("physics", &ev.physics),
            ("physics sine", &ev.physics_sine),
            ("hybrid", &ev.hybrid),
        ]
        .iter()
        .map(|(name, x)| vec![esc(name), num(x.rmse), num(x.r2), num(x.mae)])
        .collect();
        let which = if *all {
            "every record (none is a test record of the model)"
        } else {
            "the test records"
        };
        s.push_str(&table(
            &format!(
                "Displacement on {which}: {} records, {} windows, {} samples (µm)",
                ev.n_records, ev.n_windows, ev.n_samples
            ),
            &["model", "RMSE", "R²", "MAE"],
            &rows,
        ));
        let _ = write!(
            s,
            "<p>The hybrid lowers the RMSE by {} % against the physics ({} % against its \
             sine).",
            num(ev.improvement_pct),
            num(ev.improvement_vs_sine_pct)
        );
        match &ev.t_test {
            Some(tt) => {
                let _ = write!(
                    s,
                    " Paired t-test on the per-window squared errors: t = {}, df = {}, p = {}.",
                    num(tt.statistic),
                    num(tt.df),
                    num(tt.p_value)
                );
            }
            None => s.push_str(" Too few windows for a paired t-test."),
        }
        s.push_str("</p>");
        if let Some(iv) = &ev.interval {
            let _ = write!(
                s,
                "<p>Prediction intervals of the amplitude: nominal {}, coverage {} of {} \
                 windows ({}), median width {} µm.</p>",
                num(iv.nominal),
                num(iv.coverage),
                iv.n,
                esc(iv.method.name()),
                opt(iv.median_width)
            );
        }
    }
    if let Some(c) = inputs.compare {
        s.push_str(&compare_part(c));
    }
    s.push_str("</section>");
    s
}

fn tool_sure_section(m: &RecordModel, inputs: &ToolInputs<'_>) -> String {
    let mut s = String::from("<section id=\"sure\"><h2>How sure</h2>");
    if let Some(sel) = &m.correction.selection {
        s.push_str(&selection_part(sel));
    }
    match &inputs.pictures {
        Some(Ok(p)) => s.push_str(&pictures_part(p)),
        Some(Err(why)) => {
            let _ = write!(s, "<p>No figures: {}.</p>", esc(why));
        }
        None => s.push_str("<p>No figures: give the data folder to draw them.</p>"),
    }
    s.push_str("</section>");
    s
}

/// `(column, lowest, highest)` over the training windows of `samples`, for the features
/// the correction uses and the physics amplitude.
fn training_ranges(m: &RecordModel, samples: &SamplesTable) -> Vec<(String, f64, f64)> {
    let mut names = m.correction.forms.features.clone();
    names.push("A_phys".into());
    names
        .into_iter()
        .filter_map(|n| {
            let col = samples.values.column(&n)?;
            let (lo, hi) = col
                .iter()
                .zip(&samples.split)
                .filter(|(_, s)| **s == "train")
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (v, _)| {
                    (lo.min(*v), hi.max(*v))
                });
            (lo <= hi).then_some((n, lo, hi))
        })
        .collect()
}

fn tool_holds_section(m: &RecordModel, inputs: &ToolInputs<'_>) -> String {
    let mut s = String::from("<section id=\"holds\"><h2>Where it holds</h2>");
    if let Some(samples) = &inputs.samples {
        let rows: Vec<Vec<String>> = training_ranges(m, samples)
            .iter()
            .map(|(c, lo, hi)| vec![format!("<code>{}</code>", esc(c)), num(*lo), num(*hi)])
            .collect();
        if !rows.is_empty() {
            s.push_str(&table(
                "Training ranges of the correction's inputs (training windows of the data)",
                &["feature", "lowest", "highest"],
                &rows,
            ));
        }
    }
    s.push_str(&warnings_part(
        &inputs.warnings,
        if inputs.data.is_some() {
            "The records gave no warning."
        } else {
            "No data given, so no warning about it."
        },
    ));
    let _ = write!(
        s,
        "<p>Fitted on {} training records ({} windows), tested on {} records ({} windows; {} \
         split).",
        m.split.train.len(),
        m.training.n_train_windows,
        m.split.test.len(),
        m.training.n_test_windows,
        esc(&format!("{:?}", m.split.kind).to_lowercase())
    );
    if let Some((name, records, windows)) = inputs.data {
        let _ = write!(
            s,
            " This page was drawn on {records} records ({windows} windows) of <code>{}</code>.",
            esc(name)
        );
    }
    s.push_str("</p></section>");
    s
}

/// The `hxai fit` command line that refits the tool model `m` (from what its file stores:
/// the search settings beyond these are the defaults of its version).
pub fn tool_refit_command(m: &RecordModel, data: &str) -> String {
    let mut c = format!("hxai fit --data {}", quote(data));
    if let Some(seed) = m.split.seed {
        let _ = write!(c, " --seed {seed}");
    }
    if let Some(f) = m.split.test_fraction {
        let _ = write!(c, " --test-fraction {}", num(f));
    }
    let split = match m.split.kind {
        hxai_hybrid::records::SplitKind::Record => "record",
        hxai_hybrid::records::SplitKind::Window => "window",
    };
    let _ = write!(c, " --split {split}");
    if let Some(st) = m.training.strategy
        && let Ok(serde_json::Value::String(name)) = serde_json::to_value(st)
    {
        let _ = write!(c, " --strategy {name}");
    }
    let _ = write!(
        c,
        " --epochs {} --window-s {} --discard-s {}",
        m.training.epochs,
        num(m.window.length_s),
        num(m.window.discard_s)
    );
    if let Some(form) = &m.correction.form {
        let _ = write!(c, " --form {form}");
    }
    let _ = write!(
        c,
        " --conformal-folds {}",
        m.conformal.as_ref().map_or(0, |k| k.folds)
    );
    c.push_str(" --out model.json");
    c
}

/// The whole page for the recordings' tool model `m`, with what [`tool_inputs`] computed.
pub fn tool_report(m: &RecordModel, inputs: &ToolInputs<'_>) -> String {
    let data = inputs.data.map_or("DATA_FOLDER", |(n, _, _)| n);
    let body = [
        tool_model_section(m),
        tool_scores_section(m, inputs),
        tool_sure_section(m, inputs),
        tool_holds_section(m, inputs),
        reproduce_section(
            &tool_refit_command(m, data),
            inputs.version,
            m.schema_version,
        ),
    ]
    .concat();
    page(
        "hxai report: tool position",
        "Hybrid model of the tool position",
        &body,
    )
}

/// A compact card of the tool model `m` for a notebook (`_repr_html_` of Python's
/// `ToolModel`): the hybrid as MathML with its text, the correction's constants with their
/// 95 % intervals, and the correction's scores at the fit. No figure, no style sheet.
pub fn tool_card(m: &RecordModel) -> String {
    let mut s = String::from("<div class=\"hxai-card\">");
    let (mathml, text) = tool_equation(m);
    s.push_str(&equation(None, None, &mathml, &text));
    let constants: Vec<String> = m
        .correction
        .uncertainty
        .iter()
        .flat_map(|u| &u.params)
        .map(|(name, p)| match p.ci95 {
            Some(ci) => format!(
                "{} = {} (95 % {})",
                esc(name),
                num(p.value),
                interval(Some(ci))
            ),
            None => format!("{} = {}", esc(name), num(p.value)),
        })
        .collect();
    if !constants.is_empty() {
        let _ = write!(s, "<p>Constants: {}.</p>", constants.join("; "));
    }
    let _ = write!(
        s,
        "<p>{} correction, complexity {}",
        esc(tool_kind(m)),
        m.correction.forms.complexity
    );
    if let Some(x) = &m.training.delta_train {
        let _ = write!(s, "; δ training RMSE {} µm", num(x.rmse));
    }
    if let Some(x) = &m.training.delta_test {
        let _ = write!(s, ", test RMSE {} µm (R² {})", num(x.rmse), num(x.r2));
    }
    s.push_str(".</p></div>");
    s
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
