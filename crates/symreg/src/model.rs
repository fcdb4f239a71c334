//! Fitted models: evaluation on new data, export, and constant snapping.
use crate::eval::Evaluator;
use crate::expr::Expr;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::ops::Op;
use crate::program::{ComplexityMeasure, Node, Program};
use crate::{SrError, Table};
use serde::{Deserialize, Serialize};

/// A fitted symbolic model: a postfix program over named features with its parameters.
///
/// Serialises to JSON (serde) with everything needed to predict; load it back with
/// [`Model::from_json`] and evaluate it on new rows with [`Model::predict`].
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Model {
    /// Names of the features the program refers to; `Var(i)` is `features[i]`.
    pub feature_names: Vec<String>,
    /// The program.
    pub program: Program,
    /// Parameters: output scale, output offset, then each node's own.
    pub params: Vec<f64>,
    /// Complexity under the search's measure.
    pub complexity: usize,
    /// Mean squared error on the training rows (NaN when unknown; JSON `null`).
    #[serde(deserialize_with = "null_as_nan")]
    pub train_mse: f64,
    /// Criterion value (lower is better) on the training rows (NaN when unknown); under
    /// [`Criterion::CrossValidation`](crate::Criterion::CrossValidation), the mean held-out
    /// squared error.
    #[serde(deserialize_with = "null_as_nan")]
    pub score: f64,
}

/// JSON has no NaN: serde_json writes it as `null`; read `null` back as NaN.
fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Most nodes a model read from a file may have: searches stop at a few dozen, and a
/// program this long is also as deep as the recursive walks over it (printing, the
/// expression tree) can go on any thread's stack.
pub const MAX_PROGRAM_NODES: usize = 1_000;

impl Model {
    /// Builds a model and checks that program, parameters and names agree.
    ///
    /// # Errors
    /// [`SrError::MalformedModel`] if the program is not a single expression, refers to a
    /// feature that is not named, or the parameter count is wrong.
    pub fn new(
        feature_names: Vec<String>,
        program: Program,
        params: Vec<f64>,
    ) -> Result<Self, SrError> {
        let m = Model {
            complexity: program.complexity(ComplexityMeasure::FeaturesPlusOperators),
            feature_names,
            program,
            params,
            train_mse: f64::NAN,
            score: f64::NAN,
        };
        m.check()?;
        Ok(m)
    }

    /// Checks a model read from a file in full: [`Model::new`]'s checks, plus finite
    /// parameters and unique feature names. Call it on a model deserialised by other means
    /// than [`Model::from_json`] (for example as part of a larger file) before using it.
    ///
    /// # Errors
    /// [`SrError::MalformedModel`] naming what is wrong.
    pub fn validate(&self) -> Result<(), SrError> {
        if self.program.nodes.len() > MAX_PROGRAM_NODES {
            return Err(SrError::MalformedModel(format!(
                "the program has {} nodes, more than the {MAX_PROGRAM_NODES} a model can have; \
                 the file was not written by a search",
                self.program.nodes.len()
            )));
        }
        self.check()?;
        if let Some(i) = self.params.iter().position(|p| !p.is_finite()) {
            return Err(SrError::MalformedModel(format!(
                "parameter {i} is {}; every parameter must be a finite number",
                self.params[i]
            )));
        }
        for (i, n) in self.feature_names.iter().enumerate() {
            if self.feature_names[..i].contains(n) {
                return Err(SrError::MalformedModel(format!(
                    "feature name `{n}` appears twice"
                )));
            }
        }
        Ok(())
    }

    pub(crate) fn check(&self) -> Result<(), SrError> {
        if self.program.nodes.is_empty() || !self.program.is_valid() {
            return Err(SrError::MalformedModel(
                "the program is not a single well-formed expression".into(),
            ));
        }
        if self.params.len() != self.program.n_params() {
            return Err(SrError::MalformedModel(format!(
                "the program needs {} parameters but {} are stored",
                self.program.n_params(),
                self.params.len()
            )));
        }
        for n in &self.program.nodes {
            if let Node::Var(j) = n
                && *j as usize >= self.feature_names.len()
            {
                return Err(SrError::MalformedModel(format!(
                    "input index {j} has no feature name"
                )));
            }
        }
        Ok(())
    }

