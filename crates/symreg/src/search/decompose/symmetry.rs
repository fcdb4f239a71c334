//! Symmetries and powers: two more questions the search's most accurate model answers about
//! the law (AI Feynman's translational and scaling symmetry tests, Udrescu and Tegmark 2020;
//! issue 24 item 2), asked by [`super::separable`] of the same oracle ([`super::oracle`]) on the same test points.
//!
//! - **A pair that enters as one input.** If `f` depends on `x_a` and `x_b` only through
//!   `x_a - x_b`, moving both by the same amount leaves `f` as it is; through `x_a / x_b`,
//!   scaling both by the same factor does; through `x_a x_b`, scaling one up and the other
//!   down; through `x_a + x_b`, moving them in opposite directions. [`find`] makes each move
//!   on the test points and takes the pair and symmetry whose move changes the oracle least,
//!   against the change of moving `x_a` alone; the search then runs on one input fewer, the
//!   pair replaced by its combination, and the sub-model is written back over the inputs
//!   ([`substitute`]).
//! - **An input that enters as a power.** A part of a product that is one input `x` is
//!   `c x^k` when the oracle's elasticity `d ln f / d ln x` is the same at every test point;
//!   [`power`] tests that, with `k` a whole or half number, and the part is then taken as
//!   that power instead of being searched for.
//!
//! Either way the result is one more candidate for selection, refitted and judged like the
//! others, so a symmetry the oracle shows and the law does not costs time, not accuracy.
use super::oracle::{Oracle, spread};
use crate::ops::Op;
use crate::program::{Node, Program};

/// The move of one input, as a share of the smaller spread of the pair over the test
/// points (translations), ...
const SHIFT: f64 = 0.2;

/// ... or as a factor (scalings).
const SCALE: f64 = 1.1;

/// Fewest test points whose moved pair stays inside the data's ranges for a symmetry to be
/// tested.
const MIN_MOVED_POINTS: usize = 20;

/// A symmetry holds when its move changes the oracle by at most this share of the change
/// that moving the first input alone makes (and by at most the split test's tolerance of
/// the oracle's spread).
const SYMMETRY_RATIO: f64 = 0.05;

/// The factor by which an input is scaled to measure the oracle's elasticity.
const POWER_STEP: f64 = 1.1;

/// Largest distance of the elasticity from the whole or half number it is taken as, at
/// every test point.
const POWER_TOLERANCE: f64 = 0.05;

/// Largest power tried, in halves (`|k| <= 4`).
const MAX_POWER_HALVES: i32 = 8;

/// How a pair of inputs enters the law.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Symmetry {
    /// `x_a - x_b`
    Difference,
    /// `x_a / x_b`
    Ratio,
    /// `x_a * x_b`
    Product,
    /// `x_a + x_b`
    Sum,
}

impl Symmetry {
    const ALL: [Self; 4] = [Self::Difference, Self::Ratio, Self::Product, Self::Sum];

    /// The operator that combines the pair.
    pub(super) fn op(self) -> Op {
        match self {
            Self::Difference => Op::Sub,
            Self::Ratio => Op::Div,
            Self::Product => Op::Mul,
            Self::Sum => Op::Add,
        }
    }

    /// The combined input's value.
    pub(super) fn combine(self, a: f64, b: f64) -> f64 {
        match self {
            Self::Difference => a - b,
            Self::Ratio => a / b,
            Self::Product => a * b,
            Self::Sum => a + b,
        }
    }

    /// The combined input's column name.
    pub(super) fn name(self, a: &str, b: &str) -> String {
        let sign = match self {
            Self::Difference => "-",
            Self::Ratio => "/",
            Self::Product => "*",
            Self::Sum => "+",
        };
        format!("({a}{sign}{b})")
    }

    /// The new values of `x_a` and `x_b` under the move that leaves the combination as it
    /// is; `step` is a shift for translations and unused for scalings.
    fn moved(self, a: f64, b: f64, step: f64) -> (f64, f64) {
        match self {
            Self::Difference => (a + step, b + step),
            Self::Sum => (a + step, b - step),
            Self::Ratio => (a * SCALE, b * SCALE),
            Self::Product => (a * SCALE, b / SCALE),
        }
    }
}

/// A symmetry of the oracle: inputs `a` and `b` enter through `symmetry`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Found {
    pub a: usize,
    pub b: usize,
    pub symmetry: Symmetry,
}

fn rms_change(moved: &[f64], base: &[f64]) -> f64 {
    (moved
        .iter()
        .zip(base)
        .map(|(m, b)| (m - b) * (m - b))
        .sum::<f64>()
        / base.len().max(1) as f64)
        .sqrt()
}

