//! The table hybrid's page ([`table_report`]) and card ([`table_card`]): its calibrated
//! physics, its scores on the fitting table's split, the selection and pictures of its
//! correction, its training ranges and the command that refits it.

use super::{
    ReportInputs, compare_part, correction_part, equation, esc, interval_val, num, opt_val, page,
    pictures_part, quote, reproduce_section, selection_part, share, table, val, warnings_part,
};
use crate::explain::Pictures;
use hxai_hybrid::tables::TableModel;
use std::fmt::Write as _;

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
                val(&["physics", name, "value"], *v),
                opt_val(&["physics", name, "se"], se),
                interval_val(&["physics", name], ci),
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
    if let Some(c) = &m.correction.choice {
        s.push_str(&choice_table(c));
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
    let pair = |name: &str, id: &str, p: &hxai_hybrid::tables::PairScores| {
        vec![
            esc(name),
            val(&[id, "physics", "rmse"], p.physics.rmse),
            val(&[id, "physics", "r2"], p.physics.r2),
            val(&[id, "hybrid", "rmse"], p.hybrid.rmse),
            val(&[id, "hybrid", "r2"], p.hybrid.r2),
        ]
    };
    let mut rows = vec![pair(
        &format!("training rows ({})", m.split.train.len()),
        "train",
        &m.scores.train,
    )];
    if let Some(t) = &m.scores.test {
        rows.push(pair(
            &format!("test rows ({})", m.split.test.len()),
            "test",
            t,
        ));
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
            val(&["black_boxes", "physics_forest"], bb.physics_forest),
            val(&["black_boxes", "boosting"], bb.boosting),
            val(
                &["black_boxes", "hybrid_over_best_black_box"],
                bb.hybrid_over_best_black_box
            ),
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
                    format!(
                        "<code>{}</code>",
                        esc(&hxai_symreg::expr::readable_names(&x.template))
                    ),
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
            .map(|(c, (lo, hi))| {
                vec![
                    format!("<code>{}</code>", esc(c)),
                    val(&["range", c, "lo"], *lo),
                    val(&["range", c, "hi"], *hi),
                ]
            })
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

/// `--form auto`'s choice as a table: each form's cross-validated error with its standard
/// error, the one picked marked, and the rule under it.
fn choice_table(c: &hxai_hybrid::tables::auto::FormChoice) -> String {
    let forms = ["none", "factors", "free"];
    let rows: Vec<Vec<String>> = forms
        .iter()
        .filter_map(|f| c.cv.get(*f).map(|e| (f, e)))
        .map(|(f, e)| {
            vec![
                format!("<code>{f}</code>"),
                num(e.mean),
                num(e.se),
                if c.picked == *f {
                    "picked".into()
                } else {
                    String::new()
                },
            ]
        })
        .collect();
    let mut s = table(
        &format!(
            "How the correction's form was chosen (--form auto): {}",
            c.picked
        ),
        &["form", "held-out mean squared error", "standard error", ""],
        &rows,
    );
    let _ = write!(s, "<p class=\"note\">{}.</p>", esc(&c.rule));
    s
}

/// `--form auto`'s choice in one sentence (the notebook card's).
fn choice_sentence(c: &hxai_hybrid::tables::auto::FormChoice) -> String {
    let errors: Vec<String> = ["none", "factors", "free"]
        .iter()
        .filter_map(|f| {
            c.cv.get(*f)
                .map(|e| format!("{f} {} ± {}", num(e.mean), num(e.se)))
        })
        .collect();
    let what = if c.picked == "none" {
        "the physics alone is as good as any correction these rows support".to_string()
    } else {
        format!("the {} form", c.picked)
    };
    format!(
        "Form auto picked <code>{}</code>: {} (held-out mean squared error {}).",
        esc(&c.picked),
        esc(&what),
        errors.join(", ")
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
    s.push_str(".</p>");
    if let Some(c) = &m.correction.choice {
        let _ = write!(s, "<p>{}</p>", choice_sentence(c));
    }
    if !m.warnings.is_empty() {
        s.push_str("<p>Warnings:</p><ul>");
        for w in &m.warnings {
            let _ = write!(s, "<li>{}</li>", esc(w));
        }
        s.push_str("</ul>");
    }
    s.push_str("</div>");
    s
}
