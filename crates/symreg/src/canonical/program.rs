//! A canonical form read back as a [`Program`], so that a fitted model the rules prove equal
//! to a shorter one can be returned as the shorter one ([`canonical_program`]).
//!
//! The canonical form is an [`Expr`] in the core operators: `gaussian(a)` is written out as
//! `exp(-a^2)`, an affine input `w*x + b` as a product and a sum, the output's scale and
//! offset as a factor and a term. Read back as a program, each of these goes back where the
//! search's parameterisation keeps it: a leading number and a trailing one are the output's
//! scale and offset; under affine inputs, `w*x + b`, `w*x`, `x + b` and `-x` are one input
//! leaf with its weight and bias; `exp(-a^2)`, `exp(-c*a^2)` (`c > 0`) and
//! `exp(-(a^2 + b^2))` are `gaussian` and `gaussian2` again. Whether the program read back
//! is better than the one that went in (shorter, no more constants, the same loss, only the
//! operators and nestings the search allows) is the caller's judgement.

use super::{Effort, canonicalize};
use crate::expr::Expr;
use crate::ops::Op;
use crate::program::{Node, Program};

/// The canonical form of `program` with `params` over inputs named `names`
/// ([`Effort::Full`]), read back as a program over the same inputs with the same
/// parameterisation (`program.affine`), and its parameters: `None` when the form has a
/// name outside `names`, is a constant, or does not read back into a valid program.
///
/// The result computes what `program` computes wherever both are finite, up to the rounding
/// of folded constants (about 1e-12 relative): the rules are identities.
pub fn canonical_program(
    program: &Program,
    params: &[f64],
    names: &[String],
) -> Option<(Program, Vec<f64>)> {
    let e = Expr::from_program(program, params, names);
    let form = canonicalize(&e, Effort::Full).expr;
    let (rest, offset) = match form {
        Expr::Bin(Op::Add, a, b) if matches!(*b, Expr::Num(_)) => {
            let Expr::Num(d) = *b else { return None };
            (*a, d)
        }
        other => (other, 0.0),
    };
    let (scale, body) = split_scale(rest);
    if matches!(body, Expr::Num(_)) {
        return None;
    }
    let mut w = Writer {
        names,
        affine: program.affine,
        nodes: Vec::new(),
        params: vec![scale, offset],
    };
    w.emit(&body)?;
    let out = Program {
        nodes: w.nodes,
        affine: program.affine,
    };
    (out.is_valid() && out.n_params() == w.params.len()).then_some((out, w.params))
}

/// `(s, rest)` with `e = s * rest` and `s` the leading number of a product (or a quotient's
/// numerator), 1 when there is none.
fn split_scale(e: Expr) -> (f64, Expr) {
    match e {
        Expr::Neg(x) => {
            let (s, rest) = split_scale(*x);
            (-s, rest)
        }
        Expr::Bin(Op::Mul, a, b) => match *a {
            Expr::Num(s) => (s, *b),
            a => {
                let (s, a) = split_scale(a);
                (s, Expr::Bin(Op::Mul, Box::new(a), b))
            }
        },
        Expr::Bin(Op::Div, a, b) => match *a {
            Expr::Num(s) => (s, Expr::Un(Op::Inverse, b)),
            a => {
                let (s, a) = split_scale(a);
                (s, Expr::Bin(Op::Div, Box::new(a), b))
            }
        },
        e => (1.0, e),
    }
}

/// An input leaf under affine inputs, `w*x + b`: `(name, w, b)`.
fn affine_leaf(e: &Expr) -> Option<(&str, f64, f64)> {
    match e {
        Expr::Var(n) => Some((n, 1.0, 0.0)),
        Expr::Neg(x) => match &**x {
            Expr::Var(n) => Some((n, -1.0, 0.0)),
            _ => None,
        },
        Expr::Bin(Op::Mul, a, x) => match (&**a, &**x) {
            (Expr::Num(w), Expr::Var(n)) => Some((n, *w, 0.0)),
            _ => None,
        },
        Expr::Bin(op @ (Op::Add | Op::Sub), a, b) => match (affine_leaf(a), &**b) {
            (Some((n, w, 0.0)), Expr::Num(c)) => {
                Some((n, w, if *op == Op::Add { *c } else { -*c }))
            }
            _ => None,
        },
        _ => None,
    }
}

/// `(a, k)` when `e` is `k*a^2` with `k > 0`.
fn positive_square(e: &Expr) -> Option<(&Expr, f64)> {
    match e {
        Expr::Un(Op::Square, a) => Some((a, 1.0)),
        Expr::Bin(Op::Mul, k, sq) => match (&**k, &**sq) {
            (Expr::Num(k), Expr::Un(Op::Square, a)) if *k > 0.0 => Some((a, *k)),
            _ => None,
        },
        _ => None,
    }
}

/// `(a, k)` when `e` is `-k*a^2` with `k > 0`: the argument of a gaussian `exp(-k*a^2)`.
fn negative_square(e: &Expr) -> Option<(&Expr, f64)> {
    match e {
        Expr::Neg(x) => positive_square(x),
        Expr::Bin(Op::Mul, k, sq) => match (&**k, &**sq) {
            (Expr::Num(k), Expr::Un(Op::Square, a)) if *k < 0.0 => Some((a, -*k)),
            _ => None,
        },
        _ => None,
    }
}

type Scaled<'e> = (&'e Expr, f64);

