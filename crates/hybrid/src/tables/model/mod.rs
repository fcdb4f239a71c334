//! The model file of a table hybrid: physics equation and parameters, correction, the
//! whole hybrid as one equation; prediction and evaluation on new tables.
//!
//! This file holds the model file's schema (the types serialised to JSON) and loading and
//! checking a model; the physics compiled and the hybrid as one program are in `program.rs`,
//! prediction, intervals and the explanation in `predict.rs`, evaluation on a table in
//! `evaluate.rs`.

mod evaluate;
pub(crate) use evaluate::defined_t_test;
mod predict;
mod program;

pub(crate) use program::{
    Combined, columns_of, combine, combine_values, compile_physics, deltas, finite_physics, forms,
};

use super::CorrectionForm;
use crate::HybridError;
use crate::conformal::ConformalInfo;
use crate::correction::CorrectionInfo;
use crate::intervals::IntervalReport;
use crate::split::SplitInfo;
use hxai_eval::Metrics;
use hxai_symreg::{Model, ParamEstimate, Uncertainty};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Schema version of the table model file.
pub const SCHEMA_VERSION: u32 = 1;

/// The physics part of the model file.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct PhysicsInfo {
    /// The equation as given (over column and parameter names).
    pub equation: String,
    /// Columns the equation uses, in order of first use.
    pub columns: Vec<String>,
    /// Every parameter's value: fitted (calibrated) or given (`--set`).
    pub parameters: BTreeMap<String, f64>,
    /// Standard error of each calibrated parameter (`null` where undefined).
    pub standard_errors: BTreeMap<String, Option<f64>>,
    /// The calibrated parameters.
    pub calibrated: Vec<String>,
    /// Starting values of the calibrated parameters (what `physics` means in `compare`).
    pub initial: BTreeMap<String, f64>,
    /// The equation with the parameter values substituted (sympy text, full precision).
    pub sympy: String,
    /// The same in LaTeX (4 significant digits).
    pub latex: String,
    /// Each calibrated parameter with its standard error and 95 % interval
    /// (`value +- t_{n-k, 0.975} std_error`, `n` training rows, `k` calibrated parameters;
    /// `null` where undefined). Empty in files written before it existed.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub params: BTreeMap<String, ParamEstimate>,
}

/// An equation in three forms.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct EquationInfo {
    /// Plain text, 4 significant digits (for reading).
    pub equation: String,
    /// sympy-parseable text with full-precision constants: reproduces `predict` to
    /// rounding (and parses back with `hxai_symreg::infix`).
    pub sympy: String,
    /// LaTeX, 4 significant digits.
    pub latex: String,
    /// For the hybrid: the whole equation as a template over the columns, the calibrated
    /// parameters (by name) and the correction's free constants (`p0`, `p1`, ...), with
    /// their covariance on the training rows, which prediction intervals use.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<Uncertainty>,
}

/// Physics vs hybrid scores on one side of the split.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct PairScores {
    /// The (calibrated) physics alone.
    pub physics: Metrics,
    /// The hybrid.
    pub hybrid: Metrics,
}

/// Scores on the fitting table.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ScoresInfo {
    /// On the training rows.
    pub train: PairScores,
    /// On the test rows (absent when the split left none).
    pub test: Option<PairScores>,
    /// The black boxes on the same split (`hxai hybrid fit`, with two test rows or more):
    /// absent from files written before it existed, from `fit_split`, and without test rows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub black_boxes: Option<BlackBoxScores>,
}

/// The black boxes an engineer would compare the hybrid with, fitted on the hybrid's
/// training rows and scored on its test rows, as `hxai hybrid compare` fits them (the model
/// file's `scores.black_boxes`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BlackBoxScores {
    /// Test RMSE of the calibrated physics plus a random forest on its `delta`.
    pub physics_forest: f64,
    /// Test RMSE of gradient boosting of the target on the physics' columns and the
    /// correction's features (scikit-learn's `HistGradientBoostingRegressor` defaults).
    pub boosting: f64,
    /// The better of the two.
    pub best_black_box: BlackBox,
    /// The hybrid's test RMSE divided by the best black box's.
    pub hybrid_over_best_black_box: f64,
    /// The training rows the black boxes were trained on, when fewer than the fit's (a
    /// large table's sample stratified on the target, issue 67: at most
    /// `BLACK_BOX_ROWS`); absent when they were trained on every training row.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub training_rows: Option<usize>,
}

