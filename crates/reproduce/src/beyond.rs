//! "Beyond the paper: the framework on two more processes": the hybrid of any process
//! (`hxai_hybrid::process`) on the roughness and cutting-force tables of `hxai_sim::cases`
//! (hidden truths in `docs/cases.md`).
//!
//! Per case: [`compare_process`] at a random split (with k-fold cross-validation) and at an
//! extrapolation split (train on the low values of one column, test on the high ones), the
//! calibrated parameters with standard errors, the correction and the hybrid as equations,
//! the issue's goals measured (not assumed), and one figure (predicted vs measured for the
//! calibrated physics and the hybrid at both splits; error vs the extrapolated column).
//!
//! Design decision: the settings of each case (physics, calibrated parameters, correction
//! form, extrapolated column) are fixed here from the physics of the case, before looking at
//! any result, and are printed with the results; nothing is chosen by its score.

use crate::figures::{Panel, Series, draw};
use crate::{Progress, ReproduceConfig, ReproduceError};
use hxai_hybrid::process::{
    Comparison, CorrectionForm, ModelScore, ProcessConfig, ProcessModel, compare_process,
};
use hxai_sim::cases::{
    CuttingForceConfig, RoughnessConfig, cutting_force, cutting_force::HANDBOOK_KC11,
    cutting_force::HANDBOOK_MC, roughness,
};
use hxai_table::Table;
use serde::Serialize;
use std::collections::BTreeMap;

/// Stage name of the progress events of this section.
pub const STAGE: &str = "beyond the paper";

/// Significance level of the goal "hybrid below calibrated physics" (issue 13).
pub const GOAL_P: f64 = 1e-3;
/// Most features the correction may use by default (issue 13's goal).
pub const GOAL_FEATURES: usize = 4;
/// Highest complexity of the correction by default (issue 13's goal).
pub const GOAL_COMPLEXITY: usize = 10;

/// The whole section, as it goes into `results.json` under `beyond_the_paper`.
#[derive(Debug, Clone, Serialize)]
pub struct BeyondResults {
    /// Rows per table.
    pub rows: usize,
    /// Seed of the generators, splits, searches and forests.
    pub seed: u64,
    /// Search epochs.
    pub epochs: usize,
    /// Highest correction complexity allowed.
    pub max_complexity: usize,
    /// Cross-validation folds (random split only).
    pub folds: usize,
    /// Held-out fraction of both splits.
    pub test_fraction: f64,
    /// One entry per process.
    pub cases: Vec<CaseResult>,
}

/// One process: its settings and both splits.
#[derive(Debug, Clone, Serialize)]
pub struct CaseResult {
    /// `roughness` or `cutting_force` (the `hxai simulate --case` name).
    pub name: String,
    /// Human title.
    pub title: String,
    /// Target column.
    pub target: String,
    /// Unit of the target.
    pub unit: String,
    /// The physics equation as given.
    pub physics: String,
    /// Calibrated parameters with their starting values (what `physics` means).
    pub init: BTreeMap<String, f64>,
    /// `additive` or `multiplicative`.
    pub correction_form: String,
    /// Columns kept out of the correction's features (identifiers).
    pub excluded: Vec<String>,
    /// The column of the extrapolation split.
    pub extrapolate: String,
    /// What each column stands for in the generator (`docs/cases.md`).
    pub column_roles: BTreeMap<String, String>,
    /// The random split (with cross-validation).
    pub random: SplitResult,
    /// The extrapolation split.
    pub extrapolation: SplitResult,
    /// The issue's goals, measured.
    pub goals: Goals,
}

/// One split of one case.
#[derive(Debug, Clone, Serialize)]
pub struct SplitResult {
    /// `random` or `extrapolate`.
    pub split: String,
    /// Training rows.
    pub n_train: usize,
    /// Test rows.
    pub n_test: usize,
    /// Range of the extrapolated column on the training and the test rows.
    pub ranges: Option<[[f64; 2]; 2]>,
    /// Test-split scores of every model.
    pub models: Vec<ModelScore>,
    /// k-fold cross-validation (empty at the extrapolation split).
    pub cv: Vec<CvRow>,
    /// Paired t-tests of the hybrid's squared errors against each other model's.
    pub t_tests: Vec<TTestRow>,
    /// Physics parameters after calibration.
    pub parameters: Vec<ParameterRow>,
    /// The correction.
    pub correction: EquationRow,
    /// The whole hybrid as one equation.
    pub hybrid: EquationRow,
    /// Coverage of the hybrid's 95 % prediction intervals on the test rows (`None` when
    /// they cannot be computed).
    pub interval: Option<hxai_hybrid::IntervalReport>,
}

