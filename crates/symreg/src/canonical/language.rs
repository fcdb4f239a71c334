//! The e-graph's language: `Math` (the core operators, numbers as their bits, inputs by
//! rank), the constant-folding analysis `Fold` that keeps one number per constant class,
//! and `Builder`, which adds an expression's core form (the shorthands written out) to an
//! e-graph.

use crate::expr::Expr;
use crate::ops::Op;
use egg::{Analysis, DidMerge, EGraph, Id, Language, define_language};
use std::cmp::Ordering;
use std::fmt;
use std::str::FromStr;

/// `f64::total_cmp` as an unsigned key.
pub(super) fn order_key(v: f64) -> u64 {
    let b = v.to_bits();
    if b >> 63 == 1 { !b } else { b | (1 << 63) }
}

/// The number of an [`order_key`].
pub(super) fn from_order_key(k: u64) -> f64 {
    f64::from_bits(if k >> 63 == 1 { k & !(1 << 63) } else { !k })
}

/// The bits of an `f64`, the numbers of the e-graph (ordered by bits: the e-graph only needs
/// some total order; reading back orders by value).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(super) struct Bits(u64);

impl Bits {
    pub(super) fn value(self) -> f64 {
        f64::from_bits(self.0)
    }
}

impl fmt::Display for Bits {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.value())
    }
}

impl FromStr for Bits {
    type Err = std::num::ParseFloatError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let v: f64 = s.parse()?;
        Ok(Bits(v.to_bits()))
    }
}

/// An input, by its rank among the sorted names of the expression's inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(super) struct VarId(pub(super) u32);

impl fmt::Display for VarId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "v{}", self.0)
    }
}

impl FromStr for VarId {
    type Err = ();
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        s.strip_prefix('v')
            .and_then(|d| d.parse().ok())
            .map(VarId)
            .ok_or(())
    }
}

define_language! {
    /// The core operators: the search's, less the shorthands (see the module docs).
    pub(super) enum Math {
        "+" = Add([Id; 2]),
        "*" = Mul([Id; 2]),
        "pow" = Pow([Id; 2]),
        "inv" = Inv(Id),
        "exp" = Exp(Id),
        "log" = Log(Id),
        "sqrt" = Sqrt(Id),
        "square" = Square(Id),
        "sin" = Sin(Id),
        "cos" = Cos(Id),
        "tanh" = Tanh(Id),
        "tan" = Tan(Id),
        "abs" = Abs(Id),
        Num(Bits),
        Var(VarId),
    }
}

/// Relative distance under which two folded numbers are one (see the module docs).
const SNAP: f64 = 1e-12;

/// Constant folding: the value of a class whose every term is a number.
#[derive(Debug, Default)]
pub(super) struct Fold {
    /// The numbers folded so far, as [`order_key`]s: a new one within [`SNAP`] of one of
    /// them is taken to be it, and only one that is not enters.
    seen: std::collections::BTreeSet<u64>,
}

impl Fold {
    /// `v`, or the smallest number already seen within [`SNAP`] of it.
    fn snap(&mut self, v: f64) -> f64 {
        let d = SNAP * v.abs();
        let (lo, hi) = (order_key(v - d), order_key(v + d));
        if let Some(k) = self.seen.range(lo..=hi).next() {
            return from_order_key(*k);
        }
        self.seen.insert(order_key(v));
        v
    }
}

pub(super) type Graph = EGraph<Math, Fold>;

impl Analysis<Math> for Fold {
    type Data = Option<f64>;

    fn make(egraph: &mut Graph, enode: &Math, _id: Id) -> Self::Data {
        let c = |i: &Id| egraph[*i].data;
        let v = match enode {
            Math::Num(b) => b.value(),
            Math::Var(_) => return None,
            Math::Add([a, b]) => c(a)? + c(b)?,
            Math::Mul([a, b]) => c(a)? * c(b)?,
            Math::Pow([a, b]) => Op::Pow.apply2(c(a)?, c(b)?),
            Math::Inv(a) => 1.0 / c(a)?,
            Math::Exp(a) => Op::Exp.apply1(c(a)?),
            Math::Log(a) => Op::Log.apply1(c(a)?),
            Math::Sqrt(a) => c(a)?.sqrt(),
            Math::Square(a) => c(a)? * c(a)?,
            Math::Sin(a) => Op::Sin.apply1(c(a)?),
            Math::Cos(a) => Op::Cos.apply1(c(a)?),
            Math::Tanh(a) => Op::Tanh.apply1(c(a)?),
            Math::Tan(a) => Op::Tan.apply1(c(a)?),
            Math::Abs(a) => c(a)?.abs(),
        };
        v.is_finite().then(|| egraph.analysis.snap(v))
    }

