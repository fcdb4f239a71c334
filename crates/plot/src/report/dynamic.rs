//! The page of a dynamic hybrid (`hxai dynamic fit`, issue 69): the hybrid ODE, the
//! calibrated physics with its intervals, each state's correction, the free-run scores, the
//! runs drawn against their measurements (with the conformal band), the warnings and the
//! refit command.

use super::{equation, esc, interval_val, num, opt_val, page, quote, reproduce_section, table};
use super::{figure, val, warnings_part};
use crate::{Panel, Series, draw};
use hxai_hybrid::dynamic::{DynamicModel, DynamicPrediction};
use hxai_symreg::Table;
use std::fmt::Write as _;

/// Runs drawn on the page at most (the first ones of the table).
pub const DRAWN_RUNS: usize = 6;

/// The hybrid ODE as MathML (`STATE' = physics + correction` per state, stacked) and as
/// text.
fn ode_mathml(m: &DynamicModel) -> (String, String) {
    let text = m.hybrid_equation.clone();
    let Ok(eqs) = m.equations() else {
        return (format!("<mtext>{}</mtext>", esc(&text)), text);
    };
    let mut s = String::from("<mtable>");
    for e in &eqs {
        let rhs = match (&e.correction, m.correction_kind.name()) {
            (None, _) => e.physics.to_mathml(4),
            (Some(c), "multiplicative") => format!(
                "<mrow><mo>(</mo>{}<mo>)</mo><mo>&#x22C5;</mo><mo>(</mo><mn>1</mn><mo>+</mo>{}\
                 <mo>)</mo></mrow>",
                e.physics.to_mathml(4),
                c.to_mathml(4)
            ),
            (Some(c), _) => format!(
                "<mrow>{}<mo>+</mo><mrow><mo>(</mo>{}<mo>)</mo></mrow></mrow>",
                e.physics.to_mathml(4),
                c.to_mathml(4)
            ),
        };
        let _ = write!(
            s,
            "<mtr><mtd><msup><mi>{}</mi><mo>&#x2032;</mo></msup><mo>=</mo>{rhs}</mtd></mtr>",
            esc(&e.state)
        );
    }
    s.push_str("</mtable>");
    (s, text)
}

fn model_section(m: &DynamicModel) -> String {
    let mut s = String::from("<section id=\"model\"><h2>The model</h2>");
    let (mm, text) = ode_mathml(m);
    let _ = write!(
        s,
        "<p>The engineer's ODE, calibrated through its trajectories, with a learned {} \
         correction inside the derivative:</p>",
        esc(m.correction_kind.name())
    );
    s.push_str(&equation(Some("hybrid-equation"), None, &mm, &text));
    let _ = write!(
        s,
        "<p>Physics as written: <code>{}</code>.</p>",
        esc(&m.ode)
    );
    let rows: Vec<Vec<String>> = m
        .physics_calibrated
        .iter()
        .map(|(p, e)| {
            vec![
                esc(p),
                val(&["physics", p], e.value),
                opt_val(&["physics", p, "se"], e.std_error),
                interval_val(&["physics", p], e.ci95),
                m.parameters
                    .get(p)
                    .map_or_else(|| "-".into(), |v| val(&["hybrid", p], *v)),
            ]
        })
        .collect();
    if !rows.is_empty() {
        s.push_str(&table(
            "Calibrated parameters: the physics alone (with standard errors and 95 % \
             intervals from the trajectories' Jacobian), and in the hybrid (refitted with the \
             correction)",
            &[
                "parameter",
                "physics",
                "std. error",
                "95 % interval",
                "hybrid",
            ],
            &rows,
        ));
    }
    for c in &m.corrections {
        let _ = write!(
            s,
            "<h3>Correction of {}'</h3><p>Form <code>{}</code>: <code>{}</code>",
            esc(&c.state),
            c.form.name(),
            esc(&c.equation)
        );
        if c.model.is_some() {
            let _ = write!(
                s,
                "; reads {}{}; found on {} of {} samples' smoothed derivatives (as found \
                 there: <code>{}</code>), then refitted through the ODE. Outside its training \
                 range each column is held at the range's edge.",
                esc(&c.features.join(", ")),
                if c.groupings.is_empty() {
                    String::new()
                } else {
                    format!(" (through {})", esc(&c.groupings.join(", ")))
                },
                c.samples[0],
                c.samples[1],
                esc(&c.searched_equation)
            );
        }
        s.push_str("</p>");
        if let Some(ch) = &c.choice {
            let _ = write!(s, "<p>{}</p>", esc(&ch.sentence()));
        }
    }
    s.push_str("</section>");
    s
}

