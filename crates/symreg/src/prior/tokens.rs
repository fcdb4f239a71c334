//! Tokens: a written law or a search [`Program`] as a prefix (Polish) sequence over the
//! search's vocabulary.
//!
//! Both go through one tree and one set of rules, listed in the module docs of
//! [`prior`](super) under "Tokens".

use crate::expr::Expr;
use crate::ops::Op;
use crate::program::{Node, Program};
use std::fmt;

/// One token of a law's prefix sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Token {
    /// The start mark: context only, never predicted.
    Start,
    /// The end mark, predicted after the last token.
    End,
    /// A measured input (`x`).
    Var,
    /// A fitted constant or a fixed number (`c`).
    Const,
    /// An operator, by its [`Op::name`].
    Op(Op),
}

impl Token {
    /// Every token the model predicts (all but [`Token::Start`]), in a fixed order: the
    /// end mark, `x`, `c`, then every [`Op`] (the search's and `pow`, `tan`).
    pub const PREDICTED: [Token; 20] = [
        Token::End,
        Token::Var,
        Token::Const,
        Token::Op(Op::Add),
        Token::Op(Op::Sub),
        Token::Op(Op::Mul),
        Token::Op(Op::Div),
        Token::Op(Op::Exp),
        Token::Op(Op::Log),
        Token::Op(Op::Sqrt),
        Token::Op(Op::Square),
        Token::Op(Op::Inverse),
        Token::Op(Op::Sin),
        Token::Op(Op::Cos),
        Token::Op(Op::Tanh),
        Token::Op(Op::Abs),
        Token::Op(Op::Gaussian),
        Token::Op(Op::Gaussian2),
        Token::Op(Op::Pow),
        Token::Op(Op::Tan),
    ];

    /// The token's name: `<s>`, `</s>`, `x`, `c` or the operator's name.
    pub fn name(self) -> &'static str {
        match self {
            Token::Start => "<s>",
            Token::End => "</s>",
            Token::Var => "x",
            Token::Const => "c",
            Token::Op(op) => op.name(),
        }
    }
}

