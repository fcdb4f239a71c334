//! The shapes a factor may take, and how a factor model is written as one program.
//!
//! A factor is a short closed form of one column (or, for an interaction, of two). How it
//! enters depends on the link ([`Link`]): a term `a * s(x)` of a sum (additive), or a
//! factor `f(x)` of a product (multiplicative and log). The constants of each factor are
//! [`Node::Const`] leaves of the program, so the model is an ordinary [`Program`]: the
//! evaluator, Levenberg-Marquardt, the printers and the uncertainty template all work on it
//! unchanged.
use super::Link;
use crate::ops::Op;
use crate::program::{ComplexityMeasure, Node, Program};
use serde::{Deserialize, Serialize};

/// The one-column laws a factor can be, in the order of preference: where the data cannot
/// tell two apart (within one standard error), the earlier one is chosen. Power laws come
/// first, as in the laws engineers write (Taylor, Kienzle, Archard).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Shape {
    /// `x^p` (a term `a x^p`); only for a column whose training values are all positive.
    Power,
    /// `1 + b x` in a product, `a x` in a sum.
    Linear,
    /// `exp(b x)` (a term `a exp(b x)`).
    Exp,
    /// `1 + b log(x)` in a product, `a log(x)` in a sum; positive columns only.
    Log,
    /// One pole outside the data: `1/(x + c)` (a term `a/(x + c)`).
    Pole,
    /// A saturation `x/(x + c)` (a term `a x/(x + c)`).
    Saturation,
    /// An interaction of two columns: `1 + a x^p y^q` in a product, `a x^p y^q` in a sum
    /// (with `p = q = 1` fixed where a column is not positive).
    Pair,
    /// One harmonic: `sin(w x + c)` (a term `a sin(w x + c)`, `1 + a sin(w x + c)` in a
    /// product): an effect that repeats over its column (a spindle's angle, a time of
    /// day). Not in a log correction, where it would be a transcendental inside one.
    Periodic,
    /// A threshold (issue 68): piecewise linear with one fitted knot `k`, written
    /// `x + |x - k|` (twice `max(x, k)` less `k`: flat below the knot, rising with slope 2
    /// above it): a term `a (x + |x - k|)`, `1 + b (x + |x - k|)` in a product.
    Hinge,
    /// A smooth step (issue 68): `tanh(w x + c)`, a logistic in the column centred at
    /// `-c/w` (a term `a tanh(w x + c)`, `1 + b tanh(w x + c)` in a product): an effect that
    /// switches over part of the column's range and saturates on both sides.
    Step,
    /// A saturating power (issue 68): `1/(1 + k x^q)`, Hill's law; with `q < 0` it grows
    /// as `x^(-q)` below `x = k^(1/q)` and saturates above (the `x^p/(1 + (x/c)^p)` of the
    /// handbooks up to the constant `c^p`); positive columns only.
    #[serde(rename = "saturating_power")]
    SaturatingPower,
}

impl Shape {
    /// The one-column shapes, in the order of preference.
    pub const MAIN: [Shape; 10] = [
        Shape::Power,
        Shape::Linear,
        Shape::Exp,
        Shape::Log,
        Shape::Pole,
        Shape::Saturation,
        Shape::Hinge,
        Shape::SaturatingPower,
        Shape::Step,
        Shape::Periodic,
    ];

    /// `power`, `linear`, `exp`, `log`, `pole`, `saturation`, `pair`, `periodic`, `hinge`,
    /// `step`, `saturating_power`.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Power => "power",
            Shape::Linear => "linear",
            Shape::Exp => "exp",
            Shape::Log => "log",
            Shape::Pole => "pole",
            Shape::Saturation => "saturation",
            Shape::Pair => "pair",
            Shape::Periodic => "periodic",
            Shape::Hinge => "hinge",
            Shape::Step => "step",
            Shape::SaturatingPower => "saturating_power",
        }
    }

    /// The shape of a name of [`Shape::name`], if any.
    pub fn from_name(name: &str) -> Option<Shape> {
        Shape::MAIN
            .into_iter()
            .chain([Shape::Pair])
            .find(|s| s.name() == name)
    }

    /// Whether the shape needs positive values of its column(s).
    pub(crate) fn needs_positive(self) -> bool {
        matches!(self, Shape::Power | Shape::Log | Shape::SaturatingPower)
    }

    /// Whether the shape is one of the flexible ones, which must beat the column's best
    /// plainer shape by [`super::FactorConfig::interaction_se`] paired standard errors, as
    /// an interaction must, to be chosen: the harmonic, the step and the saturating power
    /// (three constants of their own in a sum) and the hinge (its knot is a claim about the
    /// process; measured on issue 46's tables, a hinge let in on one standard error replaced
    /// cutting force's exponential in the speed and cost 38 % of its test RMSE).
    pub(crate) fn flexible(self) -> bool {
        matches!(
            self,
            Shape::Periodic | Shape::Step | Shape::SaturatingPower | Shape::Hinge
        )
    }
}

