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

/// The largest multiple of pi/2 (in absolute value) that is recognised as one: phases up to
/// four half-turns either way.
pub(crate) const MAX_HALF_PI_MULTIPLE: f64 = 8.0;

/// `k` when `v` is `k * pi/2` for a whole `k` with `0 < |k| <= 8`, within `ulps` units in
/// the last place of `v`.
fn half_pi_within(v: f64, ulps: f64) -> Option<i64> {
    let k = (v / std::f64::consts::FRAC_PI_2).round();
    let exact = k * std::f64::consts::FRAC_PI_2;
    (k != 0.0
        && k.abs() <= MAX_HALF_PI_MULTIPLE
        && (exact - v).abs() <= ulps * f64::EPSILON * v.abs())
    .then_some(k as i64)
}

/// `k` when `v` is exactly (to the last bit) `k * pi/2` for a whole `k` with
/// `0 < |k| <= 8`. Such values come from snapping (see `snap_candidates`) or from a fit
/// that converged to the double nearest a phase; any other value is `None`.
pub(crate) fn half_pi_multiple(v: f64) -> Option<i64> {
    half_pi_within(v, 0.0)
}

/// The largest denominator [`small_fraction`] recognises.
const MAX_FRACTION_DENOMINATOR: i64 = 12;

/// `(p, q)` when `v` is exactly (to the last bit) the double nearest `p/q` for a whole `p`
/// and a denominator `2 <= q <= 12` (the smallest such `q`), with `|v| < 1e6`; integers and
/// every other value give `None`.
///
/// Such values come from exact arithmetic on snapped constants (a half, the inverse of a
/// snapped 3); a fitted constant lands on one by chance with probability about 1e-15. The
/// sympy text writes them as fractions (`1/3`, which sympy reads as a rational), so that a
/// law written with exact constants reads back as one: `0.3333333333333333` rounded to
/// `0.333` would not.
fn small_fraction(v: f64) -> Option<(i64, i64)> {
    if !v.is_finite() || v == v.round() || v.abs() >= 1e6 {
        return None;
    }
    (2..=MAX_FRACTION_DENOMINATOR).find_map(|q| {
        let p = (v * q as f64).round();
        (p / q as f64 == v).then_some((p as i64, q))
    })
}

/// `(u, k)` when `e` is `u + k pi/2` (or `u - k pi/2`, or `k pi/2 + u`) for a whole `k`,
/// with the phase a number within a few units in the last place of the multiple.
fn split_phase(e: &Expr) -> Option<(&Expr, i64)> {
    let num = |c: &Expr| match c {
        Expr::Num(v) => Some(*v),
        _ => None,
    };
    let (u, phase) = match e {
        Expr::Bin(Op::Add, a, b) => match (num(a), num(b)) {
            (_, Some(v)) => (&**a, v),
            (Some(v), None) => (&**b, v),
            (None, None) => return None,
        },
        Expr::Bin(Op::Sub, a, b) => (&**a, -num(b)?),
        _ => return None,
    };
    half_pi_within(phase, 4.0).map(|k| (u, k))
}