    /// Predictions for every row of `data`; inputs are looked up by name, extra columns are
    /// ignored. Rows where the expression is undefined (e.g. `log` of a negative value)
    /// give NaN.
    ///
    /// # Errors
    /// [`SrError::UnknownColumn`] if a feature is missing; [`SrError::MalformedModel`] for a
    /// corrupt (e.g. hand-edited) model.
    pub fn predict(&self, data: &Table) -> Result<Vec<f64>, SrError> {
        self.check()?;
        let cols = self.columns(data)?;
        let mut out = Vec::new();
        Evaluator::new(&self.program).predict(
            &self.program,
            &self.params,
            &cols,
            data.n_rows(),
            &mut out,
        );
        Ok(out)
    }

    /// The columns of `data` the model reads, in feature order.
    pub(crate) fn columns<'a>(&self, data: &'a Table) -> Result<Vec<&'a [f64]>, SrError> {
        self.feature_names
            .iter()
            .map(|name| {
                data.column(name)
                    .ok_or_else(|| SrError::UnknownColumn(name.clone()))
            })
            .collect()
    }

    /// The simplified reporting expression.
    pub fn expr(&self) -> Expr {
        Expr::from_program(&self.program, &self.params, &self.feature_names)
    }

    /// Plain-text equation with 4 significant digits, e.g. `29.4*exp(-(...)) - 9.71`.
    pub fn equation(&self) -> String {
        self.expr().to_text(Some(4), false)
    }

    /// Text that `sympy.sympify` parses, with full-precision constants (`**` powers, `Abs`).
    /// A feature name is written as it is when sympy reads it back as a symbol of that
    /// name, otherwise as `Symbol('name')` (names such as `E`, `I`, `pi`, `lambda`, `a b`,
    /// unicode; see [`crate::expr::sympy_symbol`]), so the text always reads back with plain
    /// `sympy.sympify` and every feature stays a distinct symbol.
    pub fn sympy(&self) -> String {
        self.expr().to_text(None, true)
    }

    /// LaTeX with 4 significant digits.
    pub fn latex(&self) -> String {
        self.expr().to_latex(4)
    }

    /// Complexity (the paper's count by default: features + operators).
    pub fn complexity(&self) -> usize {
        self.complexity
    }

    /// Names of the features that appear in the equation, in first-use order.
    pub fn features(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for n in &self.program.nodes {
            if let Node::Var(j) = n {
                let name = &self.feature_names[*j as usize];
                if !out.contains(name) {
                    out.push(name.clone());
                }
            }
        }
        out
    }

    /// Serialises the model to JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default()
    }

    /// Loads a model saved with [`Model::to_json`].
    ///
    /// # Errors
    /// [`SrError::MalformedModel`] when the text is not a valid model.
    pub fn from_json(text: &str) -> Result<Self, SrError> {
        let m: Model = serde_json::from_str(text)
            .map_err(|e| SrError::MalformedModel(hxai_table::plain_json_error(&e.to_string())))?;
        m.validate()?;
        Ok(m)
    }
}

/// How close (relative) a constant must be to a third, a quarter or a named irrational
/// ([`crate::expr::named_constants`]) for that value to be tried: 1 %. Farther values would
/// rarely pass the criterion and each try costs a refit.
const NAMED_SNAP_WINDOW: f64 = 0.01;

