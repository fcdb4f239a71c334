//! One self-contained HTML page for a table hybrid (`hxai report`, issue 50): what a person
//! reads, in the order they ask it.
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
//! Self-contained: inline CSS, figures as inline `<svg>` (each in a `role="img"` element
//! with an `aria-label`), equations as presentation MathML (which every current browser
//! renders without a script) with the plain text beside them to copy; no `http:` or
//! `https:` resource, no script, no font. A print stylesheet starts each section on a new
//! page; tables scroll sideways on a phone.

use crate::explain::Pictures;
use hxai_hybrid::tables::TableModel;
use hxai_symreg::expr::xml_escape as esc;
use std::fmt::Write as _;

/// What the page shows beside the model.
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
                ci.map_or_else(
                    || "-".into(),
                    |[lo, hi]| format!("{} to {}", num(lo), num(hi)),
                ),
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
    let _ = write!(
        s,
        "<h3>Correction</h3><p>{} correction, complexity {}, on {}.</p>",
        esc(m.correction.kind.name()),
        m.correction.forms.complexity,
        esc(&m.correction.forms.features.join(", "))
    );
    let corr_mathml = m
        .correction
        .model
        .as_ref()
        .map(|c| c.expr().to_mathml(4))
        .unwrap_or_default();
    s.push_str(&equation(
        None,
        Some("δ"),
        &corr_mathml,
        &m.correction.forms.equation,
    ));
    if let Some(factors) = &m.correction.factors {
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
        s.push_str(&table(
            &format!(
                "hxai hybrid compare: every model on the {} split's test rows",
                c["split"].as_str().unwrap_or("")
            ),
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
    }
    s.push_str("</section>");
    s
}

fn sure_section(m: &TableModel, pictures: Option<&Pictures>) -> String {
    let mut s = String::from("<section id=\"sure\"><h2>How sure</h2>");
    if let Some(sel) = &m.correction.selection {
        let share = match (sel.share, sel.runs) {
            (Some(v), Some(r)) => format!(", given back by {:.0} % of {r} resamples", 100.0 * v),
            _ => String::new(),
        };
        let _ = write!(
            s,
            "<p>The correction was selected by {}; its structure <code>{}</code>{share}.</p>",
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
                        a.share
                            .map_or_else(|| "-".into(), |v| format!("{:.0} %", 100.0 * v)),
                    ]
                })
                .collect();
            s.push_str(&table(
                "Alternatives the data cannot tell apart (within one standard error)",
                &["correction", "complexity", "share of resamples"],
                &rows,
            ));
        }
    }
    if let Some(st) = &m.stability {
        let rows: Vec<Vec<String>> = st
            .structures
            .iter()
            .take(8)
            .map(|x| {
                vec![
                    format!("<code>{}</code>", esc(&x.template)),
                    format!("{:.0} %", 100.0 * x.share),
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
    if m.warnings.is_empty() {
        s.push_str("<p>The fit gave no warning.</p>");
    } else {
        s.push_str("<h3>Warnings of the fit</h3><ul>");
        for w in &m.warnings {
            let _ = write!(s, "<li class=\"warn\">{}</li>", esc(w));
        }
        s.push_str("</ul>");
    }
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
    let q = |s: &str| format!("'{}'", s.replace('\'', "'\\''"));
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
    let mut s = String::from(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">",
    );
    let _ = write!(
        s,
        "<title>hxai report: {}</title><style>{CSS}</style></head><body><h1>Hybrid model of \
         <code>{}</code></h1>",
        esc(&m.target),
        esc(&m.target)
    );
    s.push_str(&model_section(m));
    s.push_str(&scores_section(m, inputs.compare));
    s.push_str(&sure_section(m, inputs.pictures));
    s.push_str(&holds_section(m, inputs.data));
    let data = inputs.data.map_or("TABLE.csv", |(n, _)| n);
    let _ = writeln!(
        s,
        "<section id=\"reproduce\"><h2>How to reproduce</h2><p>Refit (the search settings \
         not stored in the model file at their defaults):</p><pre>{}</pre><p>Written by hxai \
         {} from a model file of schema version {}.</p></section></body></html>",
        esc(&refit_command(m, data)),
        esc(inputs.version),
        m.schema_version
    );
    s
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
