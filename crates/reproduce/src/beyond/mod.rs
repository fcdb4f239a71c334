//! "Beyond the paper: the framework on three more processes": the hybrid of any process
//! (`hxai_hybrid::tables`) on the roughness, cutting-force and tool-life tables of `hxai_sim::cases`
//! (hidden truths in `docs/cases.md`).
//!
//! Per case: [`compare`](hxai_hybrid::tables::compare) at a random split
//! (with k-fold cross-validation) and at an extrapolation split (train on the low values of
//! one column, test on the high ones), the calibrated parameters with standard errors, the
//! correction and the hybrid as equations, the goals measured (not assumed), and one
//! figure (predicted vs measured for the calibrated physics and the hybrid at both splits;
//! error vs the extrapolated column).
//!
//! Design decision: the settings of each case (physics, calibrated parameters, correction
//! form, extrapolated column) are fixed here from the physics of the case, before looking at
//! any result, and are printed with the results; nothing is chosen by its score.
//!
//! Files by job, as the paper's half is split: `results.rs` the types of `results.json`,
//! `compute.rs` the runs, `plots.rs` the figures, `report.rs` the markdown; this file the
//! fixed settings of the cases.

mod compute;
mod plots;
mod report;
mod results;

pub use compute::compute;
pub use plots::figure_name;
pub use report::markdown;
pub use results::{BeyondResults, CaseResult, EquationRow, Goals, ParameterRow, SplitResult};

use crate::{ReproduceConfig, ReproduceError};
use hxai_hybrid::tables::{CorrectionForm, TableConfig};
use hxai_sim::cases::{
    CuttingForceConfig, RoughnessConfig, ToolLifeConfig, cutting_force,
    cutting_force::HANDBOOK_KC11, cutting_force::HANDBOOK_MC, roughness, tool_life,
};
use hxai_table::Table;

/// Stage name of the progress events of this section.
pub const STAGE: &str = "beyond the paper";

/// Significance level of the goal "hybrid below calibrated physics" (issue 13).
pub const GOAL_P: f64 = 1e-3;
/// Most features the correction may use by default (issue 13's goal).
pub const GOAL_FEATURES: usize = 4;
/// Highest complexity of the correction by default (issue 13's goal).
pub const GOAL_COMPLEXITY: usize = 10;

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
    /// The generator's measurement scatter (log-sd), its default.
    noise_rel: f64,
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
    let life = tool_life(&ToolLifeConfig {
        n_rows: rows,
        seed,
        ..ToolLifeConfig::default()
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
            noise_rel: RoughnessConfig::default().noise_rel,
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
            noise_rel: CuttingForceConfig::default().noise_rel,
            table: force,
        },
        CaseSpec {
            name: "tool_life",
            title: "Tool life in turning (Taylor)",
            target: "tool_life_min",
            unit: "min",
            physics: tool_life::PHYSICS,
            init: vec![("C", tool_life::HANDBOOK_C), ("n", tool_life::HANDBOOK_N)],
            // Tool life scatters log-normally from edge to edge, and the extended Taylor
            // law's further factors are powers: the log form.
            form: CorrectionForm::Log,
            exclude: vec!["tool"],
            // The feed is what Taylor's law leaves out: does the correction extrapolate?
            extrapolate: "feed_mm",
            roles: vec![
                ("cutting_speed_m_min", "Taylor's law"),
                ("feed_mm", "extended Taylor law (the whole correction)"),
                ("coolant_temp_C", DISTRACTOR),
                ("workpiece_diameter_mm", DISTRACTOR),
                ("tool", IDENTIFIER),
            ],
            noise_rel: ToolLifeConfig::default().noise_rel,
            table: life,
        },
    ])
}

/// Rows of each table: 400, or 200 in the quick run.
fn rows(cfg: &ReproduceConfig) -> usize {
    if cfg.quick { 200 } else { 400 }
}

fn process_config(spec: &CaseSpec, cfg: &ReproduceConfig, extrapolate: bool) -> TableConfig {
    let mut p = TableConfig::new(spec.target, spec.physics);
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
