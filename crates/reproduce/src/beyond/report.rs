//! The section "Beyond the paper" of `docs/results/README.md`.

use super::results::{BeyondResults, CaseResult, SplitResult, rmse_of};
use super::{GOAL_COMPLEXITY, GOAL_FEATURES, figure_name};

/// About four significant digits, no exponent for everyday magnitudes.
fn num(x: f64) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    let a = x.abs();
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        format!("{x:.3e}")
    } else if a >= 1000.0 {
        format!("{x:.0}")
    } else if a >= 100.0 {
        format!("{x:.1}")
    } else if a >= 10.0 {
        format!("{x:.2}")
    } else if a >= 1.0 {
        format!("{x:.3}")
    } else {
        format!("{x:.4}")
    }
}

fn p_text(p: f64) -> String {
    if !p.is_finite() {
        "–".into()
    } else if p < 1e-4 {
        format!("{p:.1e}")
    } else {
        format!("{p:.4}")
    }
}

fn yes(b: bool) -> &'static str {
    if b { "**yes**" } else { "**no**" }
}

fn model_table(out: &mut String, s: &SplitResult, unit: &str) {
    out.push_str(&format!(
        "| model | R² | RMSE ({unit}) | MAE ({unit}) | paired t-test of the hybrid vs it: t, p |\n|---|---|---|---|---|\n"
    ));
    for m in &s.models {
        let t = s
            .t_tests
            .iter()
            .find(|t| t.baseline == m.name)
            .map_or("–".to_string(), |t| match &t.test {
                Some(tt) => format!("{:.2}, {}", tt.statistic, p_text(tt.p_value)),
                None => "undefined (the same errors on every row)".to_string(),
            });
        out.push_str(&format!(
            "| {} | {:.4} | {} | {} | {} |\n",
            m.name,
            m.metrics.r2,
            num(m.metrics.rmse),
            num(m.metrics.mae),
            t
        ));
    }
}

fn split_section(
    out: &mut String,
    case: &CaseResult,
    s: &SplitResult,
    heading: &str,
    folds: usize,
) {
    out.push_str(&format!(
        "#### {heading}: {} train / {} test rows\n\n",
        s.n_train, s.n_test
    ));
    if let Some([tr, te]) = s.ranges {
        out.push_str(&format!(
            "Train on `{}` in [{}, {}], test on [{}, {}].\n\n",
            case.extrapolate,
            num(tr[0]),
            num(tr[1]),
            num(te[0]),
            num(te[1])
        ));
    }
    model_table(out, s, &case.unit);
    out.push('\n');
    if let Some(iv) = &s.interval {
        let how = match iv.method {
            hxai_hybrid::IntervalMethod::Conformal => {
                "conformal, CV+ over 5 folds of the training rows; every method side by side \
                 in \"Prediction intervals by method\" below"
            }
            hxai_hybrid::IntervalMethod::Split => "split conformal",
            hxai_hybrid::IntervalMethod::Delta => {
                "delta method through the whole equation plus the residual variance"
            }
        };
        out.push_str(&format!(
            "Prediction intervals of the hybrid at {:.0} % ({how}; `hxai hybrid evaluate \
             --json`): coverage {:.1} % of the {} test rows.\n\n",
            100.0 * iv.nominal,
            100.0 * iv.coverage,
            iv.n
        ));
    }
    if !s.cv.is_empty() {
        out.push_str(&format!(
            "Cross-validation over {folds} random folds of all rows:\n\n| model | R² mean ± sd | 95 % CI (Student t) |\n|---|---|---|\n"
        ));
        for c in &s.cv {
            out.push_str(&format!(
                "| {} | {:.4} ± {:.4} | {:.4} – {:.4} |\n",
                c.name, c.r2_mean, c.r2_sd, c.r2_ci[0], c.r2_ci[1]
            ));
        }
        out.push('\n');
    }
    if !s.parameters.is_empty() {
        out.push_str("| parameter | as given | calibrated | standard error |\n|---|---|---|---|\n");
        for p in &s.parameters {
            out.push_str(&format!(
                "| `{}` | {} | {} | {} |\n",
                p.name,
                num(p.initial),
                num(p.value),
                p.standard_error.map_or("–".to_string(), num)
            ));
        }
        out.push('\n');
    }
    out.push_str(&format!(
        "Correction ({}, complexity {}, features: {}):\n\n```text\ndelta = {}\n```\n\nHybrid as one equation:\n\n```text\n{} = {}\n```\n\n$${}$$\n\n",
        case.correction_form,
        s.correction.complexity.map_or("–".to_string(), |c| c.to_string()),
        crate::report::list_or_none(&s.correction.features),
        s.correction.equation,
        case.target,
        s.hybrid.equation,
        s.hybrid.latex
    ));
}