/// Cross-validated R² of one model.
#[derive(Debug, Clone, Serialize)]
pub struct CvRow {
    /// Model name.
    pub name: String,
    /// Mean R².
    pub r2_mean: f64,
    /// Sample standard deviation of R².
    pub r2_sd: f64,
    /// Student-t 95 % interval of the mean.
    pub r2_ci: [f64; 2],
}

/// Paired two-tailed t-test of per-row squared errors, hybrid vs `baseline`.
#[derive(Debug, Clone, Serialize)]
pub struct TTestRow {
    /// The other model.
    pub baseline: String,
    /// t statistic (positive: the hybrid's errors are smaller).
    pub statistic: f64,
    /// Two-tailed p-value.
    pub p_value: f64,
}

/// One physics parameter.
#[derive(Debug, Clone, Serialize)]
pub struct ParameterRow {
    /// Name in the equation.
    pub name: String,
    /// Starting (handbook) value.
    pub initial: f64,
    /// Calibrated value.
    pub value: f64,
    /// Standard error from the Jacobian at the optimum (`None` where undefined).
    pub standard_error: Option<f64>,
}

/// An equation with its size.
#[derive(Debug, Clone, Serialize)]
pub struct EquationRow {
    /// Plain text.
    pub equation: String,
    /// LaTeX.
    pub latex: String,
    /// Complexity (features + operators; the correction only).
    pub complexity: Option<usize>,
    /// Feature columns used (the correction only).
    pub features: Vec<String>,
}

/// Issue 13's goals, as measured on this case.
#[derive(Debug, Clone, Serialize)]
pub struct Goals {
    /// Random split: hybrid RMSE below the calibrated physics' RMSE.
    pub hybrid_below_calibrated_physics: bool,
    /// Random split: p-value of the paired t-test hybrid vs calibrated physics.
    pub p_vs_calibrated_physics: f64,
    /// Both of the above, with p below [`GOAL_P`].
    pub goal_random_met: bool,
    /// Extrapolation split: hybrid RMSE below physics + forest.
    pub goal_extrapolation_met: bool,
    /// Correction of the random split: features used.
    pub n_features: usize,
    /// Correction of the random split: complexity.
    pub complexity: usize,
    /// Features at most [`GOAL_FEATURES`] and complexity at most [`GOAL_COMPLEXITY`].
    pub goal_size_met: bool,
    /// Generator effects (beyond the law itself) the random split's correction names through
    /// its features.
    pub effects_named: Vec<String>,
    /// Distractor or identifier columns the correction uses (should be empty).
    pub distractors_used: Vec<String>,
    /// Generator effects beyond the physics that no feature of the correction stands for.
    pub effects_missed: Vec<String>,
}