/// The pair of `vars` and the symmetry (of those whose operator is in `ops`) under which the
/// oracle changes least on `points`, if any holds (see the module docs); `tolerance` is the
/// split test's, a share of the oracle's spread.
pub(super) fn find(
    oracle: &mut Oracle,
    points: &[Vec<f64>],
    vars: &[usize],
    tolerance: f64,
    ops: &[Op],
) -> Option<Found> {
    let base = oracle.eval(points);
    if !base.iter().all(|v| v.is_finite()) {
        return None;
    }
    let scale = spread(&base);
    if scale <= 0.0 {
        return None;
    }
    let range = |c: &[f64]| {
        c.iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            })
    };
    let ranges: Vec<(f64, f64)> = points.iter().map(|c| range(c)).collect();
    let inside = |v: usize, x: f64| ranges[v].0 <= x && x <= ranges[v].1;
    let mut best: Option<(f64, Found)> = None;
    for (i, &a) in vars.iter().enumerate() {
        for &b in &vars[i + 1..] {
            let step = SHIFT * spread(&points[a]).min(spread(&points[b]));
            if step <= 0.0 {
                continue;
            }
            for symmetry in Symmetry::ALL {
                if !ops.contains(&symmetry.op()) {
                    continue;
                }
                // the oracle is trusted inside the data's ranges only: the points whose
                // moved pair stays there
                let kept: Vec<(usize, f64, f64)> = (0..base.len())
                    .filter_map(|k| {
                        let (na, nb) = symmetry.moved(points[a][k], points[b][k], step);
                        (inside(a, na) && inside(b, nb)).then_some((k, na, nb))
                    })
                    .collect();
                if kept.len() < MIN_MOVED_POINTS {
                    continue;
                }
                let mut at: Vec<Vec<f64>> = points
                    .iter()
                    .map(|c| kept.iter().map(|&(k, _, _)| c[k]).collect())
                    .collect();
                let here: Vec<f64> = kept.iter().map(|&(k, _, _)| base[k]).collect();
                for (j, &(_, na, _)) in kept.iter().enumerate() {
                    at[a][j] = na;
                }
                let f_alone = oracle.eval(&at);
                for (j, &(_, _, nb)) in kept.iter().enumerate() {
                    at[b][j] = nb;
                }
                let f_both = oracle.eval(&at);
                if !f_both.iter().chain(&f_alone).all(|v| v.is_finite()) {
                    continue;
                }
                let change = rms_change(&f_both, &here);
                let sensitivity = rms_change(&f_alone, &here);
                if sensitivity > 0.0
                    && change <= tolerance * scale
                    && change <= SYMMETRY_RATIO * sensitivity
                {
                    let ratio = change / sensitivity;
                    if best.is_none_or(|(r, _)| ratio < r) {
                        best = Some((ratio, Found { a, b, symmetry }));
                    }
                }
            }
        }
    }
    best.map(|(_, f)| f)
}

/// An input to a whole or half power, `x^(halves/2)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Power {
    halves: i32,
    /// Whether `ops` has `square` (else whole powers are products).
    square: bool,
}

impl Power {
    /// `x_var^(halves/2)` as a program over the inputs, each leaf with affine scaling when
    /// `affine` (at the unit parameters of [`unit_params`], the refit may move them).
    pub(super) fn program(self, var: u16, affine: bool) -> Program {
        let odd = self.halves % 2 != 0;
        let whole = if odd {
            self.halves.abs()
        } else {
            self.halves.abs() / 2
        };
        let mut nodes = vec![Node::Var(var)];
        if whole == 2 && self.square {
            nodes.push(Node::Op(Op::Square));
        } else {
            for _ in 1..whole {
                nodes.push(Node::Var(var));
                nodes.push(Node::Op(Op::Mul));
            }
        }
        if odd {
            nodes.push(Node::Op(Op::Sqrt));
        }
        if self.halves < 0 {
            nodes.push(Node::Op(Op::Inverse));
        }
        Program { nodes, affine }
    }
}