fn scores_section(m: &DynamicModel) -> String {
    let mut s = String::from("<section id=\"scores\"><h2>How good</h2>");
    let rows: Vec<Vec<String>> = ["physics", "physics_calibrated", "hybrid"]
        .iter()
        .filter_map(|k| {
            m.train_rmse
                .get(*k)
                .map(|v| vec![esc(k), val(&["train-rmse", k], *v)])
        })
        .collect();
    s.push_str(&table(
        &format!(
            "Free-run RMSE on the {} training run(s) ({} samples), each run simulated from \
             its first reading",
            m.training.runs.len(),
            m.training.samples
        ),
        &["model", "RMSE"],
        &rows,
    ));
    s.push_str(
        "<p>Held-out runs: <code>hxai dynamic compare</code> (physics, calibrated physics, \
         hybrid and a NARX boosting by free-run error on runs the fit did not see).</p>",
    );
    s.push_str("</section>");
    s
}

/// The first [`DRAWN_RUNS`] runs of `data`: measured points, the calibrated physics and the
/// hybrid over time, and the band where `p` has one; one panel per run and state.
fn runs_figure(m: &DynamicModel, data: &Table, p: &DynamicPrediction) -> Option<String> {
    let time = data.column(&m.time)?;
    let runs: Vec<f64> = match &m.run {
        Some(r) => {
            let mut ids: Vec<f64> = Vec::new();
            for v in data.column(r)? {
                if !ids.contains(v) {
                    ids.push(*v);
                }
            }
            ids
        }
        None => vec![f64::NAN],
    };
    let mut panels = Vec::new();
    for &id in runs.iter().take(DRAWN_RUNS) {
        let rows: Vec<usize> = match &m.run {
            Some(r) => {
                let col = data.column(r)?;
                let mut rows: Vec<usize> = (0..data.n_rows()).filter(|&i| col[i] == id).collect();
                rows.sort_by(|&a, &b| time[a].total_cmp(&time[b]));
                rows
            }
            None => {
                let mut rows: Vec<usize> = (0..data.n_rows()).collect();
                rows.sort_by(|&a, &b| time[a].total_cmp(&time[b]));
                rows
            }
        };
        for (j, state) in m.states.iter().enumerate() {
            let measured = data.column(state)?;
            let line = |v: &[f64]| rows.iter().map(|&i| (time[i], v[i])).collect::<Vec<_>>();
            let mut series = vec![Series::points(
                "measured",
                rows.iter().map(|&i| (time[i], measured[i])).collect(),
            )];
            if let (Some(lo), Some(hi)) = (&p.lower, &p.upper) {
                let band: Vec<(f64, f64, f64)> = rows
                    .iter()
                    .map(|&i| (time[i], lo[j][i], hi[j][i]))
                    .filter(|(_, a, b)| a.is_finite() && b.is_finite())
                    .collect();
                if !band.is_empty() {
                    series.push(Series::band("band", &band));
                }
            }
            series.push(Series::dashed("calibrated physics", line(&p.physics[j])));
            series.push(Series::line("hybrid", line(&p.hybrid[j])));
            panels.push(Panel {
                title: match &m.run {
                    Some(r) => format!("{r} {id}: {state}"),
                    None => state.clone(),
                },
                x_label: m.time.clone(),
                y_label: state.clone(),
                series,
            });
        }
    }
    draw("runs", &panels, 2).ok()
}