/// One factor of a model: its shape, its columns (indices into the feature table) and its
/// constants in the order [`emit`] writes them.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Term {
    pub shape: Shape,
    pub cols: Vec<usize>,
    pub params: Vec<f64>,
    /// Which of `params` Levenberg-Marquardt fits (an exponent fixed at a simple number,
    /// or the pair's exponents where a column is not positive, are not fitted).
    pub free: Vec<bool>,
}

/// Statistics of a column that the starting values use.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ColStats {
    pub lo: f64,
    pub hi: f64,
    pub positive: bool,
}

impl ColStats {
    pub fn of(x: &[f64]) -> Self {
        let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Self {
            lo,
            hi,
            positive: lo > 0.0,
        }
    }

    fn width(&self) -> f64 {
        (self.hi - self.lo).max(1e-12 * (1.0 + self.hi.abs()))
    }
}

/// Starting constants of a new term (several starts; the search keeps the best). The
/// amplitude of a sum's term (its first constant) starts at 0 and is set by projection on
/// the partial residual before the fit.
pub(crate) fn starts(shape: Shape, link: Link, st: &[ColStats]) -> Vec<Term> {
    let s = st[0];
    let w = s.width();
    let one = |params: Vec<f64>| vec![params];
    let sets: Vec<Vec<f64>> = match (shape, link) {
        (Shape::Power, Link::Additive) => vec![vec![0.0, 1.0], vec![0.0, -1.0], vec![0.0, 0.5]],
        (Shape::Power, _) => vec![vec![0.5], vec![-0.5], vec![1.5]],
        (Shape::Linear, Link::Additive) => one(vec![0.0]),
        (Shape::Linear, _) => one(vec![1.0, 0.0]),
        (Shape::Exp, Link::Additive) => vec![vec![0.0, 1.0 / w], vec![0.0, -1.0 / w]],
        (Shape::Exp, _) => vec![vec![1.0 / w], vec![-1.0 / w]],
        (Shape::Log, Link::Additive) => one(vec![0.0]),
        (Shape::Log, _) => one(vec![1.0, 0.0]),
        (Shape::Pole, Link::Additive) => vec![
            vec![0.0, -s.lo + 0.5 * w],
            vec![0.0, -s.lo + 2.0 * w],
            vec![0.0, -s.hi - 0.5 * w],
        ],
        (Shape::Pole, _) => vec![
            vec![-s.lo + 0.5 * w],
            vec![-s.lo + 2.0 * w],
            vec![-s.hi - 0.5 * w],
        ],
        (Shape::Saturation, Link::Additive) => {
            vec![vec![0.0, -s.lo + 0.5 * w], vec![0.0, -s.lo + 2.0 * w]]
        }
        (Shape::Saturation, _) => vec![vec![-s.lo + 0.5 * w], vec![-s.lo + 2.0 * w]],
        // half, one and two periods over the column's range, each as a sine and a cosine
        // (the amplitude's sign covers the other two phases); LM moves both from there
        (Shape::Periodic | Shape::Step, Link::Log) => Vec::new(),
        (Shape::Periodic, link) => PERIODS
            .iter()
            .flat_map(|&k| {
                let omega = 2.0 * std::f64::consts::PI * k / w;
                [0.0, std::f64::consts::FRAC_PI_2].map(|phase| {
                    let c = phase - omega * s.lo;
                    match link {
                        Link::Additive => vec![0.0, omega, c],
                        _ => vec![1.0, PERIODIC_START, omega, c],
                    }
                })
            })
            .collect(),
        // knots at a quarter, half and three quarters of the range (a product's slope
        // small but not 0, where the knot would have no gradient)
        (Shape::Hinge, link) => [0.25, 0.5, 0.75]
            .iter()
            .map(|q| match link {
                Link::Additive => vec![0.0, -(s.lo + q * w)],
                _ => vec![1.0, PERIODIC_START / w, -(s.lo + q * w)],
            })
            .collect(),
        // a step over a third of the range, centred at a quarter, half, three quarters
        (Shape::Step, link) => [0.25, 0.5, 0.75]
            .iter()
            .map(|q| {
                let rate = 6.0 / w;
                let c = -rate * (s.lo + q * w);
                match link {
                    Link::Additive => vec![0.0, rate, c],
                    _ => vec![1.0, PERIODIC_START, rate, c],
                }
            })
            .collect(),
        // `1/(1 + k x^q)` switching at the range's middle (`k = mid^(-q)`), from a growth
        // as `x^2` or `x^0.5` below it, or a fall
        (Shape::SaturatingPower, link) => [-2.0, -0.5, 1.0]
            .iter()
            .map(|&q| {
                let mid = 0.5 * (s.lo + s.hi);
                let k = mid.powf(-q);
                match link {
                    Link::Additive => vec![0.0, 1.0, k, q],
                    _ => vec![1.0, k, q],
                }
            })
            .collect(),
        (Shape::Pair, link) => {
            let positive = st.iter().all(|c| c.positive);
            let pairs: Vec<(f64, f64)> = if positive {
                vec![(1.0, 1.0), (0.5, 1.5), (1.5, 0.5)]
            } else {
                vec![(1.0, 1.0)]
            };
            pairs
                .into_iter()
                .map(|(p, q)| match link {
                    Link::Additive => vec![0.0, p, q],
                    _ => vec![1.0, 0.0, p, q],
                })
                .collect()
        }
    };
    sets.into_iter()
        .map(|params| {
            let free = free_flags(shape, link, &params, st);
            Term {
                shape,
                cols: Vec::new(),
                params,
                free,
            }
        })
        .collect()
}

