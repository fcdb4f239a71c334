//! The physics equation compiled over a table's columns, and the hybrid as one program:
//! physics and correction joined by the correction form, evaluated, differentiated and
//! printed as one equation.

use super::EquationInfo;
use crate::HybridError;
use crate::tables::CorrectionForm;
use hxai_symreg::infix::{Compiled, compile, parse};
use hxai_symreg::{Model, Node, Op, Program, Table, expr::Expr};
use std::collections::BTreeMap;

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

impl Combined {
    /// The one-program hybrid's predictions with `params` on every row of `table`.
    ///
    /// # Errors
    /// A column the table lacks.
    pub(crate) fn predict_with(
        &self,
        params: &[f64],
        table: &Table,
    ) -> Result<Vec<f64>, HybridError> {
        let cols = super::columns_of(table, &self.names, "column")?;
        let mut out = Vec::new();
        hxai_symreg::eval::Evaluator::new(&self.program).predict(
            &self.program,
            params,
            &cols,
            table.n_rows(),
            &mut out,
        );
        Ok(out)
    }
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

/// `delta` on `rows` for the correction form, refusing rows where it is undefined.
pub(crate) fn deltas(
    kind: CorrectionForm,
    y: &[f64],
    physics: &[f64],
    rows: &[usize],
) -> Result<Vec<f64>, HybridError> {
    rows.iter()
        .map(|&i| match kind {
            CorrectionForm::Additive => Ok(y[i] - physics[i]),
            CorrectionForm::Multiplicative => {
                if physics[i] == 0.0 {
                    Err(HybridError::BadPhysics {
                        row: i,
                        value: physics[i],
                        why: "so the multiplicative correction y / f_p - 1 is undefined: use --correction additive".into(),
                    })
                } else {
                    Ok(y[i] / physics[i] - 1.0)
                }
            }
            CorrectionForm::Log => {
                if y[i] > 0.0 && physics[i] > 0.0 {
                    Ok((y[i] / physics[i]).ln())
                } else {
                    let why = if physics[i] > 0.0 {
                        format!(
                            "but the target there is {}: the log correction ln(y / f_p) needs a positive target; use --correction multiplicative or additive",
                            y[i]
                        )
                    } else {
                        "so the log correction ln(y / f_p) is undefined: use --correction additive".into()
                    };
                    Err(HybridError::BadPhysics {
                        row: i,
                        value: physics[i],
                        why,
                    })
                }
            }
        })
        .collect()
}