/// The two-stage result that a joint refit replaced.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct JointInfo {
    /// Physics parameters after calibration alone (before the joint refit).
    pub sequential_parameters: BTreeMap<String, f64>,
    /// Their standard errors.
    pub sequential_standard_errors: BTreeMap<String, Option<f64>>,
    /// The correction before the joint refit (sympy text).
    pub sequential_correction: String,
    /// Training RMSE of the hybrid before the joint refit.
    pub sequential_train_rmse: f64,
    /// Training RMSE after it.
    pub joint_train_rmse: f64,
}

/// A fitted table hybrid: everything needed to predict, and its report.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct TableModel {
    /// [`SCHEMA_VERSION`].
    pub schema_version: u32,
    /// The target column.
    pub target: String,
    /// The physics equation and its parameters.
    pub physics: PhysicsInfo,
    /// The learned correction.
    pub correction: CorrectionInfo<CorrectionForm>,
    /// The whole hybrid as one equation over the columns, every parameter substituted.
    pub hybrid: EquationInfo,
    /// The split of the fitting table.
    pub split: SplitInfo<String, usize>,
    /// The grouping column, if any.
    pub group: Option<String>,
    /// With a joint refit (`--joint`): the two-stage values it replaced.
    pub joint: Option<JointInfo>,
    /// Physics vs hybrid on the fitting table.
    pub scores: ScoresInfo,
    /// With `hxai hybrid fit --stability N`: the stability of the correction's structure
    /// over bootstrap resamples of the training rows ([`super::stability`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stability: Option<hxai_symreg::Stability>,
    /// What conformal prediction intervals need ([`ConformalInfo`]: CV+ over folds of the
    /// training rows); absent in files written before it existed, or fitted with
    /// `conformal_folds` 0, where the delta method is the only one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conformal: Option<ConformalInfo>,
    /// The fit's warnings: input that gave numbers that may not mean what they seem to
    /// ([`super::traps`]); absent when there were none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// How empty cells were handled (`--missing drop|impute`): absent when the table had to
    /// be complete (the default, `refuse`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub missing: Option<MissingInfo>,
    /// With `--calibrate-per COL=P1,P2`: the text column, its levels and the physics
    /// parameters fitted once per level (`physics.parameters` holds `P1[level]`); `predict`
    /// builds the same level indicators and refuses a level it never saw.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub per_class: Option<super::per_class::PerClassInfo>,
    /// The training rows' range of every column the hybrid reads and of the target, which
    /// `predict` flags rows against (`outside_training`) and whose target's sign a
    /// prediction is checked against; absent from files written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub training: Option<TrainingRanges>,
    /// With `--correction-per COL`: the correction's constants per level of the text column
    /// (each level's constants, equation and training rows); `predict` uses the row's
    /// level's constants and refuses a level it never saw.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correction_per: Option<super::correction_per::CorrectionPerInfo>,
    /// The learned slots of the physics (`f(C)` in `A*exp(-E/T)*f(C)`, [`super::slots`]):
    /// what each became, its constants calibrated with the physics'; `physics.equation` is
    /// the physics with them substituted. Absent without slots.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub slots: Vec<SlotInfo>,
    /// The rows the correction's structure was searched on when the training rows were
    /// more than `search_rows` (issue 67); absent when every training row was used.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search_sample: Option<SearchSample>,
}

/// How a large table's correction was found (issue 67): its structure (the form `auto`'s
/// choice, the search, the conformal and stability refits) on a sample of the training rows,
/// its constants and the physics' calibration on every training row.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SearchSample {
    /// Rows of the sample.
    pub rows: usize,
    /// Training rows, on which the constants were fitted.
    pub training_rows: usize,
    /// How the sample was drawn.
    pub method: String,
}