/// How a snap candidate is judged by [`snap_params`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Snap {
    /// An exact value of the plain kinds (0, +-1, an integer, a half, a multiple of pi/2):
    /// kept when the criterion over all snaps so far is no worse.
    Exact,
    /// An exact value of the kinds tried only near the fitted value (a third, a quarter, a
    /// named irrational): kept only when it pays for itself, its loss within one
    /// parameter's charge of the loss just before it, so it cannot use the allowance that
    /// earlier snaps left unused (a quarter that costs 2.7 % of the loss at n = 1,000 is
    /// refused where the three snaps before it each cost nothing).
    ExactAlone,
    /// `v` rounded to 1-3 significant digits: still a fitted value.
    Rounded,
}

/// Candidate simple values near `v`, simplest first, each with how it is judged: exact
/// values (0, +-1, an integer, a half, a multiple of pi/2; a third or a quarter, a named
/// irrational such as `sqrt(2)` or `1/sqrt(2 pi)` when `named`) before `v` rounded to 1-3
/// significant digits.
fn snap_candidates(v: f64, weight: bool, named: bool) -> Vec<(f64, Snap)> {
    let mut c: Vec<(f64, Snap)> = if weight {
        vec![(1.0, Snap::Exact), (-1.0, Snap::Exact), (0.0, Snap::Exact)]
    } else {
        vec![(0.0, Snap::Exact)]
    };
    c.extend([
        (v.round(), Snap::Exact),
        ((v * 2.0).round() / 2.0, Snap::Exact),
    ]);
    // a whole number of quarter turns (a phase: sin(u - pi/2) is -cos(u)), printed as pi
    let k = (v / std::f64::consts::FRAC_PI_2).round();
    if k != 0.0 && k.abs() <= crate::expr::MAX_HALF_PI_MULTIPLE {
        c.push((k * std::f64::consts::FRAC_PI_2, Snap::Exact));
    }
    let a = v.abs();
    let near = |x: f64| (x - v).abs() <= NAMED_SNAP_WINDOW * a;
    if a > 0.0 && a < 1e6 {
        for q in [3.0, 4.0] {
            let x = (v * q).round() / q;
            if near(x) {
                c.push((x, Snap::ExactAlone));
            }
        }
        for (value, _) in crate::expr::named_constants().into_iter().filter(|_| named) {
            let x = value.copysign(v);
            if near(x) {
                c.push((x, Snap::ExactAlone));
            }
        }
    }
    if a > 0.0 && a.is_finite() {
        for digits in [1i32, 2, 3] {
            let mag = a.log10().floor() as i32;
            let f = 10f64.powi(digits - 1 - mag);
            c.push(((v * f).round() / f, Snap::Rounded));
        }
    }
    let mut out: Vec<(f64, Snap)> = Vec::new();
    for (x, kind) in c {
        if x != v && x.is_finite() && !out.iter().any(|o| o.0 == x) {
            out.push((x, kind));
        }
    }
    out
}

/// What [`snap_params`] accepts: a rounding to 1-3 significant digits when the loss grows by
/// at most `rel_tol` (plus `abs_tol`), an exact value when the criterion does not get worse
/// (`penalty`: what it charges for one parameter), the named irrationals among the exact
/// values when `named`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SnapRule {
    pub rel_tol: f64,
    pub abs_tol: f64,
    pub penalty: f64,
    pub named: bool,
}

