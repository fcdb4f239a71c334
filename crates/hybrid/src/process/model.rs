//! The model file of a process hybrid: physics equation and parameters, correction, the
//! whole hybrid as one equation; prediction and evaluation on new tables.
use super::CorrectionForm;
use crate::HybridError;
use crate::conformal::ConformalInfo;
use crate::evaluate::{DEFAULT_INTERVAL, IntervalReport};
use hxai_eval::{IntervalMethod, Metrics};
use hxai_symreg::infix::{Compiled, compile, parse};
use hxai_symreg::{Model, Node, Op, ParamEstimate, Program, Table, Uncertainty, expr::Expr};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Schema version of the process model file.
pub const PROCESS_SCHEMA_VERSION: u32 = 1;

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

/// The correction part of the model file.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CorrectionInfo {
    /// `additive` (`y = f_p + delta`), `multiplicative` (`y = f_p (1 + delta)`) or `log`
    /// (`y = f_p exp(delta)`).
    pub kind: CorrectionForm,
    /// The equation's forms, complexity and features (JSON keys `equation`, `sympy`,
    /// `latex`, `complexity`, `features` beside `kind`).
    #[serde(flatten)]
    pub forms: hxai_symreg::ModelForms,
    /// Feature columns the search was offered.
    pub candidates: Vec<String>,
    /// The fitted symbolic model (what `predict` evaluates).
    pub model: Model,
    /// The correction's constants as a template with named parameters and their
    /// uncertainty, fitted to `delta` on the training rows (`hxai_symreg::uncertainty`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<Uncertainty>,
    /// The Pareto front of the correction's search, for `hxai explain`; absent in files
    /// written before it was stored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pareto: Option<Vec<crate::explain::ParetoMember>>,
    /// How the correction was selected, its structure's share over resamples (consensus or
    /// stability runs) and the alternatives the data cannot tell apart from it
    /// ([`hxai_symreg::SelectionReport`]); absent in files written before it was stored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub selection: Option<hxai_symreg::SelectionReport>,
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

/// Which rows were used for fitting and which were held out.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct SplitInfo {
    /// `random`, `grouped`, `extrapolate` or `given`.
    pub kind: String,
    /// Training rows (0-based, in the table's order).
    pub train: Vec<usize>,
    /// Test rows.
    pub test: Vec<usize>,
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
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct ScoresInfo {
    /// On the training rows.
    pub train: PairScores,
    /// On the test rows (absent when the split left none).
    pub test: Option<PairScores>,
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

/// A fitted process hybrid: everything needed to predict, and its report.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ProcessModel {
    /// [`PROCESS_SCHEMA_VERSION`].
    pub schema_version: u32,
    /// The target column.
    pub target: String,
    /// The physics equation and its parameters.
    pub physics: PhysicsInfo,
    /// The learned correction.
    pub correction: CorrectionInfo,
    /// The whole hybrid as one equation over the columns, every parameter substituted.
    pub hybrid: EquationInfo,
    /// The split of the fitting table.
    pub split: SplitInfo,
    /// The grouping column, if any.
    pub group: Option<String>,
    /// With a joint refit (`--joint`): the two-stage values it replaced.
    pub joint: Option<JointInfo>,
    /// Physics vs hybrid on the fitting table.
    pub scores: ScoresInfo,
    /// With `hxai hybrid fit --stability N`: the stability of the correction's structure
    /// over bootstrap resamples of the training rows ([`super::process_stability`]).
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
}

/// Per-row predictions of a process hybrid.
#[derive(Clone, Debug, PartialEq)]
pub struct ProcessPrediction {
    /// The physics equation.
    pub physics: Vec<f64>,
    /// The correction `delta`.
    pub correction: Vec<f64>,
    /// The hybrid.
    pub hybrid: Vec<f64>,
}