impl fmt::Display for Token {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The tree both forms pass through: `C(Some(v))` is a fixed number (kept for the power
/// rules), `C(None)` a fitted constant.
#[derive(Clone, Debug, PartialEq)]
enum Tree {
    X,
    C(Option<f64>),
    U(Op, Box<Tree>),
    B(Op, Box<Tree>, Box<Tree>),
}

use Tree::{B, C, U, X};

fn fitted() -> Box<Tree> {
    Box::new(C(None))
}

fn unary(op: Op, a: Tree) -> Tree {
    match a {
        C(v) => C(v.map(|v| op.apply1(v)).filter(|v| v.is_finite())),
        a => U(op, Box::new(a)),
    }
}

fn binary(op: Op, a: Tree, b: Tree) -> Tree {
    match (a, b) {
        (C(u), C(v)) => C(u
            .zip(v)
            .map(|(u, v)| op.apply2(u, v))
            .filter(|v| v.is_finite())),
        (a, b) if op == Op::Pow => power(a, b),
        (C(Some(1.0)), b) if op == Op::Div => U(Op::Inverse, Box::new(b)),
        (a, b) => B(op, Box::new(a), Box::new(b)),
    }
}

/// `base^exponent` where not both are constant (rule 3 of the tokens in the `prior` docs).
fn power(base: Tree, exponent: Tree) -> Tree {
    match (base, exponent) {
        (C(_), e) => U(Op::Exp, Box::new(B(Op::Mul, fitted(), Box::new(e)))),
        (a, C(Some(1.0))) => a,
        (a, C(Some(2.0))) => U(Op::Square, Box::new(a)),
        (a, C(Some(0.5))) => U(Op::Sqrt, Box::new(a)),
        (a, C(Some(-1.0))) => U(Op::Inverse, Box::new(a)),
        (a, C(Some(-2.0))) => U(Op::Inverse, Box::new(U(Op::Square, Box::new(a)))),
        (a, C(Some(-0.5))) => U(Op::Inverse, Box::new(U(Op::Sqrt, Box::new(a)))),
        (a, e) => B(Op::Pow, Box::new(a), Box::new(e)),
    }
}

fn from_expr(e: &Expr, variables: &[&str]) -> Tree {
    match e {
        Expr::Num(v) => C(Some(*v)),
        Expr::Var(name) => {
            if variables.contains(&name.as_str()) {
                X
            } else {
                C(None)
            }
        }
        Expr::Neg(a) => match from_expr(a, variables) {
            C(v) => C(v.map(|v| -v)),
            a => B(Op::Mul, Box::new(C(Some(-1.0))), Box::new(a)),
        },
        Expr::Un(op, a) => unary(*op, from_expr(a, variables)),
        Expr::Bin(op, a, b) => binary(*op, from_expr(a, variables), from_expr(b, variables)),
    }
}

/// The tree of a postfix program, or `None` for a malformed one.
fn from_program(program: &Program) -> Option<Tree> {
    let mut stack: Vec<Tree> = Vec::with_capacity(program.nodes.len());
    for n in &program.nodes {
        let t = match n {
            Node::Var(_) => X,
            Node::Const => C(None),
            Node::Op(op) if op.arity() == 2 => {
                let b = stack.pop()?;
                let a = stack.pop()?;
                binary(*op, a, b)
            }
            Node::Op(op) => unary(*op, stack.pop()?),
        };
        stack.push(t);
    }
    if stack.len() == 1 { stack.pop() } else { None }
}

/// `exp(c*log(a))` and `exp(log(a)*c)` become `pow a c`, everywhere in the tree.
fn powers(t: Tree) -> Tree {
    match t {
        U(op, a) => {
            let a = powers(*a);
            if op == Op::Exp
                && let B(Op::Mul, p, q) = &a
            {
                let base = match (&**p, &**q) {
                    (C(_), U(Op::Log, base)) | (U(Op::Log, base), C(_)) => Some(base.clone()),
                    _ => None,
                };
                if let Some(base) = base {
                    return B(Op::Pow, base, fitted());
                }
            }
            U(op, Box::new(a))
        }
        B(op, a, b) => B(op, Box::new(powers(*a)), Box::new(powers(*b))),
        leaf => leaf,
    }
}

/// Drops the outer affine map (rule 5 of the tokens in the `prior` docs).
fn strip(mut t: Tree) -> Tree {
    loop {
        t = match t {
            B(Op::Add | Op::Sub | Op::Mul, a, r) if matches!(*a, C(_)) => *r,
            B(Op::Add | Op::Sub | Op::Mul | Op::Div, r, b) if matches!(*b, C(_)) => *r,
            B(Op::Div, a, r) if matches!(*a, C(_)) => U(Op::Inverse, r),
            U(Op::Inverse, r) if matches!(&*r, B(Op::Pow, _, e) if matches!(**e, C(_))) => *r,
            U(Op::Inverse, r) if matches!(*r, U(Op::Inverse, _)) => match *r {
                U(_, inner) => *inner,
                other => other,
            },
            other => return other,
        };
    }
}

fn prefix(t: &Tree, out: &mut Vec<Token>) {
    match t {
        X => out.push(Token::Var),
        C(_) => out.push(Token::Const),
        U(op, a) => {
            out.push(Token::Op(*op));
            prefix(a, out);
        }
        B(op, a, b) => {
            out.push(Token::Op(*op));
            prefix(a, out);
            prefix(b, out);
        }
    }
}

fn tokens(t: Tree) -> Vec<Token> {
    let mut out = Vec::new();
    prefix(&strip(powers(t)), &mut out);
    out
}

/// The prefix tokens of a written expression whose names in `variables` are inputs and
/// every other name a fitted constant.
pub fn expr_tokens(expr: &Expr, variables: &[&str]) -> Vec<Token> {
    tokens(from_expr(expr, variables))
}

/// The prefix tokens of a search program (its nodes only: the output's scale and offset
/// and any affine input maps are parameters, not tokens), or `None` if the nodes are not
/// one well-formed expression.
pub fn program_tokens(program: &Program) -> Option<Vec<Token>> {
    from_program(program).map(tokens)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::infix::parse;

    fn names(text: &str, vars: &[&str]) -> String {
        let e = parse(text).unwrap().expr;
        let t: Vec<&str> = expr_tokens(&e, vars).iter().map(|t| t.name()).collect();
        t.join(" ")
    }

    /// Each rule of the module docs on one example.
    #[test]
    fn written_laws_become_the_search_form() {
        assert_eq!(names("C / v^(1/n)", &["v"]), "pow x c");
        assert_eq!(names("A*exp(-Ea/(R*T))", &["T"]), "exp div c mul c x");
        assert_eq!(names("Vmax*S/(Km + S)", &["S"]), "div mul c x add c x");
        assert_eq!(names("c*x + c", &["x"]), "x");
        assert_eq!(names("-x", &["x"]), "x");
        assert_eq!(names("y0 - a*exp(-k*t)", &["t"]), "exp mul c x");
        assert_eq!(names("k/(x + b)", &["x"]), "inverse add x c");
        assert_eq!(names("sqrt(2*g*h)", &["h"]), "sqrt mul c x");
        assert_eq!(
            names("x^0.5 + x^(-1/2) + x^-1", &["x"]),
            "add add sqrt x inverse sqrt x inverse x"
        );
        assert_eq!(
            names("R1*Q10^((T - T1)/10)", &["T"]),
            "exp mul c div sub x c c"
        );
        assert_eq!(names("exp(b*log(x))", &["x"]), "pow x c");
        assert_eq!(names("log(x)/log(10)", &["x"]), "log x");
        assert_eq!(names("a*x^3*y", &["x", "y"]), "mul mul c pow x c x");
    }
}