/// A black box of the comparison and its test RMSE.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BlackBox {
    /// `physics_forest` or `boosting`.
    pub name: String,
    /// Its test RMSE.
    pub rmse: f64,
}

/// The columns a fitted model reads to predict (the physics' columns and the correction's
/// features, and the group column), and the target when `with_target` (to evaluate).
pub fn model_columns(model: &TableModel, with_target: bool) -> Vec<String> {
    let mut used = model.physics.columns.clone();
    used.extend(
        model
            .correction
            .model
            .iter()
            .flat_map(|m| m.feature_names.iter().cloned()),
    );
    used.extend(model.group.iter().cloned());
    if with_target {
        used.push(model.target.clone());
    }
    used
}

/// A learned slot as the model file stores it (JSON entry of `slots`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct SlotInfo {
    /// The slot's name in the physics (`f`).
    pub name: String,
    /// The columns it reads.
    pub columns: Vec<String>,
    /// How it was searched: `factors` or `free`.
    pub form: String,
    /// Its structure over the columns with named constants (`f_c0*C^f_c1`), as written
    /// into `physics.equation`.
    pub template: String,
    /// The slot with its calibrated constants (4 significant digits).
    pub equation: String,
    /// Each constant's value, standard error and 95 % interval from the calibration.
    pub uncertainty: BTreeMap<String, ParamEstimate>,
    /// Backfitting rounds run.
    pub rounds: usize,
}

/// The ranges of the training rows (the model file's `training`).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct TrainingRanges {
    /// Each column the hybrid reads (physics columns and correction features): its
    /// smallest and largest training value.
    pub columns: BTreeMap<String, [f64; 2]>,
    /// The target's smallest and largest training value.
    pub target: [f64; 2],
}

/// How far beyond a training range a value may lie, as a share of the range's width, before
/// its row is flagged `outside_training` (issue 63: 10 %).
pub const OUTSIDE_MARGIN: f64 = 0.1;

impl TrainingRanges {
    /// The ranges of `columns` and the target `y` over the rows `rows` of `table`
    /// (columns the table lacks, and non-finite values, are left out).
    pub fn of(table: &hxai_symreg::Table, columns: &[String], y: &[f64], rows: &[usize]) -> Self {
        let range = |v: &[f64]| -> Option<[f64; 2]> {
            let mut it = rows
                .iter()
                .filter_map(|&i| v.get(i))
                .filter(|x| x.is_finite());
            let first = *it.next()?;
            Some(it.fold([first, first], |[lo, hi], &x| [lo.min(x), hi.max(x)]))
        };
        let columns = columns
            .iter()
            .filter_map(|c| Some((c.clone(), range(table.column(c)?)?)))
            .collect();
        TrainingRanges {
            columns,
            target: range(y).unwrap_or([f64::NAN, f64::NAN]),
        }
    }

    /// For each row of `table`: whether any column lies outside its training range by more
    /// than [`OUTSIDE_MARGIN`] of the range's width (a non-finite value counts as outside).
    pub fn outside(&self, table: &hxai_symreg::Table) -> Vec<bool> {
        let mut out = vec![false; table.n_rows()];
        for (name, [lo, hi]) in &self.columns {
            let Some(col) = table.column(name) else {
                continue;
            };
            let margin = OUTSIDE_MARGIN * (hi - lo);
            for (o, &v) in out.iter_mut().zip(col) {
                if !(v >= lo - margin && v <= hi + margin) {
                    *o = true;
                }
            }
        }
        out
    }

