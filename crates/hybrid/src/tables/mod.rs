//! Hybrid models of any process, on tables (`hxai hybrid ...`).
//!
//! The paper's generic hybrid framework (its section 2) for a user's own process: a physics equation
//! `f_p` written as text over the table's columns and named parameters, calibrated
//! parameters fitted by Levenberg-Marquardt on the training rows (grey-box calibration,
//! with standard errors from the Jacobian at the optimum), the physics' error `delta`
//! learned by symbolic regression on feature columns, and the hybrid printed as one
//! equation over the columns.
//!
//! - [`TableConfig`]: target, physics text, parameters to calibrate / fix, features,
//!   correction form ([`CorrectionForm`]), split, search settings.
//! - [`fit`] (and [`fit_split`] for a given split) returns a
//!   [`TableModel`], the serialisable model file, with [`TableModel::predict`],
//!   [`TableModel::evaluate`], [`TableModel::to_json`] and [`TableModel::from_json`].
//! - Prediction intervals ([`TableModel::intervals_with`]): conformal (CV+ over folds of
//!   the training rows, [`ConformalInfo`]), split conformal, or the delta method.
//! - [`compare`]: physics as given, calibrated physics, symbolic regression alone,
//!   physics + random forest, and the hybrid on the same split, with k-fold CV and paired
//!   t-tests ([`Comparison`]).
//!
//! Design decision: the physics equation is compiled to a symreg
//! [`Program`](hxai_symreg::Program) whose
//! parameters are constant leaves, so physics, correction and the joint refit are all
//! evaluated and differentiated by one evaluator, and the hybrid is itself one program:
//! its printed form is the one equation of the model file, which reproduces `predict`.
//!
//! ```
//! use hxai_hybrid::tables::{TableConfig, fit};
//! use hxai_symreg::Table;
//! let f: Vec<f64> = (0..120).map(|i| 0.05 + 0.002 * i as f64).collect();
//! let r: Vec<f64> = (0..120).map(|i| 0.4 + 0.4 * ((i * 7) % 11) as f64 / 10.0).collect();
//! // "measured" roughness: twice the kinematic law plus an offset
//! let ra: Vec<f64> = f.iter().zip(&r).map(|(f, r)| 2.0 * f * f / (32.0 * r) + 1e-4).collect();
//! let table = Table::new(vec!["f".into(), "r".into(), "Ra".into()], vec![f, r, ra])?;
//! let mut cfg = TableConfig::new("Ra", "k*f^2/(32*r)");
//! cfg.calibrate = vec!["k".into()];
//! cfg.search.epochs = 2;
//! cfg.search.candidates_per_epoch = 200;
//! let model = fit(&table, &cfg, &mut |_| {})?;
//! assert!((model.physics.parameters["k"] - 2.0).abs() < 0.05);
//! let back = hxai_hybrid::tables::TableModel::from_json(&model.to_json())?;
//! assert_eq!(back, model);
//! # Ok::<(), hxai_hybrid::HybridError>(())
//! ```
mod calibrate;
mod columns;
mod compare;
mod conformal;
pub mod correction_per;
pub mod design;
mod fit;
mod model;
pub mod per_class;
mod physics;
mod prepare;
mod resolve;
pub mod slots;
mod split;
pub mod traps;

pub use crate::conformal::{ConformalInfo, DEFAULT_CONFORMAL_FOLDS, ResidualScale};
pub use crate::correction::Form;
pub use columns::{check_text_columns, check_used_columns, first_bad_cell};
pub use compare::{Comparison, CvScore, ModelScore, TTestScore, compare};
pub use correction_per::{CorrectionPer, CorrectionPerInfo};
pub use fit::auto;
pub use fit::{fit, fit_split, measure_stability, stability};
pub use model::{
    BlackBox, BlackBoxScores, EquationInfo, JointInfo, MissingInfo, OUTSIDE_MARGIN, PairScores,
    PhysicsInfo, SCHEMA_VERSION, ScoresInfo, SearchSample, TableEvaluation, TableModel,
    TablePrediction, TrainingRanges, model_columns,
};
pub use per_class::PerClassInfo;
pub use prepare::{CalibratePer, PerLevel, Prepared, prepare};
pub use slots::SlotInfo;
pub use split::split_rows;