/// `sin(u + k pi/2)` or `cos(u + k pi/2)` written without the phase: `cos(u)`, `-sin(u)`, ...
fn shift_trig(op: Op, u: Expr, k: i64) -> Expr {
    // sin(u + q pi/2) for q = 0..3 is sin, cos, -sin, -cos of u; cos(u + q pi/2) is
    // sin(u + (q + 1) pi/2)
    let q = (k + i64::from(op == Op::Cos)).rem_euclid(4);
    let f = if q % 2 == 0 { Op::Sin } else { Op::Cos };
    let e = Expr::Un(f, Box::new(u));
    if q >= 2 { Expr::Neg(Box::new(e)) } else { e }
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
            Un(op, a) => {
                let a = a.simplify();
                // a phase of a whole number of quarter turns is a shift between sin and cos:
                // sin(u - pi/2) is -cos(u)
                if let (Op::Sin | Op::Cos, Some((u, k))) = (op, split_phase(&a)) {
                    return shift_trig(op, u.clone(), k).simplify();
                }
                match (op, a) {
                    (_, Num(v)) => Num(op.apply1(v)),
                    // log undoes exp wherever exp is finite (where it is not, neither is the
                    // model)
                    (Op::Log, Un(Op::Exp, x)) => *x,
                    (Op::Log, Un(Op::Gaussian, x)) => Neg(Box::new(Un(Op::Square, x))),
                    // even functions drop a sign
                    (Op::Square | Op::Abs | Op::Cos | Op::Gaussian, Neg(x)) => Un(op, x),
                    (_, x) => Un(op, Box::new(x)),
                }
            }
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
            // pi is an atom; 3*pi/2 is a product
            Expr::Num(v) if half_pi_multiple(*v).is_some_and(|k| k != 2) => 2,
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

    /// The expression with its leading minus sign taken off (`-0.5*x` gives `0.5*x`), or
    /// `None` if its printed form does not start with one. The printers use it to write
    /// `a - 0.5*x` for `a + (-0.5*x)`, and `a + 0.5*x` for `a - (-0.5*x)`.
    fn without_minus(&self) -> Option<Expr> {
        match self {
            Expr::Num(v) if *v < 0.0 => Some(Expr::Num(-v)),
            Expr::Neg(a) => Some((**a).clone()),
            Expr::Bin(op @ (Op::Mul | Op::Div), a, b) => a
                .without_minus()
                .map(|a| Expr::Bin(*op, Box::new(a), b.clone())),
            _ => None,
        }
    }

    /// [`Expr::prec`] in text, where the full-precision sympy form writes exact fractions as
    /// quotients (`1/3`), which bind like a division.
    fn text_prec(&self, fractions: bool) -> u8 {
        match self {
            Expr::Num(v) if fractions && small_fraction(*v).is_some() => 2,
            e => e.prec(),
        }
    }

    /// Plain-text form with `digits` significant digits (`None` for full precision).
    ///
    /// The full-precision sympy form (`digits` `None`, `sympy` true) writes a constant that
    /// is exactly a small fraction as one (`1/3*x`, `x**(1/2)`: denominators up to 12, the
    /// smallest that fits).
    pub fn to_text(&self, digits: Option<usize>, sympy: bool) -> String {
        let fractions = sympy && digits.is_none();
        let fmt_num = |v: f64| match small_fraction(v) {
            Some((p, q)) if fractions => format!("{p}/{q}"),
            _ => fmt_number(v, digits),
        };
        let wrap = |e: &Expr, min: u8| {
            let s = e.to_text(digits, sympy);
            if e.text_prec(fractions) < min {
                format!("({s})")
            } else {
                s
            }
        };
        let wrap_right = |e: &Expr, min: u8| {
            if e.leads_with_minus() {
                format!("({})", e.to_text(digits, sympy))
            } else {
                wrap(e, min)
            }
        };
        match self {
            Expr::Num(v) => half_pi_multiple(*v).map_or_else(|| fmt_num(*v), pi_text),
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
                Op::Add | Op::Sub => {
                    let (sign, right, min) = signed_right(*op, b);
                    format!("{} {sign} {}", wrap(a, 1), wrap_right(&right, min))
                }
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
            Expr::Num(v) => match half_pi_multiple(*v) {
                Some(k) => pi_latex(k),
                None => {
                    let s = fmt_number(*v, Some(digits));
                    match s.split_once('e') {
                        Some((m, e)) => {
                            format!("{m} \\cdot 10^{{{}}}", e.trim_start_matches('+'))
                        }
                        None => s,
                    }
                }
            },
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
                Op::Add | Op::Sub => {
                    let (sign, right, min) = signed_right(*op, b);
                    format!("{} {sign} {}", wrap(a, 1), wrap_right(&right, min))
                }
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

/// The sign and right operand a sum or difference `a op b` prints with, and the precedence
/// the operand needs: a right term that leads with a minus turns the sign (`a - 0.5*x` for
/// `a + (-0.5*x)`); a subtracted sum needs parentheses, an added one does not.
fn signed_right(op: Op, b: &Expr) -> (&'static str, std::borrow::Cow<'_, Expr>, u8) {
    use std::borrow::Cow;
    match (b.without_minus(), op == Op::Add) {
        (Some(p), true) => ("-", Cow::Owned(p), 2),
        (Some(p), false) => ("+", Cow::Owned(p), 1),
        (None, true) => ("+", Cow::Borrowed(b), 1),
        (None, false) => ("-", Cow::Borrowed(b), 2),
    }
}

/// `k pi/2` in plain or sympy text: `pi`, `-pi`, `2*pi`, `pi/2`, `-pi/2`, `3*pi/2`, ...
fn pi_text(k: i64) -> String {
    match (k % 2 == 0, k) {
        (true, 2) => "pi".into(),
        (true, -2) => "-pi".into(),
        (true, _) => format!("{}*pi", k / 2),
        (false, 1) => "pi/2".into(),
        (false, -1) => "-pi/2".into(),
        (false, _) => format!("{k}*pi/2"),
    }
}

/// `k pi/2` in LaTeX: `\pi`, `-\pi`, `2 \pi`, `\frac{\pi}{2}`, `-\frac{3\pi}{2}`, ...
fn pi_latex(k: i64) -> String {
    let sign = if k < 0 { "-" } else { "" };
    let a = k.abs();
    match (a % 2 == 0, a) {
        (true, 2) => format!("{sign}\\pi"),
        (true, _) => format!("{sign}{} \\pi", a / 2),
        (false, 1) => format!("{sign}\\frac{{\\pi}}{{2}}"),
        (false, _) => format!("{sign}\\frac{{{a}\\pi}}{{2}}"),
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