    /// The warning for predictions of a sign the training target never had (every
    /// training value positive and a prediction below 0, or the other way round), naming
    /// the rows (1-based, the first ten); `None` when there are none.
    pub fn sign_warning(&self, predictions: &[f64], what: &str) -> Option<String> {
        let [lo, hi] = self.target;
        // the training target's sign, and the word for the other one
        let (s, sign) = if lo > 0.0 {
            (1.0, "negative")
        } else if hi < 0.0 {
            (-1.0, "positive")
        } else {
            return None;
        };
        let rows: Vec<usize> = predictions
            .iter()
            .enumerate()
            .filter(|(_, p)| **p * s < 0.0)
            .map(|(i, _)| i + 1)
            .collect();
        if rows.is_empty() {
            return None;
        }
        let shown: Vec<String> = rows.iter().take(10).map(ToString::to_string).collect();
        Some(format!(
            "{} {what} predicted {sign}, a sign the training target never had (it lies in [{}, \
             {}]): row(s) {}{}; the equation is extrapolated there, check those settings",
            rows.len(),
            crate::error::num(lo),
            crate::error::num(hi),
            shown.join(", "),
            if rows.len() > 10 { ", ..." } else { "" }
        ))
    }
}

/// How a table hybrid's fit handled empty cells (`--missing`, the model file's `missing`).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct MissingInfo {
    /// `drop` or `impute`.
    pub policy: String,
    /// Under `impute`, each feature column's training median, with which `predict --missing
    /// impute` fills a new row's empty cell.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub medians: std::collections::BTreeMap<String, f64>,
}

/// Per-row predictions of a table hybrid.
#[derive(Clone, Debug, PartialEq)]
pub struct TablePrediction {
    /// The physics equation.
    pub physics: Vec<f64>,
    /// The correction `delta`.
    pub correction: Vec<f64>,
    /// The hybrid.
    pub hybrid: Vec<f64>,
}

/// Physics vs hybrid against the target on a table.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct TableEvaluation {
    /// Scores of the physics alone.
    pub physics: Metrics,
    /// Scores of the hybrid.
    pub hybrid: Metrics,
    /// `(rmse_physics - rmse_hybrid) / rmse_physics * 100`.
    pub improvement_pct: f64,
    /// Paired two-tailed t-test of the per-row squared errors (physics vs hybrid); `null`
    /// where it is undefined (the hybrid predicts the physics on every row), with
    /// `t_test_reason`.
    pub t_test: Option<hxai_eval::TTest>,
    /// Why `t_test` is `null`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_test_reason: Option<String>,
    /// Rows evaluated.
    pub n_samples: usize,
    /// Coverage of the hybrid's prediction intervals (when the model stores the
    /// uncertainty of the hybrid).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interval: Option<IntervalReport>,
    /// Rows outside the training ranges, per column ([`TableModel::range_warnings`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

