//! What `hxai hybrid` prints in text mode: the fitted model, interval coverage and the
//! comparison table (the `--json` documents are the library's types, serialised).
use hxai_data::format_number as n;
use hxai_hybrid::tables::{Comparison, TableModel};

fn fmt_se(se: Option<&Option<f64>>) -> String {
    match se {
        Some(Some(s)) => format!(" +- {}", n(*s)),
        Some(None) => " +- (undefined)".into(),
        None => String::new(),
    }
}

#[allow(clippy::print_stdout)]
pub(super) fn print_model(m: &TableModel) {
    println!("physics: {}", m.physics.equation);
    for (name, v) in &m.physics.parameters {
        let slot = m.slots.iter().find(|s| s.uncertainty.contains_key(name));
        let tag = match (m.physics.calibrated.contains(name), slot) {
            (true, Some(s)) => format!("slot {}, calibrated", s.name),
            (true, None) => "calibrated".into(),
            // a slot's scale beside a law's own is held where the rows cannot tell them apart
            (false, Some(s)) => format!("slot {}, held: not separable from the law's", s.name),
            (false, None) => "set".into(),
        };
        let ci = m
            .physics
            .params
            .get(name)
            .and_then(|p| p.ci95)
            .map(|[lo, hi]| format!(", 95 % CI [{}, {}]", n(lo), n(hi)))
            .unwrap_or_default();
        println!(
            "  {name} = {}{}{ci} ({tag})",
            n(*v),
            fmt_se(m.physics.standard_errors.get(name))
        );
    }
    for s in &m.slots {
        println!(
            "slot {}({}) ({}, {} round(s)): {}",
            s.name,
            s.columns.join(", "),
            s.form,
            s.rounds,
            s.equation
        );
    }
    println!(
        "correction ({}, complexity {}): {}",
        m.correction.kind.name(),
        m.correction.forms.complexity,
        m.correction.forms.equation
    );
    if let Some(choice) = &m.correction.choice {
        println!("{}", choice.sentence());
    }
    if let Some(factors) = &m.correction.factors {
        for f in factors {
            let on = f
                .column
                .clone()
                .or_else(|| f.columns.as_ref().map(|c| c.join(" x ")))
                .unwrap_or_default();
            println!(
                "  factor of {on} ({}, complexity {}): {}",
                f.shape.name(),
                f.complexity,
                f.equation
            );
        }
    }
    if let Some(cp) = &m.correction_per {
        println!(
            "correction constants per level of `{}` (the equation above has the shared ones):",
            cp.column
        );
        for l in cp.lines() {
            println!("{l}");
        }
    }
    println!("hybrid: {} = {}", m.target, m.hybrid.equation);
    if let Some(j) = &m.joint {
        println!(
            "joint refit: train RMSE {} -> {} (two-stage correction: {})",
            n(j.sequential_train_rmse),
            n(j.joint_train_rmse),
            j.sequential_correction
        );
    }
    let s = &m.scores;
    println!(
        "train ({} rows): physics RMSE {} R^2 {:.4}, hybrid RMSE {} R^2 {:.4}",
        m.split.train.len(),
        n(s.train.physics.rmse),
        s.train.physics.r2,
        n(s.train.hybrid.rmse),
        s.train.hybrid.r2
    );
    if let Some(t) = &s.test {
        println!(
            "test  ({} rows, {} split): physics RMSE {} R^2 {:.4}, hybrid RMSE {} R^2 {:.4}",
            m.split.test.len(),
            m.split.kind,
            n(t.physics.rmse),
            t.physics.r2,
            n(t.hybrid.rmse),
            t.hybrid.r2
        );
    }
    if let Some(b) = &s.black_boxes {
        println!(
            "black boxes on the test rows{}: physics + forest RMSE {}, boosting RMSE {}; the \
             hybrid has {:.2} times the best black box's test RMSE",
            b.training_rows
                .map(|r| format!(" (trained on a sample of {r} training rows)"))
                .unwrap_or_default(),
            n(b.physics_forest),
            n(b.boosting),
            b.hybrid_over_best_black_box
        );
    }
    if let Some(sample) = &m.search_sample {
        println!(
            "structure searched on a sample of {} of the {} training rows (stratified on the \
             target); calibration and constants on every training row",
            sample.rows, sample.training_rows
        );
    }
}

#[allow(clippy::print_stdout)]
pub(super) fn print_interval(iv: &hxai_hybrid::IntervalReport, what: &str) {
    println!(
        "prediction intervals ({}) at {:.1} %: coverage {:.1} % of {} {what}, median width {}",
        iv.method.name(),
        100.0 * iv.nominal,
        100.0 * iv.coverage,
        iv.n,
        iv.median_width.map_or_else(|| "(none)".to_string(), n)
    );
}

#[allow(clippy::print_stdout)]
pub(super) fn print_comparison(c: &Comparison) {
    println!(
        "{} split: {} train rows, {} test rows",
        c.split, c.n_train, c.n_test
    );
    println!("{:<20} {:>10} {:>14} {:>14}", "model", "R^2", "RMSE", "MAE");
    for m in &c.models {
        println!(
            "{:<20} {:>10.4} {:>14} {:>14}",
            m.name,
            m.metrics.r2,
            n(m.metrics.rmse),
            n(m.metrics.mae)
        );
    }
    if !c.cv.is_empty() {
        println!(
            "{}-fold CV, R^2 mean +- sd [95 % Student-t interval]:",
            c.folds
        );
        for s in &c.cv {
            println!(
                "{:<20} {:>8.4} +- {:.4} [{:.4}, {:.4}]",
                s.name, s.r2_mean, s.r2_sd, s.r2_ci[0], s.r2_ci[1]
            );
        }
    }
    for t in &c.t_tests {
        match (&t.test, &t.reason) {
            (Some(tt), _) => println!(
                "paired t-test {} vs {} (squared errors): t = {:.3}, p = {}",
                t.model,
                t.baseline,
                tt.statistic,
                n(tt.p_value)
            ),
            (None, reason) => println!(
                "paired t-test {} vs {}: none ({})",
                t.model,
                t.baseline,
                reason.as_deref().unwrap_or("undefined")
            ),
        }
    }
    if let Some(iv) = &c.interval {
        print_interval(iv, "test rows");
    }
    println!(
        "hybrid: {:.2} times the best black box's test RMSE ({}, {})",
        c.hybrid_over_best_black_box,
        c.best_black_box.name,
        n(c.best_black_box.rmse)
    );
    // issue 68: the glass box an engineer compares with lives in Python
    println!(
        "EBM (InterpretML's glass box): not run by the command line; Python's hxai.compare \
         adds it beside boosting where the interpret package is installed"
    );
    println!("hybrid: {} = {}", c.target, c.hybrid.hybrid.equation);
}