use hxai_symreg::SearchConfig;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// How the correction enters the hybrid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CorrectionForm {
    /// `y = f_p + delta`, `delta = y - f_p` (eq. 2-5).
    #[default]
    Additive,
    /// `y = f_p (1 + delta)`, `delta = y / f_p - 1`, for laws whose error scales with
    /// the prediction.
    Multiplicative,
    /// `y = f_p exp(delta)`, `delta = ln(y / f_p)`: multiplicative, with the correction
    /// found on the log scale, for scatter that grows with the quantity (log-normal, as
    /// tool life and wear scatter) and for power-law corrections, which are linear in the
    /// logarithms there. Every target and physics value must be positive.
    Log,
}

impl CorrectionForm {
    /// The link of a factor correction of this form.
    pub fn link(self) -> hxai_symreg::factors::Link {
        use hxai_symreg::factors::Link;
        match self {
            CorrectionForm::Additive => Link::Additive,
            CorrectionForm::Multiplicative => Link::Multiplicative,
            CorrectionForm::Log => Link::Log,
        }
    }

    /// `additive`, `multiplicative` or `log`.
    pub fn name(self) -> &'static str {
        match self {
            CorrectionForm::Additive => "additive",
            CorrectionForm::Multiplicative => "multiplicative",
            CorrectionForm::Log => "log",
        }
    }

    /// The interval `(lo, hi)` of the correction `delta` that the interval `[lo, hi]` of
    /// the target `y` is where the physics predicts `p`: `y - p` (additive), `y / p - 1`
    /// (multiplicative; the bounds swap where `p` is negative) or `ln(y / p)` (log). `(NaN,
    /// NaN)` where that is undefined (`p` = 0, or a bound not positive in the log form).
    pub fn delta_interval(self, lo: f64, hi: f64, p: f64) -> (f64, f64) {
        const NONE: (f64, f64) = (f64::NAN, f64::NAN);
        match self {
            CorrectionForm::Additive => (lo - p, hi - p),
            CorrectionForm::Multiplicative if p > 0.0 => (lo / p - 1.0, hi / p - 1.0),
            CorrectionForm::Multiplicative if p < 0.0 => (hi / p - 1.0, lo / p - 1.0),
            CorrectionForm::Log if p > 0.0 && lo > 0.0 => ((lo / p).ln(), (hi / p).ln()),
            _ => NONE,
        }
    }
}

/// Default of [`TableConfig::search_rows`]: the sample the structure is searched on.
pub const SEARCH_ROWS: usize = 2000;

/// The smallest [`TableConfig::search_rows`] accepted.
pub const MIN_SEARCH_ROWS: usize = 100;

/// The operators that write a harmonic: allowed in a correction only with `--periodic`.
const TRIG_OPERATORS: [&str; 2] = ["sin", "cos"];

/// The table hybrid's default ceiling on the factor form's pair factors (`--interactions`,
/// issue 68): each pair is kept only where it lowers the held-out error by two paired
/// standard errors, so the rule, not the ceiling, decides how many. Measured at 1 and 3
/// (docs/benchmarks.md, "Pairs where they pay"): at 3 issue 46's runout table falls from
/// 0.305 to 0.192 and roughness from 0.268 to 0.253, and a real production table (plm's
/// Produc) from 1.26x to 1.00x gradient boosting; that table's extrapolation got worse
/// (`auto` then kept the physics alone: 0.51x to 1.00x the calibrated physics) and a
/// farm table's test error rose 0.5 %.
pub const TABLE_INTERACTIONS: usize = 3;

