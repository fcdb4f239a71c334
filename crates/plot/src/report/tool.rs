//! The recordings' tool model's page ([`tool_report`]) and card ([`tool_card`]): the
//! signal chain as its physics, the correction's scores at the fit, physics against
//! hybrid on the records given ([`tool_inputs`]), its pictures and the command that
//! refits it.

use super::{
    compare_part, correction_part, equation, esc, interval, num, opt, page, pictures_part, quote,
    reproduce_section, selection_part, table, val, warnings_part,
};
use crate::explain::Pictures;
use hxai_hybrid::records::{RecordInput, RecordModel, SamplesTable};
use std::fmt::Write as _;

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
    for (name, id, n, metrics) in [
        (
            "training windows",
            "delta_train",
            t.n_train_windows,
            &t.delta_train,
        ),
        (
            "test windows",
            "delta_test",
            t.n_test_windows,
            &t.delta_test,
        ),
    ] {
        if let Some(x) = metrics {
            rows.push(vec![
                format!("{name} ({n})"),
                val(&[id, "rmse"], x.rmse),
                val(&[id, "r2"], x.r2),
                val(&[id, "mae"], x.mae),
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
        .map(|(name, x)| {
            vec![
                esc(name),
                val(&["evaluation", name, "rmse"], x.rmse),
                val(&["evaluation", name, "r2"], x.r2),
                val(&["evaluation", name, "mae"], x.mae),
            ]
        })
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
            val(&["evaluation", "improvement_pct"], ev.improvement_pct),
            val(
                &["evaluation", "improvement_vs_sine_pct"],
                ev.improvement_vs_sine_pct
            )
        );
        match &ev.t_test {
            Some(tt) => {
                let _ = write!(
                    s,
                    " Paired t-test on the per-window squared errors: t = {}, df = {}, p = {}.",
                    val(&["evaluation", "t_test", "statistic"], tt.statistic),
                    num(tt.df),
                    val(&["evaluation", "t_test", "p_value"], tt.p_value)
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
            .map(|(c, lo, hi)| {
                vec![
                    format!("<code>{}</code>", esc(c)),
                    val(&["range", c, "lo"], *lo),
                    val(&["range", c, "hi"], *hi),
                ]
            })
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
