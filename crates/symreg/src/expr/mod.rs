//! Expression trees for reporting: built from a program and its parameters, simplified, and
//! printed as plain text, sympy-parseable text or LaTeX.
//!
//! Files by job: this file the tree and its building and evaluation, `simplify.rs` the
//! value-preserving simplification (with the recognition of pi/2 multiples and small
//! fractions), `print.rs` the text, sympy and LaTeX forms and the name rules.

mod mathml;
mod print;
mod simplify;

pub use mathml::xml_escape;
pub use print::{SYMPY_RESERVED, fmt_number, readable_names, sanitize, sympy_symbol};
pub(crate) use simplify::{MAX_HALF_PI_MULTIPLE, named_constants};

use crate::ops::Op;
use crate::program::{Node, Program};

/// A reporting expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A number.
    Num(f64),
    /// A named input.
    Var(String),
    /// Negation.
    Neg(Box<Expr>),
    /// A unary operator.
    Un(Op, Box<Expr>),
    /// A binary operator.
    Bin(Op, Box<Expr>, Box<Expr>),
}

impl Expr {
    /// Builds the full expression `scale * root + offset` of a program.
    pub fn from_program(prog: &Program, params: &[f64], names: &[String]) -> Expr {
        Self::from_program_with_symbols(prog, params, names, &[])
    }

    /// [`Expr::from_program`] with some parameters written as named symbols instead of
    /// numbers: parameter `i` becomes [`Expr::Var`]`(symbols[i])` where that is `Some`
    /// (indices past the end of `symbols` stay numbers). The template of a model's
    /// constants ([`crate::uncertainty`]) is built this way, so substituting the values
    /// gives back the expression of [`Expr::from_program`] (up to the folding of numbers,
    /// which only the numeric form can do).
    pub fn from_program_with_symbols(
        prog: &Program,
        params: &[f64],
        names: &[String],
        symbols: &[Option<String>],
    ) -> Expr {
        let num = |i: usize| match symbols.get(i) {
            Some(Some(name)) => Expr::Var(name.clone()),
            _ => Expr::Num(params[i]),
        };
        let offs = prog.param_offsets();
        let mut stack: Vec<Expr> = Vec::new();
        for (k, n) in prog.nodes.iter().enumerate() {
            let e = match n {
                Node::Var(j) => {
                    let name = names
                        .get(*j as usize)
                        .cloned()
                        .unwrap_or_else(|| format!("x{j}"));
                    if prog.affine {
                        let w = num(offs[k]);
                        let b = num(offs[k] + 1);
                        Expr::Bin(
                            Op::Add,
                            Box::new(Expr::Bin(Op::Mul, Box::new(w), Box::new(Expr::Var(name)))),
                            Box::new(b),
                        )
                    } else {
                        Expr::Var(name)
                    }
                }
                Node::Const => num(offs[k]),
                Node::Op(op) => {
                    if op.arity() == 2 {
                        let b = stack.pop().unwrap_or(Expr::Num(f64::NAN));
                        let a = stack.pop().unwrap_or(Expr::Num(f64::NAN));
                        Expr::Bin(*op, Box::new(a), Box::new(b))
                    } else {
                        let a = stack.pop().unwrap_or(Expr::Num(f64::NAN));
                        Expr::Un(*op, Box::new(a))
                    }
                }
            };
            stack.push(e);
        }
        let root = stack.pop().unwrap_or(Expr::Num(f64::NAN));
        Expr::Bin(
            Op::Add,
            Box::new(Expr::Bin(Op::Mul, Box::new(num(0)), Box::new(root))),
            Box::new(num(1)),
        )
        .simplify()
    }

