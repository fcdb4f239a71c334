//! Grey-box dynamic models (issue 69, `hxai dynamic`): the engineer's ODE, calibrated
//! through its own trajectories, with a learned correction term inside the derivative.
//!
//! A long table holds one row per sample of one or more runs (`--run`), with a time column,
//! the measured states and the inputs (held from one sample to the next). The fit:
//!
//! 1. **calibrate** the physics' parameters by Levenberg-Marquardt on the simulated
//!    trajectories of the training runs (`calibrate.rs`; every run from its first reading,
//!    or from an estimated initial state);
//! 2. **search the correction** on the states' smoothed derivatives minus the calibrated
//!    physics' derivative, with the table workflow's forms and rules (`correction.rs`);
//! 3. **refit every constant through the ODE** (physics and correction together), keep the
//!    correction only if the trajectories get better, and calibrate conformal bands over
//!    runs (`fit.rs`);
//! 4. under `--form auto`, **check the correction on held-out trajectories** (`validate.rs`):
//!    refitted without a quarter of the runs (or, with fewer than 4 runs, without the last
//!    quarter of each run's time), it must predict them better than the physics refitted
//!    the same way, or it is dropped.
//!
//! `predict` simulates each run from its first reading (`model.rs`); `compare` scores the
//! physics, the calibrated physics, the hybrid and a NARX gradient boosting by free-run
//! error on held-out runs (`compare.rs`, `narx.rs`). Files by job: `spec.rs` the `--ode`
//! text, `system.rs` the integrated system and the runs.

mod calibrate;
mod compare;
mod correction;
mod fit;
mod model;
mod narx;
mod spec;
mod system;
mod validate;

pub use compare::{
    CorrectionSummary, DynamicComparison, DynamicScore, HybridSummary, TEST_SHARE, TestSplit,
    compare,
};
pub use model::{
    DynamicModel, DynamicPrediction, RunConformal, SCHEMA_VERSION, StateCorrection,
    StateExpressions, Training,
};

use crate::tables::{CorrectionForm, Form};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// How each run's initial state is taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Initial {
    /// The run's first reading (noise and all).
    #[default]
    First,
    /// Calibrated with the parameters (one unknown per run and state); new runs still start
    /// from their first reading.
    Estimate,
}

impl Initial {
    /// Parses `first` or `estimate`.
    ///
    /// # Errors
    /// [`crate::HybridError::InvalidConfig`] naming the choices.
    pub fn parse(s: &str) -> Result<Self, crate::HybridError> {
        match s.trim() {
            "first" => Ok(Initial::First),
            "estimate" => Ok(Initial::Estimate),
            o => Err(crate::HybridError::InvalidConfig(format!(
                "--initial {o:?}: use first or estimate"
            ))),
        }
    }
}

/// Default window of the derivatives' local quadratic (samples).
pub const DEFAULT_SMOOTH: usize = 9;

/// Settings of [`fit`] and [`compare`] (the flags of `hxai dynamic`; JSON for Python).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DynamicConfig {
    /// The time column (`--time`).
    pub time: String,
    /// The run column (`--run`); `None`: the table is one run.
    pub run: Option<String>,
    /// The measured states (`--state`), each with one equation in `ode`.
    pub states: Vec<String>,
    /// The input columns (`--inputs`), held from each sample to the next.
    pub inputs: Vec<String>,
    /// The system, `T' = ...; P' = ...` (`--ode`).
    pub ode: String,
    /// Parameters calibrated on the training runs (`--calibrate`).
    pub calibrate: Vec<String>,
    /// Starting values of the calibrated parameters (`--init`; default 1).
    pub init: BTreeMap<String, f64>,
    /// Values of the parameters that are not calibrated (`--set`).
    pub set: BTreeMap<String, f64>,
    /// How the correction enters the derivative: `additive` (`f + c`) or `multiplicative`
    /// (`f (1 + c)`).
    pub correction: CorrectionForm,
    /// The correction's form (`--form`, default `auto`: none, factors or free by
    /// cross-validation over runs).
    pub form: Form,
    /// Each run's initial state (`--initial`).
    pub initial: Initial,
    /// Columns a harmonic may use in the correction (`--periodic`, as in `hybrid`).
    pub periodic: Vec<String>,
    /// Window of the derivatives' local quadratic, in samples (`--smooth`, default
    /// [`DEFAULT_SMOOTH`]).
    pub smooth: usize,
    /// Seed of the search and of the default split.
    pub seed: u64,
    /// Levenberg-Marquardt iterations at most, per calibration.
    pub max_iter: usize,
    /// Folds over runs of the conformal bands (0: none; at most the training runs).
    pub conformal_folds: usize,
}