/// Settings of [`fit`] and [`compare`].
#[derive(Clone, Debug)]
pub struct TableConfig {
    /// The target column.
    pub target: String,
    /// The physics equation (infix text, see [`hxai_symreg::infix`]).
    pub physics: String,
    /// Parameters fitted on the training rows.
    pub calibrate: Vec<String>,
    /// Starting values of calibrated parameters (default 1).
    pub init: BTreeMap<String, f64>,
    /// Values of parameters that are not calibrated.
    pub set: BTreeMap<String, f64>,
    /// Feature columns of the correction (`None`: every column except the target, the
    /// group column and `exclude`).
    pub features: Option<Vec<String>>,
    /// Columns left out of the default feature set.
    pub exclude: Vec<String>,
    /// Correction form.
    pub correction: CorrectionForm,
    /// How the correction is searched: free form or one factor per column.
    pub form: Form,
    /// Settings of the factor form (its seed is [`TableConfig::seed`]).
    pub factors: hxai_symreg::factors::FactorConfig,
    /// Rows sharing this column's value stay on one side of every split.
    pub group: Option<String>,
    /// Share of rows (or groups) held out for testing.
    pub test_fraction: f64,
    /// Test on the rows with the top `test_fraction` of this column (train low, test high).
    pub extrapolate: Option<String>,
    /// Seed of the split and of the search (overrides `search.seed`).
    pub seed: u64,
    /// Refit physics parameters and correction constants together once the correction's
    /// structure is chosen.
    pub joint: bool,
    /// Symbolic-regression settings of the correction (and of `symbolic` in compare).
    pub search: SearchConfig,
    /// Folds of the CV+ calibration of conformal prediction intervals (0: none; the model
    /// file then offers only the delta method). See [`ConformalInfo`].
    pub conformal_folds: usize,
    /// Training rows above which the correction's structure is searched on a sample of this
    /// many, stratified on the target (issue 67): the form `auto`'s folds, the search, the
    /// factor form's selection and the conformal and stability refits; the physics'
    /// calibration and the correction's constants still use every training row. Default
    /// [`SEARCH_ROWS`]; `usize::MAX` searches on every row.
    pub search_rows: usize,
    /// `--correction-per COL`: the correction's constants refitted per level of a text
    /// column, read from its indicator columns ([`correction_per::expand`] sets it).
    pub correction_per: Option<CorrectionPer>,
    /// `--periodic`: the columns an engineer knows repeat (a spindle angle, a time of day).
    /// Only these may carry a harmonic in the correction (the factor form's `sin(w x + c)`;
    /// the free form gets `sin` and `cos` among its operators only when one is declared).
    /// Empty (the default): no sine or cosine in any correction (issue 64).
    pub periodic: Vec<String>,
    /// `--monotone COL=+` (issue 68): columns whose effect in the correction must not
    /// decrease over their training range, in every factor and pair
    /// ([`hxai_symreg::factors::FactorConfig::increasing`]); the factor form only (the form
    /// `free` is refused with it, and `auto` chooses between `none` and `factors`).
    pub increasing: Vec<String>,
    /// `--monotone COL=-`: columns whose effect in the correction must not increase.
    pub decreasing: Vec<String>,
    /// Indicator columns (1 on a level's rows, 0 elsewhere) whose levels a random split
    /// keeps on both sides in proportion, so that every level keeps training rows
    /// (`--calibrate-per` and `--correction-per` add theirs: a level wholly in the test rows
    /// would keep its constant's start value).
    pub strata: Vec<String>,
    /// The per-level settings as asked (`--calibrate-per`, `--correction-per`), which
    /// [`prepare`] writes out (into the physics, `correction_per` and indicator columns).
    pub per_level: PerLevel,
    /// What the table's reader did with empty cells (`--missing drop|impute`), written into
    /// the model file by [`Prepared`]; `None` when the table had to be complete.
    pub missing: Option<MissingInfo>,
}

