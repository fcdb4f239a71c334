//! The engineer's ODE as text (`--ode "T' = (q*n^1.5 - h*(T - Ta))/C"`): parsed into one
//! right-hand side per state, compiled to the symbolic-regression programs, and evaluated
//! at one point by a small stack machine (the integrator asks for one point at a time).

use crate::HybridError;
use hxai_symreg::expr::Expr;
use hxai_symreg::infix::{Compiled, Parsed, compile, parse};
use hxai_symreg::{Model, Node, Op, Program};
use std::collections::BTreeMap;

/// One state's equation `NAME' = expr`, compiled over the system's variables.
#[derive(Clone, Debug)]
pub(crate) struct StateEquation {
    /// The state it gives the derivative of.
    pub(crate) state: String,
    /// The right-hand side as written.
    pub(crate) text: String,
    /// Compiled over [`OdeSpec::variables`]; named constants in `compiled.slots`.
    pub(crate) compiled: Compiled,
}

/// A grouping of variables the engineer wrote in the physics (`T - Ta`): a sum or
/// difference of terms that read only states, inputs and the time. The correction is
/// offered these beside the columns, so it can write `n*(T - Ta)` as a product of two
/// factors, in the physics' own quantities.
#[derive(Clone, Debug)]
pub(crate) struct Grouping {
    /// Its text in parentheses, `(T - Ta)`: the feature's name.
    pub(crate) name: String,
    /// Compiled over the base variables (states, inputs, time).
    pub(crate) compiled: Compiled,
}

/// A parsed system: the states (in `--state` order), the variables the right-hand sides
/// read (states, inputs, then the time column), the physics' groupings and the named
/// parameters.
#[derive(Clone, Debug)]
pub(crate) struct OdeSpec {
    pub(crate) equations: Vec<StateEquation>,
    /// `states ++ inputs ++ [time] ++ groupings`: the point a right-hand side and its
    /// correction are evaluated at.
    pub(crate) variables: Vec<String>,
    /// How many of `variables` are states, inputs and the time (the rest are groupings).
    pub(crate) n_base: usize,
    pub(crate) groupings: Vec<Grouping>,
    /// Every named parameter of the system, with its current value.
    pub(crate) parameters: BTreeMap<String, f64>,
}

/// Splits `T' = ...; P' = ...` into `(state, right-hand side)` pairs.
fn split_equations(text: &str) -> Result<Vec<(String, String)>, HybridError> {
    let bad = |why: String| HybridError::InvalidConfig(format!("--ode: {why}"));
    let mut out = Vec::new();
    for part in text.split(';').map(str::trim).filter(|p| !p.is_empty()) {
        let (lhs, rhs) = part.split_once('=').ok_or_else(|| {
            bad(format!(
                "{part:?} has no `=`: write one `NAME' = expression` per state, `;` between them"
            ))
        })?;
        let lhs = lhs.trim();
        let name = lhs.strip_suffix('\'').map(str::trim).ok_or_else(|| {
            bad(format!(
                "the left side {lhs:?} is not a derivative: write `{lhs}' = ...` (a prime after \
                 the state's name)"
            ))
        })?;
        let name = name.trim_matches('`').to_string();
        if name.is_empty() || rhs.trim().is_empty() {
            return Err(bad(format!("{part:?} is incomplete")));
        }
        if out.iter().any(|(n, _): &(String, String)| *n == name) {
            return Err(bad(format!("the state {name} has two equations")));
        }
        out.push((name, rhs.trim().to_string()));
    }
    if out.is_empty() {
        return Err(bad("no equation: write `NAME' = expression`".into()));
    }
    Ok(out)
}