/// Replaces parameters by simple nearby values one at a time, refitting the others, and
/// returns the final mean squared error and which parameters were fixed at exact values
/// (`true` at their index: no longer fitted). Parameters marked in `already` are fixed at
/// exact values before it starts (an earlier snap): they are neither snapped nor refitted.
///
/// Two kinds of snap, tried in that order for each parameter (biases first, then weights and
/// constants, then the output map):
/// - to an exact value (0, +-1, an integer, a half, a multiple of pi/2): the parameter is then no longer fitted,
///   so the snap is accepted when the information criterion does not get worse, that is when
///   `n ln(mse' / mse)` stays within `penalty` (what the criterion charges for one
///   parameter: `ln n` for BIC, 2 for AIC);
/// - to 1-3 significant digits: still a fitted value, accepted only when the mean squared
///   error stays within `rel_tol` (plus `abs_tol`).
///
/// Either way the snapped model's criterion is never worse than the unsnapped model's, up
/// to the `rel_tol` slack. On noisy data the first kind removes offsets and factors that
/// only fit the noise (`(3.006 V - 0.02) (0.5 pr - 0.003) + 0.03` becomes `1.503 V pr`).
pub(crate) fn snap_params(
    prog: &Program,
    params: &mut Vec<f64>,
    cols: &[&[f64]],
    y: &[f64],
    rule: &SnapRule,
    already: &[bool],
) -> (f64, Vec<bool>) {
    let SnapRule {
        rel_tol,
        abs_tol,
        penalty,
        named,
    } = *rule;
    let mut ev = Evaluator::new(prog);
    let base = ev.mse(prog, params, cols, y);
    let mut exact_fixed = already.to_vec();
    if !base.is_finite() {
        return (base, exact_fixed);
    }
    let per_param = (penalty / y.len() as f64).exp();
    let mut limit = base * (1.0 + rel_tol) + abs_tol;
    let offs = prog.param_offsets();
    let mut order: Vec<usize> = Vec::new();
    for (k, n) in prog.nodes.iter().enumerate() {
        if matches!(n, Node::Var(_)) && prog.affine {
            order.push(offs[k] + 1);
        }
    }
    order.push(1);
    let n_bias = order.len();
    for (k, n) in prog.nodes.iter().enumerate() {
        match n {
            Node::Var(_) if prog.affine => order.push(offs[k]),
            Node::Const => order.push(offs[k]),
            _ => {}
        }
    }
    order.push(0);
    let mut fixed = already.to_vec();
    let mut current = base;
    for (&i, weight) in order.iter().zip((0..).map(|k| k >= n_bias)) {
        if already[i] {
            continue;
        }
        for (cand, kind) in snap_candidates(params[i], weight, named) {
            let exact = kind != Snap::Rounded;
            let allowed = match kind {
                Snap::Exact => limit * per_param,
                Snap::ExactAlone => (limit * per_param).min(current * per_param + abs_tol),
                Snap::Rounded => limit,
            };
            let mut trial = params.clone();
            trial[i] = cand;
            let mut fx = fixed.clone();
            fx[i] = true;
            let free: Vec<usize> = (0..trial.len()).filter(|&p| !fx[p]).collect();
            let mse = if free.is_empty() {
                ev.mse(prog, &trial, cols, y)
            } else {
                let direct = ev.mse(prog, &trial, cols, y);
                if direct <= allowed {
                    direct
                } else {
                    levenberg_marquardt(
                        prog,
                        &mut trial,
                        Unknowns::Free(&free),
                        cols,
                        y,
                        &LmSettings::new(20, 1e-10),
                        &mut ev,
                    )
                }
            };
            if mse.is_finite() && mse <= allowed {
                *params = trial;
                fixed = fx;
                current = mse;
                if exact {
                    limit = allowed;
                    exact_fixed[i] = true;
                }
                break;
            }
        }
    }
    (current, exact_fixed)
}

/// Largest relative spread `(max - min) / max(|max|, |min|)` of a subtree's values over the
/// rows for [`fold_data_constants`] to treat it as one constant: far below any noise, far
/// above rounding. A term such as `exp(-1e10 x^2)` on rows where `x >= 1` (0 to the last
/// bit) or `tanh(9 x)` on `x >= 1` (1 within 3e-8) is a constant in disguise.
const DATA_CONSTANT_SPREAD: f64 = 1e-6;

