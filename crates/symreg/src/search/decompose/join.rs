//! Joining the parts of a decomposition back into one program: their sum or their product,
//! with the constants that make the join exact.
use super::symmetry;
use crate::ops::Op;
use crate::program::{Node, Program};

/// A join of groups: their sum or their product.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Join {
    /// `g(xA) + h(xB)`
    Sum,
    /// `g(xA) h(xB)`
    Product,
}

/// Joins the sub-models `subs` (each `s * root + o` over the full inputs) into one program:
/// their sum or their product.
pub(super) fn join_programs(
    subs: &[(Program, Vec<f64>)],
    join: Join,
) -> Option<(Program, Vec<f64>)> {
    let mut affine = subs.first()?.0.affine;
    let plain: Vec<(Program, Vec<f64>)>;
    let subs = if subs.iter().any(|(p, _)| p.affine != affine) {
        // a sub-model that is itself a decomposition (or a shorter form) may have no affine
        // leaves where the others have: every part is then written without them
        affine = false;
        plain = subs
            .iter()
            .map(|(p, ps)| {
                let n = p.vars().into_iter().max().map_or(0, |v| usize::from(v) + 1);
                let same: Vec<Vec<Node>> = (0..n).map(|k| vec![Node::Var(k as u16)]).collect();
                symmetry::substitute(p, ps, &same)
            })
            .collect();
        &plain
    } else {
        subs
    };
    let mut nodes: Vec<Node> = Vec::new();
    let mut params = vec![1.0, 0.0];
    let (mut scale, mut offset) = (1.0, 0.0);
    let first_scale = subs[0].1[0];
    for (i, (p, ps)) in subs.iter().enumerate() {
        let (s, o) = (ps[0], ps[1]);
        nodes.extend_from_slice(&p.nodes);
        params.extend_from_slice(&ps[2..]);
        match join {
            Join::Sum => {
                offset += o;
                if i == 0 {
                    scale = s;
                } else {
                    nodes.push(Node::Const);
                    params.push(s / first_scale);
                    nodes.push(Node::Op(Op::Mul));
                    nodes.push(Node::Op(Op::Add));
                }
            }
            Join::Product => {
                scale *= s;
                if o != 0.0 {
                    nodes.push(Node::Const);
                    params.push(o / s);
                    nodes.push(Node::Op(Op::Add));
                }
                if i > 0 {
                    nodes.push(Node::Op(Op::Mul));
                }
            }
        }
    }
    params[0] = scale;
    params[1] = offset;
    let program = Program { nodes, affine };
    (program.is_valid() && params.iter().all(|v| v.is_finite())).then_some((program, params))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Evaluator;

    /// The join of `2 x0 + 1` and `3 x1 - 1` is their sum, and their product.
    #[test]
    fn joins_add_and_multiply_the_parts() {
        let line = |v: u16, s: f64, o: f64| {
            (
                Program {
                    nodes: vec![Node::Var(v)],
                    affine: false,
                },
                vec![s, o],
            )
        };
        let subs = [line(0, 2.0, 1.0), line(1, 3.0, -1.0)];
        let cols: Vec<Vec<f64>> = vec![vec![0.5, 2.0, -1.0], vec![1.5, -0.25, 4.0]];
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        for (join, want) in [
            (Join::Sum, [5.5, 3.25, 10.0]),
            (Join::Product, [7.0, -8.75, -11.0]),
        ] {
            let (p, params) = join_programs(&subs, join).expect("join");
            let mut out = Vec::new();
            Evaluator::new(&p).predict(&p, &params, &refs, 3, &mut out);
            for (g, w) in out.iter().zip(want) {
                assert!((g - w).abs() < 1e-12, "{join:?}: {out:?} vs {want:?}");
            }
        }
    }
}