    /// The smaller value (by total order) when two constant classes merge: their values can
    /// differ by rounding; the choice must not depend on the order of the merges.
    fn merge(&mut self, to: &mut Self::Data, from: Self::Data) -> DidMerge {
        match (*to, from) {
            (None, None) => DidMerge(false, false),
            (None, Some(y)) => {
                *to = Some(y);
                DidMerge(true, false)
            }
            (Some(_), None) => DidMerge(false, true),
            (Some(x), Some(y)) => match y.total_cmp(&x) {
                Ordering::Less => {
                    *to = Some(y);
                    DidMerge(true, true)
                }
                Ordering::Equal => DidMerge(false, false),
                Ordering::Greater => DidMerge(false, true),
            },
        }
    }

    /// A constant class keeps its numbers only: nothing else about it matters, and pruning
    /// keeps the rules from rearranging constant sub-expressions.
    fn modify(egraph: &mut Graph, id: Id) {
        if let Some(v) = egraph[id].data {
            let n = egraph.add(Math::Num(Bits(v.to_bits())));
            egraph.union(id, n);
            egraph[id].nodes.retain(|n| n.is_leaf());
        }
    }
}

/// Builds the core form of an expression into an e-graph (see the module docs for the
/// shorthands).
pub(super) struct Builder<'a> {
    pub(super) g: &'a mut Graph,
    /// Sorted input names: `Var(i)` is `names[i]`.
    pub(super) names: Vec<String>,
}

impl Builder<'_> {
    pub(super) fn num(&mut self, v: f64) -> Id {
        self.g.add(Math::Num(Bits(v.to_bits())))
    }

    fn neg(&mut self, a: Id) -> Id {
        let m1 = self.num(-1.0);
        self.g.add(Math::Mul([m1, a]))
    }

    pub(super) fn var(&mut self, name: &str) -> Id {
        let i = self.names.binary_search_by(|n| n.as_str().cmp(name));
        let i = i.unwrap_or_else(|i| i); // every name was collected first
        self.g.add(Math::Var(VarId(i as u32)))
    }

    pub(super) fn un(&mut self, op: Op, a: Id) -> Id {
        let n = match op {
            Op::Exp => Math::Exp(a),
            Op::Log => Math::Log(a),
            Op::Sqrt => Math::Sqrt(a),
            Op::Square => Math::Square(a),
            Op::Inverse => Math::Inv(a),
            Op::Sin => Math::Sin(a),
            Op::Cos => Math::Cos(a),
            Op::Tanh => Math::Tanh(a),
            Op::Tan => Math::Tan(a),
            Op::Abs => Math::Abs(a),
            Op::Gaussian => {
                let s = self.g.add(Math::Square(a));
                let n = self.neg(s);
                Math::Exp(n)
            }
            // a binary operator with one operand has no value
            _ => return self.num(f64::NAN),
        };
        self.g.add(n)
    }

    pub(super) fn bin(&mut self, op: Op, a: Id, b: Id, b_num: Option<f64>) -> Id {
        let n = match op {
            Op::Add => Math::Add([a, b]),
            Op::Sub => {
                let nb = self.neg(b);
                Math::Add([a, nb])
            }
            Op::Mul => Math::Mul([a, b]),
            Op::Div => {
                let ib = self.g.add(Math::Inv(b));
                Math::Mul([a, ib])
            }
            Op::Gaussian2 => {
                let sa = self.g.add(Math::Square(a));
                let sb = self.g.add(Math::Square(b));
                let s = self.g.add(Math::Add([sa, sb]));
                let n = self.neg(s);
                Math::Exp(n)
            }
            Op::Pow => match b_num {
                Some(0.0) => return self.num(1.0),
                Some(1.0) => return a,
                Some(2.0) => Math::Square(a),
                Some(-1.0) => Math::Inv(a),
                Some(0.5) => Math::Sqrt(a),
                _ => Math::Pow([a, b]),
            },
            _ => return self.num(f64::NAN),
        };
        self.g.add(n)
    }

    /// Adds `e`, its numbers mapped by `num`.
    pub(super) fn expr(&mut self, e: &Expr, num: &mut dyn FnMut(f64) -> f64) -> Id {
        match e {
            Expr::Num(v) => {
                let v = num(*v);
                self.num(v)
            }
            Expr::Var(n) => self.var(n),
            Expr::Neg(a) => {
                let a = self.expr(a, num);
                self.neg(a)
            }
            Expr::Un(op, a) => {
                let a = self.expr(a, num);
                self.un(*op, a)
            }
            Expr::Bin(op, a, b) => {
                let ia = self.expr(a, num);
                let ib = self.expr(b, num);
                let b_num = self.g[ib].data;
                self.bin(*op, ia, ib, b_num)
            }
        }
    }
}

pub(super) fn collect_names(e: &Expr, out: &mut Vec<String>) {
    match e {
        Expr::Num(_) => {}
        Expr::Var(n) => out.push(n.clone()),
        Expr::Neg(a) | Expr::Un(_, a) => collect_names(a, out),
        Expr::Bin(_, a, b) => {
            collect_names(a, out);
            collect_names(b, out);
        }
    }
}