/// Physics vs hybrid against the target on a table.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ProcessEvaluation {
    /// Scores of the physics alone.
    pub physics: Metrics,
    /// Scores of the hybrid.
    pub hybrid: Metrics,
    /// `(rmse_physics - rmse_hybrid) / rmse_physics * 100`.
    pub improvement_pct: f64,
    /// Paired two-tailed t-test of the per-row squared errors (physics vs hybrid).
    pub t_test: hxai_eval::TTest,
    /// Rows evaluated.
    pub n_samples: usize,
    /// Coverage of the hybrid's prediction intervals (when the model stores the
    /// uncertainty of the hybrid).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interval: Option<IntervalReport>,
    /// Rows outside the training ranges, per column ([`ProcessModel::range_warnings`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

pub(crate) fn columns_of<'a>(
    table: &'a Table,
    names: &[String],
    what: &'static str,
) -> Result<Vec<&'a [f64]>, HybridError> {
    names
        .iter()
        .map(|n| {
            table.column(n).ok_or_else(|| HybridError::MissingColumn {
                what,
                name: n.clone(),
                columns: table.names().join(", "),
            })
        })
        .collect()
}

/// The physics `phys` (over the columns `inputs`) on every row of `table`, refusing a
/// non-finite value (naming the row).
pub(crate) fn finite_physics(
    table: &Table,
    phys: &Compiled,
    inputs: &[String],
) -> Result<Vec<f64>, HybridError> {
    let cols = columns_of(table, inputs, "physics column")?;
    let v = phys.eval_columns(&cols, table.n_rows());
    if let Some((row, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(HybridError::BadPhysics {
            row,
            value: *x,
            why: "not a finite number: check the equation's domain at this row".into(),
        });
    }
    Ok(v)
}

/// Compiles the physics equation with the given parameter values.
pub(crate) fn compile_physics(
    equation: &str,
    columns: &[String],
    parameters: &BTreeMap<String, f64>,
) -> Result<Compiled, HybridError> {
    let parsed = parse(equation).map_err(|source| HybridError::Equation {
        equation: equation.to_string(),
        source,
    })?;
    compile(&parsed, columns, parameters).map_err(|source| HybridError::Equation {
        equation: equation.to_string(),
        source,
    })
}

/// The hybrid as one program over `names`: physics nodes, then the correction with its
/// affine inputs and output map spelled out as constant leaves, joined by the correction
/// form. Returns the program, its parameters, the input names, and where each physics
/// parameter slot and each correction parameter went.
pub(crate) struct Combined {
    pub program: Program,
    pub params: Vec<f64>,
    pub names: Vec<String>,
    /// physics param index -> combined index (for constant leaves)
    pub phys_map: BTreeMap<usize, usize>,
    /// correction param index -> combined index
    pub corr_map: Vec<usize>,
}

pub(crate) fn combine(phys: &Compiled, corr: &Model, kind: CorrectionForm) -> Combined {
    let mut names: Vec<String> = phys.inputs.clone();
    for f in &corr.feature_names {
        if !names.contains(f) {
            names.push(f.clone());
        }
    }
    let idx = |n: &str, names: &[String]| names.iter().position(|m| m == n).unwrap_or(0) as u16;
    let mut nodes: Vec<Node> = Vec::new();
    let mut params = vec![1.0, 0.0];
    let mut phys_map = BTreeMap::new();
    let phys_offs = phys.program.param_offsets();
    for (k, n) in phys.program.nodes.iter().enumerate() {
        match n {
            Node::Var(j) => nodes.push(Node::Var(idx(&phys.inputs[*j as usize], &names))),
            Node::Const => {
                phys_map.insert(phys_offs[k], params.len());
                params.push(phys.params[phys_offs[k]]);
                nodes.push(Node::Const);
            }
            Node::Op(op) => nodes.push(Node::Op(*op)),
        }
    }
    let mut corr_map = vec![0usize; corr.params.len()];
    let offs = corr.program.param_offsets();
    let mut konst = |nodes: &mut Vec<Node>, params: &mut Vec<f64>, from: usize| {
        corr_map[from] = params.len();
        params.push(corr.params[from]);
        nodes.push(Node::Const);
    };
    for (k, n) in corr.program.nodes.iter().enumerate() {
        match n {
            Node::Var(j) => {
                let v = Node::Var(idx(&corr.feature_names[*j as usize], &names));
                if corr.program.affine {
                    konst(&mut nodes, &mut params, offs[k]);
                    nodes.push(v);
                    nodes.push(Node::Op(Op::Mul));
                    konst(&mut nodes, &mut params, offs[k] + 1);
                    nodes.push(Node::Op(Op::Add));
                } else {
                    nodes.push(v);
                }
            }
            Node::Const => konst(&mut nodes, &mut params, offs[k]),
            Node::Op(op) => nodes.push(Node::Op(*op)),
        }
    }
    konst(&mut nodes, &mut params, 0);
    nodes.push(Node::Op(Op::Mul));
    konst(&mut nodes, &mut params, 1);
    nodes.push(Node::Op(Op::Add));
    match kind {
        CorrectionForm::Additive => nodes.push(Node::Op(Op::Add)),
        CorrectionForm::Multiplicative => {
            nodes.push(Node::Const);
            params.push(1.0);
            nodes.push(Node::Op(Op::Add));
            nodes.push(Node::Op(Op::Mul));
        }
        CorrectionForm::Log => {
            nodes.push(Node::Op(Op::Exp));
            nodes.push(Node::Op(Op::Mul));
        }
    }
    Combined {
        program: Program {
            nodes,
            affine: false,
        },
        params,
        names,
        phys_map,
        corr_map,
    }
}

/// Re-associates `a + (-x + c)` as `(a - x) + c` (and `a + (-x - c)` as `(a - x) - c`),
/// which arises where the physics meets a correction that starts with a minus sign, so the
/// printed hybrid reads `a - x + c` instead of `a + -x + c`. Equal up to rounding.
fn tidy(e: Expr) -> Expr {
    match e {
        Expr::Bin(op, a, b) => {
            let a = tidy(*a);
            let b = tidy(*b);
            match (op, b) {
                (Op::Add, Expr::Bin(inner @ (Op::Add | Op::Sub), l, r)) => match *l {
                    Expr::Neg(x) => {
                        Expr::Bin(inner, Box::new(Expr::Bin(Op::Sub, Box::new(a), x)), r)
                    }
                    l => Expr::Bin(
                        Op::Add,
                        Box::new(a),
                        Box::new(Expr::Bin(inner, Box::new(l), r)),
                    ),
                },
                (op, b) => Expr::Bin(op, Box::new(a), Box::new(b)),
            }
        }
        Expr::Un(op, a) => Expr::Un(op, Box::new(tidy(*a))),
        Expr::Neg(a) => Expr::Neg(Box::new(tidy(*a))),
        e => e,
    }
}

/// The three printed forms of an expression.
pub(crate) fn forms(e: &Expr) -> EquationInfo {
    let e = &tidy(e.clone());
    EquationInfo {
        equation: e.to_text(Some(4), false),
        sympy: e.to_text(None, true),
        latex: e.to_latex(4),
        uncertainty: None,
    }
}

/// Combines physics and correction values by the correction form.
pub(crate) fn combine_values(kind: CorrectionForm, physics: f64, delta: f64) -> f64 {
    match kind {
        CorrectionForm::Additive => physics + delta,
        CorrectionForm::Multiplicative => physics * (1.0 + delta),
        CorrectionForm::Log => physics * delta.exp(),
    }
}

impl ProcessModel {
    /// The physics equation compiled with the model's parameter values.
    ///
    /// # Errors
    /// A corrupt model file (the equation does not parse or names an unknown symbol).
    pub fn physics_program(&self) -> Result<Compiled, HybridError> {
        compile_physics(
            &self.physics.equation,
            &self.physics.columns,
            &self.physics.parameters,
        )
    }

    /// Physics, correction and hybrid for every row of `table` (the target is not needed;
    /// extra columns are ignored).
    ///
    /// # Errors
    /// [`HybridError::MissingColumn`] for a column the model needs;
    /// [`HybridError::BadPhysics`] naming the first row where the physics is not finite.
    pub fn predict(&self, table: &Table) -> Result<ProcessPrediction, HybridError> {
        let phys = self.physics_program()?;
        let physics = finite_physics(table, &phys, &phys.inputs)?;
        columns_of(
            table,
            &self.correction.model.feature_names,
            "correction feature",
        )?;
        let correction = self.correction.model.predict(table)?;
        if let Some((row, v)) = correction.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(HybridError::BadCorrection { row, value: *v });
        }
        let hybrid = physics
            .iter()
            .zip(&correction)
            .map(|(p, d)| combine_values(self.correction.kind, *p, *d))
            .collect();
        Ok(ProcessPrediction {
            physics,
            correction,
            hybrid,
        })
    }

    /// Physics vs hybrid against the target column of `table`.
    ///
    /// # Errors
    /// A missing column (the target included), a bad physics value, or fewer than two rows
    /// or non-finite predictions (from the statistics).
    pub fn evaluate(&self, table: &Table) -> Result<ProcessEvaluation, HybridError> {
        self.evaluate_at(table, DEFAULT_INTERVAL)
    }

    /// [`ProcessModel::evaluate`] with the coverage and median width of the hybrid's
    /// prediction intervals at `level` ([`ProcessEvaluation::interval`]) by the model's
    /// default method ([`ProcessModel::default_interval_method`]), when it has one.
    ///
    /// # Errors
    /// As [`ProcessModel::evaluate`], and a `level` outside (0, 1).
    pub fn evaluate_at(&self, table: &Table, level: f64) -> Result<ProcessEvaluation, HybridError> {
        match self.default_interval_method(level) {
            Some(method) => self.evaluate_with(table, level, method),
            None => {
                let y = columns_of(table, std::slice::from_ref(&self.target), "target")?[0];
                let p = self.predict(table)?;
                let mut ev = evaluation(y, &p.physics, &p.hybrid)?;
                ev.warnings = self.range_warnings(table);
                Ok(ev)
            }
        }
    }

    /// [`ProcessModel::evaluate_at`] with the intervals made by `method`.
    ///
    /// # Errors
    /// As [`ProcessModel::evaluate_at`], and those of [`ProcessModel::intervals_with`] (a
    /// method the model file cannot serve among them).
    pub fn evaluate_with(
        &self,
        table: &Table,
        level: f64,
        method: IntervalMethod,
    ) -> Result<ProcessEvaluation, HybridError> {
        let y = columns_of(table, std::slice::from_ref(&self.target), "target")?[0];
        let p = self.predict(table)?;
        let mut ev = evaluation(y, &p.physics, &p.hybrid)?;
        let iv = self.intervals_with(table, level, method)?;
        ev.interval = Some(IntervalReport::of(method, level, y, &iv));
        ev.warnings = self.range_warnings(table);
        Ok(ev)
    }

    /// Warnings for rows of `table` outside the ranges of the training rows, per input
    /// column of the hybrid ([`super::traps::range_warnings`]; the ranges are those the
    /// conformal calibration stores, so a file fitted without it gives none).
    pub fn range_warnings(&self, table: &Table) -> Vec<String> {
        let Some(w) = self.conformal.as_ref().and_then(|c| c.widening.as_ref()) else {
            return Vec::new();
        };
        let ranges: Vec<(String, f64, f64)> = w
            .columns
            .iter()
            .zip(w.lo.iter().zip(&w.hi))
            .map(|(n, (lo, hi))| (n.clone(), *lo, *hi))
            .collect();
        super::traps::range_warnings(table, &ranges)
    }

    /// The coverage and median width of the intervals by `method` at `level` on the test
    /// rows of the model's own split of `table` (the table it was fitted on); `None` when
    /// the split has no test rows.
    ///
    /// # Errors
    /// A table with fewer rows than the split names, and those of
    /// [`ProcessModel::intervals_with`].
    pub fn test_interval(
        &self,
        table: &Table,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Option<IntervalReport>, HybridError> {
        if self.split.test.is_empty() {
            return Ok(None);
        }
        if let Some(&i) = self.split.test.iter().find(|&&i| i >= table.n_rows()) {
            return Err(HybridError::InvalidConfig(format!(
                "the model's split names row {} but the table has {} rows: pass the table the model was fitted on",
                i + 1,
                table.n_rows()
            )));
        }
        let test = table.select_rows(&self.split.test)?;
        let y = columns_of(&test, std::slice::from_ref(&self.target), "target")?[0];
        let iv = self.intervals_with(&test, level, method)?;
        Ok(Some(IntervalReport::of(method, level, y, &iv)))
    }

    /// The interval method used at `level` when none is asked for: conformal (CV+) when the
    /// file stores its calibration and it has enough scores for `level`
    /// ([`crate::conformal::ConformalInfo::serves`]: 19 at 95 %), else the delta method when it stores the hybrid's
    /// uncertainty, else none.
    pub fn default_interval_method(&self, level: f64) -> Option<IntervalMethod> {
        if self.conformal.as_ref().is_some_and(|c| c.serves(level)) {
            Some(IntervalMethod::Conformal)
        } else if self.hybrid.uncertainty.is_some() {
            Some(IntervalMethod::Delta)
        } else {
            None
        }
    }

    /// Prediction intervals `(lo, hi)` of the hybrid at `level` for every row of `table`, by
    /// the model's default method ([`ProcessModel::default_interval_method`]).
    ///
    /// # Errors
    /// As [`ProcessModel::intervals_with`]; [`HybridError::InvalidConfig`] when the file
    /// stores neither conformal calibration nor uncertainty.
    pub fn intervals(&self, table: &Table, level: f64) -> Result<Vec<(f64, f64)>, HybridError> {
        let method = self
            .default_interval_method(level)
            .unwrap_or(IntervalMethod::Delta);
        self.intervals_with(table, level, method)
    }

    /// Prediction intervals `(lo, hi)` of the hybrid at `level` for every row of `table` by
    /// `method`:
    ///
    /// - [`IntervalMethod::Conformal`]: CV+ over the folds of the fit with scores
    ///   normalised by the local scale ([`ConformalInfo`]); coverage at least `2 level - 1`
    ///   (in practice near `level`) for rows exchangeable with the training rows.
    /// - [`IntervalMethod::Split`]: split conformal with the first fold's model, calibrated
    ///   on that fold's rows alone; coverage at least `level` for such rows.
    /// - [`IntervalMethod::Delta`]: the delta method through the whole hybrid equation
    ///   (calibrated physics parameters and the correction's free constants, with their
    ///   covariance on the training rows) plus the residual variance of the hybrid on the
    ///   training rows. Assumes independent residuals of constant variance and the structure
    ///   fixed; the physics parameters and the correction were fitted one after the other,
    ///   and their covariance is taken as if they had been fitted together (the joint fit's;
    ///   see `hxai_symreg::uncertainty`).
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] when the model file cannot serve `method` (no
    /// conformal calibration, or no uncertainty: a file written before they existed, or
    /// fitted without conformal folds: refit), too few calibration scores for `level`, a
    /// `level` outside (0, 1), a missing column, a non-finite value.
    pub fn intervals_with(
        &self,
        table: &Table,
        level: f64,
        method: IntervalMethod,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        if !(level > 0.0 && level < 1.0) {
            return Err(HybridError::InvalidConfig(format!(
                "interval level {level}: give a probability between 0 and 1, such as 0.95"
            )));
        }
        let phys = self.physics_program()?;
        let c = combine(&phys, &self.correction.model, self.correction.kind);
        if method != IntervalMethod::Delta {
            let Some(conf) = &self.conformal else {
                return Err(HybridError::InvalidConfig(format!(
                    "this model file stores no conformal calibration (written before conformal \
                     intervals existed, or fitted with --conformal-folds 0): refit it with \
                     `hxai hybrid fit`, or use --interval-method delta instead of {}",
                    method.name()
                )));
            };
            return super::conformal::intervals(conf, &c, table, level, method);
        }
        let Some(unc) = &self.hybrid.uncertainty else {
            return Err(HybridError::InvalidConfig(
                "this model file stores no uncertainty (written before prediction intervals \
                 existed): refit it with `hxai hybrid fit`"
                    .into(),
            ));
        };
        let cols = columns_of(table, &c.names, "column")?;
        Ok(unc.intervals(&c.program, &c.params, &cols, table.n_rows(), level)?)
    }

    /// The explanation of the correction ([`crate::explain::explain`]): with `table` (the
    /// table the model was fitted on, every row of its split present) the correction's
    /// response to each feature it uses and predicted vs true `delta` (`y - f_p`,
    /// `y / f_p - 1` for a multiplicative correction, `ln(y / f_p)` for the log form) on the
    /// split's rows, with prediction intervals of the correction at `level` by `method`
    /// (default: the file's,
    /// [`ProcessModel::default_interval_method`]; none when the file stores no way to make
    /// them); the Pareto front when the file stores it.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] when `table` has fewer rows than the split names, and
    /// those of [`ProcessModel::predict`] and [`crate::explain::explain`].
    pub fn explain(
        &self,
        table: Option<&Table>,
        level: f64,
        method: Option<IntervalMethod>,
    ) -> Result<crate::explain::Explanation, HybridError> {
        let pareto = self.correction.pareto.as_deref();
        let model = &self.correction.model;
        let Some(table) = table else {
            return crate::explain::explain(model, None, pareto, None, "delta", level);
        };
        let rows: Vec<usize> = self
            .split
            .train
            .iter()
            .chain(&self.split.test)
            .copied()
            .collect();
        if let Some(&i) = rows.iter().find(|&&i| i >= table.n_rows()) {
            return Err(HybridError::InvalidConfig(format!(
                "the model was fitted on a table with at least {} rows, this one has {}: pass the table the model was fitted on",
                i + 1,
                table.n_rows()
            )));
        }
        let y = columns_of(table, std::slice::from_ref(&self.target), "target")?[0];
        let physics = self.predict(table)?.physics;
        let delta = super::deltas(self.correction.kind, y, &physics, &rows)?;
        let features = table.select_rows(&rows)?;
        let is_test: Vec<bool> = (0..rows.len())
            .map(|k| k >= self.split.train.len())
            .collect();
        let data = crate::explain::ExplainData {
            features: &features,
            target: &delta,
            is_test: &is_test,
        };
        // the columns a response grid lacks (the physics' own) are held at their median
        // on the training rows, as the grid holds the correction's other features
        let phys = self.physics_program()?;
        let c = combine(&phys, &self.correction.model, self.correction.kind);
        let mut fill = Vec::new();
        for name in &c.names {
            let col = table.require(name)?;
            let m = crate::explain::median(self.split.train.iter().map(|&i| col[i]))
                .ok_or_else(|| HybridError::NoData("no training rows to explain on".into()))?;
            fill.push((name.clone(), m));
        }
        let band = method
            .or_else(|| self.default_interval_method(level))
            .map(|m| {
                (m, move |t: &Table, l: f64| {
                    self.correction_intervals(t, l, m, &fill)
                })
            });
        let band = band
            .as_ref()
            .map(|(m, b)| (b as &crate::explain::Band<'_>, *m));
        crate::explain::explain(model, band, pareto, Some(&data), "delta", level)
    }

    /// Prediction intervals of the correction `delta` at `level` by `method` for the rows of
    /// `features`: the hybrid's intervals ([`ProcessModel::intervals_with`]; a column
    /// `features` lacks is held at its value in `fill`) taken back to `delta` through the
    /// physics' prediction ([`CorrectionForm::delta_interval`]).
    fn correction_intervals(
        &self,
        features: &Table,
        level: f64,
        method: IntervalMethod,
        fill: &[(String, f64)],
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        let mut names = features.names().to_vec();
        let mut cols: Vec<Vec<f64>> = names
            .iter()
            .map(|n| features.require(n).map(<[f64]>::to_vec))
            .collect::<Result<_, _>>()?;
        for (name, v) in fill {
            if !names.contains(name) {
                names.push(name.clone());
                cols.push(vec![*v; features.n_rows()]);
            }
        }
        let full = Table::new(names, cols)?;
        let iv = self.intervals_with(&full, level, method)?;
        let phys = self.physics_program()?;
        let physics = finite_physics(&full, &phys, &phys.inputs)?;
        Ok(iv
            .into_iter()
            .zip(physics)
            .map(|((lo, hi), p)| self.correction.kind.delta_interval(lo, hi, p))
            .collect())
    }

    /// The whole hybrid as one expression over the columns.
    ///
    /// # Errors
    /// A corrupt model file.
    pub fn hybrid_expr(&self) -> Result<Expr, HybridError> {
        let phys = self.physics_program()?;
        let c = combine(&phys, &self.correction.model, self.correction.kind);
        Ok(Expr::from_program(&c.program, &c.params, &c.names))
    }

    /// Pretty JSON of the model file.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Reads a model file written by [`ProcessModel::to_json`] and checks it.
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`] for text that is not such a model,
    /// [`HybridError::SchemaVersion`] for another version, or a physics equation that no
    /// longer compiles.
    pub fn from_json(text: &str) -> Result<Self, HybridError> {
        let v: serde_json::Value =
            serde_json::from_str(text).map_err(|e| HybridError::ModelFormat(e.to_string()))?;
        if v.get("target").is_none() && v.get("window").is_some() && v.get("features").is_some() {
            return Err(HybridError::ModelFormat(
                "this is a model of `hxai fit` (the tool position from an accelerometer), not of \
                 `hxai hybrid fit`: apply it with `hxai predict`, `hxai evaluate` or `hxai stream`"
                    .into(),
            ));
        }
        match v.get("schema_version").and_then(serde_json::Value::as_u64) {
            Some(n) if n == u64::from(PROCESS_SCHEMA_VERSION) => {}
            other => {
                return Err(HybridError::SchemaVersion {
                    found: other.map_or_else(|| "none".to_string(), |n| n.to_string()),
                    expected: PROCESS_SCHEMA_VERSION,
                });
            }
        }
        let m: ProcessModel =
            serde_json::from_value(v).map_err(|e| HybridError::ModelFormat(e.to_string()))?;
        let phys = m.physics_program()?;
        // the correction model checks itself on the way in
        Model::from_json(&serde_json::to_string(&m.correction.model).unwrap_or_default())?;
        if let Some(conf) = &m.conformal {
            let c = combine(&phys, &m.correction.model, m.correction.kind);
            conf.check(c.params.len())?;
            if conf.scores.len() != m.split.train.len() {
                return Err(HybridError::ModelFormat(format!(
                    "`conformal` has {} scores for {} training rows",
                    conf.scores.len(),
                    m.split.train.len()
                )));
            }
        }
        Ok(m)
    }
}

pub(crate) fn evaluation(
    y: &[f64],
    physics: &[f64],
    hybrid: &[f64],
) -> Result<ProcessEvaluation, HybridError> {
    if y.len() < 2 {
        return Err(HybridError::InvalidConfig(format!(
            "{} row(s) to evaluate on: R² and the paired t-test need at least 2",
            y.len()
        )));
    }
    let ps = hxai_eval::score(y, physics)?;
    let hs = hxai_eval::score(y, hybrid)?;
    let se_p = hxai_eval::squared_errors(y, physics)?;
    let se_h = hxai_eval::squared_errors(y, hybrid)?;
    Ok(ProcessEvaluation {
        improvement_pct: hxai_eval::improvement_pct(ps.rmse, hs.rmse)?,
        t_test: hxai_eval::paired_t_test(&se_p, &se_h)?,
        physics: ps,
        hybrid: hs,
        n_samples: y.len(),
        interval: None,
        warnings: Vec::new(),
    })
}