impl TableConfig {
    /// Defaults: additive correction, 20 % random test split, seed 42, the search of
    /// [`SearchConfig::laws`] (law operators, readable nesting, cross-validated selection;
    /// complexity at most 10), conformal intervals calibrated over
    /// [`DEFAULT_CONFORMAL_FOLDS`] folds.
    pub fn new(target: &str, physics: &str) -> Self {
        Self {
            target: target.to_string(),
            physics: physics.to_string(),
            calibrate: Vec::new(),
            init: BTreeMap::new(),
            set: BTreeMap::new(),
            features: None,
            exclude: Vec::new(),
            correction: CorrectionForm::Additive,
            form: Form::Free,
            factors: hxai_symreg::factors::FactorConfig {
                interactions: TABLE_INTERACTIONS,
                ..Default::default()
            },
            group: None,
            test_fraction: 0.2,
            extrapolate: None,
            seed: 42,
            joint: false,
            search: SearchConfig::laws(),
            conformal_folds: DEFAULT_CONFORMAL_FOLDS,
            search_rows: SEARCH_ROWS,
            correction_per: None,
            periodic: Vec::new(),
            increasing: Vec::new(),
            decreasing: Vec::new(),
            strata: Vec::new(),
            per_level: PerLevel::default(),
            missing: None,
        }
    }

    /// Checks the settings that need no table, once, before any work: the search's
    /// configuration (operators, nesting, budgets), `--joint` with `--correction-per` (not
    /// built), and a single conformal fold (CV+ needs 2, or 0 for none). What the table
    /// decides (columns, names, the split's sides) is checked against it by the fit.
    /// [`fit`], [`fit_split`] and [`compare`] call it first, so a bad setting is refused
    /// before a search has run rather than after it, and every search of the run (the
    /// correction's, the comparison's symbolic model and folds) takes the checked search
    /// configuration it returns instead of checking it again.
    ///
    /// # Errors
    /// [`crate::HybridError::InvalidConfig`] naming the setting, or the search's own
    /// [`hxai_symreg::SrError`].
    pub fn check(&self) -> Result<ValidTable, crate::HybridError> {
        if self.joint && self.correction_per.is_some() {
            return Err(crate::HybridError::InvalidConfig(
                "--joint with --correction-per is not built: the joint refit fits one set of \
                 correction constants; use one of them"
                    .into(),
            ));
        }
        if self.conformal_folds == 1 {
            return Err(crate::HybridError::InvalidConfig(
                "1 conformal fold(s): CV+ needs at least 2 (or 0 to fit without conformal \
                 intervals)"
                    .into(),
            ));
        }
        if self.search_rows < MIN_SEARCH_ROWS {
            return Err(crate::HybridError::InvalidConfig(format!(
                "--search-rows {}: the structure needs a sample of at least {MIN_SEARCH_ROWS} \
                 rows (default {SEARCH_ROWS})",
                self.search_rows
            )));
        }
        if let Some(c) = self.increasing.iter().find(|c| self.decreasing.contains(c)) {
            return Err(crate::HybridError::InvalidConfig(format!(
                "--monotone {c}: the column is declared both increasing (+) and decreasing (-)"
            )));
        }
        if self.monotone() && self.form == Form::Free {
            return Err(crate::HybridError::InvalidConfig(
                "--monotone with --form free is not built: the free form's equations are \
                 not constrained; use --form factors or auto (which then chooses between \
                 none and factors)"
                    .into(),
            ));
        }
        let search = self.search_config().check()?;
        Ok(ValidTable {
            cfg: self.clone(),
            search,
        })
    }

    /// The factor form's settings for a correction over the columns `features` (their
    /// order is the factor table's): harmonics only on the `--periodic` ones.
    fn factor_config(&self, features: &[String]) -> hxai_symreg::factors::FactorConfig {
        hxai_symreg::factors::FactorConfig {
            seed: self.seed,
            par: self.search.par,
            max_rows: self.search_rows,
            // `--consensus N` binds both forms' selections
            consensus: self.search.consensus_runs,
            shapes: shapes_of_operators(self.factors.shapes, &self.search.operators),
            periodic: Some(hxai_symreg::factors::FactorConfig::periodic_mask(
                features,
                &self.periodic,
            )),
            increasing: hxai_symreg::factors::FactorConfig::periodic_mask(
                features,
                &self.increasing,
            ),
            decreasing: hxai_symreg::factors::FactorConfig::periodic_mask(
                features,
                &self.decreasing,
            ),
            ..self.factors
        }
    }

