//! Expression trees for reporting: built from a program and its parameters, simplified, and
//! printed as plain text, sympy-parseable text or LaTeX.
use crate::ops::Op;
use crate::program::{Node, Program};
use crate::vmath;

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

fn add_num(e: Expr, x: f64) -> Expr {
    if x < 0.0 {
        Expr::Bin(Op::Sub, Box::new(e), Box::new(Expr::Num(-x)))
    } else {
        Expr::Bin(Op::Add, Box::new(e), Box::new(Expr::Num(x)))
    }
}

fn num(v: f64) -> Expr {
    Expr::Num(v)
}

impl Expr {
    /// Builds the full expression `scale * root + offset` of a program.
    pub fn from_program(prog: &Program, params: &[f64], names: &[String]) -> Expr {
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
                        let w = params[offs[k]];
                        let b = params[offs[k] + 1];
                        Expr::Bin(
                            Op::Add,
                            Box::new(Expr::Bin(
                                Op::Mul,
                                Box::new(num(w)),
                                Box::new(Expr::Var(name)),
                            )),
                            Box::new(num(b)),
                        )
                    } else {
                        Expr::Var(name)
                    }
                }
                Node::Const => num(params[offs[k]]),
                Node::Op(op) => {
                    if op.arity() == 2 {
                        let b = stack.pop().unwrap_or(num(f64::NAN));
                        let a = stack.pop().unwrap_or(num(f64::NAN));
                        Expr::Bin(*op, Box::new(a), Box::new(b))
                    } else {
                        let a = stack.pop().unwrap_or(num(f64::NAN));
                        Expr::Un(*op, Box::new(a))
                    }
                }
            };
            stack.push(e);
        }
        let root = stack.pop().unwrap_or(num(f64::NAN));
        Expr::Bin(
            Op::Add,
            Box::new(Expr::Bin(Op::Mul, Box::new(num(params[0])), Box::new(root))),
            Box::new(num(params[1])),
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

    /// Value-preserving simplification (for finite values): folds constants, drops `*1`,
    /// `+0`, `0*x`, merges nested numeric factors and offsets, turns `x + (-c)` into `x - c`.
    pub fn simplify(self) -> Expr {
        use Expr::*;
        match self {
            Neg(a) => match a.simplify() {
                Num(v) => Num(-v),
                Neg(x) => *x,
                x => Neg(Box::new(x)),
            },
            Un(op, a) => match (op, a.simplify()) {
                (_, Num(v)) => Num(op.apply1(v)),
                // log undoes exp wherever exp is finite (where it is not, neither is the model)
                (Op::Log, Un(Op::Exp, x)) => *x,
                (Op::Log, Un(Op::Gaussian, x)) => Neg(Box::new(Un(Op::Square, x))),
                // even functions drop a sign
                (Op::Square | Op::Abs | Op::Cos | Op::Gaussian, Neg(x)) => Un(op, x),
                (_, x) => Un(op, Box::new(x)),
            },
            Bin(op, a, b) => {
                let a = a.simplify();
                let b = b.simplify();
                match (op, a, b) {
                    (_, Num(x), Num(y)) => Num(op.apply2(x, y)),
                    // gaussian2 with a constant argument c is exp(-c^2) gaussian(other)
                    (Op::Gaussian2, Num(c), y) | (Op::Gaussian2, y, Num(c)) => Bin(
                        Op::Mul,
                        Box::new(Num(vmath::exp(-c * c))),
                        Box::new(Un(Op::Gaussian, Box::new(y))),
                    )
                    .simplify(),
                    // gaussian2 squares both arguments: their signs do not matter
                    (Op::Gaussian2, Neg(x), y) => Bin(op, x, Box::new(y)).simplify(),
                    (Op::Gaussian2, x, Neg(y)) => Bin(op, Box::new(x), y),
                    (Op::Mul, Num(x), e) | (Op::Mul, e, Num(x)) => {
                        if x == 1.0 {
                            e
                        } else if x == 0.0 {
                            Num(0.0)
                        } else if x == -1.0 {
                            Neg(Box::new(e)).simplify()
                        } else {
                            match e {
                                Bin(Op::Mul, inner_a, inner_b) => match *inner_a {
                                    Num(y) => {
                                        Bin(Op::Mul, Box::new(Num(x * y)), inner_b).simplify()
                                    }
                                    other => Bin(
                                        Op::Mul,
                                        Box::new(Num(x)),
                                        Box::new(Bin(Op::Mul, Box::new(other), inner_b)),
                                    ),
                                },
                                Neg(inner) => Bin(Op::Mul, Box::new(Num(-x)), inner),
                                e => Bin(Op::Mul, Box::new(Num(x)), Box::new(e)),
                            }
                        }
                    }
                    (Op::Add, Num(x), e) | (Op::Add, e, Num(x)) => {
                        if x == 0.0 {
                            e
                        } else {
                            match e {
                                Bin(Op::Add, ia, ib) => match *ib {
                                    Num(y) => Bin(Op::Add, ia, Box::new(Num(x + y))).simplify(),
                                    other => add_num(Bin(Op::Add, ia, Box::new(other)), x),
                                },
                                Bin(Op::Sub, ia, ib) => match *ib {
                                    Num(y) => Bin(Op::Add, ia, Box::new(Num(x - y))).simplify(),
                                    other => add_num(Bin(Op::Sub, ia, Box::new(other)), x),
                                },
                                e => add_num(e, x),
                            }
                        }
                    }
                    // pull signs out of products and quotients: -a * b is -(a * b)
                    (Op::Mul | Op::Div, Neg(x), y) => {
                        Neg(Box::new(Bin(op, x, Box::new(y)).simplify())).simplify()
                    }
                    (Op::Mul | Op::Div, x, Neg(y)) => {
                        Neg(Box::new(Bin(op, Box::new(x), y).simplify())).simplify()
                    }
                    // pull numeric factors out of products and quotients
                    (Op::Mul, Bin(Op::Mul, pa, x), y) if matches!(*pa, Num(_)) => Bin(
                        Op::Mul,
                        pa,
                        Box::new(Bin(Op::Mul, x, Box::new(y)).simplify()),
                    )
                    .simplify(),
                    (Op::Mul, x, Bin(Op::Mul, pb, y)) if matches!(*pb, Num(_)) => Bin(
                        Op::Mul,
                        pb,
                        Box::new(Bin(Op::Mul, Box::new(x), y).simplify()),
                    )
                    .simplify(),
                    (Op::Div, Bin(Op::Mul, pa, x), y) if matches!(*pa, Num(_)) => Bin(
                        Op::Mul,
                        pa,
                        Box::new(Bin(Op::Div, x, Box::new(y)).simplify()),
                    )
                    .simplify(),
                    (Op::Div, x, Bin(Op::Mul, pb, y)) if matches!(*pb, Num(_)) => match *pb {
                        Num(q) => Bin(
                            Op::Mul,
                            Box::new(Num(1.0 / q)),
                            Box::new(Bin(Op::Div, Box::new(x), y).simplify()),
                        )
                        .simplify(),
                        other => Bin(
                            Op::Div,
                            Box::new(x),
                            Box::new(Bin(Op::Mul, Box::new(other), y)),
                        ),
                    },
                    (Op::Sub, e, Num(x)) => Bin(Op::Add, Box::new(e), Box::new(Num(-x))).simplify(),
                    (Op::Sub, Num(0.0), e) => Neg(Box::new(e)).simplify(),
                    (Op::Div, e, Num(1.0)) => e,
                    (Op::Add, a, Neg(b)) => Bin(Op::Sub, Box::new(a), b),
                    (Op::Sub, a, Neg(b)) => Bin(Op::Add, Box::new(a), b),
                    (op, a, b) => Bin(op, Box::new(a), Box::new(b)),
                }
            }
            e => e,
        }
    }

    fn prec(&self) -> u8 {
        match self {
            Expr::Num(v) if *v < 0.0 => 2,
            // a power binds less tightly than an atom: (x**2)**2, not x**2**2 (which Python
            // reads as x**(2**2))
            Expr::Un(Op::Square, _) | Expr::Bin(Op::Pow, ..) => 8,
            Expr::Num(_) | Expr::Var(_) | Expr::Un(..) => 9,
            Expr::Bin(Op::Gaussian2, ..) => 9,
            Expr::Neg(_) => 3,
            Expr::Bin(Op::Add | Op::Sub, ..) => 1,
            Expr::Bin(..) => 2,
        }
    }

    /// Whether the printed form starts with a minus sign, so it needs parentheses as the
    /// right operand of a binary operator (`a*(-b)`, `a - (-3)`).
    fn leads_with_minus(&self) -> bool {
        matches!(self, Expr::Neg(_)) || matches!(self, Expr::Num(v) if *v < 0.0)
    }

    /// Plain-text form with `digits` significant digits (`None` for full precision).
    pub fn to_text(&self, digits: Option<usize>, sympy: bool) -> String {
        let fmt_num = |v: f64| fmt_number(v, digits);
        let wrap = |e: &Expr, min: u8| {
            let s = e.to_text(digits, sympy);
            if e.prec() < min { format!("({s})") } else { s }
        };
        let wrap_right = |e: &Expr, min: u8| {
            if e.leads_with_minus() {
                format!("({})", e.to_text(digits, sympy))
            } else {
                wrap(e, min)
            }
        };
        match self {
            Expr::Num(v) => fmt_num(*v),
            Expr::Var(n) => {
                if sympy {
                    sympy_symbol(n)
                } else {
                    n.clone()
                }
            }
            Expr::Neg(a) => format!("-{}", wrap(a, 3)),
            Expr::Un(op, a) => {
                let s = a.to_text(digits, sympy);
                match op {
                    Op::Square => format!("{}**2", wrap(a, 9)),
                    Op::Inverse => format!("1/{}", wrap(a, 4)),
                    Op::Abs => {
                        if sympy {
                            format!("Abs({s})")
                        } else {
                            format!("abs({s})")
                        }
                    }
                    Op::Gaussian => format!("exp(-{}**2)", wrap(a, 9)),
                    _ => format!("{}({s})", op.name()),
                }
            }
            Expr::Bin(op, a, b) => match op {
                Op::Add => format!("{} + {}", wrap(a, 1), wrap_right(b, 1)),
                Op::Sub => format!("{} - {}", wrap(a, 1), wrap_right(b, 2)),
                Op::Mul => format!("{}*{}", wrap(a, 2), wrap_right(b, 2)),
                Op::Div => format!("{}/{}", wrap(a, 2), wrap_right(b, 3)),
                Op::Gaussian2 => format!("exp(-({}**2 + {}**2))", wrap(a, 9), wrap(b, 9)),
                Op::Pow => format!("{}**{}", wrap(a, 9), wrap(b, 9)),
                _ => format!(
                    "{}({}, {})",
                    op.name(),
                    a.to_text(digits, sympy),
                    b.to_text(digits, sympy)
                ),
            },
        }
    }

    /// LaTeX form with `digits` significant digits.
    pub fn to_latex(&self, digits: usize) -> String {
        let wrap = |e: &Expr, min: u8| {
            let s = e.to_latex(digits);
            if e.prec() < min {
                format!("\\left({s}\\right)")
            } else {
                s
            }
        };
        let wrap_right = |e: &Expr, min: u8| {
            if e.leads_with_minus() {
                format!("\\left({}\\right)", e.to_latex(digits))
            } else {
                wrap(e, min)
            }
        };
        match self {
            Expr::Num(v) => {
                let s = fmt_number(*v, Some(digits));
                match s.split_once('e') {
                    Some((m, e)) => format!("{m} \\cdot 10^{{{}}}", e.trim_start_matches('+')),
                    None => s,
                }
            }
            Expr::Var(n) => latex_name(n),
            Expr::Neg(a) => format!("-{}", wrap(a, 3)),
            Expr::Un(op, a) => {
                let s = a.to_latex(digits);
                match op {
                    Op::Square => format!("{}^{{2}}", wrap(a, 9)),
                    Op::Inverse => format!("\\frac{{1}}{{{s}}}"),
                    Op::Abs => format!("\\left|{s}\\right|"),
                    Op::Sqrt => format!("\\sqrt{{{s}}}"),
                    Op::Exp => format!("e^{{{s}}}"),
                    Op::Gaussian => format!("e^{{-{}^{{2}}}}", wrap(a, 9)),
                    Op::Log => format!("\\log\\left({s}\\right)"),
                    Op::Sin => format!("\\sin\\left({s}\\right)"),
                    Op::Cos => format!("\\cos\\left({s}\\right)"),
                    Op::Tanh => format!("\\tanh\\left({s}\\right)"),
                    Op::Tan => format!("\\tan\\left({s}\\right)"),
                    _ => format!("\\operatorname{{{}}}\\left({s}\\right)", op.name()),
                }
            }
            Expr::Bin(op, a, b) => match op {
                Op::Add => format!("{} + {}", wrap(a, 1), wrap_right(b, 1)),
                Op::Sub => format!("{} - {}", wrap(a, 1), wrap_right(b, 2)),
                Op::Mul => {
                    let (l, r) = (wrap(a, 2), wrap_right(b, 2));
                    // Juxtaposed digits would read as one number: "2 3" -> "2 \cdot 3".
                    if r.starts_with(|c: char| c.is_ascii_digit()) {
                        format!("{l} \\cdot {r}")
                    } else {
                        format!("{l} {r}")
                    }
                }
                Op::Div => format!("\\frac{{{}}}{{{}}}", a.to_latex(digits), b.to_latex(digits)),
                Op::Gaussian2 => format!(
                    "e^{{-\\left({}^{{2}} + {}^{{2}}\\right)}}",
                    wrap(a, 4),
                    wrap(b, 4)
                ),
                Op::Pow => format!("{}^{{{}}}", wrap(a, 9), b.to_latex(digits)),
                _ => format!(
                    "\\operatorname{{{}}}\\left({}, {}\\right)",
                    op.name(),
                    a.to_latex(digits),
                    b.to_latex(digits)
                ),
            },
        }
    }
}

