//! A polynomial of a transformed target: AI Feynman's second tool (Udrescu and Tegmark 2020;
//! issue 24 item 2).
//!
//! Many laws of one to three inputs are a low-degree polynomial once the target is inverted,
//! squared or taken the log of: `1/sqrt(1 - z^2)` is `1 - z^2` under `1/y^2`, a Gaussian is
//! a quadratic under `ln y`. A search finds such a law only by composing three or four
//! operators in the right order; a least-squares fit finds it at once. For each transform
//! `T` the search's operators can undo, [`polynomials`] fits a polynomial to `T(y)` (every
//! monomial up to the degree, linear in its coefficients, so the fit is one solve) and
//! offers `T^-1(polynomial)` to selection, refitted on the target's own scale, snapped
//! (coefficients that are 0 drop out) and judged by the criterion like every candidate.
//! With `--separability` (where the decomposition's parts are the small problems this
//! serves), on searches of at most [`MAX_INPUTS`] inputs.
use crate::eval::Evaluator;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::ops::Op;
use crate::program::{Node, Program};
use crate::search::archive::Fitted;
use crate::search::fitting::{Problem, refitted};

/// Most inputs a polynomial is fitted over.
pub(crate) const MAX_INPUTS: usize = 3;

/// Highest degree: cubic in one input, quadratic in two or three (at most ten monomials).
fn degree(inputs: usize) -> u32 {
    if inputs == 1 { 3 } else { 2 }
}

/// Accepted steps of the polynomial's least-squares fit (linear in its coefficients, so a
/// few steps reach the solution).
const LINEAR_FIT_ITERATIONS: usize = 20;

/// A transform of the target, by the operators that undo it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Transform {
    /// `y`
    Identity,
    /// `1 / y`, undone by `inverse`
    Inverse,
    /// `y^2`, undone by `sqrt` (a target of one sign)
    Square,
    /// `1 / y^2`, undone by `sqrt` then `inverse`
    InverseSquare,
    /// `sqrt(y)`, undone by `square` (a target of one sign)
    Sqrt,
    /// `ln y`, undone by `exp` (a target of one sign)
    Log,
}

impl Transform {
    const ALL: [Self; 6] = [
        Self::Identity,
        Self::Inverse,
        Self::Square,
        Self::InverseSquare,
        Self::Sqrt,
        Self::Log,
    ];

    /// `T(|y|)` (the target's sign is the output scale's).
    fn apply(self, y: f64) -> f64 {
        match self {
            Self::Identity => y,
            Self::Inverse => 1.0 / y,
            Self::Square => y * y,
            Self::InverseSquare => 1.0 / (y * y),
            Self::Sqrt => y.sqrt(),
            Self::Log => y.ln(),
        }
    }

    /// The operators that take `T(y)` back to `y`, innermost first.
    fn undo(self) -> &'static [Op] {
        match self {
            Self::Identity => &[],
            Self::Inverse => &[Op::Inverse],
            Self::Square => &[Op::Sqrt],
            Self::InverseSquare => &[Op::Sqrt, Op::Inverse],
            Self::Sqrt => &[Op::Square],
            Self::Log => &[Op::Exp],
        }
    }

    /// Whether it needs a target of one sign (taken as `|y|`, the sign restored by the
    /// output scale).
    fn signed(self) -> bool {
        matches!(
            self,
            Self::Square | Self::Sqrt | Self::Log | Self::InverseSquare
        )
    }
}

/// The monomials of `inputs` inputs up to `degree` (each a list of input indices, with
/// repeats), the constant left out.
fn monomials(inputs: usize, degree: u32) -> Vec<Vec<u16>> {
    let mut out: Vec<Vec<u16>> = Vec::new();
    let mut frontier: Vec<Vec<u16>> = vec![Vec::new()];
    for _ in 0..degree {
        let mut next = Vec::new();
        for m in &frontier {
            let from = m.last().map_or(0, |&v| v);
            for v in from..inputs as u16 {
                let mut t = m.clone();
                t.push(v);
                next.push(t);
            }
        }
        out.extend(next.iter().cloned());
        frontier = next;
    }
    out
}