    /// Whether a monotone constraint is declared (`--monotone`).
    pub fn monotone(&self) -> bool {
        !self.increasing.is_empty() || !self.decreasing.is_empty()
    }

    fn search_config(&self) -> SearchConfig {
        let mut operators = self.search.operators.clone();
        // harmonics only where declared (issue 64): without --periodic no sin or cos in
        // the correction, with it the free form may use both over the declared columns
        if self.periodic.is_empty() {
            operators.retain(|o| !TRIG_OPERATORS.contains(&o.as_str()));
        } else {
            for o in TRIG_OPERATORS {
                if !operators.iter().any(|x| x == o) {
                    operators.push(o.to_string());
                }
            }
        }
        SearchConfig {
            seed: self.seed,
            operators,
            // and with it, a sin or cos reads only the columns declared
            harmonic_inputs: (!self.periodic.is_empty()).then(|| self.periodic.clone()),
            ..self.search.clone()
        }
    }
}

/// A [`TableConfig`] that passed [`TableConfig::check`], with the search configuration the
/// check derived (its seed the table's [`TableConfig::seed`]). Reads as the configuration
/// it was made from (it dereferences to it); only [`TableConfig::check`] makes one.
#[derive(Clone, Debug)]
pub struct ValidTable {
    cfg: TableConfig,
    search: hxai_symreg::ValidSearch,
}

impl ValidTable {
    /// The configuration checked.
    pub fn config(&self) -> &TableConfig {
        &self.cfg
    }

    /// The correction's search configuration, checked, with the table's seed.
    pub fn search(&self) -> &hxai_symreg::ValidSearch {
        &self.search
    }
}

impl std::ops::Deref for ValidTable {
    type Target = TableConfig;

    fn deref(&self) -> &TableConfig {
        &self.cfg
    }
}

/// Reported while fitting: which task of how many, and the search's own progress.
#[derive(Clone, Debug, PartialEq)]
pub struct TableProgress {
    /// Task index (1-based).
    pub task: usize,
    /// Tasks planned.
    pub tasks: usize,
    /// What runs (`correction`, `symbolic`, `fold 2/5 correction`, ...).
    pub label: String,
    /// The search's progress within the task; for a phase that is not a search
    /// (`step`), its steps done (`epoch`) of its steps (`epochs`).
    pub search: hxai_symreg::Progress,
    /// Whether this reports a phase of the fit other than a search (issue 67: every phase
    /// named): `label` names it (`calibrating the physics on 800000 training rows`,
    /// `conformal calibration`, `black boxes`, ...), `search.epoch` of `search.epochs` its
    /// steps.
    pub step: bool,
}

impl TableProgress {
    /// A phase of the fit that is not a search: `label`, `done` of `steps` steps.
    pub fn phase(label: impl Into<String>, done: usize, steps: usize) -> Self {
        Self {
            task: 1,
            tasks: 1,
            label: label.into(),
            search: hxai_symreg::Progress {
                epoch: done,
                epochs: steps,
                evaluations: 0,
                best_loss: f64::NAN,
            },
            step: true,
        }
    }
}

/// The factor form's `shapes` less those that write an operator missing from `operators`
/// (`--operators`, which binds both forms; [`hxai_symreg::factors::Shapes::allowed_by`],
/// powers and pairs needing `div`: a negative exponent is a division). The hinge and the
/// step are taken with `--shapes` alone (their `abs` and `tanh` are not among the law
/// operators a correction searches by default). Measured: with `--operators add,sub,mul`
/// a pair `f^2/r` was kept.
fn shapes_of_operators(
    shapes: hxai_symreg::factors::Shapes,
    operators: &[String],
) -> hxai_symreg::factors::Shapes {
    // the names were checked with the search's settings; one that is not an operator
    // allows nothing
    let ops: Vec<hxai_symreg::Op> = operators
        .iter()
        .filter_map(|o| hxai_symreg::Op::parse(o).ok())
        .collect();
    shapes.allowed_by(&ops, true)
}
