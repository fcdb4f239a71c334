//! The section's results as they go into `results.json` (key `beyond_the_paper`).

use crate::intervals::{MethodInterval, TableCase, TableSplit};
use hxai_hybrid::tables::ModelScore;
use serde::Serialize;
use std::collections::BTreeMap;

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
    /// The generator's measurement scatter (log-sd of the measured/true ratio).
    pub noise_rel: Option<f64>,
    /// The goals, measured.
    pub goals: Goals,
}

impl CaseResult {
    /// The case as the section "Prediction intervals by method" shows it.
    pub fn intervals(&self) -> TableCase<'_> {
        fn split(s: &SplitResult) -> TableSplit<'_> {
            TableSplit {
                split: &s.split,
                n_test: s.n_test,
                intervals: &s.intervals,
            }
        }
        TableCase {
            title: &self.title,
            correction_form: &self.correction_form,
            extrapolate: &self.extrapolate,
            noise_rel: self.noise_rel,
            splits: [split(&self.random), split(&self.extrapolation)],
        }
    }
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
    pub cv: Vec<hxai_hybrid::tables::CvScore>,
    /// Paired t-tests of the hybrid's squared errors against each other model's.
    pub t_tests: Vec<hxai_hybrid::tables::TTestScore>,
    /// Physics parameters after calibration.
    pub parameters: Vec<ParameterRow>,
    /// The correction.
    pub correction: EquationRow,
    /// The whole hybrid as one equation.
    pub hybrid: EquationRow,
    /// The hybrid's 95 % prediction intervals on the test rows by the model's default
    /// method (`None` when they cannot be computed).
    pub interval: Option<hxai_hybrid::IntervalReport>,
    /// The same by every method the model file offers ([`crate::intervals`]).
    pub intervals: Vec<MethodInterval>,
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
    /// Both of the above, with p below [`GOAL_P`](super::GOAL_P).
    pub goal_random_met: bool,
    /// Extrapolation split: hybrid RMSE below physics + forest.
    pub goal_extrapolation_met: bool,
    /// Correction of the random split: features used.
    pub n_features: usize,
    /// Correction of the random split: complexity.
    pub complexity: usize,
    /// Features at most [`GOAL_FEATURES`](super::GOAL_FEATURES) and complexity at most
    /// [`GOAL_COMPLEXITY`](super::GOAL_COMPLEXITY).
    pub goal_size_met: bool,
    /// Generator effects (beyond the law itself) the random split's correction names through
    /// its features.
    pub effects_named: Vec<String>,
    /// Distractor or identifier columns the correction uses (should be empty).
    pub distractors_used: Vec<String>,
    /// Generator effects beyond the physics that no feature of the correction stands for.
    pub effects_missed: Vec<String>,
}

pub(super) fn rmse_of(s: &SplitResult, name: &str) -> Option<f64> {
    s.models
        .iter()
        .find(|m| m.name == name)
        .map(|m| m.metrics.rmse)
}

pub(super) fn p_of(s: &SplitResult, baseline: &str) -> Option<f64> {
    s.t_tests
        .iter()
        .find(|t| t.baseline == baseline)
        .and_then(|t| t.test.as_ref())
        .map(|t| t.p_value)
}
