//! The tokens read back decoded into a term and printed as an [`Expr`] the usual way
//! (signs, divisors, negated terms and numbers placed as the module docs say); in a
//! structure key every parameter is the input `c`.

use super::extract::{TAGS, Tok, num_tok};
use super::is_literal;
use super::language::from_order_key;
use crate::expr::Expr;
use crate::ops::Op;

/// A term read back from tokens.
pub(super) enum Term {
    Gen,
    Num(f64),
    Var(u32),
    Op(u8, Vec<Term>),
}

impl Term {
    /// The parameters in a structure's term: generic values and numbers that are not small
    /// literals (those [`Pretty`] prints `c` in a key).
    pub(super) fn parameters(&self) -> usize {
        match self {
            Term::Gen => 1,
            Term::Num(v) => usize::from(!is_literal(*v)),
            Term::Var(_) => 0,
            Term::Op(_, ch) => ch.iter().map(Term::parameters).sum(),
        }
    }
}

pub(super) fn decode(toks: &[Tok], at: &mut usize) -> Term {
    let t = toks.get(*at).copied().unwrap_or(num_tok(f64::NAN));
    *at += 1;
    match t {
        Tok::Gen => Term::Gen,
        Tok::Num(k, s) => {
            let v = from_order_key(k);
            Term::Num(if s == 1 { -v } else { v })
        }
        Tok::Var(i) => Term::Var(i),
        Tok::Op(o) => {
            let arity = TAGS.get(o as usize).map_or(1, |t| t.1);
            Term::Op(o, (0..arity).map(|_| decode(toks, at)).collect())
        }
    }
}

const UNARY: [(u8, Op); 10] = [
    (3, Op::Inverse),
    (4, Op::Exp),
    (5, Op::Log),
    (6, Op::Sqrt),
    (7, Op::Square),
    (8, Op::Sin),
    (9, Op::Cos),
    (10, Op::Tanh),
    (11, Op::Tan),
    (12, Op::Abs),
];

/// Prints a term the usual way (see the module docs); in a key, parameters are `c`.
pub(super) struct Pretty<'a> {
    pub(super) names: &'a [String],
    pub(super) key: bool,
}

impl Pretty<'_> {
    fn flatten<'t>(op: u8, t: &'t Term, out: &mut Vec<&'t Term>) {
        match t {
            Term::Op(o, ch) if *o == op => {
                for c in ch {
                    Self::flatten(op, c, out);
                }
            }
            other => out.push(other),
        }
    }

    pub(super) fn expr(&self, t: &Term) -> Expr {
        match t {
            Term::Gen => Expr::Var("c".into()),
            Term::Num(v) => {
                if self.key && !is_literal(*v) {
                    Expr::Var("c".into())
                } else {
                    Expr::Num(*v)
                }
            }
            Term::Var(i) => Expr::Var(
                self.names
                    .get(*i as usize)
                    .cloned()
                    .unwrap_or_else(|| format!("x{i}")),
            ),
            Term::Op(0, _) => self.sum(t),
            Term::Op(1, _) => self.product(t),
            Term::Op(2, ch) if ch.len() == 2 => Expr::Bin(
                Op::Pow,
                Box::new(self.expr(&ch[0])),
                Box::new(self.expr(&ch[1])),
            ),
            Term::Op(o, ch) => {
                let op = UNARY.iter().find(|u| u.0 == *o).map_or(Op::Exp, |u| u.1);
                let a = ch.first().map_or(Expr::Num(f64::NAN), |c| self.expr(c));
                Expr::Un(op, Box::new(a))
            }
        }
    }

    /// Terms of a sum: inputs and functions first, negated terms next, numbers last.
    fn sum(&self, t: &Term) -> Expr {
        let mut terms = Vec::new();
        Self::flatten(0, t, &mut terms);
        let mut pos = Vec::new();
        let mut neg = Vec::new();
        let mut nums = Vec::new();
        for term in terms {
            match self.expr(term) {
                Expr::Neg(x) => neg.push(*x),
                e @ (Expr::Num(_) | Expr::Var(_)) if matches!(term, Term::Num(_) | Term::Gen) => {
                    nums.push(e)
                }
                e => pos.push(e),
            }
        }
        let mut acc: Option<Expr> = None;
        for e in pos {
            acc = Some(match acc {
                None => e,
                Some(a) => Expr::Bin(Op::Add, Box::new(a), Box::new(e)),
            });
        }
        for e in neg {
            acc = Some(match acc {
                None => Expr::Neg(Box::new(e)),
                Some(a) => Expr::Bin(Op::Sub, Box::new(a), Box::new(e)),
            });
        }
        for e in nums {
            acc = Some(match acc {
                None => e,
                Some(a) => Expr::Bin(Op::Add, Box::new(a), Box::new(e)),
            });
        }
        acc.unwrap_or(Expr::Num(0.0))
    }

    /// Factors of a product: a factor -1 is a sign, numbers come first, inverses are
    /// divisors.
    fn product(&self, t: &Term) -> Expr {
        let mut factors = Vec::new();
        Self::flatten(1, t, &mut factors);
        let mut negative = false;
        let mut numbers: Vec<Expr> = Vec::new();
        let mut num: Vec<Expr> = Vec::new();
        let mut den: Vec<Expr> = Vec::new();
        for f in factors {
            match f {
                Term::Num(v) if *v == -1.0 => negative = !negative,
                Term::Num(_) | Term::Gen => numbers.push(self.expr(f)),
                Term::Op(3, ch) if ch.len() == 1 => den.push(self.expr(&ch[0])),
                other => num.push(self.expr(other)),
            }
        }
        numbers.append(&mut num);
        let num = numbers;
        let prod = |v: Vec<Expr>| {
            v.into_iter()
                .reduce(|a, b| Expr::Bin(Op::Mul, Box::new(a), Box::new(b)))
        };
        let e = match (prod(num), prod(den)) {
            (Some(n), Some(d)) => Expr::Bin(Op::Div, Box::new(n), Box::new(d)),
            (Some(n), None) => n,
            (None, Some(d)) => Expr::Un(Op::Inverse, Box::new(d)),
            (None, None) => Expr::Num(1.0),
        };
        if negative { Expr::Neg(Box::new(e)) } else { e }
    }
}