fn verdicts(case: &CaseResult) -> String {
    let g = &case.goals;
    let r = &case.random;
    let e = &case.extrapolation;
    let rm = |s: &SplitResult, n: &str| rmse_of(s, n).map_or("–".to_string(), num);
    let mut out = String::new();
    out.push_str(&format!(
        "Goals of issue 13 on this case:\n\n- random split, hybrid RMSE below the calibrated physics with p < 1e-3: {} (RMSE {} vs {} {}, p = {}).\n",
        yes(g.goal_random_met),
        rm(r, "hybrid"),
        rm(r, "physics_calibrated"),
        case.unit,
        p_text(g.p_vs_calibrated_physics)
    ));
    out.push_str(&format!(
        "- extrapolation split, hybrid RMSE below physics + forest: {} (RMSE {} vs {} {}).\n",
        yes(g.goal_extrapolation_met),
        rm(e, "hybrid"),
        rm(e, "physics_forest"),
        case.unit
    ));
    out.push_str(&format!(
        "- correction with at most {GOAL_FEATURES} features and complexity at most {GOAL_COMPLEXITY}: {} ({} features, complexity {}).\n",
        yes(g.goal_size_met),
        g.n_features,
        g.complexity
    ));
    out.push_str(&format!(
        "- effects of the generator the random split's correction names (through its features): {}{}.\n",
        crate::report::list_or_none(&g.effects_named),
        if g.distractors_used.is_empty() {
            String::new()
        } else {
            format!(
                "; it also uses {} (no effect in the generator)",
                g.distractors_used.join(", ")
            )
        }
    ));
    out.push_str(&format!(
        "- effects of the generator it does not name: {}.\n",
        crate::report::list_or_none(&g.effects_missed)
    ));
    // Where the hybrid does not win, say so in words.
    let mut losses = Vec::new();
    for (s, label) in [(r, "random"), (e, "extrapolation")] {
        if let Some(h) = rmse_of(s, "hybrid") {
            for m in &s.models {
                if m.name != "hybrid" && m.metrics.rmse <= h {
                    losses.push(format!(
                        "`{}` matches or beats it at the {label} split (test RMSE {})",
                        m.name,
                        num(m.metrics.rmse)
                    ));
                }
            }
        }
    }
    let hybrid_cv = r.cv.iter().find(|c| c.name == "hybrid").map(|c| c.r2_mean);
    if let Some(h) = hybrid_cv {
        for c in &r.cv {
            if c.name != "hybrid" && c.r2_mean >= h {
                losses.push(format!(
                    "`{}` in cross-validation (mean R² {:.4} vs {h:.4})",
                    c.name, c.r2_mean
                ));
            }
        }
    }
    if !g.goal_random_met {
        losses.push(format!(
            "the paired t-test against the calibrated physics at the random split, which does not reach p < 1e-3 (p = {})",
            p_text(g.p_vs_calibrated_physics)
        ));
    }
    if losses.is_empty() {
        out.push_str(
            "\nThe hybrid has the lowest test RMSE of all models at both splits and the highest mean R² in cross-validation.\n\n",
        );
    } else {
        out.push_str(&format!(
            "\n**Where the hybrid does not win**: {}.\n\n",
            losses.join("; ")
        ));
    }
    out
}

/// The section of `docs/results/README.md`.
pub fn markdown(b: &BeyondResults) -> String {
    let mut out = String::new();
    out.push_str("\n## Beyond the paper: the framework on three more processes\n\n");
    out.push_str(&format!(
        "The paper's framework on three more manufacturing processes, from tables made by the seeded generators of `hxai_sim::cases` (`hxai simulate --case NAME`). Their hidden truths, the effects they add to the engineer's law and the sources are in [../cases.md](../cases.md), so the corrections below can be judged against what the generator put in. Each case runs `hxai hybrid compare` (library: `hxai_hybrid::tables::compare`) with fixed settings chosen from the physics before any result was seen: {} rows, seed {}, {} search epochs, correction complexity at most {}, {} % held out; models on the same split: `physics` (the law with its given values), `physics_calibrated` (its parameters fitted by Levenberg-Marquardt on the training rows), `symbolic` (symbolic regression of the target alone), `physics_forest` (calibrated physics with a random forest on the same correction target), `boosting` (gradient boosting of the target alone, scikit-learn's `HistGradientBoostingRegressor` defaults written in `hxai-baselines`) and `hybrid` (calibrated physics with the symbolic correction). The random split is cross-validated over {} folds; the extrapolation split trains on the low {} % of one column and tests on the top {} %. Which runs to measure next on tool life and on a held-out wear process (`hxai hybrid design` in a closed loop against random runs and a Latin hypercube, with its plots): [design_loop.md](design_loop.md).\n\n",
        b.rows,
        b.seed,
        b.epochs,
        b.max_complexity,
        (b.test_fraction * 100.0).round(),
        b.folds,
        ((1.0 - b.test_fraction) * 100.0).round(),
        (b.test_fraction * 100.0).round(),
    ));
    for c in &b.cases {
        out.push_str(&format!("### {} (`--case {}`)\n\n", c.title, c.name));
        let init: Vec<String> = c.init.iter().map(|(n, v)| format!("{n}={v}")).collect();
        out.push_str(&format!(
            "Physics `{}` = `{}`, calibrating {} (as given: {}); {} correction; features: every column except `{}` and {}; extrapolation on `{}`.\n\n",
            c.target,
            c.physics,
            c.init.keys().map(|k| format!("`{k}`")).collect::<Vec<_>>().join(", "),
            init.join(", "),
            c.correction_form,
            c.target,
            c.excluded.iter().map(|k| format!("`{k}`")).collect::<Vec<_>>().join(", "),
            c.extrapolate
        ));
        split_section(&mut out, c, &c.random, "Random split", b.folds);
        split_section(
            &mut out,
            c,
            &c.extrapolation,
            "Extrapolation split",
            b.folds,
        );
        out.push_str(&verdicts(c));
        out.push_str(&format!(
            "![{}: predicted vs measured at both splits; error vs {}]({})\n\n",
            c.title,
            c.extrapolate,
            figure_name(&c.name)
        ));
    }
    out
}
