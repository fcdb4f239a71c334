//! Runs both cases: [`compare`] at both splits, the goals measured, the figures drawn.

use super::plots::{error_panel, parity, rows_of};
use super::results::{
    BeyondResults, CaseResult, EquationRow, Goals, ParameterRow, SplitResult, p_of, rmse_of,
};
use super::{
    CaseSpec, DISTRACTOR, GOAL_COMPLEXITY, GOAL_FEATURES, GOAL_P, IDENTIFIER, STAGE, figure_name,
    process_config, rows, specs,
};
use crate::figures::draw;
use crate::{Progress, ReproduceConfig, ReproduceError};
use hxai_hybrid::tables::{Comparison, TableModel, compare};
use hxai_table::Table;

fn split_result(c: &Comparison, table: &Table, extrapolate: Option<&str>) -> SplitResult {
    let m: &TableModel = &c.hybrid;
    let ranges = extrapolate.and_then(|col| {
        let v = table.column(col)?;
        let pick = |rows: &[usize]| {
            let values: Vec<f64> = rows.iter().filter_map(|&i| v.get(i).copied()).collect();
            hxai_eval::extent(&values).ok().map(|e| [e.min, e.max])
        };
        Some([pick(&m.split.train)?, pick(&m.split.test)?])
    });
    let interval = table
        .select_rows(&m.split.test)
        .ok()
        .and_then(|test| m.evaluate_at(&test, hxai_hybrid::DEFAULT_INTERVAL).ok())
        .and_then(|e| e.interval);
    SplitResult {
        intervals: crate::intervals::of_table(
            m,
            table,
            &m.split.test,
            hxai_hybrid::DEFAULT_INTERVAL,
        ),
        interval,
        split: c.split.clone(),
        n_train: c.n_train,
        n_test: c.n_test,
        ranges,
        models: c.models.clone(),
        cv: c.cv.clone(),
        t_tests: c.t_tests.clone(),
        parameters: m
            .physics
            .calibrated
            .iter()
            .map(|n| ParameterRow {
                name: n.clone(),
                initial: m.physics.initial.get(n).copied().unwrap_or(f64::NAN),
                value: m.physics.parameters.get(n).copied().unwrap_or(f64::NAN),
                standard_error: m.physics.standard_errors.get(n).copied().flatten(),
            })
            .collect(),
        correction: EquationRow {
            equation: m.correction.forms.equation.clone(),
            latex: m.correction.forms.latex.clone(),
            complexity: Some(m.correction.forms.complexity),
            features: m.correction.forms.features.clone(),
        },
        hybrid: EquationRow {
            equation: m.hybrid.equation.clone(),
            latex: m.hybrid.latex.clone(),
            complexity: None,
            features: Vec::new(),
        },
    }
}

/// Whether a column role is the engineer's law itself rather than an effect the generator adds.
fn is_law(role: &str) -> bool {
    role.starts_with("kinematic") || role.starts_with("Kienzle")
}

fn goals(spec: &CaseSpec, random: &SplitResult, extra: &SplitResult) -> Goals {
    let below = |s: &SplitResult, other: &str| match (rmse_of(s, "hybrid"), rmse_of(s, other)) {
        (Some(h), Some(o)) => h < o,
        _ => false,
    };
    let hybrid_below_calibrated_physics = below(random, "physics_calibrated");
    let p = p_of(random, "physics_calibrated").unwrap_or(f64::NAN);
    let features = &random.correction.features;
    let complexity = random.correction.complexity.unwrap_or(usize::MAX);
    let role = |f: &str| {
        spec.roles
            .iter()
            .find(|(c, _)| *c == f)
            .map_or("", |(_, r)| *r)
    };
    let mut effects_named: Vec<String> = Vec::new();
    let mut distractors_used = Vec::new();
    for f in features {
        let r = role(f);
        if r == DISTRACTOR || r == IDENTIFIER {
            distractors_used.push(f.clone());
        } else {
            for e in r.split("; ") {
                if !e.is_empty() && !is_law(e) && !effects_named.iter().any(|x| x == e) {
                    effects_named.push(e.to_string());
                }
            }
        }
    }
    let mut effects_missed: Vec<String> = Vec::new();
    for (_, r) in &spec.roles {
        if *r == DISTRACTOR || *r == IDENTIFIER {
            continue;
        }
        for e in r.split("; ") {
            if !is_law(e)
                && !effects_named.iter().any(|x| x == e)
                && !effects_missed.iter().any(|x| x == e)
            {
                effects_missed.push(e.to_string());
            }
        }
    }
    Goals {
        hybrid_below_calibrated_physics,
        p_vs_calibrated_physics: p,
        goal_random_met: hybrid_below_calibrated_physics && p < GOAL_P,
        goal_extrapolation_met: below(extra, "physics_forest"),
        n_features: features.len(),
        complexity,
        goal_size_met: features.len() <= GOAL_FEATURES && complexity <= GOAL_COMPLEXITY,
        effects_named,
        distractors_used,
        effects_missed,
    }
}