/// Whether the oracle is `c x^k` in input `var` on `points` (its elasticity within
/// [`POWER_TOLERANCE`] of one whole or half `k` at every point), and `x^k` can be written
/// with `ops` and is defined on every value of the input's `column`.
pub(super) fn power(
    oracle: &mut Oracle,
    points: &[Vec<f64>],
    var: usize,
    column: &[f64],
    ops: &[Op],
) -> Option<Power> {
    let base = oracle.eval(points);
    let mut scaled = points.to_vec();
    for x in &mut scaled[var] {
        *x *= POWER_STEP;
    }
    let moved = oracle.eval(&scaled);
    let elasticity: Vec<f64> = base
        .iter()
        .zip(&moved)
        .map(|(b, m)| (m / b).ln() / POWER_STEP.ln())
        .collect();
    if elasticity.is_empty() || !elasticity.iter().all(|e| e.is_finite()) {
        return None;
    }
    let mean = elasticity.iter().sum::<f64>() / elasticity.len() as f64;
    let halves = (2.0 * mean).round() as i32;
    let k = f64::from(halves) / 2.0;
    if halves == 0
        || halves.abs() > MAX_POWER_HALVES
        || elasticity.iter().any(|e| (e - k).abs() > POWER_TOLERANCE)
    {
        return None;
    }
    let odd = halves % 2 != 0;
    let whole = if odd { halves.abs() } else { halves.abs() / 2 };
    let square = ops.contains(&Op::Square);
    let writable = (whole < 2 || ops.contains(&Op::Mul) || (whole == 2 && square))
        && (!odd || ops.contains(&Op::Sqrt))
        && (halves > 0 || ops.contains(&Op::Inverse));
    let defined = column
        .iter()
        .all(|&x| x.is_finite() && (!odd || x > 0.0) && (halves > 0 || x != 0.0));
    (writable && defined).then_some(Power { halves, square })
}

/// The parameters of `program` at which it is its bare expression: output scale 1 and
/// offset 0, and every affine leaf `1 * x + 0` (a program without constants).
pub(super) fn unit_params(program: &Program) -> Vec<f64> {
    let mut params = vec![1.0, 0.0];
    for n in &program.nodes {
        match n {
            Node::Var(_) if program.affine => params.extend([1.0, 0.0]),
            Node::Const => params.push(1.0),
            _ => {}
        }
    }
    params
}

