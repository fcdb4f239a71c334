//! Fitted models: evaluation on new data and export (`mod.rs`), constant snapping
//! (`snap.rs`), folding and pruning that keep the values (`fold.rs`), and dropping a
//! constant's term (`drop.rs`).
mod drop;
mod fold;
mod snap;

use crate::eval::Evaluator;
use crate::expr::Expr;
use crate::program::{ComplexityMeasure, Node, Program};
use crate::{SrError, Table};
pub(crate) use fold::{fold_data_constants, prune_snapped};
use serde::{Deserialize, Serialize};
pub use snap::is_exact;
pub(crate) use snap::{SnapRule, snap_params};

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

/// `prog` over the columns `names` with its inputs renumbered to the columns it reads (in
/// increasing column order), and those columns' names: what a model of it names as its
/// features (the search's export, a model with a term dropped).
pub(crate) fn over_used_columns(prog: &Program, names: &[String]) -> (Vec<String>, Program) {
    let used = prog.vars();
    let nodes = prog
        .nodes
        .iter()
        .map(|n| match n {
            Node::Var(j) => Node::Var(used.iter().position(|u| u == j).unwrap_or(0) as u16),
            other => *other,
        })
        .collect();
    let feature_names = used.iter().map(|&j| names[j as usize].clone()).collect();
    (
        feature_names,
        Program {
            nodes,
            affine: prog.affine,
        },
    )
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
