//! Compiling a parsed equation into a [`Program`] whose names and numbers are constant
//! leaves, evaluated by the search's [`Evaluator`].

use super::{Parsed, parse};
use crate::SrError;
use crate::eval::Evaluator;
use crate::expr::Expr;
use crate::ops::Op;
use crate::program::{Node, Program};
use std::collections::BTreeMap;

/// A compiled equation: a program over `inputs` whose numbers and named constants are
/// constant leaves with their values in `params`.
#[derive(Clone, Debug, PartialEq)]
pub struct Compiled {
    /// The program (no affine inputs; output scale 1 and offset 0 in `params[0..2]`).
    pub program: Program,
    /// Parameter vector in the program's layout.
    pub params: Vec<f64>,
    /// Input names; `Node::Var(i)` is `inputs[i]`.
    pub inputs: Vec<String>,
    /// For each named constant, the indices into `params` of its leaves (a name used twice
    /// has two leaves that must move together).
    pub slots: BTreeMap<String, Vec<usize>>,
}

impl Compiled {
    /// Sets every leaf of the named constant to `value` (no-op for an unknown name).
    pub fn set(&mut self, name: &str, value: f64) {
        if let Some(slots) = self.slots.get(name) {
            for &i in slots {
                self.params[i] = value;
            }
        }
    }

    /// Current value of a named constant.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.slots
            .get(name)
            .and_then(|s| s.first())
            .map(|&i| self.params[i])
    }

    /// Evaluates on columns given in the order of `inputs`.
    pub fn eval_columns(&self, cols: &[&[f64]], n_rows: usize) -> Vec<f64> {
        let mut out = Vec::new();
        Evaluator::new(&self.program).predict(&self.program, &self.params, cols, n_rows, &mut out);
        out
    }

    /// Evaluates at one row given in the order of `inputs`.
    pub fn eval_row(&self, row: &[f64]) -> f64 {
        let cols: Vec<&[f64]> = row.iter().map(std::slice::from_ref).collect();
        self.eval_columns(&cols, 1)
            .first()
            .copied()
            .unwrap_or(f64::NAN)
    }

    /// The equation with every constant's value substituted, as a reporting expression.
    pub fn expr(&self) -> Expr {
        Expr::from_program(&self.program, &self.params, &self.inputs)
    }
}

fn emit(
    e: &Expr,
    inputs: &[String],
    constants: &BTreeMap<String, f64>,
    parsed: &Parsed,
    nodes: &mut Vec<Node>,
    values: &mut Vec<f64>,
    named: &mut Vec<(String, usize)>,
) -> Result<(), SrError> {
    let constant = |v: f64, nodes: &mut Vec<Node>, values: &mut Vec<f64>| {
        nodes.push(Node::Const);
        values.push(v);
    };
    match e {
        Expr::Num(v) => constant(*v, nodes, values),
        Expr::Var(name) => {
            if let Some(j) = inputs.iter().position(|n| n == name) {
                let j = u16::try_from(j).map_err(|_| {
                    SrError::InvalidConfig("an equation may use at most 65535 inputs".into())
                })?;
                nodes.push(Node::Var(j));
            } else if let Some(v) = constants.get(name) {
                named.push((name.clone(), values.len()));
                constant(*v, nodes, values);
            } else {
                return Err(SrError::UnknownSymbol {
                    name: name.clone(),
                    position: parsed.position(name).unwrap_or(0),
                });
            }
        }
        Expr::Neg(a) => {
            constant(-1.0, nodes, values);
            emit(a, inputs, constants, parsed, nodes, values, named)?;
            nodes.push(Node::Op(Op::Mul));
        }
        Expr::Un(op, a) => {
            emit(a, inputs, constants, parsed, nodes, values, named)?;
            nodes.push(Node::Op(*op));
        }
        Expr::Bin(op, a, b) => {
            emit(a, inputs, constants, parsed, nodes, values, named)?;
            emit(b, inputs, constants, parsed, nodes, values, named)?;
            nodes.push(Node::Op(*op));
        }
    }
    Ok(())
}

/// Compiles a parsed equation: names in `inputs` become inputs, names in `constants` become
/// constant leaves with those values, numbers become constant leaves.
///
/// # Errors
/// [`SrError::UnknownSymbol`] for a name in neither list.
pub fn compile(
    parsed: &Parsed,
    inputs: &[String],
    constants: &BTreeMap<String, f64>,
) -> Result<Compiled, SrError> {
    let mut nodes = Vec::new();
    let mut values = Vec::new();
    let mut named = Vec::new();
    emit(
        &parsed.expr,
        inputs,
        constants,
        parsed,
        &mut nodes,
        &mut values,
        &mut named,
    )?;
    let program = Program {
        nodes,
        affine: false,
    };
    // Constants own one parameter each, in node order, after the output scale and offset.
    let mut params = vec![1.0, 0.0];
    params.extend_from_slice(&values);
    let mut slots: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (name, k) in named {
        slots.entry(name).or_default().push(k + 2);
    }
    Ok(Compiled {
        program,
        params,
        inputs: inputs.to_vec(),
        slots,
    })
}

/// Parses and compiles in one step, treating every name that is not a constant as an
/// input (in order of first use).
///
/// # Errors
/// As [`parse`].
pub fn compile_text(text: &str, constants: &BTreeMap<String, f64>) -> Result<Compiled, SrError> {
    let parsed = parse(text)?;
    let inputs: Vec<String> = parsed
        .names()
        .into_iter()
        .filter(|n| !constants.contains_key(*n))
        .map(str::to_string)
        .collect();
    compile(&parsed, &inputs, constants)
}
