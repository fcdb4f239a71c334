//! The dynamic model file (JSON) and its predictions: each run simulated from its first
//! reading, with conformal bands over runs.

use super::calibrate::CALIBRATION_ODE;
use super::spec::OdeSpec;
use super::system::System;
use super::{DynamicConfig, Initial};
use crate::HybridError;
use crate::correction::FormChoice;
use crate::tables::{CorrectionForm, Form};
use hxai_symreg::{Model, ParamEstimate, Table};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Version of the dynamic model file.
pub const SCHEMA_VERSION: u32 = 1;

/// One state's learned correction (JSON `corrections[i]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StateCorrection {
    /// The state whose derivative it corrects.
    pub state: String,
    /// The form kept: `none`, `factors` or `free`.
    pub form: Form,
    /// The correction after the refit through the ODE (`0` for none).
    pub equation: String,
    /// The correction as the search found it on the derivatives, before that refit.
    pub searched_equation: String,
    /// The columns it reads (states and inputs; a grouping of the physics counts as the
    /// columns in it).
    pub features: Vec<String>,
    /// The physics' groupings it reads (`(T_C - ambient_C)`), each a feature of its model.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub groupings: Vec<String>,
    /// The model (`null` for none).
    pub model: Option<Model>,
    /// `[low, high]` of each feature on the training samples: outside it the correction is
    /// evaluated at the nearest edge (held constant), so it never extrapolates.
    #[serde(default)]
    pub ranges: Vec<[f64; 2]>,
    /// With `--form auto`: how the form was chosen.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choice: Option<FormChoice>,
    /// `[samples the derivative was taken at, samples in all]`.
    pub samples: [usize; 2],
}

/// The runs the model was fitted on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Training {
    /// Their run values.
    pub runs: Vec<f64>,
    /// Samples in all.
    pub samples: usize,
    /// With `--test-after T`: the runs were cut at `T`.
    pub test_after: Option<f64>,
}

/// Conformal scores over runs (CV over folds of runs): per state, each training run's
/// largest absolute free-run error when its fold was held out.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunConformal {
    /// Folds of runs.
    pub folds: usize,
    /// `[state][run]`; `null` (infinite) where a held-out run could not be integrated.
    #[serde(with = "inf_as_null")]
    pub scores: Vec<Vec<f64>>,
}

mod inf_as_null {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub(super) fn serialize<S: Serializer>(v: &[Vec<f64>], s: S) -> Result<S::Ok, S::Error> {
        let o: Vec<Vec<Option<f64>>> = v
            .iter()
            .map(|r| r.iter().map(|x| x.is_finite().then_some(*x)).collect())
            .collect();
        o.serialize(s)
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<f64>>, D::Error> {
        let o: Vec<Vec<Option<f64>>> = Vec::deserialize(d)?;
        Ok(o.into_iter()
            .map(|r| r.into_iter().map(|x| x.unwrap_or(f64::INFINITY)).collect())
            .collect())
    }
}

/// A fitted dynamic hybrid (`hxai dynamic fit --out MODEL.json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DynamicModel {
    /// [`SCHEMA_VERSION`].
    pub schema_version: u32,
    /// The time column.
    pub time: String,
    /// The run column (`null`: one run).
    pub run: Option<String>,
    /// The states.
    pub states: Vec<String>,
    /// The inputs.
    pub inputs: Vec<String>,
    /// The physics as written.
    pub ode: String,
    /// The calibrated parameters.
    pub calibrated: Vec<String>,
    /// Every parameter's starting (or fixed) value: the uncalibrated physics.
    pub starting: BTreeMap<String, f64>,
    /// The calibrated physics alone: its parameters with standard errors and 95 %
    /// intervals (from the trajectories' Jacobian).
    pub physics_calibrated: BTreeMap<String, ParamEstimate>,
    /// The hybrid's physics parameters (after the joint refit with the correction).
    pub parameters: BTreeMap<String, f64>,
    /// Iterations of the joint refit (`null`: no correction was refitted).
    pub joint_iterations: Option<usize>,
    /// `additive` (`f + c`) or `multiplicative` (`f (1 + c)`).
    pub correction_kind: CorrectionForm,
    /// One per state.
    pub corrections: Vec<StateCorrection>,
    /// The hybrid ODE, every constant substituted.
    pub hybrid_equation: String,
    /// How the fit took the initial states.
    pub initial: Initial,
    /// The training runs.
    pub training: Training,
    /// Free-run RMSE on the training runs of `physics`, `physics_calibrated` and `hybrid`.
    pub train_rmse: BTreeMap<String, f64>,
    /// Conformal scores over runs (`null`: fewer than 3 runs, or folds 0).
    pub conformal: Option<RunConformal>,
    /// What the fit warns about.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// The settings the model was fitted with (the report's refit command).
    #[serde(default)]
    pub settings: DynamicConfig,
}