/// The program with every largest subtree (of two or more nodes) whose value is constant
/// over the rows of `cols` (within [`DATA_CONSTANT_SPREAD`]) replaced by one fitted constant
/// at the middle of its range, or `None` when there is none. The parameters of the other
/// nodes and their `fixed` flags are kept; the new constant is not fixed (snapping may fix
/// it). The replacement changes the model's values by at most the subtree's spread carried
/// through the rest of the program: the caller judges it by the loss.
pub(crate) fn fold_data_constants(
    prog: &Program,
    params: &[f64],
    fixed: &[bool],
    cols: &[&[f64]],
    n_rows: usize,
) -> Option<(Program, Vec<f64>, Vec<bool>)> {
    let offs = prog.param_offsets();
    let param_end = |k: usize| offs[k] + prog.node_params(&prog.nodes[k]);
    // (start, end, value) of the largest constant subtrees, found from the root down
    let mut folds: Vec<(usize, usize, f64)> = Vec::new();
    let mut end = prog.nodes.len();
    let mut values = Vec::new();
    while end > 0 {
        end -= 1;
        let start = prog.subtree_start(end);
        if start == end {
            continue;
        }
        let sub = Program {
            nodes: prog.nodes[start..=end].to_vec(),
            affine: prog.affine,
        };
        let mut sub_params = vec![1.0, 0.0];
        sub_params.extend_from_slice(&params[offs[start]..param_end(end)]);
        Evaluator::new(&sub).predict(&sub, &sub_params, cols, n_rows, &mut values);
        let (lo, hi) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        if lo.is_finite()
            && hi.is_finite()
            && hi - lo <= DATA_CONSTANT_SPREAD * hi.abs().max(lo.abs())
        {
            folds.push((start, end, 0.5 * (lo + hi)));
            // the nodes below are inside the folded subtree
            end = start;
        }
    }
    if folds.is_empty() {
        return None;
    }
    let (mut nodes, mut out_params, mut out_fixed) =
        (Vec::new(), params[..2].to_vec(), fixed[..2].to_vec());
    // copy the nodes outside the folds, each fold's root becoming the constant (`folds` is
    // ordered from the root down, so it is popped in program order)
    let mut j = 0;
    while j < prog.nodes.len() {
        if let Some(&(_, end, value)) = folds.last().filter(|f| f.0 == j) {
            folds.pop();
            nodes.push(Node::Const);
            out_params.push(value);
            out_fixed.push(false);
            j = end + 1;
        } else {
            nodes.push(prog.nodes[j]);
            out_params.extend_from_slice(&params[offs[j]..param_end(j)]);
            out_fixed.extend_from_slice(&fixed[offs[j]..param_end(j)]);
            j += 1;
        }
    }
    let folded = Program {
        nodes,
        affine: prog.affine,
    };
    Some((folded, out_params, out_fixed))
}

/// A subtree while [`prune_snapped`] rebuilds a program: a known number (folded), or codes
/// with their parameters and fixed flags.
enum Part {
    /// A constant value and whether it is fixed (made only of exact, unfitted values).
    Num(f64, bool),
    /// Postfix codes with their own parameters and fixed flags, in node order.
    Codes(Vec<Node>, Vec<f64>, Vec<bool>),
}

impl Part {
    fn into_codes(self) -> (Vec<Node>, Vec<f64>, Vec<bool>) {
        match self {
            Part::Num(v, f) => (vec![Node::Const], vec![v], vec![f]),
            Part::Codes(n, p, f) => (n, p, f),
        }
    }

    fn join(parts: Vec<Part>, op: Op) -> Part {
        let (mut nodes, mut params, mut fixed) = (Vec::new(), Vec::new(), Vec::new());
        for part in parts {
            let (n, p, f) = part.into_codes();
            nodes.extend(n);
            params.extend(p);
            fixed.extend(f);
        }
        nodes.push(Node::Op(op));
        Part::Codes(nodes, params, fixed)
    }
}