/// Formats a number: integers without a decimal point, otherwise `digits` significant digits
/// (shortest round-trip representation when `digits` is `None`).
pub fn fmt_number(v: f64, digits: Option<usize>) -> String {
    if v.is_finite() && v == v.round() && v.abs() < 1e15 {
        return format!("{}", v as i64);
    }
    match digits {
        None => format!("{v:?}"),
        Some(d) => {
            let a = v.abs();
            if a != 0.0 && !(1e-4..1e6).contains(&a) {
                format!("{:.*e}", d.saturating_sub(1), v)
            } else {
                let mag = if a == 0.0 {
                    0
                } else {
                    a.log10().floor() as i32
                };
                let decimals = (d as i32 - 1 - mag).max(0) as usize;
                let s = format!("{v:.decimals$}");
                if s.contains('.') {
                    s.trim_end_matches('0').trim_end_matches('.').to_string()
                } else {
                    s
                }
            }
        }
    }
}

/// How a column name is written in sympy text so that `sympy.sympify` reads it back as
/// the symbol of exactly that name.
///
/// A plain ASCII identifier (a letter, then letters, digits and `_`) that sympy's parser
/// does not already know is written as it is (`f3`, `A_phys`). Anything else is written as
/// `Symbol('...')` with a Python string literal: names sympy would read as something else
/// (`E`, `I`, `pi`, `oo`, `N`, `S`, `Q`, `O`, `beta`, `gamma`, `lambda`, `re`, `sin`, Python
/// keywords and builtins; the list is [`SYMPY_RESERVED`]), names with spaces or
/// punctuation, and non-ASCII names (escaped as `\uXXXX`, so the text is ASCII and
/// unicode normalisation cannot merge two names). `a b` and `a_b` therefore stay two
/// symbols.
///
/// ```
/// use hxai_symreg::expr::sympy_symbol;
/// assert_eq!(sympy_symbol("f3"), "f3");
/// assert_eq!(sympy_symbol("E"), "Symbol('E')");
/// assert_eq!(sympy_symbol("a b"), "Symbol('a b')");
/// assert_eq!(sympy_symbol("it's"), "Symbol('it\\'s')");
/// assert_eq!(sympy_symbol("\u{3bc}m"), "Symbol('\\u03bcm')");
/// ```
pub fn sympy_symbol(name: &str) -> String {
    let mut chars = name.chars();
    let plain = chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && SYMPY_RESERVED.binary_search(&name).is_err();
    if plain {
        return name.to_owned();
    }
    let mut out = String::from("Symbol('");
    for c in name.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\'' => out.push_str("\\'"),
            ' '..='~' => out.push(c),
            c if (c as u32) <= 0xffff => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push_str(&format!("\\U{:08x}", c as u32)),
        }
    }
    out.push_str("')");
    out
}