    /// Evaluates the expression with variables looked up by `lookup`.
    pub fn eval(&self, lookup: &dyn Fn(&str) -> f64) -> f64 {
        match self {
            Expr::Num(v) => *v,
            Expr::Var(n) => lookup(n),
            Expr::Neg(a) => -a.eval(lookup),
            Expr::Un(op, a) => op.apply1(a.eval(lookup)),
            Expr::Bin(op, a, b) => op.apply2(a.eval(lookup), b.eval(lookup)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::simplify::small_fraction;
    use super::*;

    fn var(n: &str) -> Box<Expr> {
        Box::new(Expr::Var(n.into()))
    }

    /// A negated right operand must keep its sign visibly attached: `x*(-y)` is a product,
    /// while LaTeX's juxtaposition `x -y` would read as a difference.
    #[test]
    fn negated_right_operands_are_parenthesised() {
        let e = Expr::Bin(Op::Mul, var("x"), Box::new(Expr::Neg(var("y"))));
        assert_eq!(e.to_text(None, true), "x*(-y)");
        assert_eq!(e.to_latex(3), "x \\left(-y\\right)");
        // a - (-3) prints as the sum it is
        let e = Expr::Bin(Op::Sub, var("x"), Box::new(Expr::Num(-3.0)));
        assert_eq!(e.to_text(None, false), "x + 3");
        assert_eq!(e.to_latex(3), "x + 3");
    }

    /// A sum whose right term leads with a minus prints as a difference (`a - 0.5*y`, not
    /// `a + -0.5*y`), and a difference of such a term as a sum; the printed text means the
    /// same number as the tree.
    #[test]
    fn leading_minus_of_a_right_term_turns_the_sign() {
        let term = |c: f64| Box::new(Expr::Bin(Op::Mul, Box::new(Expr::Num(c)), var("y")));
        let e = Expr::Bin(Op::Add, var("x"), term(-0.5));
        assert_eq!(e.to_text(Some(3), true), "x - 0.5*y");
        assert_eq!(e.to_latex(3), "x - 0.5 y");
        let e = Expr::Bin(Op::Sub, var("x"), term(-0.5));
        assert_eq!(e.to_text(Some(3), true), "x + 0.5*y");
        // a quotient led by a negated sum keeps the sum in parentheses
        let sum = Expr::Bin(Op::Add, var("y"), Box::new(Expr::Num(1.0)));
        let q = Expr::Bin(Op::Div, Box::new(Expr::Neg(Box::new(sum))), var("z"));
        let e = Expr::Bin(Op::Add, var("x"), Box::new(q));
        assert_eq!(e.to_text(None, false), "x - (y + 1)/z");
        // positive terms print as before
        let e = Expr::Bin(Op::Add, var("x"), term(0.5));
        assert_eq!(e.to_text(Some(3), true), "x + 0.5*y");
        // the printed text parses back to the same value
        for e in [
            Expr::Bin(Op::Add, var("x"), term(-0.5)),
            Expr::Bin(Op::Sub, var("x"), term(-0.5)),
        ] {
            let back = crate::infix::parse(&e.to_text(None, false))
                .expect("parses")
                .expr;
            let at = |e: &Expr| e.eval(&|n: &str| if n == "x" { 0.7 } else { 1.9 });
            assert_eq!(at(&back), at(&e));
        }
    }

    /// A phase of a whole number of quarter turns turns sin into cos and back, and values
    /// that are exactly k pi/2 print with the symbol pi, so a recovered law reads as one
    /// (and survives rounding its printed constants).
    /// A constant that is exactly a named irrational prints by its name in the
    /// full-precision sympy text (so sympy reads it exactly and SRBench's 3-decimal rounding
    /// leaves it alone), with its sign; rounded forms and values off by one bit print as
    /// numbers.
    #[test]
    fn named_irrationals_print_by_name_in_sympy_text() {
        use std::f64::consts::PI;
        let sympy = |v: f64| Expr::Num(v).to_text(None, true);
        assert_eq!(sympy(1.0 / 2f64.sqrt()), "sqrt(2)/2");
        assert_eq!(sympy(-(3f64.sqrt())), "-sqrt(3)");
        assert_eq!(sympy(1.0 / (2.0 * PI).sqrt()), "1/sqrt(2*pi)");
        assert_eq!(sympy(1.0 / (4.0 * PI)), "1/(4*pi)");
        let x = Expr::Var("x".into());
        let prod = Expr::Bin(Op::Mul, Box::new(Expr::Num(1.0 / PI)), Box::new(x));
        assert_eq!(prod.to_text(None, true), "1/pi*x");
        assert_eq!(
            Expr::Num(1.0 / 2f64.sqrt()).to_text(Some(4), true),
            "0.7071"
        );
        let off = f64::from_bits((1.0 / 2f64.sqrt()).to_bits() + 1);
        assert!(sympy(off).starts_with("0.707"), "{}", sympy(off));
    }

    #[test]
    fn quarter_turn_phases_and_pi() {
        use std::f64::consts::{FRAC_PI_2, PI};
        let trig = |op: Op, u: Box<Expr>, c: f64| {
            Expr::Un(op, Box::new(Expr::Bin(Op::Add, u, Box::new(Expr::Num(c))))).simplify()
        };
        let xy = || Box::new(Expr::Bin(Op::Mul, var("x"), var("y")));
        let two_x = || Box::new(Expr::Bin(Op::Mul, Box::new(Expr::Num(2.0)), var("x")));
        let cases = [
            (trig(Op::Sin, var("x"), -FRAC_PI_2), "-cos(x)"),
            (trig(Op::Cos, var("x"), -FRAC_PI_2), "sin(x)"),
            (trig(Op::Cos, xy(), -PI), "-cos(x*y)"),
            (trig(Op::Sin, two_x(), -PI), "-sin(2*x)"),
            (trig(Op::Sin, var("x"), 7.0 * FRAC_PI_2), "-cos(x)"),
            (trig(Op::Cos, var("x"), 2.0 * PI), "cos(x)"),
            // one unit in the last place off a fitted phase is still the phase
            (
                trig(Op::Sin, var("x"), f64::from_bits(FRAC_PI_2.to_bits() + 1)),
                "cos(x)",
            ),
            // a phase that is not a quarter turn stays
            (trig(Op::Sin, var("x"), FRAC_PI_2 + 1e-4), "sin(x + 1.571)"),
        ];
        for (e, text) in &cases {
            assert_eq!(e.to_text(Some(4), true), *text);
        }
        // the rewrite keeps the value (to rounding)
        let x: f64 = 0.37;
        for (c, want) in [(-FRAC_PI_2, -(x.cos())), (7.0 * FRAC_PI_2, -(x.cos()))] {
            let e = trig(Op::Sin, var("x"), c);
            assert!((e.eval(&|_| x) - want).abs() < 1e-15);
            assert!(((x + c).sin() - want).abs() < 1e-14);
        }
        // exact multiples print as pi, everything else as numbers
        let num = |v: f64| Expr::Num(v).to_text(Some(4), true);
        assert_eq!(num(PI), "pi");
        assert_eq!(num(-PI), "-pi");
        assert_eq!(num(FRAC_PI_2), "pi/2");
        assert_eq!(num(-FRAC_PI_2), "-pi/2");
        assert_eq!(num(3.0 * FRAC_PI_2), "3*pi/2");
        assert_eq!(num(2.0 * PI), "2*pi");
        assert_eq!(num(PI + 1e-4), "3.142");
        assert_eq!(Expr::Num(-3.0 * FRAC_PI_2).to_latex(4), "-\\frac{3\\pi}{2}");
        assert_eq!(Expr::Num(PI).to_latex(4), "\\pi");
        // as an exponent or a right operand the product keeps its parentheses
        let pow = Expr::Bin(Op::Pow, var("x"), Box::new(Expr::Num(3.0 * FRAC_PI_2)));
        assert_eq!(pow.to_text(None, true), "x**(3*pi/2)");
        let sum = Expr::Bin(Op::Sub, var("x"), Box::new(Expr::Num(-FRAC_PI_2)));
        assert_eq!(sum.to_text(None, true), "x + pi/2");
        // and the text parses back to the same value
        for e in [
            pow,
            sum,
            Expr::Bin(Op::Mul, var("x"), Box::new(Expr::Num(PI))),
        ] {
            let back = crate::infix::parse(&e.to_text(None, false))
                .expect("parses")
                .expr;
            assert_eq!(
                back.eval(&|_| 1.3),
                e.eval(&|_| 1.3),
                "{}",
                e.to_text(None, false)
            );
        }
    }

    /// Constants that are exactly small fractions (a snapped half, the inverse of a snapped
    /// 3) print as fractions in the full-precision sympy text, so sympy reads them as
    /// rationals, with the parentheses a quotient needs; the 4-digit and plain texts keep
    /// decimals, and every text evaluates to the same value.
    #[test]
    fn exact_fractions_print_as_quotients_in_sympy_text() {
        let third = 1.0 / 3.0;
        assert_eq!(small_fraction(third), Some((1, 3)));
        assert_eq!(small_fraction(-2.5), Some((-5, 2)));
        assert_eq!(small_fraction(0.75), Some((3, 4)));
        assert_eq!(small_fraction(5.0 / 12.0), Some((5, 12)));
        for v in [
            2.0,
            0.0,
            0.1 + 0.2,
            1.0 / 13.0,
            std::f64::consts::FRAC_1_SQRT_2,
            third + f64::EPSILON,
            f64::NAN,
            f64::INFINITY,
            2.5e6,
        ] {
            assert_eq!(small_fraction(v), None, "{v}");
        }
        let num = |v: f64| Box::new(Expr::Num(v));
        let cases = [
            (Expr::Num(third), "1/3"),
            (Expr::Num(-0.5), "-1/2"),
            (Expr::Bin(Op::Mul, num(third), var("x")), "1/3*x"),
            (Expr::Bin(Op::Div, var("x"), num(third)), "x/(1/3)"),
            (Expr::Bin(Op::Div, num(0.5), var("x")), "1/2/x"),
            (Expr::Bin(Op::Pow, var("x"), num(0.5)), "x**(1/2)"),
            (Expr::Un(Op::Square, num(1.5)), "(3/2)**2"),
            (Expr::Bin(Op::Sub, var("x"), num(-0.25)), "x + 1/4"),
            (Expr::Bin(Op::Add, var("x"), num(-0.25)), "x - 1/4"),
            (Expr::Bin(Op::Mul, var("x"), num(-0.5)), "x*(-1/2)"),
            (Expr::Neg(num(third)), "-(1/3)"),
            (
                Expr::Un(Op::Sin, Box::new(Expr::Bin(Op::Mul, num(0.5), var("x")))),
                "sin(1/2*x)",
            ),
        ];
        for (e, text) in &cases {
            assert_eq!(e.to_text(None, true), *text);
            let sympy = crate::infix::parse(text).expect("parses").expr;
            let plain = e.to_text(None, false);
            assert_ne!(plain, *text, "the plain text keeps decimals");
            let back = crate::infix::parse(&plain).expect("parses").expr;
            let at = |e: &Expr| e.eval(&|_| 1.7);
            assert!((at(&sympy) - at(e)).abs() <= 1e-15 * at(e).abs(), "{text}");
            assert_eq!(at(&back), at(e), "{plain}");
        }
        assert_eq!(Expr::Num(third).to_text(None, false), "0.3333333333333333");
        assert_eq!(Expr::Num(third).to_text(Some(4), true), "0.3333");
        assert_eq!(Expr::Num(0.5).to_latex(4), "0.5");
    }

    /// Two juxtaposed numbers would read as one: the product of 2 and 3 prints with `\cdot`.
    #[test]
    fn latex_products_of_numbers_use_cdot() {
        let e = Expr::Bin(Op::Mul, Box::new(Expr::Num(2.0)), Box::new(Expr::Num(3.0)));
        assert_eq!(e.to_latex(3), "2 \\cdot 3");
    }

    /// A number times a quotient of a number folds into one numerator: the search writes
    /// `4.8 * (1 / (f + 0.5))` (a snapped 1 over an input), which read `4.8*1/(f + 0.5)`.
    #[test]
    fn a_number_times_a_numeric_quotient_is_one_quotient() {
        let q = |num: f64, den: Box<Expr>| Expr::Bin(Op::Div, Box::new(Expr::Num(num)), den);
        let sum = Box::new(Expr::Bin(Op::Add, var("f"), Box::new(Expr::Num(0.5))));
        let e = Expr::Bin(
            Op::Mul,
            Box::new(Expr::Num(4.8)),
            Box::new(q(1.0, sum.clone())),
        );
        let s = e.clone().simplify();
        assert_eq!(s.to_text(Some(4), true), "4.8/(f + 0.5)");
        let e2 = Expr::Bin(Op::Mul, Box::new(q(2.0, sum)), Box::new(Expr::Num(3.4)));
        assert_eq!(
            e2.clone().simplify().to_text(Some(4), true),
            "6.8/(f + 0.5)"
        );
        for x in [0.1, 0.4, 3.0] {
            let at = |e: &Expr| e.eval(&|_: &str| x);
            assert!((at(&s) - at(&e)).abs() <= 1e-15 * at(&e).abs());
            assert!((at(&e2.clone().simplify()) - at(&e2)).abs() <= 1e-15 * at(&e2).abs());
        }
    }

    /// A snapped exponent of 1 or -1 reads as the column or its reciprocal: `v**1` is `v`,
    /// `f**2*r**(-1)` is `f**2/r`, and the value is unchanged.
    #[test]
    fn unit_exponents_read_as_the_column_or_its_reciprocal() {
        let num = |v: f64| Box::new(Expr::Num(v));
        let pow = |name: &str, p: f64| Box::new(Expr::Bin(Op::Pow, var(name), num(p)));
        let e = Expr::Bin(Op::Mul, num(2e-4), pow("v", 1.0)).simplify();
        assert_eq!(e.to_text(None, false), "0.0002*v");
        let f2r = Expr::Bin(
            Op::Mul,
            Box::new(Expr::Bin(Op::Mul, num(-0.36), pow("f", 2.0))),
            pow("r", -1.0),
        );
        let s = f2r.clone().simplify();
        assert_eq!(s.to_text(None, false), "-0.36*f**2/r");
        let at = |e: &Expr| e.eval(&|n: &str| if n == "f" { 0.2 } else { 1.3 });
        assert!((at(&s) - at(&f2r)).abs() <= 1e-15 * at(&f2r).abs());
        // a product with an inverse reads as a quotient
        let inv = Expr::Bin(
            Op::Mul,
            num(-9.0),
            Box::new(Expr::Un(
                Op::Inverse,
                Box::new(Expr::Bin(Op::Add, var("c"), num(4.0))),
            )),
        );
        let q = inv.clone().simplify();
        assert_eq!(q.to_text(None, false), "-9/(c + 4)");
        assert!((at(&q) - at(&inv)).abs() <= 1e-15 * at(&inv).abs());
    }

    /// log(exp(u)) is u and log(gaussian(u)) is -u^2, so reported equations do not carry
    /// the pair (it appeared in a selected delta model).
    #[test]
    fn log_of_exp_and_gaussian_simplify() {
        let u = || Box::new(Expr::Bin(Op::Mul, Box::new(Expr::Num(2.0)), var("x")));
        let e = Expr::Un(Op::Log, Box::new(Expr::Un(Op::Exp, u()))).simplify();
        assert_eq!(e.to_text(None, false), "2*x");
        let e = Expr::Un(Op::Log, Box::new(Expr::Un(Op::Gaussian, u()))).simplify();
        let at = |e: &Expr, x: f64| e.eval(&|_: &str| x);
        assert_eq!(at(&e, 0.7), -(1.4f64 * 1.4));
        assert!(!e.to_text(None, false).contains("log"));
        // and the square of that negation loses the sign
        let sq = Expr::Un(Op::Square, Box::new(e)).simplify();
        assert_eq!(sq.to_text(Some(3), true), "((2*x)**2)**2");
        assert_eq!(sq.to_latex(3), "\\left(\\left(2 x\\right)^{2}\\right)^{2}");
        assert_eq!(at(&sq, 0.7), (1.4f64 * 1.4) * (1.4 * 1.4));
        let g = Expr::Bin(Op::Gaussian2, Box::new(Expr::Num(1.0)), var("x")).simplify();
        assert_eq!(g.to_text(Some(4), true), "0.3679*exp(-x**2)");
        let g = Expr::Bin(Op::Gaussian2, Box::new(Expr::Num(0.0)), var("x")).simplify();
        assert_eq!(g.to_text(Some(4), true), "exp(-x**2)");
        let g = Expr::Bin(Op::Gaussian2, var("y"), Box::new(Expr::Neg(var("x")))).simplify();
        assert!(
            !g.to_text(None, false).contains("-x"),
            "{}",
            g.to_text(None, false)
        );
    }
}

#[cfg(test)]
mod power_law_tests {
    use super::*;

    fn num(v: f64) -> Box<Expr> {
        Box::new(Expr::Num(v))
    }

    // exp(a log(u) + b) prints as the power law e^b u^a, and keeps its values where u > 0
    #[test]
    fn an_exponential_of_a_scaled_log_prints_as_a_power() {
        let u = Expr::Bin(
            Op::Add,
            Box::new(Expr::Bin(
                Op::Mul,
                num(2.0),
                Box::new(Expr::Var("f".into())),
            )),
            num(1.0),
        );
        let arg = Expr::Bin(
            Op::Add,
            Box::new(Expr::Bin(
                Op::Mul,
                num(-0.5),
                Box::new(Expr::Un(Op::Log, Box::new(u))),
            )),
            num(0.3),
        );
        let e = Expr::Un(Op::Exp, Box::new(arg));
        let s = e.clone().simplify();
        let text = s.to_text(None, true);
        assert!(!text.contains("exp") && text.contains("**"), "{text}");
        for f in [0.1, 0.7, 3.0] {
            let look = |_: &str| f;
            let (a, b) = (e.eval(&look), s.eval(&look));
            assert!((a - b).abs() <= 1e-12 * a.abs(), "{f}: {a} vs {b}");
        }
        // a plain log inside exp is the base itself
        let plain = Expr::Un(
            Op::Exp,
            Box::new(Expr::Un(Op::Log, Box::new(Expr::Var("f".into())))),
        );
        assert_eq!(plain.simplify().to_text(None, true), "f");
    }
}