/// Periods over the column's range that a [`Shape::Periodic`] term starts from (a shorter
/// period is scatter a few hundred rows hardly pin down).
const PERIODS: [f64; 3] = [1.0, 2.0, 3.0];

/// Fewest periods a harmonic may run through over its column's range once fitted: one
/// period, less what the sampled range falls short of the column's span at its ends (a
/// spindle angle drawn over 0-360 degrees spans about 359). Less is a bend, not an effect
/// the rows show repeating, and a three-constant sine fits a bend better than the plain
/// shapes by chance or where the truth is a step. Chosen on issue 46's tables
/// (docs/benchmarks.md, "One harmonic"): at 0.75 roughness's built-up-edge step in the
/// cutting speed came back as 0.89 of a period of a sine, and a `1 + 0.05 r` factor of a
/// unit test as a quarter period; runout's one true period is fitted at 1.003. Checked on
/// the fit on every row, where the shape is decided; a fold's refit may run a few per cent
/// slower (at 0.95 checked on the folds too, runout lost its harmonic).
pub(crate) const MIN_CYCLES: f64 = 0.95;

/// The starting amplitude of a periodic factor `1 + a sin(w x + c)` (a sum's is set by
/// projection): small, so the product starts near the model without it, but not 0, where
/// the frequency and the phase would have no gradient.
const PERIODIC_START: f64 = 0.05;

/// Which constants of a fresh term are fitted: all but the `1` of `1 + b x` and, for a
/// pair over a column that is not positive, its exponents (fixed at 1).
fn free_flags(shape: Shape, link: Link, params: &[f64], st: &[ColStats]) -> Vec<bool> {
    let mut free = vec![true; params.len()];
    let product = link != Link::Additive;
    if product
        && matches!(
            shape,
            Shape::Linear | Shape::Log | Shape::Pair | Shape::Periodic | Shape::Hinge | Shape::Step
        )
    {
        free[0] = false;
    }
    // the `1` of `1/(1 + k x^q)`
    if shape == Shape::SaturatingPower {
        free[usize::from(!product)] = false;
    }
    if shape == Shape::Pair && !st.iter().all(|c| c.positive) {
        let n = free.len();
        free[n - 1] = false;
        free[n - 2] = false;
    }
    free
}