/// `program` (with `params`) with input `k` replaced by the expression `inputs[k]` (inputs
/// and operators only), as a program without affine leaves: each leaf's `w * x + b` is
/// written out around its expression.
pub(super) fn substitute(
    program: &Program,
    params: &[f64],
    inputs: &[Vec<Node>],
) -> (Program, Vec<f64>) {
    let off = program.param_offsets();
    let mut nodes = Vec::new();
    let mut out = vec![params[0], params[1]];
    for (i, n) in program.nodes.iter().enumerate() {
        match n {
            Node::Var(v) => {
                nodes.extend_from_slice(&inputs[usize::from(*v)]);
                if program.affine {
                    crate::program::affine(
                        params[off[i]],
                        params[off[i] + 1],
                        &mut nodes,
                        &mut out,
                    );
                }
            }
            Node::Const => {
                nodes.push(Node::Const);
                out.push(params[off[i]]);
            }
            Node::Op(op) => nodes.push(Node::Op(*op)),
        }
    }
    (
        Program {
            nodes,
            affine: false,
        },
        out,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Table;
    use crate::eval::Evaluator;
    use crate::search::config::SearchConfig;

    fn table(rows: usize) -> Table {
        let cols: Vec<Vec<f64>> = (0..3)
            .map(|c| {
                (0..rows)
                    .map(|r| 1.0 + 2.0 * (((r * (7 + 4 * c) + 3 * c) % 97) as f64) / 97.0)
                    .collect()
            })
            .collect();
        Table::new(vec!["a".into(), "b".into(), "c".into()], cols).expect("table")
    }

    /// The oracle of `prog` (postfix nodes, no affine leaves) with `params`.
    fn oracle_of(nodes: Vec<Node>, params: Vec<f64>) -> (Program, Vec<f64>) {
        (
            Program {
                nodes,
                affine: false,
            },
            params,
        )
    }

    /// Each symmetry is found on the pair that has it, and none where no pair has one.
    #[test]
    fn symmetries_are_found_on_the_pair_that_has_them() {
        let data = table(150);
        let ops = crate::ops::parse_operators(&SearchConfig::default().operators).expect("ops");
        let v = Node::Var;
        let op = Node::Op;
        let cases = [
            // (x0 - x1) * x2
            (
                vec![v(0), v(1), op(Op::Sub), v(2), op(Op::Mul)],
                Some((0, 1, Symmetry::Difference)),
            ),
            // x0 / x2 + exp(x1)  (x1 is not a part of the pair)
            (
                vec![v(0), v(2), op(Op::Div), v(1), op(Op::Exp), op(Op::Add)],
                Some((0, 2, Symmetry::Ratio)),
            ),
            // sin(x1 * x2) * x0
            (
                vec![v(1), v(2), op(Op::Mul), op(Op::Sin), v(0), op(Op::Mul)],
                Some((1, 2, Symmetry::Product)),
            ),
            // x0 * x1 + x0 * x2^2: every pair interacts, and no move leaves it as it is (x0 * x1
            // + x0 * x2 would be x0 (x1 + x2), a sum)
            (
                vec![
                    v(0),
                    v(1),
                    op(Op::Mul),
                    v(0),
                    v(2),
                    op(Op::Square),
                    op(Op::Mul),
                    op(Op::Add),
                ],
                None,
            ),
        ];
        for (nodes, want) in cases {
            let (prog, params) = oracle_of(nodes, vec![1.0, 0.0]);
            let mut oracle = Oracle::new(&prog, &params);
            let got = find(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &ops);
            let want = want.map(|(a, b, symmetry)| Found { a, b, symmetry });
            assert_eq!(got, want, "{:?}", prog.nodes);
        }
        // without `sub` among the operators, a difference is not offered
        let (prog, params) = oracle_of(
            vec![v(0), v(1), op(Op::Sub), v(2), op(Op::Mul)],
            vec![1.0, 0.0],
        );
        let mut oracle = Oracle::new(&prog, &params);
        let no_sub: Vec<Op> = ops.iter().copied().filter(|&o| o != Op::Sub).collect();
        assert_eq!(
            find(&mut oracle, data.columns(), &[0, 1, 2], 0.02, &no_sub),
            None
        );
    }

    /// `x0^1.5 x1` is a power in x0 (three halves) and in x1 (one); `exp(x0) x1` is none in
    /// x0; a half power is not taken where the input has a negative value.
    #[test]
    fn a_power_is_read_off_the_elasticity() {
        let data = table(150);
        let ops = crate::ops::parse_operators(&SearchConfig::default().operators).expect("ops");
        let v = Node::Var;
        let op = Node::Op;
        let (prog, params) = oracle_of(
            vec![
                v(0),
                v(0),
                op(Op::Mul),
                v(0),
                op(Op::Mul),
                op(Op::Sqrt),
                v(1),
                op(Op::Mul),
            ],
            vec![2.0, 0.0],
        );
        let mut oracle = Oracle::new(&prog, &params);
        let cols = data.columns();
        let p = power(&mut oracle, cols, 0, &cols[0], &ops).expect("x0^1.5");
        // the power's program is x0^1.5 over the inputs, at its unit parameters
        for affine in [false, true] {
            let program = p.program(0, affine);
            let unit = unit_params(&program);
            let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
            let mut out = Vec::new();
            Evaluator::new(&program).predict(&program, &unit, &refs, 150, &mut out);
            for (o, x) in out.iter().zip(&cols[0]) {
                assert!(
                    (o - x.powf(1.5)).abs() < 1e-12 * x.powf(1.5),
                    "{o} vs {x}^1.5"
                );
            }
        }
        assert!(power(&mut oracle, cols, 1, &cols[1], &ops).is_some());
        let negative: Vec<f64> = cols[0].iter().map(|x| x - 2.0).collect();
        assert!(power(&mut oracle, cols, 0, &negative, &ops).is_none());
        let (prog, params) = oracle_of(vec![v(0), op(Op::Exp), v(1), op(Op::Mul)], vec![1.0, 0.0]);
        let mut oracle = Oracle::new(&prog, &params);
        assert!(power(&mut oracle, cols, 0, &cols[0], &ops).is_none());
    }

    /// A substituted input takes its affine leaf's weight and bias around its expression.
    #[test]
    fn substitution_keeps_the_values() {
        // 3 * exp(w0 * z + b0) * (w1 * x2 + b1) + 1, with z = x0 / x1
        let program = Program {
            nodes: vec![
                Node::Var(0),
                Node::Op(Op::Exp),
                Node::Var(1),
                Node::Op(Op::Mul),
            ],
            affine: true,
        };
        let params = vec![3.0, 1.0, 0.5, -0.25, 2.0, 0.75];
        let inputs = vec![
            vec![Node::Var(0), Node::Var(1), Node::Op(Op::Div)],
            vec![Node::Var(2)],
        ];
        let (p, q) = substitute(&program, &params, &inputs);
        let cols: Vec<Vec<f64>> = vec![
            vec![0.5, 2.0, -1.0],
            vec![1.5, -0.25, 4.0],
            vec![2.0, 3.0, 0.1],
        ];
        let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
        let mut out = Vec::new();
        Evaluator::new(&p).predict(&p, &q, &refs, 3, &mut out);
        for r in 0..3 {
            let z = cols[0][r] / cols[1][r];
            let want = 3.0 * (0.5 * z - 0.25).exp() * (2.0 * cols[2][r] + 0.75) + 1.0;
            assert!(
                (out[r] - want).abs() < 1e-12 * want.abs(),
                "{} vs {want}",
                out[r]
            );
        }
    }
}