/// The program left when snapping killed terms, with its parameters and fixed flags.
///
/// Value-preserving rewrites (where the model is finite): an affine input whose weight is
/// exactly 0 becomes the constant of its bias; an operator over constants is folded into one
/// constant (fixed when all its constants were); `0 * a` becomes 0, `a + 0`, `a - 0`,
/// `1 * a` and `a / 1` become `a`. So a snapped model lists only the features it still uses,
/// and its complexity counts only the operators that still act. `fixed` marks the
/// parameters not fitted (the output map's included), as [`snap_params`] returns them.
pub(crate) fn prune_snapped(
    prog: &Program,
    params: &[f64],
    fixed: &[bool],
) -> (Program, Vec<f64>, Vec<bool>) {
    let offs = prog.param_offsets();
    let mut stack: Vec<Part> = Vec::with_capacity(prog.nodes.len());
    for (k, n) in prog.nodes.iter().enumerate() {
        let o = offs[k];
        let part = match *n {
            Node::Var(_) if prog.affine => {
                if params[o] == 0.0 {
                    Part::Num(params[o + 1], fixed[o + 1])
                } else {
                    Part::Codes(
                        vec![*n],
                        params[o..o + 2].to_vec(),
                        fixed[o..o + 2].to_vec(),
                    )
                }
            }
            Node::Var(_) => Part::Codes(vec![*n], Vec::new(), Vec::new()),
            Node::Const => Part::Num(params[o], fixed[o]),
            Node::Op(op) if op.arity() == 1 => {
                let a = stack.pop().unwrap_or(Part::Num(f64::NAN, false));
                match a {
                    Part::Num(v, f) if op.apply1(v).is_finite() => Part::Num(op.apply1(v), f),
                    a => Part::join(vec![a], op),
                }
            }
            Node::Op(op) => {
                let b = stack.pop().unwrap_or(Part::Num(f64::NAN, false));
                let a = stack.pop().unwrap_or(Part::Num(f64::NAN, false));
                match (op, a, b) {
                    (_, Part::Num(x, fx), Part::Num(y, fy)) if op.apply2(x, y).is_finite() => {
                        Part::Num(op.apply2(x, y), fx && fy)
                    }
                    (Op::Mul, Part::Num(z, fz), _) | (Op::Mul, _, Part::Num(z, fz)) if z == 0.0 => {
                        Part::Num(0.0, fz)
                    }
                    (Op::Add, Part::Num(z, _), e) | (Op::Add | Op::Sub, e, Part::Num(z, _))
                        if z == 0.0 =>
                    {
                        e
                    }
                    (Op::Mul, Part::Num(u, _), e) | (Op::Mul | Op::Div, e, Part::Num(u, _))
                        if u == 1.0 =>
                    {
                        e
                    }
                    (_, a, b) => Part::join(vec![a, b], op),
                }
            }
        };
        stack.push(part);
    }
    let root = stack.pop().unwrap_or(Part::Num(f64::NAN, false));
    let (nodes, own, own_fixed) = root.into_codes();
    let mut out_params = vec![params[0], params[1]];
    out_params.extend(own);
    let mut out_fixed = vec![fixed[0], fixed[1]];
    out_fixed.extend(own_fixed);
    (
        Program {
            nodes,
            affine: prog.affine,
        },
        out_params,
        out_fixed,
    )
}

#[cfg(test)]
mod limits {
    use super::*;
    use crate::ops::Op;
    use crate::program::Node;

    /// A hand-made program longer than [`MAX_PROGRAM_NODES`] (a well-formed chain
    /// `x0 + x0 + ...`, as deep as it is long) is refused by `validate` by name; one within
    /// the limit passes.
    #[test]
    fn a_program_too_long_is_refused() {
        let chain = |terms: usize| {
            let mut nodes = vec![Node::Var(0)];
            for _ in 1..terms {
                nodes.extend([Node::Var(0), Node::Op(Op::Add)]);
            }
            Program {
                nodes,
                affine: false,
            }
        };
        let long = chain(MAX_PROGRAM_NODES / 2 + 2);
        let params = vec![1.0; long.n_params()];
        let m = Model::new(vec!["x".into()], long, params);
        match m.and_then(|m| m.validate().map(|()| m)) {
            Err(SrError::MalformedModel(msg)) => assert!(msg.contains("nodes"), "{msg}"),
            other => panic!("{other:?}"),
        }
        let short = chain(100);
        let params = vec![1.0; short.n_params()];
        Model::new(vec!["x".into()], short, params)
            .and_then(|m| m.validate())
            .expect("a program of 199 nodes is fine");
    }
}