/// Appends `term` to a program under construction: nodes, and its constants in the same
/// order (each [`Node::Const`] owns the next entry of `params`).
pub(crate) fn emit(term: &Term, link: Link, var: &dyn Fn(usize) -> u16, b: &mut Builder) {
    let x = var(term.cols[0]);
    let p = &term.params;
    let additive = link == Link::Additive;
    // the shape itself, with its own constants (the sum's amplitude comes first, below)
    let body = |b: &mut Builder, q: &[f64]| match term.shape {
        Shape::Power => {
            b.var(x);
            b.konst(q[0]);
            b.op(Op::Pow);
        }
        Shape::Linear => b.var(x),
        Shape::Exp => {
            b.konst(q[0]);
            b.var(x);
            b.op(Op::Mul);
            b.op(Op::Exp);
        }
        Shape::Log => {
            b.var(x);
            b.op(Op::Log);
        }
        Shape::Pole => {
            b.var(x);
            b.konst(q[0]);
            b.op(Op::Add);
            b.op(Op::Inverse);
        }
        Shape::Saturation => {
            b.var(x);
            b.var(x);
            b.konst(q[0]);
            b.op(Op::Add);
            b.op(Op::Div);
        }
        Shape::Pair => {
            let y = var(term.cols[1]);
            b.var(x);
            b.konst(q[0]);
            b.op(Op::Pow);
            b.var(y);
            b.konst(q[1]);
            b.op(Op::Pow);
            b.op(Op::Mul);
        }
        Shape::Periodic | Shape::Step => {
            b.konst(q[0]);
            b.var(x);
            b.op(Op::Mul);
            b.konst(q[1]);
            b.op(Op::Add);
            b.op(if term.shape == Shape::Step {
                Op::Tanh
            } else {
                Op::Sin
            });
        }
        Shape::Hinge => {
            b.var(x);
            b.var(x);
            b.konst(q[0]);
            b.op(Op::Add);
            b.op(Op::Abs);
            b.op(Op::Add);
        }
        Shape::SaturatingPower => {
            b.konst(q[0]);
            b.konst(q[1]);
            b.var(x);
            b.konst(q[2]);
            b.op(Op::Pow);
            b.op(Op::Mul);
            b.op(Op::Add);
            b.op(Op::Inverse);
        }
    };
    if additive {
        // a * s(x)
        b.konst(p[0]);
        body(b, &p[1..]);
        b.op(Op::Mul);
        return;
    }
    match term.shape {
        // 1 + b * s(x)
        Shape::Linear | Shape::Log | Shape::Pair | Shape::Periodic | Shape::Hinge | Shape::Step => {
            b.konst(p[0]);
            b.konst(p[1]);
            body(b, &p[2..]);
            b.op(Op::Mul);
            b.op(Op::Add);
        }
        _ => body(b, p),
    }
}

/// A program being written node by node, with its constants.
#[derive(Debug, Default)]
pub(crate) struct Builder {
    pub nodes: Vec<Node>,
    pub consts: Vec<f64>,
}

impl Builder {
    pub fn var(&mut self, j: u16) {
        self.nodes.push(Node::Var(j));
    }
    pub fn konst(&mut self, v: f64) {
        self.nodes.push(Node::Const);
        self.consts.push(v);
    }
    pub fn op(&mut self, op: Op) {
        self.nodes.push(Node::Op(op));
    }
}

/// The complexity of a factor as the search counts it (inputs and operators; constants
/// and the `1 + b *` around a product's factor are free, as a search's affine input
/// scaling is): `x` 1, `x^p`, `exp(b x)`, `log(x)` 2, `1/(x + c)`, `sin(w x + c)`,
/// `tanh(w x + c)` 3, `x/(x + c)` 4, `x^p y^q`, `x + |x + c|`, `1/(1 + k x^q)` 5.
pub fn complexity(shape: Shape) -> usize {
    let t = Term {
        shape,
        cols: vec![0, 1],
        params: vec![1.0; 5],
        free: vec![true; 5],
    };
    let mut b = Builder::default();
    emit(&t, Link::Additive, &|c| c as u16, &mut b);
    let prog = Program {
        nodes: b.nodes,
        affine: false,
    };
    // the amplitude's `a *` is free, and so is the `b *` inside `exp(b x)`
    let free_muls = 1 + usize::from(matches!(shape, Shape::Exp | Shape::Periodic | Shape::Step));
    prog.complexity(ComplexityMeasure::FeaturesPlusOperators) - free_muls
}