/// Pushes one monomial: its inputs multiplied (`square` for a repeated pair when `square`).
fn monomial_nodes(m: &[u16], square: bool, nodes: &mut Vec<Node>) {
    let mut first = true;
    let mut i = 0;
    while i < m.len() {
        if square && i + 1 < m.len() && m[i + 1] == m[i] {
            nodes.push(Node::Var(m[i]));
            nodes.push(Node::Op(Op::Square));
            i += 2;
        } else {
            nodes.push(Node::Var(m[i]));
            i += 1;
        }
        if !first {
            nodes.push(Node::Op(Op::Mul));
        }
        first = false;
    }
}

/// `sum c_k m_k` over `terms`, each coefficient a constant, with parameters `[1, c0, c_k...]`
/// (scale 1, offset the constant term).
fn polynomial(terms: &[Vec<u16>], square: bool) -> Program {
    let mut nodes = Vec::new();
    for (k, m) in terms.iter().enumerate() {
        monomial_nodes(m, square, &mut nodes);
        nodes.push(Node::Const);
        nodes.push(Node::Op(Op::Mul));
        if k > 0 {
            nodes.push(Node::Op(Op::Add));
        }
    }
    Program {
        nodes,
        affine: false,
    }
}

/// The candidates `T^-1(polynomial)` of the problem (see the module docs); none when it has
/// more than [`MAX_INPUTS`] inputs or the operators cannot write them.
pub(crate) fn polynomials(problem: &Problem, ops: &[Op]) -> Vec<Fitted> {
    let inputs = problem.fit_cols.len();
    if inputs == 0 || inputs > MAX_INPUTS || !ops.contains(&Op::Mul) || !ops.contains(&Op::Add) {
        return Vec::new();
    }
    let y = &problem.fit_y;
    let sign = if y.iter().all(|&v| v > 0.0) {
        Some(1.0)
    } else if y.iter().all(|&v| v < 0.0) {
        Some(-1.0)
    } else {
        None
    };
    let square = ops.contains(&Op::Square);
    let terms = monomials(inputs, degree(inputs));
    let poly = polynomial(&terms, square);
    let cols = problem.fit_cols();
    let mut ev = Evaluator::new(&poly);
    let free: Vec<usize> = (1..poly.n_params()).collect();
    let mut out = Vec::new();
    for t in Transform::ALL {
        if !t.undo().iter().all(|op| ops.contains(op)) {
            continue;
        }
        let s = match (t.signed(), sign) {
            (false, _) => 1.0,
            (true, Some(s)) => s,
            (true, None) => continue,
        };
        let ty: Vec<f64> = y.iter().map(|&v| t.apply(s * v)).collect();
        if !ty.iter().all(|v| v.is_finite()) {
            continue;
        }
        let mut params = vec![0.0; poly.n_params()];
        params[0] = 1.0;
        let mse = levenberg_marquardt(
            &poly,
            &mut params,
            Unknowns::Free(&free),
            &cols,
            &ty,
            &LmSettings::new(LINEAR_FIT_ITERATIONS, 0.0),
            &mut ev,
        );
        if !mse.is_finite() {
            continue;
        }
        // T^-1(polynomial): the polynomial's offset goes inside, the sign outside
        let mut nodes = poly.nodes.clone();
        let mut p = vec![s, 0.0];
        p.extend_from_slice(&params[2..]);
        if params[1] != 0.0 {
            nodes.push(Node::Const);
            p.push(params[1]);
            nodes.push(Node::Op(Op::Add));
        }
        nodes.extend(t.undo().iter().map(|&op| Node::Op(op)));
        let program = Program {
            nodes,
            affine: false,
        };
        if program.is_valid() {
            out.extend(refitted(problem, program, p));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::config::SearchConfig;
    use crate::search::fitting::variance;
    use crate::{ComplexityMeasure, Table};

    #[test]
    fn monomials_are_every_product_up_to_the_degree() {
        assert_eq!(monomials(1, 3), vec![vec![0], vec![0, 0], vec![0, 0, 0]]);
        let two = monomials(2, 2);
        assert_eq!(
            two,
            vec![vec![0], vec![1], vec![0, 0], vec![0, 1], vec![1, 1]]
        );
        assert_eq!(monomials(3, 2).len(), 9);
    }

    /// `1/sqrt(1 - z^2)` and `exp(-(a - b)^2/2)`: each is one of the candidates, exact on the
    /// rows; a target that is no polynomial under any transform gets none that fit.
    #[test]
    fn a_transformed_polynomial_is_found_by_one_fit() {
        let cfg = SearchConfig::default();
        let ops = crate::ops::parse_operators(&cfg.operators).expect("ops");
        let z: Vec<f64> = (0..200)
            .map(|i| 0.1 + 0.57 * f64::from(i) / 200.0)
            .collect();
        let w: Vec<f64> = (0..200).map(|i| ((i * 37) % 200) as f64 / 100.0).collect();
        let cases: [(Vec<Vec<f64>>, Vec<f64>, bool); 3] = [
            (
                vec![z.clone()],
                z.iter().map(|v| 1.0 / (1.0 - v * v).sqrt()).collect(),
                true,
            ),
            (
                vec![z.clone(), w.clone()],
                z.iter()
                    .zip(&w)
                    .map(|(a, b)| (-(a - b) * (a - b) / 2.0).exp())
                    .collect(),
                true,
            ),
            (
                vec![z.clone()],
                z.iter()
                    .map(|v| (12.0 * v).sin() + (3.0 * v).cos())
                    .collect(),
                false,
            ),
        ];
        for (cols, y, exact) in cases {
            let names = (0..cols.len()).map(|k| format!("x{k}")).collect();
            let data = Table::new(names, cols).expect("table");
            let valid = cfg.check().expect("valid");
            let problem = Problem::all_rows(&data, &y, variance(&y), &valid);
            let c = polynomials(&problem, &ops);
            assert!(!c.is_empty());
            let best = c
                .iter()
                .map(|f| f.mse / problem.y_var)
                .fold(f64::INFINITY, f64::min);
            assert_eq!(best < 1e-16, exact, "relative mse {best}");
            for f in &c {
                assert!(f.program.is_valid());
                assert_eq!(
                    f.complexity,
                    f.program.complexity_with(
                        ComplexityMeasure::FeaturesPlusOperators,
                        &problem.op_costs
                    )
                );
            }
        }
    }

    /// The law operators have no `inverse`, `sqrt` or `square`: only the identity and the
    /// log are offered; four inputs get nothing.
    #[test]
    fn only_what_the_operators_can_write() {
        let cfg = SearchConfig::default();
        let laws: Vec<Op> = crate::ops::parse_operators(
            &crate::LAW_OPERATORS
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>(),
        )
        .expect("ops");
        let z: Vec<f64> = (0..50).map(|i| 1.0 + f64::from(i) / 10.0).collect();
        let y: Vec<f64> = z.iter().map(|v| 2.0 * v * v + 1.0).collect();
        let data = Table::new(vec!["z".into()], vec![z.clone()]).expect("table");
        let valid = cfg.check().expect("valid");
        let problem = Problem::all_rows(&data, &y, variance(&y), &valid);
        let c = polynomials(&problem, &laws);
        assert_eq!(c.len(), 2);
        for f in &c {
            let ops: Vec<Op> = f
                .program
                .nodes
                .iter()
                .filter_map(|n| match n {
                    Node::Op(op) => Some(*op),
                    _ => None,
                })
                .collect();
            assert!(ops.iter().all(|op| laws.contains(op)), "{ops:?}");
        }
        let four = Table::new(
            (0..4).map(|k| format!("x{k}")).collect(),
            vec![z.clone(), z.clone(), z.clone(), z.clone()],
        )
        .expect("table");
        let valid = cfg.check().expect("valid");
        let p4 = Problem::all_rows(&four, &y, variance(&y), &valid);
        assert!(polynomials(&p4, &laws).is_empty());
        // three inputs on eight rows: the quadratic's eleven parameters outnumber the rows,
        // and a fit that interpolates them is not offered
        let few: Vec<f64> = z[..8].to_vec();
        let three = Table::new(
            (0..3).map(|k| format!("x{k}")).collect(),
            vec![
                few.clone(),
                few.iter().map(|v| v * v).collect(),
                few.clone(),
            ],
        )
        .expect("table");
        let valid = cfg.check().expect("valid");
        let p3 = Problem::all_rows(&three, &y[..8], variance(&y[..8]), &valid);
        assert!(polynomials(&p3, &laws).is_empty());
    }
}