/// The command that refits the model from `data`.
pub fn dynamic_refit_command(m: &DynamicModel, data: &str) -> String {
    let s = &m.settings;
    let q = quote;
    let mut c = format!("hxai dynamic fit --data {} --time {}", q(data), q(&m.time));
    if let Some(r) = &m.run {
        let _ = write!(c, " --run {}", q(r));
    }
    let _ = write!(c, " --state {}", q(&m.states.join(",")));
    if !m.inputs.is_empty() {
        let _ = write!(c, " --inputs {}", q(&m.inputs.join(",")));
    }
    let _ = write!(c, " --ode {}", q(&m.ode));
    let pairs = |v: &std::collections::BTreeMap<String, f64>| {
        v.iter()
            .map(|(k, x)| format!("{k}={x}"))
            .collect::<Vec<_>>()
            .join(",")
    };
    if !m.calibrated.is_empty() {
        let _ = write!(c, " --calibrate {}", q(&m.calibrated.join(",")));
        let init: std::collections::BTreeMap<String, f64> = m
            .calibrated
            .iter()
            .filter_map(|p| m.starting.get(p).map(|v| (p.clone(), *v)))
            .collect();
        let _ = write!(c, " --init {}", q(&pairs(&init)));
    }
    let fixed: std::collections::BTreeMap<String, f64> = m
        .starting
        .iter()
        .filter(|(p, _)| !m.calibrated.contains(p))
        .map(|(p, v)| (p.clone(), *v))
        .collect();
    if !fixed.is_empty() {
        let _ = write!(c, " --set {}", q(&pairs(&fixed)));
    }
    let initial = match m.initial {
        hxai_hybrid::dynamic::Initial::First => "first",
        hxai_hybrid::dynamic::Initial::Estimate => "estimate",
    };
    let _ = write!(
        c,
        " --correction {} --form {} --initial {initial} --smooth {} --seed {} \
         --conformal-folds {} --out MODEL.json",
        m.correction_kind.name(),
        s.form.name(),
        s.smooth,
        s.seed,
        s.conformal_folds
    );
    if !s.periodic.is_empty() {
        let _ = write!(c, " --periodic {}", q(&s.periodic.join(",")));
    }
    c
}