/// The structure of a factor with its constants written `p0`, `p1`, ... (the sum's
/// amplitude and the product's `1 +` left out): `x**p0`, `exp(p0*x)`, `log(x)`, ...; the
/// key of the factor shares in a stability report.
pub fn template(shape: Shape, names: &[&str]) -> String {
    let x = names[0];
    match shape {
        Shape::Power => format!("{x}**p0"),
        Shape::Linear => x.to_string(),
        Shape::Exp => format!("exp(p0*{x})"),
        Shape::Log => format!("log({x})"),
        Shape::Pole => format!("1/({x} + p0)"),
        Shape::Saturation => format!("{x}/({x} + p0)"),
        Shape::Pair => format!("{x}**p0*{}**p1", names.get(1).copied().unwrap_or("?")),
        Shape::Periodic => format!("sin(p0*{x} + p1)"),
        Shape::Hinge => format!("{x} + Abs({x} + p0)"),
        Shape::Step => format!("tanh(p0*{x} + p1)"),
        Shape::SaturatingPower => format!("1/(1 + p0*{x}**p1)"),
    }
}

/// A set of [`Shape`]s (the interaction is [`Shape::Pair`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shapes(u16);

impl Shapes {
    /// Every shape, the threshold and saturation shapes of issue 68 included.
    pub const ALL: Shapes = Shapes(u16::MAX);

    /// The shapes of the default: every shape but issue 68's hinge, smooth step and
    /// saturating power, which a fit takes where asked (`--shapes all`): they are measured
    /// in docs/benchmarks.md before they become a default.
    pub const CLASSIC: Shapes = Shapes(
        !((1 << Shape::Hinge as u16)
            | (1 << Shape::Step as u16)
            | (1 << Shape::SaturatingPower as u16)),
    );

    /// No shape.
    pub const NONE: Shapes = Shapes(0);

    /// Whether `shape` is in the set.
    pub fn contains(self, shape: Shape) -> bool {
        self.0 & (1 << shape as u16) != 0
    }

    /// The set with `shape` added.
    #[must_use]
    pub fn with(self, shape: Shape) -> Shapes {
        Shapes(self.0 | (1 << shape as u16))
    }

    /// The set without `shape`.
    #[must_use]
    pub fn without(self, shape: Shape) -> Shapes {
        Shapes(self.0 & !(1 << shape as u16))
    }

    /// The set less the shapes that write an operator missing from `ops`: the exponential
    /// without `exp`, the logarithm without `log`, the pole and the saturations without
    /// `div` or `inverse`; with `powers_divide`, the power and the pair too (a negative
    /// exponent is then written as a division; `hxai sr`'s candidates keep them).
    #[must_use]
    pub fn allowed_by(self, ops: &[Op], powers_divide: bool) -> Shapes {
        let mut s = self;
        if !ops.contains(&Op::Exp) {
            s = s.without(Shape::Exp);
        }
        if !ops.contains(&Op::Log) {
            s = s.without(Shape::Log);
        }
        if !ops.contains(&Op::Div) && !ops.contains(&Op::Inverse) {
            let mut gone = vec![Shape::Pole, Shape::Saturation, Shape::SaturatingPower];
            if powers_divide {
                gone.extend([Shape::Power, Shape::Pair]);
            }
            for sh in gone {
                s = s.without(sh);
            }
        }
        s
    }

    /// The shapes of a setting: `classic` ([`Shapes::CLASSIC`]), `all` ([`Shapes::ALL`]),
    /// or a comma-separated list of [`Shape::name`]s (`power,linear,hinge`); `None` for a
    /// name that is not a shape.
    pub fn parse(text: &str) -> Option<Shapes> {
        match text.trim() {
            "classic" => Some(Shapes::CLASSIC),
            "all" => Some(Shapes::ALL),
            list => list
                .split(',')
                .map(|n| Shape::from_name(n.trim()))
                .try_fold(Shapes::NONE, |set, s| s.map(|s| set.with(s))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn complexities_are_those_documented() {
        let got: Vec<usize> = [
            Shape::Linear,
            Shape::Power,
            Shape::Exp,
            Shape::Log,
            Shape::Pole,
            Shape::Saturation,
            Shape::Pair,
            Shape::Periodic,
            Shape::Hinge,
            Shape::Step,
            Shape::SaturatingPower,
        ]
        .iter()
        .map(|&s| complexity(s))
        .collect();
        assert_eq!(got, [1, 2, 2, 2, 3, 4, 5, 3, 5, 3, 5]);
    }
}