impl OdeSpec {
    /// Parses `text` for `states` over `inputs` and the `time` column: each state needs one
    /// equation; any other name is a parameter, which needs a value in `values` (the
    /// calibrated parameters' starting values, `--init`, and the fixed ones, `--set`).
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] for a malformed system, a state without an equation,
    /// an equation of a column that is not a state, or a parameter without a value;
    /// [`HybridError::Equation`] for a right-hand side that does not parse.
    pub(crate) fn parse(
        text: &str,
        states: &[String],
        inputs: &[String],
        time: &str,
        values: &BTreeMap<String, f64>,
    ) -> Result<Self, HybridError> {
        let eqs = split_equations(text)?;
        if let Some((n, _)) = eqs.iter().find(|(n, _)| !states.contains(n)) {
            return Err(HybridError::InvalidConfig(format!(
                "--ode writes the derivative of {n}, which is not among --state ({}); list it \
                 there or fix the name",
                states.join(", ")
            )));
        }
        let mut variables: Vec<String> = states.to_vec();
        variables.extend(inputs.iter().cloned());
        variables.push(time.to_string());
        let mut equations = Vec::new();
        let mut parameters = BTreeMap::new();
        for s in states {
            let (_, rhs) = eqs.iter().find(|(n, _)| n == s).ok_or_else(|| {
                HybridError::InvalidConfig(format!(
                    "--ode has no equation for the state {s}: write `{s}' = ...`"
                ))
            })?;
            let parsed = parse(rhs).map_err(|e| HybridError::Equation {
                equation: rhs.clone(),
                source: e,
            })?;
            for name in parsed.names() {
                if variables.iter().any(|v| v == name) {
                    continue;
                }
                let v = values.get(name).copied().ok_or_else(|| {
                    HybridError::InvalidConfig(format!(
                        "--ode: {name} in `{s}' = {rhs}` is neither a state, an input nor the \
                         time column, so it is a parameter, and it has no value: calibrate it \
                         (--calibrate {name} --init {name}=V) or fix it (--set {name}=V), or \
                         list the column in --inputs"
                    ))
                })?;
                parameters.insert(name.to_string(), v);
            }
            let compiled =
                compile(&parsed, &variables, &parameters).map_err(|e| HybridError::Equation {
                    equation: rhs.clone(),
                    source: e,
                })?;
            equations.push(StateEquation {
                state: s.clone(),
                text: rhs.clone(),
                compiled,
            });
        }
        let n_base = variables.len();
        let mut found: Vec<Expr> = Vec::new();
        for e in &equations {
            if let Ok(p) = parse(&e.text) {
                groupings_of(&p.expr, &variables, &mut found);
            }
        }
        let mut groupings = Vec::new();
        for e in found {
            let name = format!("({})", e.to_text(None, false));
            if variables.contains(&name) {
                continue;
            }
            let parsed = Parsed {
                expr: e,
                positions: Vec::new(),
            };
            if let Ok(compiled) = compile(&parsed, &variables[..n_base], &BTreeMap::new()) {
                variables.push(name.clone());
                groupings.push(Grouping { name, compiled });
            }
        }
        Ok(Self {
            equations,
            variables,
            n_base,
            groupings,
            parameters,
        })
    }

    /// Index of the time among [`OdeSpec::variables`].
    pub(crate) fn time_index(&self) -> usize {
        self.n_base - 1
    }

    /// Sets a named parameter in every equation that uses it.
    pub(crate) fn set(&mut self, name: &str, value: f64) {
        for e in &mut self.equations {
            e.compiled.set(name, value);
        }
        if let Some(v) = self.parameters.get_mut(name) {
            *v = value;
        }
    }

    /// The system as written, `T' = ...; P' = ...`.
    pub(crate) fn text(&self) -> String {
        self.equations
            .iter()
            .map(|e| format!("{}' = {}", e.state, e.text))
            .collect::<Vec<_>>()
            .join("; ")
    }
}

/// Whether `e` reads a name, and only names among `vars` (no parameter).
fn reads_only(e: &Expr, vars: &[String]) -> (bool, bool) {
    match e {
        Expr::Num(_) => (false, true),
        Expr::Var(n) => (true, vars.contains(n)),
        Expr::Neg(a) | Expr::Un(_, a) => reads_only(a, vars),
        Expr::Bin(_, a, b) => {
            let (ra, oa) = reads_only(a, vars);
            let (rb, ob) = reads_only(b, vars);
            (ra || rb, oa && ob)
        }
    }
}

/// The sums and differences in `e` of two terms that each read a variable and nothing but
/// variables and numbers (`T - Ta`), each once, outermost first.
fn groupings_of(e: &Expr, vars: &[String], out: &mut Vec<Expr>) {
    match e {
        Expr::Bin(op, a, b) => {
            if matches!(op, Op::Add | Op::Sub) {
                let (ra, oa) = reads_only(a, vars);
                let (rb, ob) = reads_only(b, vars);
                if ra && rb && oa && ob && !out.contains(e) {
                    out.push(e.clone());
                }
            }
            groupings_of(a, vars, out);
            groupings_of(b, vars, out);
        }
        Expr::Neg(a) | Expr::Un(_, a) => groupings_of(a, vars, out),
        Expr::Num(_) | Expr::Var(_) => {}
    }
}

/// A program evaluated at one point: `vars[map[i]]` is the program's input `i`.
pub(crate) fn eval_point(
    prog: &Program,
    params: &[f64],
    vars: &[f64],
    map: &[usize],
    stack: &mut Vec<f64>,
) -> f64 {
    stack.clear();
    let mut p = 2;
    for n in &prog.nodes {
        match *n {
            Node::Var(i) => {
                let x = vars[map[i as usize]];
                if prog.affine {
                    stack.push(params[p] * x + params[p + 1]);
                    p += 2;
                } else {
                    stack.push(x);
                }
            }
            Node::Const => {
                stack.push(params[p]);
                p += 1;
            }
            Node::Op(op) => {
                if op.arity() == 2 {
                    let b = stack.pop().unwrap_or(f64::NAN);
                    let a = stack.pop().unwrap_or(f64::NAN);
                    stack.push(op.apply2(a, b));
                } else {
                    let a = stack.pop().unwrap_or(f64::NAN);
                    stack.push(op.apply1(a));
                }
            }
        }
    }
    params[0] * stack.pop().unwrap_or(f64::NAN) + params[1]
}

/// Where each feature of `model` sits among `variables`.
///
/// # Errors
/// [`HybridError::ModelFormat`] for a feature that is not a variable.
pub(crate) fn feature_map(model: &Model, variables: &[String]) -> Result<Vec<usize>, HybridError> {
    model
        .feature_names
        .iter()
        .map(|f| {
            variables.iter().position(|v| v == f).ok_or_else(|| {
                HybridError::ModelFormat(format!(
                    "the correction reads {f}, which is not a state, an input or the time"
                ))
            })
        })
        .collect()
}