impl Default for DynamicConfig {
    fn default() -> Self {
        Self {
            time: String::new(),
            run: None,
            states: Vec::new(),
            inputs: Vec::new(),
            ode: String::new(),
            calibrate: Vec::new(),
            init: BTreeMap::new(),
            set: BTreeMap::new(),
            correction: CorrectionForm::Additive,
            form: Form::Auto,
            initial: Initial::First,
            periodic: Vec::new(),
            smooth: DEFAULT_SMOOTH,
            seed: 42,
            max_iter: 50,
            conformal_folds: 5,
        }
    }
}

impl DynamicConfig {
    /// Checks the settings that need no table.
    ///
    /// # Errors
    /// [`crate::HybridError::InvalidConfig`] naming the setting.
    pub fn check(&self) -> Result<(), crate::HybridError> {
        let bad = |s: String| Err(crate::HybridError::InvalidConfig(s));
        if self.time.is_empty() {
            return bad("--time: name the time column".into());
        }
        if self.states.is_empty() {
            return bad("--state: name at least one state column".into());
        }
        if self.ode.trim().is_empty() {
            return bad("--ode: write the system, `NAME' = expression` per state".into());
        }
        if self.correction == CorrectionForm::Log {
            return bad(
                "--correction log is not built for dynamic models: use additive or \
                 multiplicative"
                    .into(),
            );
        }
        if self.smooth < 3 {
            return bad(format!(
                "--smooth {}: the local quadratic needs a window of at least 3 samples",
                self.smooth
            ));
        }
        if self.conformal_folds == 1 {
            return bad("1 conformal fold: use 0 (none) or at least 2".into());
        }
        let mut cols: Vec<&String> = self.states.iter().chain(&self.inputs).collect();
        cols.push(&self.time);
        if let Some(r) = &self.run {
            cols.push(r);
        }
        for (i, c) in cols.iter().enumerate() {
            if cols[..i].contains(c) {
                return bad(format!(
                    "the column {c} is named twice among --time, --run, --state and --inputs"
                ));
            }
        }
        for p in &self.calibrate {
            if self.set.contains_key(p) {
                return bad(format!(
                    "{p} is both calibrated (--calibrate) and fixed (--set); choose one"
                ));
            }
            if cols.contains(&p) {
                return bad(format!("{p} is a column; it cannot be calibrated"));
            }
        }
        if let Some(p) = self.init.keys().find(|p| !self.calibrate.contains(p)) {
            return bad(format!(
                "--init {p}=...: {p} is not calibrated; give a fixed value with --set {p}=V"
            ));
        }
        Ok(())
    }

    /// The runs of `table` as these settings read them ([`system::runs_of`]).
    pub(crate) fn runs(
        &self,
        table: &hxai_symreg::Table,
    ) -> Result<Vec<system::Run>, crate::HybridError> {
        system::runs_of(
            table,
            &self.time,
            self.run.as_deref(),
            &self.states,
            &self.inputs,
        )
    }

    /// Every parameter's starting or fixed value (calibrated ones default to 1).
    pub(crate) fn values(&self) -> BTreeMap<String, f64> {
        let mut v = self.set.clone();
        for p in &self.calibrate {
            v.insert(p.clone(), self.init.get(p).copied().unwrap_or(1.0));
        }
        v
    }
}

/// Fits a dynamic hybrid on every run of `table`.
///
/// # Errors
/// Bad settings or columns ([`crate::HybridError::InvalidConfig`],
/// [`crate::HybridError::MissingColumn`]),
/// an ODE that cannot be integrated at its starting values, or a failed search.
pub fn fit(
    table: &hxai_symreg::Table,
    cfg: &DynamicConfig,
    progress: &mut dyn FnMut(&str),
) -> Result<DynamicModel, crate::HybridError> {
    cfg.check()?;
    validate::fit_runs(&cfg.runs(table)?, cfg, None, progress)
}