/// The two arguments of `exp(-(k1*a^2 + k2*b^2))` (`k1, k2 > 0`), written as a sum of two
/// negative squares, a difference, or the negation of a sum.
fn gaussian2_arguments(e: &Expr) -> Option<(Scaled<'_>, Scaled<'_>)> {
    match e {
        Expr::Bin(Op::Add, a, b) => Some((negative_square(a)?, negative_square(b)?)),
        Expr::Bin(Op::Sub, a, b) => Some((negative_square(a)?, positive_square(b)?)),
        Expr::Neg(x) => match &**x {
            Expr::Bin(Op::Add, a, b) => Some((positive_square(a)?, positive_square(b)?)),
            _ => None,
        },
        _ => None,
    }
}

/// `k * e` written without a node for `k`, where `e` has a place for it: a number, a
/// product's number, an affine leaf's weight and bias (under affine inputs), both terms of
/// a sum, a factor of a product, a quotient's numerator (or its denominator, by `1/k`).
/// `None` where there is none.
fn absorb(e: &Expr, k: f64, affine: bool) -> Option<Expr> {
    let num = |v: f64| Box::new(Expr::Num(v));
    if affine && let Some((n, w, b)) = affine_leaf(e) {
        let wx = Expr::Bin(Op::Mul, num(k * w), Box::new(Expr::Var(n.to_owned())));
        return Some(Expr::Bin(Op::Add, Box::new(wx), num(k * b)));
    }
    match e {
        Expr::Num(v) => Some(Expr::Num(k * v)),
        Expr::Neg(a) => absorb(a, -k, affine),
        Expr::Bin(Op::Mul, c, x) if matches!(**c, Expr::Num(_)) => {
            let Expr::Num(c) = **c else { return None };
            Some(Expr::Bin(Op::Mul, num(k * c), x.clone()))
        }
        Expr::Bin(op @ (Op::Add | Op::Sub), a, b) => Some(Expr::Bin(
            *op,
            Box::new(absorb(a, k, affine)?),
            Box::new(absorb(b, k, affine)?),
        )),
        Expr::Bin(Op::Mul, a, b) => match absorb(a, k, affine) {
            Some(a) => Some(Expr::Bin(Op::Mul, Box::new(a), b.clone())),
            None => Some(Expr::Bin(
                Op::Mul,
                a.clone(),
                Box::new(absorb(b, k, affine)?),
            )),
        },
        Expr::Bin(Op::Div, a, b) => match absorb(a, k, affine) {
            Some(a) => Some(Expr::Bin(Op::Div, Box::new(a), b.clone())),
            None => Some(Expr::Bin(
                Op::Div,
                a.clone(),
                Box::new(absorb(b, 1.0 / k, affine)?),
            )),
        },
        Expr::Un(Op::Inverse, a) => {
            Some(Expr::Un(Op::Inverse, Box::new(absorb(a, 1.0 / k, affine)?)))
        }
        _ => None,
    }
}

struct Writer<'a> {
    names: &'a [String],
    affine: bool,
    nodes: Vec<Node>,
    params: Vec<f64>,
}

impl Writer<'_> {
    fn var(&mut self, name: &str, w: f64, b: f64) -> Option<()> {
        let j = self.names.iter().position(|n| n == name)?;
        self.nodes.push(Node::Var(u16::try_from(j).ok()?));
        if self.affine {
            self.params.extend([w, b]);
        } else if (w, b) != (1.0, 0.0) {
            return None;
        }
        Some(())
    }

    fn constant(&mut self, v: f64) {
        self.nodes.push(Node::Const);
        self.params.push(v);
    }

    fn op(&mut self, op: Op) {
        self.nodes.push(Node::Op(op));
    }

    /// `k * e`, with `k` taken into a number or an affine leaf of `e` where it can go
    /// without a node of its own ([`absorb`]).
    fn scaled(&mut self, e: &Expr, k: f64) -> Option<()> {
        if k == 1.0 {
            return self.emit(e);
        }
        if let Some(x) = absorb(e, k, self.affine) {
            return self.emit(&x);
        }
        self.constant(k);
        self.emit(e)?;
        self.op(Op::Mul);
        Some(())
    }

    fn emit(&mut self, e: &Expr) -> Option<()> {
        if self.affine
            && let Some((n, w, b)) = affine_leaf(e)
        {
            return self.var(n, w, b);
        }
        match e {
            Expr::Num(v) => self.constant(*v),
            Expr::Var(n) => self.var(n, 1.0, 0.0)?,
            Expr::Neg(x) => {
                let (s, rest) = split_scale((**x).clone());
                self.scaled(&rest, -s)?;
            }
            Expr::Un(Op::Exp, x) => {
                if let Some(((a, ka), (b, kb))) = gaussian2_arguments(x) {
                    self.scaled(a, ka.sqrt())?;
                    self.scaled(b, kb.sqrt())?;
                    self.op(Op::Gaussian2);
                } else if let Some((a, k)) = negative_square(x) {
                    self.scaled(a, k.sqrt())?;
                    self.op(Op::Gaussian);
                } else {
                    self.emit(x)?;
                    self.op(Op::Exp);
                }
            }
            Expr::Bin(Op::Mul, k, x) if matches!(**k, Expr::Num(_)) => {
                let Expr::Num(k) = **k else { return None };
                self.scaled(x, k)?;
            }
            Expr::Un(op, x) => {
                self.emit(x)?;
                self.op(*op);
            }
            Expr::Bin(op, a, b) => {
                self.emit(a)?;
                self.emit(b)?;
                self.op(*op);
            }
        }
        Some(())
    }
}