#[cfg(test)]
mod snapping {
    use super::{Snap, snap_candidates};

    /// The exact candidates near a constant include the third, the quarter and the named
    /// irrational within 1 % (with its sign), and none farther away.
    #[test]
    fn thirds_quarters_and_named_irrationals_are_exact_candidates() {
        let exact = |v: f64| -> Vec<f64> {
            snap_candidates(v, true, true)
                .into_iter()
                .filter(|c| c.1 != Snap::Rounded)
                .map(|c| c.0)
                .collect()
        };
        assert!(exact(0.3336).contains(&(1.0 / 3.0)));
        assert!(exact(-0.7496).contains(&(-3.0 / 4.0)));
        assert!(exact(0.70712).contains(&(1.0 / 2f64.sqrt())));
        assert!(exact(-0.39890).contains(&(-1.0 / (2.0 * std::f64::consts::PI).sqrt())));
        assert!(exact(1.7321).contains(&3f64.sqrt()));
        // 2 % away from 1/sqrt(2) and from 2/3, 3/4: not tried as those
        let far = exact(0.69);
        assert!(!far.contains(&(1.0 / 2f64.sqrt())), "{far:?}");
        assert!(
            !far.contains(&(2.0 / 3.0)) && !far.contains(&0.75),
            "{far:?}"
        );
    }
}

#[cfg(test)]
mod data_constants {
    use super::*;

    fn program(nodes: Vec<Node>) -> Program {
        Program {
            nodes,
            affine: true,
        }
    }

    fn values(prog: &Program, params: &[f64], cols: &[&[f64]]) -> Vec<f64> {
        let mut out = Vec::new();
        Evaluator::new(prog).predict(prog, params, cols, cols[0].len(), &mut out);
        out
    }

    /// A dead term (`gaussian(1e5 x)` on rows where `x >= 1`, 0 to the last bit) and a
    /// saturated one (`tanh(20 x)`, 1 within 1e-17) are each replaced by one constant; the
    /// model's values do not change beyond the term's spread, the other nodes keep their
    /// parameters and fixed flags, and a term that varies is left alone.
    #[test]
    fn constant_subtrees_fold_and_varying_ones_stay() {
        let x: Vec<f64> = (0..50).map(|i| 1.0 + 0.04 * f64::from(i)).collect();
        let cols = [x.as_slice()];
        let var = Node::Var(0);
        for (op, w) in [(Op::Gaussian, 1e5), (Op::Tanh, 20.0)] {
            // 2 x + 0.5 + op(w x), with the first input's weight marked fixed
            let prog = program(vec![var, var, Node::Op(op), Node::Op(Op::Add)]);
            let params = vec![1.0, 0.0, 2.0, 0.5, w, 0.0];
            let fixed = vec![false, false, true, false, false, false];
            let (folded, p, f) =
                fold_data_constants(&prog, &params, &fixed, &cols, x.len()).expect("a fold");
            assert_eq!(folded.nodes, vec![var, Node::Const, Node::Op(Op::Add)]);
            assert_eq!(&p[..4], &[1.0, 0.0, 2.0, 0.5]);
            assert_eq!(f, vec![false, false, true, false, false]);
            let (before, after) = (values(&prog, &params, &cols), values(&folded, &p, &cols));
            for (a, b) in before.iter().zip(&after) {
                assert!((a - b).abs() <= 1e-12, "{op:?}: {a} vs {b}");
            }
        }
        let prog = program(vec![var, var, Node::Op(Op::Tanh), Node::Op(Op::Add)]);
        let params = vec![1.0, 0.0, 2.0, 0.5, 0.3, 0.0];
        assert!(fold_data_constants(&prog, &params, &[false; 6], &cols, x.len()).is_none());
    }
}