impl TableModel {
    /// Pretty JSON of the model file.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// [`TableModel::to_json`], checked: the text is read back with
    /// [`TableModel::from_json`] and written again, and the two texts must be equal, so that
    /// no file is written that hxai cannot read (a value that is not a finite number is
    /// written as `null`, which only the fields documented as "NaN when unknown" accept).
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`] naming what does not read back.
    pub fn to_checked_json(&self) -> Result<String, HybridError> {
        let json = self.to_json();
        match Self::from_json(&json) {
            Ok(back) if back.to_json() == json => Ok(json),
            Ok(back) => {
                let again = back.to_json();
                let line = json
                    .lines()
                    .zip(again.lines())
                    .position(|(a, b)| a != b)
                    .unwrap_or_else(|| json.lines().count().min(again.lines().count()));
                let text = json.lines().nth(line).unwrap_or("").trim();
                Err(HybridError::ModelFormat(format!(
                    "the model does not read back as it was written (line {} of the file, \
                     `{text}`, comes back otherwise: a value that is not a finite number, or a \
                     field out of order); nothing was written",
                    line + 1
                )))
            }
            Err(e) => Err(HybridError::ModelFormat(format!(
                "the model could not be read back ({e}); nothing was written"
            ))),
        }
    }

    /// Reads a model file written by [`TableModel::to_json`] and checks it.
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`] for text that is not such a model,
    /// [`HybridError::SchemaVersion`] for another version, or a physics equation that no
    /// longer compiles.
    pub fn from_json(text: &str) -> Result<Self, HybridError> {
        let v: serde_json::Value = serde_json::from_str(text)
            .map_err(|e| HybridError::ModelFormat(hxai_table::plain_json_error(&e.to_string())))?;
        if v.get("target").is_none() && v.get("window").is_some() && v.get("features").is_some() {
            return Err(HybridError::ModelFormat(
                "this is a model of `hxai fit` (the tool position from an accelerometer), not of \
                 `hxai hybrid fit`: apply it with `hxai predict`, `hxai evaluate` or `hxai stream`"
                    .into(),
            ));
        }
        if let Some(what) = not_a_table_model(&v) {
            return Err(HybridError::ModelFormat(what));
        }
        match v.get("schema_version").and_then(serde_json::Value::as_u64) {
            Some(n) if n == u64::from(SCHEMA_VERSION) => {}
            other => {
                return Err(HybridError::SchemaVersion {
                    found: other.map_or_else(|| "none".to_string(), |n| n.to_string()),
                    expected: SCHEMA_VERSION,
                });
            }
        }
        // From the text, not from `v`: a `serde_json::Value` object sorts its keys, and
        // `uncertainty.params` is an ordered map (template order: `k` before `c`, `p10` after
        // `p9`) whose order the `slots` and the covariance follow (issue 63).
        drop(v);
        let m: TableModel = serde_json::from_str(text)
            .map_err(|e| HybridError::ModelFormat(hxai_table::plain_json_error(&e.to_string())))?;
        let phys = m.physics_program()?;
        // the correction model checks itself on the way in
        Model::from_json(&serde_json::to_string(m.correction.fitted()?).unwrap_or_default())?;
        if let Some(conf) = &m.conformal {
            let c = combine(&phys, m.correction.fitted()?, m.correction.kind);
            conf.check(c.params.len())?;
            // one score per training row, or per row of the search sample (issue 67)
            let rows = m
                .search_sample
                .as_ref()
                .map_or(m.split.train.len(), |s| s.rows);
            if conf.scores.len() != rows {
                return Err(HybridError::ModelFormat(format!(
                    "`conformal` has {} scores for {rows} training rows{}",
                    conf.scores.len(),
                    if m.search_sample.is_some() {
                        " of the search sample"
                    } else {
                        ""
                    }
                )));
            }
        }
        Ok(m)
    }
}

/// What a JSON document that cannot be a table model is, for the message (issue 52: every
/// such file said "schema_version none"): `None` for an object that may be one.
fn not_a_table_model(v: &serde_json::Value) -> Option<String> {
    use serde_json::Value;
    let ask = "is this a model written by `hxai hybrid fit`?";
    let found = match v {
        Value::Null => "JSON `null`".to_string(),
        Value::Bool(b) => format!("JSON `{b}`"),
        Value::Number(n) => format!("the number {n}"),
        Value::String(_) => "a JSON text (a string)".to_string(),
        Value::Array(a) => format!("a JSON list of {} item(s)", a.len()),
        Value::Object(o) if o.is_empty() => "an empty JSON object `{}`".to_string(),
        Value::Object(o) => {
            if o.contains_key("best") && o.contains_key("pareto") && !o.contains_key("target") {
                return Some(format!(
                    "the file holds an equation search's result, not a table hybrid: {ask} it \
                     looks like the output of `hxai sr --json`"
                ));
            }
            match o.get("schema_version") {
                Some(Value::String(t)) => {
                    format!("`schema_version` {t:?}, a text where a whole number is expected")
                }
                Some(Value::Number(n)) if n.as_u64().is_none() => {
                    format!("`schema_version` {n}, not a whole number")
                }
                Some(Value::Number(_)) | None => return None,
                Some(other) => format!("`schema_version` {other}, not a whole number"),
            }
        }
    };
    Some(format!(
        "the file holds {found}, not a table hybrid (a JSON object with `schema_version` \
         {SCHEMA_VERSION}, `target`, `physics`, `correction`, ...): {ask}"
    ))
}