/// Runs both cases and renders their figures: the results and `(file name, SVG)` pairs.
///
/// # Errors
/// The generators' or the hybrid's errors, or a figure that cannot be drawn.
pub fn compute(
    cfg: &ReproduceConfig,
    progress: &mut dyn FnMut(Progress),
) -> Result<(BeyondResults, Vec<(String, String)>), ReproduceError> {
    let n = rows(cfg);
    let specs = specs(n, cfg.seed)?;
    let total = 2 * specs.len() as u64;
    let mut done = 0;
    progress(Progress::start(STAGE, total));
    let mut cases = Vec::new();
    let mut files = Vec::new();
    for spec in &specs {
        let mut splits = Vec::new();
        let mut panels = Vec::new();
        for extrapolate in [false, true] {
            let pc = process_config(spec, cfg, extrapolate);
            let folds = if extrapolate { 0 } else { cfg.folds };
            let label = format!(
                "{}: {} split",
                spec.name,
                if extrapolate {
                    "extrapolation"
                } else {
                    "random"
                }
            );
            let mut on_search = |p: &hxai_hybrid::tables::TableProgress| {
                progress(Progress {
                    stage: STAGE,
                    done,
                    total,
                    message: format!("{label}, task {}/{}", p.task, p.tasks),
                });
            };
            let c = compare(&spec.table, &pc, folds, &mut on_search)?;
            if !extrapolate {
                files.push(crate::pages::table(
                    spec.name,
                    &format!("{}.csv", spec.name),
                    &c,
                    &spec.table,
                )?);
            }
            let rows = rows_of(&c.hybrid, spec)?;
            panels.push(parity(
                &rows,
                format!(
                    "{} split, test rows",
                    if extrapolate {
                        "extrapolation"
                    } else {
                        "random"
                    }
                ),
                spec.unit,
                spec.target,
            ));
            if extrapolate {
                panels.push(error_panel(&rows, spec));
            }
            splits.push(split_result(
                &c,
                &spec.table,
                extrapolate.then_some(spec.extrapolate),
            ));
            done += 1;
            progress(Progress::done_of(STAGE, done, total));
        }
        let extrapolation = splits.pop();
        let random = splits.pop();
        let (Some(random), Some(extrapolation)) = (random, extrapolation) else {
            return Err(ReproduceError::Pipeline("a case lost a split".into()));
        };
        let name = figure_name(spec.name);
        files.push((name.clone(), draw(&name, &panels, 3)?));
        cases.push(CaseResult {
            name: spec.name.to_string(),
            title: spec.title.to_string(),
            target: spec.target.to_string(),
            unit: spec.unit.to_string(),
            physics: spec.physics.to_string(),
            init: spec.init.iter().map(|(n, v)| (n.to_string(), *v)).collect(),
            correction_form: spec.form.name().to_string(),
            excluded: spec.exclude.iter().map(|s| s.to_string()).collect(),
            extrapolate: spec.extrapolate.to_string(),
            column_roles: spec
                .roles
                .iter()
                .map(|(c, r)| (c.to_string(), r.to_string()))
                .collect(),
            goals: goals(spec, &random, &extrapolation),
            random,
            extrapolation,
            noise_rel: Some(spec.noise_rel),
        });
    }
    Ok((
        BeyondResults {
            rows: n,
            seed: cfg.seed,
            epochs: cfg.epochs(),
            max_complexity: GOAL_COMPLEXITY,
            folds: cfg.folds,
            test_fraction: cfg.test_fraction,
            cases,
        },
        files,
    ))
}