pub use crate::sympy_names::SYMPY_RESERVED;

/// Turns a column name into a Python identifier (non-alphanumerics become `_`, a leading
/// digit gets a `_` prefix). Not injective (`a b` and `a_b` both give `a_b`) and not safe
/// for names sympy knows (`E`); the sympy export uses [`sympy_symbol`] instead.
pub fn sanitize(name: &str) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.chars().next().is_none_or(|c| c.is_ascii_digit()) {
        s.insert(0, '_');
    }
    s
}

fn latex_name(n: &str) -> String {
    // f12 -> f_{12}; other names in \mathrm with escaped underscores.
    let (head, tail): (String, String) = {
        let i = n.find(|c: char| c.is_ascii_digit()).unwrap_or(n.len());
        (n[..i].to_string(), n[i..].to_string())
    };
    if head.len() == 1 && !tail.is_empty() && tail.chars().all(|c| c.is_ascii_digit()) {
        format!("{head}_{{{tail}}}")
    } else if n.len() == 1 {
        n.to_string()
    } else {
        format!("\\mathrm{{{}}}", n.replace('_', "\\_"))
    }
}

#[cfg(test)]
mod tests {
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
        let e = Expr::Bin(Op::Sub, var("x"), Box::new(Expr::Num(-3.0)));
        assert_eq!(e.to_text(None, false), "x - (-3)");
    }

    /// Two juxtaposed numbers would read as one: the product of 2 and 3 prints with `\cdot`.
    #[test]
    fn latex_products_of_numbers_use_cdot() {
        let e = Expr::Bin(Op::Mul, Box::new(Expr::Num(2.0)), Box::new(Expr::Num(3.0)));
        assert_eq!(e.to_latex(3), "2 \\cdot 3");
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