/// The page of a dynamic hybrid; with `data` (its name and table), its runs drawn with the
/// model's free runs and, where the model has conformal scores, its 0.9 band.
pub fn dynamic_report(m: &DynamicModel, data: Option<(&str, &Table)>, version: &str) -> String {
    let mut body = vec![model_section(m), scores_section(m)];
    let mut notes = Vec::new();
    let mut sure = String::from("<section id=\"sure\"><h2>How sure</h2>");
    match &m.conformal {
        Some(c) => {
            let rows: Vec<Vec<String>> = m
                .states
                .iter()
                .enumerate()
                .map(|(j, st)| {
                    let at = |p: f64| {
                        m.band(p)
                            .ok()
                            .and_then(|b| b.get(j).copied())
                            .filter(|v| v.is_finite())
                            .map_or_else(|| "-".into(), |v| val(&["band", st, &p.to_string()], v))
                    };
                    vec![esc(st), at(0.8), at(0.9)]
                })
                .collect();
            sure.push_str(&table(
                &format!(
                    "Half-width of the conformal band over runs ({} folds of the {} training                      runs; it holds a whole new run's trajectory at the level when runs are                      exchangeable, and is optimistic: the folds keep the correction's                      structure)",
                    c.folds,
                    m.training.runs.len()
                ),
                &["state", "0.8", "0.9"],
                &rows,
            ));
        }
        None => sure.push_str(
            "<p>No conformal band: the model was fitted on fewer than 3 runs or with 0 \
             conformal folds.</p>",
        ),
    }
    if let Some((name, t)) = data {
        let level = m.conformal.as_ref().map(|_| 0.9);
        let pred = m.predict(t, level).or_else(|_| m.predict(t, None));
        let fig = match &pred {
            Ok(p) => {
                notes.extend(p.warnings.iter().cloned());
                runs_figure(m, t, p)
            }
            Err(e) => {
                notes.push(format!("no figure of the runs: {e}"));
                None
            }
        };
        let _ = write!(
            sure,
            "<p>{} ({} rows): each run simulated from its first reading with its inputs; at \
             most the first {DRAWN_RUNS} runs are drawn{}.</p>",
            esc(name),
            t.n_rows(),
            if level.is_some() {
                ", with the band at 0.9"
            } else {
                ""
            }
        );
        if let Some(svg) = fig {
            sure.push_str(&figure(
                &svg,
                "Measured states against the calibrated physics and the hybrid, per run",
            ));
        }
    }
    sure.push_str("</section>");
    body.push(sure);
    let mut warnings = m.warnings.clone();
    warnings.extend(notes);
    let mut holds = String::from("<section id=\"holds\"><h2>Where it holds</h2>");
    let _ = write!(
        holds,
        "<p>Fitted on {} run(s), {} samples{}.</p>",
        m.training.runs.len(),
        m.training.samples,
        m.training
            .test_after
            .map_or(String::new(), |t| format!(", each cut at time {}", num(t)))
    );
    let ranges: Vec<Vec<String>> = m
        .corrections
        .iter()
        .filter_map(|c| c.model.as_ref().map(|mm| (c, mm)))
        .flat_map(|(c, mm)| {
            mm.feature_names
                .iter()
                .zip(&c.ranges)
                .filter(|(f, _)| {
                    mm.program
                        .vars()
                        .iter()
                        .any(|&j| mm.feature_names[j as usize] == **f)
                })
                .map(|(f, [lo, hi])| vec![esc(f), num(*lo), num(*hi)])
                .collect::<Vec<_>>()
        })
        .collect();
    if !ranges.is_empty() {
        holds.push_str(&table(
            "The correction's columns on the training samples (held at these edges beyond them)",
            &["column", "low", "high"],
            &ranges,
        ));
    }
    holds.push_str(&warnings_part(&warnings, "The fit raised no warning."));
    holds.push_str("</section>");
    body.push(holds);
    body.push(reproduce_section(
        &dynamic_refit_command(m, data.map_or("TABLE.csv", |(n, _)| n)),
        version,
        m.schema_version,
    ));
    let title = format!("hxai dynamic model of {}", m.states.join(", "));
    page(&title, &esc(&title), &body.concat())
}

/// A compact card of a dynamic hybrid for Jupyter: the ODE, the calibrated parameters and
/// the free-run scores.
pub fn dynamic_card(m: &DynamicModel) -> String {
    let mut s = String::from("<div class=\"hxai-card\">");
    let (mm, text) = ode_mathml(m);
    s.push_str(&equation(None, None, &mm, &text));
    let params: Vec<String> = m
        .physics_calibrated
        .iter()
        .map(|(p, e)| match e.ci95 {
            Some([lo, hi]) => format!(
                "{} = {} (95 % {} to {})",
                esc(p),
                num(e.value),
                num(lo),
                num(hi)
            ),
            None => format!("{} = {}", esc(p), num(e.value)),
        })
        .collect();
    if !params.is_empty() {
        let _ = write!(s, "<p>Calibrated physics: {}.</p>", params.join("; "));
    }
    let r = |k: &str| m.train_rmse.get(k).copied().map_or_else(|| "-".into(), num);
    let _ = write!(
        s,
        "<p>Free-run RMSE on {} training run(s): physics {}, calibrated physics {}, hybrid {}.</p>",
        m.training.runs.len(),
        r("physics"),
        r("physics_calibrated"),
        r("hybrid")
    );
    s.push_str("</div>");
    s
}