/// One state's equation of a fitted model, as expressions ([`DynamicModel::equations`]).
#[derive(Clone, Debug, PartialEq)]
pub struct StateExpressions {
    /// The state.
    pub state: String,
    /// The physics' right-hand side, the hybrid's parameters substituted.
    pub physics: hxai_symreg::expr::Expr,
    /// The correction (`None`: none).
    pub correction: Option<hxai_symreg::expr::Expr>,
}

/// Predictions of [`DynamicModel::predict`], one value per row of the table, in its order.
#[derive(Clone, Debug, PartialEq)]
pub struct DynamicPrediction {
    /// `[state][row]`: the hybrid's free run.
    pub hybrid: Vec<Vec<f64>>,
    /// `[state][row]`: the calibrated physics' free run.
    pub physics: Vec<Vec<f64>>,
    /// `[state][row]` bounds of the conformal band (with an interval).
    pub lower: Option<Vec<Vec<f64>>>,
    /// Upper bounds.
    pub upper: Option<Vec<Vec<f64>>>,
    /// What the prediction warns about.
    pub warnings: Vec<String>,
}

impl DynamicModel {
    /// The model's JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Reads a model file's JSON.
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`] or [`HybridError::SchemaVersion`].
    pub fn from_json(text: &str) -> Result<Self, HybridError> {
        let m: Self = serde_json::from_str(text).map_err(|e| {
            HybridError::ModelFormat(format!("not a dynamic model file (hxai dynamic fit): {e}"))
        })?;
        if m.schema_version != SCHEMA_VERSION {
            return Err(HybridError::SchemaVersion {
                found: m.schema_version.to_string(),
                expected: SCHEMA_VERSION,
            });
        }
        for c in m.corrections.iter().filter_map(|c| c.model.as_ref()) {
            c.validate()?;
        }
        Ok(m)
    }

    fn config(&self) -> DynamicConfig {
        DynamicConfig {
            time: self.time.clone(),
            run: self.run.clone(),
            states: self.states.clone(),
            inputs: self.inputs.clone(),
            ode: self.ode.clone(),
            correction: self.correction_kind,
            ..DynamicConfig::default()
        }
    }

    /// The system with `values` for its parameters and (with `hybrid`) the corrections.
    pub(crate) fn system(
        &self,
        values: &BTreeMap<String, f64>,
        hybrid: bool,
    ) -> Result<System, HybridError> {
        let spec = OdeSpec::parse(&self.ode, &self.states, &self.inputs, &self.time, values)?;
        let mut sys = System::physics(spec, self.correction_kind);
        if hybrid {
            for (j, c) in self.corrections.iter().enumerate() {
                sys.set_correction(j, c.model.clone(), c.ranges.clone())?;
            }
        }
        Ok(sys)
    }

    /// The calibrated physics' parameter values.
    pub(crate) fn calibrated_values(&self) -> BTreeMap<String, f64> {
        let mut v = self.starting.clone();
        for (p, e) in &self.physics_calibrated {
            v.insert(p.clone(), e.value);
        }
        v
    }

    /// Each state's physics (the hybrid's parameters substituted) and correction, as
    /// expressions, for pages that typeset them.
    ///
    /// # Errors
    /// An ODE or a correction that does not read back (a damaged file).
    pub fn equations(&self) -> Result<Vec<StateExpressions>, HybridError> {
        let sys = self.system(&self.parameters, true)?;
        Ok(sys
            .spec
            .equations
            .iter()
            .zip(&self.corrections)
            .map(|(e, c)| StateExpressions {
                state: e.state.clone(),
                physics: e.compiled.expr().simplify(),
                correction: c.model.as_ref().map(Model::expr),
            })
            .collect())
    }

    /// Sets [`DynamicModel::hybrid_equation`] from the parameters and corrections.
    pub(crate) fn with_equation(mut self) -> Self {
        if let Ok(sys) = self.system(&self.parameters, true) {
            self.hybrid_equation = sys
                .spec
                .equations
                .iter()
                .zip(&self.corrections)
                .map(|(e, c)| {
                    let p = e.compiled.expr().simplify().to_text(Some(6), false);
                    match (c.model.as_ref(), self.correction_kind) {
                        (None, _) => format!("{}' = {p}", e.state),
                        (Some(_), CorrectionForm::Multiplicative) => {
                            format!("{}' = ({p})*(1 + {})", e.state, c.equation)
                        }
                        (Some(_), _) => format!("{}' = {p} + {}", e.state, c.equation),
                    }
                })
                .collect::<Vec<_>>()
                .join("; ");
        }
        self
    }

    /// Simulates every run of `table` from its first reading with its inputs; with
    /// `interval` P in (0, 1), the conformal band that holds a whole new run's trajectory
    /// with probability at least P (when runs are exchangeable).
    ///
    /// # Errors
    /// A missing column, a run that cannot be integrated, or an interval without conformal
    /// scores or outside (0, 1).
    pub fn predict(
        &self,
        table: &Table,
        interval: Option<f64>,
    ) -> Result<DynamicPrediction, HybridError> {
        let cfg = self.config();
        let runs = cfg.runs(table)?;
        let hyb = self.system(&self.parameters, true)?;
        let phys = self.system(&self.calibrated_values(), false)?;
        let n = table.n_rows();
        let ns = self.states.len();
        let mut hybrid = vec![vec![f64::NAN; n]; ns];
        let mut physics = vec![vec![f64::NAN; n]; ns];
        let mut warnings = Vec::new();
        for run in &runs {
            let x0 = run.state_at(0);
            for (sys, out, what) in [
                (&hyb, &mut hybrid, "hybrid"),
                (&phys, &mut physics, "physics"),
            ] {
                match sys.simulate(run, &x0, &CALIBRATION_ODE) {
                    Ok(sim) => {
                        for (k, &row) in run.rows.iter().enumerate() {
                            for j in 0..ns {
                                out[j][row] = sim[k][j];
                            }
                        }
                    }
                    Err(e) => warnings.push(format!(
                        "run {}: the {what} cannot be integrated ({e}); its predictions are empty",
                        run.id
                    )),
                }
            }
        }
        let (lower, upper) = match interval {
            None => (None, None),
            Some(p) => {
                let q = self.band(p)?;
                let mut lo = hybrid.clone();
                let mut hi = hybrid.clone();
                for j in 0..ns {
                    if !q[j].is_finite() {
                        warnings.push(format!(
                            "{}: too few training runs ({}) for a {p} band; its bounds are empty",
                            self.states[j],
                            self.training.runs.len()
                        ));
                    }
                    for v in &mut lo[j] {
                        *v = if q[j].is_finite() {
                            *v - q[j]
                        } else {
                            f64::NAN
                        };
                    }
                    for v in &mut hi[j] {
                        *v = if q[j].is_finite() {
                            *v + q[j]
                        } else {
                            f64::NAN
                        };
                    }
                }
                (Some(lo), Some(hi))
            }
        };
        Ok(DynamicPrediction {
            hybrid,
            physics,
            lower,
            upper,
            warnings,
        })
    }

    /// Each state's band half-width at level `p`: the `ceil((n + 1) p)`-th smallest of the
    /// `n` runs' scores (infinite when that exceeds `n`).
    ///
    /// # Errors
    /// `p` outside (0, 1), or a model without conformal scores.
    pub fn band(&self, p: f64) -> Result<Vec<f64>, HybridError> {
        if !(p > 0.0 && p < 1.0) {
            return Err(HybridError::InvalidConfig(format!(
                "--interval {p}: give a level between 0 and 1 (0.9 for a 90 % band)"
            )));
        }
        let c = self.conformal.as_ref().ok_or_else(|| {
            HybridError::InvalidConfig(
                "the model has no conformal scores (fitted on fewer than 3 runs, or with 0 \
                 conformal folds): refit it on more runs for --interval"
                    .into(),
            )
        })?;
        Ok(c.scores
            .iter()
            .map(|s| {
                let mut v = s.clone();
                v.sort_by(f64::total_cmp);
                let n = v.len();
                let k = ((n as f64 + 1.0) * p).ceil() as usize;
                if k == 0 || k > n {
                    f64::INFINITY
                } else {
                    v[k - 1]
                }
            })
            .collect())
    }
}