/// The fixed settings of one case.
struct CaseSpec {
    name: &'static str,
    title: &'static str,
    target: &'static str,
    unit: &'static str,
    physics: &'static str,
    init: Vec<(&'static str, f64)>,
    form: CorrectionForm,
    exclude: Vec<&'static str>,
    extrapolate: &'static str,
    roles: Vec<(&'static str, &'static str)>,
    table: Table,
}

/// Role text of a distractor column (the correction should not use it).
const DISTRACTOR: &str = "distractor (no effect)";
/// Role text of an identifier column (kept out of the features).
const IDENTIFIER: &str = "insert id (group; not a feature)";

fn specs(rows: usize, seed: u64) -> Result<Vec<CaseSpec>, ReproduceError> {
    let rough = roughness(&RoughnessConfig {
        n_rows: rows,
        seed,
        ..RoughnessConfig::default()
    })?;
    let force = cutting_force(&CuttingForceConfig {
        n_rows: rows,
        seed,
        ..CuttingForceConfig::default()
    })?;
    Ok(vec![
        CaseSpec {
            name: "roughness",
            title: "Finish-turning surface roughness",
            target: "Ra_um",
            unit: "µm",
            // The kinematic law plus a calibrated residual roughness `Ra0` (0 as given).
            physics: "1000*feed_mm^2/(32*nose_radius_mm) + Ra0",
            init: vec![("Ra0", 0.0)],
            // Wear scales the roughness; the other effects matter where the law is small.
            form: CorrectionForm::Multiplicative,
            exclude: vec!["tool"],
            // The law's own variable: does the correction keep the law's extrapolation?
            extrapolate: "feed_mm",
            roles: vec![
                ("feed_mm", "kinematic law; ploughing (Brammertz)"),
                ("nose_radius_mm", "kinematic law; ploughing (Brammertz)"),
                ("cutting_speed_m_min", "built-up edge; wear rate"),
                ("cutting_time_min", "flank wear"),
                ("depth_of_cut_mm", "vibration"),
                ("coolant_temp_C", DISTRACTOR),
                ("workpiece_diameter_mm", DISTRACTOR),
                ("tool", IDENTIFIER),
            ],
            table: rough,
        },
        CaseSpec {
            name: "cutting_force",
            title: "Main cutting force (Kienzle)",
            target: "Fc_N",
            unit: "N",
            physics: "kc*width_of_cut_mm*chip_thickness_mm^(1-mc)",
            init: vec![("kc", HANDBOOK_KC11), ("mc", HANDBOOK_MC)],
            // The handbooks' corrections are factors on kc.
            form: CorrectionForm::Multiplicative,
            exclude: vec!["tool"],
            // Tool wear keeps growing after the training data end.
            extrapolate: "cutting_time_min",
            roles: vec![
                ("chip_thickness_mm", "Kienzle's law"),
                ("width_of_cut_mm", "Kienzle's law"),
                ("rake_angle_deg", "rake-angle factor"),
                ("cutting_speed_m_min", "speed factor; wear rate"),
                ("cutting_time_min", "flank wear"),
                ("coolant_temp_C", DISTRACTOR),
                ("tool", IDENTIFIER),
            ],
            table: force,
        },
    ])
}

/// Rows of each table: 400, or 200 in the quick run.
fn rows(cfg: &ReproduceConfig) -> usize {
    if cfg.quick { 200 } else { 400 }
}

fn process_config(spec: &CaseSpec, cfg: &ReproduceConfig, extrapolate: bool) -> ProcessConfig {
    let mut p = ProcessConfig::new(spec.target, spec.physics);
    p.calibrate = spec.init.iter().map(|(n, _)| n.to_string()).collect();
    p.init = spec.init.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    p.exclude = spec.exclude.iter().map(|s| s.to_string()).collect();
    p.correction = spec.form;
    p.test_fraction = cfg.test_fraction;
    p.seed = cfg.seed;
    p.search.epochs = cfg.epochs();
    p.search.max_complexity = GOAL_COMPLEXITY;
    if extrapolate {
        p.extrapolate = Some(spec.extrapolate.to_string());
    }
    p
}

fn span(v: impl Iterator<Item = f64>) -> [f64; 2] {
    v.fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], x| {
        [lo.min(x), hi.max(x)]
    })
}

fn split_result(c: &Comparison, table: &Table, extrapolate: Option<&str>) -> SplitResult {
    let m: &ProcessModel = &c.hybrid;
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
        interval,
        split: c.split.clone(),
        n_train: c.n_train,
        n_test: c.n_test,
        ranges,
        models: c.models.clone(),
        cv: c
            .cv
            .iter()
            .map(|s| CvRow {
                name: s.name.clone(),
                r2_mean: s.r2_mean,
                r2_sd: s.r2_sd,
                r2_ci: s.r2_ci,
            })
            .collect(),
        t_tests: c
            .t_tests
            .iter()
            .map(|t| TTestRow {
                baseline: t.baseline.clone(),
                statistic: t.test.statistic,
                p_value: t.test.p_value,
            })
            .collect(),
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
            equation: m.correction.equation.clone(),
            latex: m.correction.latex.clone(),
            complexity: Some(m.correction.complexity),
            features: m.correction.features.clone(),
        },
        hybrid: EquationRow {
            equation: m.hybrid.equation.clone(),
            latex: m.hybrid.latex.clone(),
            complexity: None,
            features: Vec::new(),
        },
    }
}

fn rmse_of(s: &SplitResult, name: &str) -> Option<f64> {
    s.models
        .iter()
        .find(|m| m.name == name)
        .map(|m| m.metrics.rmse)
}

