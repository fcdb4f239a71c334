//! Simplifying a fitted model without changing its values: subtrees constant over the rows
//! folded into one constant ([`fold_data_constants`]) and the terms a snapped weight killed
//! pruned ([`prune_snapped`]).
use crate::eval::Evaluator;
use crate::ops::Op;
use crate::program::{Node, Program};

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