fn p_of(s: &SplitResult, baseline: &str) -> Option<f64> {
    s.t_tests
        .iter()
        .find(|t| t.baseline == baseline)
        .map(|t| t.p_value)
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

/// Per-row values a figure needs: `(measured, physics, hybrid, extrapolated column, is_test)`.
type Rows = Vec<(f64, f64, f64, f64, bool)>;

fn rows_of(m: &ProcessModel, spec: &CaseSpec) -> Result<Rows, ReproduceError> {
    let pred = m.predict(&spec.table)?;
    let col = |name: &str| {
        spec.table
            .column(name)
            .ok_or_else(|| ReproduceError::Pipeline(format!("{}: no column {name}", spec.name)))
    };
    let (y, x) = (col(spec.target)?, col(spec.extrapolate)?);
    let mut is_test = vec![false; y.len()];
    for &i in &m.split.test {
        if let Some(t) = is_test.get_mut(i) {
            *t = true;
        }
    }
    Ok((0..y.len())
        .map(|i| (y[i], pred.physics[i], pred.hybrid[i], x[i], is_test[i]))
        .collect())
}

fn parity(rows: &Rows, title: String, unit: &str, target: &str) -> Panel {
    let test: Vec<_> = rows.iter().filter(|r| r.4).collect();
    let phys: Vec<_> = test.iter().map(|r| (r.0, r.1)).collect();
    let hyb: Vec<_> = test.iter().map(|r| (r.0, r.2)).collect();
    let [lo, hi] = span(test.iter().flat_map(|r| [r.0, r.1, r.2]));
    Panel {
        title,
        x_label: format!("measured {target} ({unit})"),
        y_label: format!("predicted ({unit})"),
        series: vec![
            Series::points("physics, calibrated", phys),
            Series::points("hybrid", hyb),
            Series::dashed("y = x", vec![(lo, lo), (hi, hi)]),
        ],
    }
}

fn error_panel(rows: &Rows, spec: &CaseSpec) -> Panel {
    let pick = |test: bool, hybrid: bool| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r.4 == test)
            .map(|r| (r.3, if hybrid { r.2 } else { r.1 } - r.0))
            .collect()
    };
    Panel {
        title: format!("error vs {} (extrapolation split)", spec.extrapolate),
        x_label: spec.extrapolate.to_string(),
        y_label: format!("prediction - measured ({})", spec.unit),
        series: vec![
            Series::points("physics, train", pick(false, false)),
            Series::points("hybrid, train", pick(false, true)),
            Series::points("physics, test", pick(true, false)),
            Series::points("hybrid, test", pick(true, true)),
        ],
    }
}

/// File name of a case's figure.
pub fn figure_name(case: &str) -> String {
    format!("fig_beyond_{case}.svg")
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
            let mut on_search = |p: &hxai_hybrid::process::ProcessProgress| {
                progress(Progress {
                    stage: STAGE,
                    done,
                    total,
                    message: format!("{label}, task {}/{}", p.task, p.tasks),
                });
            };
            let c = compare_process(&spec.table, &pc, folds, &mut on_search)?;
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
            .map_or("–".to_string(), |t| {
                format!("{:.2}, {}", t.statistic, p_text(t.p_value))
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
        out.push_str(&format!(
            "Prediction intervals of the hybrid at {:.0} % (delta method through the whole \
             equation plus the residual variance, `hxai hybrid evaluate --json`): coverage \
             {:.1} % of the {} test rows.\n\n",
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
    out.push_str("\n## Beyond the paper: the framework on two more processes\n\n");
    out.push_str(&format!(
        "The paper's framework on two more manufacturing processes, from tables made by the seeded generators of `hxai_sim::cases` (`hxai simulate --case NAME`). Their hidden truths, the effects they add to the engineer's law and the sources are in [../cases.md](../cases.md), so the corrections below can be judged against what the generator put in. Each case runs `hxai hybrid compare` (library: `hxai_hybrid::process::compare_process`) with fixed settings chosen from the physics before any result was seen: {} rows, seed {}, {} search epochs, correction complexity at most {}, {} % held out; models on the same split: `physics` (the law with its given values), `physics_calibrated` (its parameters fitted by Levenberg-Marquardt on the training rows), `symbolic` (symbolic regression of the target alone), `physics_forest` (calibrated physics with a random forest on the same correction target) and `hybrid` (calibrated physics with the symbolic correction). The random split is cross-validated over {} folds; the extrapolation split trains on the low {} % of one column and tests on the top {} %.\n\n",
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
