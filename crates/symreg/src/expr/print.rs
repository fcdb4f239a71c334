//! Printing an [`Expr`]: plain text, sympy-parseable text and LaTeX, numbers and names.

use super::Expr;
use super::simplify::{half_pi_multiple, named_constant, small_fraction};
use crate::ops::Op;

impl Expr {
    pub(super) fn prec(&self) -> u8 {
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
    pub(super) fn leads_with_minus(&self) -> bool {
        matches!(self, Expr::Neg(_)) || matches!(self, Expr::Num(v) if *v < 0.0)
    }

    /// The expression with its leading minus sign taken off (`-0.5*x` gives `0.5*x`), or
    /// `None` if its printed form does not start with one. The printers use it to write
    /// `a - 0.5*x` for `a + (-0.5*x)`, and `a + 0.5*x` for `a - (-0.5*x)`.
    pub(super) fn without_minus(&self) -> Option<Expr> {
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
            Expr::Num(v)
                if fractions && (small_fraction(*v).is_some() || named_constant(*v).is_some()) =>
            {
                2
            }
            e => e.prec(),
        }
    }

    /// Plain-text form with `digits` significant digits (`None` for full precision).
    ///
    /// The full-precision sympy form (`digits` `None`, `sympy` true) writes a constant that
    /// is exactly a small fraction as one (`1/3*x`, `x**(1/2)`: denominators up to 12, the
    /// smallest that fits), and one that is exactly a named irrational by its name
    /// (`sqrt(2)/2*x`, `1/sqrt(2*pi)`; see `named_constants`).
    pub fn to_text(&self, digits: Option<usize>, sympy: bool) -> String {
        let fractions = sympy && digits.is_none();
        let fmt_num = |v: f64| match (small_fraction(v), named_constant(v)) {
            (Some((p, q)), _) if fractions => format!("{p}/{q}"),
            (_, Some(name)) if fractions => name,
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
                } else if is_identifier(n) {
                    n.clone()
                } else {
                    // a column such as `v [m/min]` or `insul=After` is written as the infix
                    // parser reads it back
                    format!("`{n}`")
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
pub(super) fn signed_right(op: Op, b: &Expr) -> (&'static str, std::borrow::Cow<'_, Expr>, u8) {
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

/// Whether `n` is a bare name of the infix syntax (a letter or `_`, then letters, digits
/// and `_`, as its lexer reads names).
fn is_identifier(n: &str) -> bool {
    let mut c = n.chars();
    c.next().is_some_and(|f| f.is_alphabetic() || f == '_')
        && c.all(|ch| ch.is_alphanumeric() || ch == '_')
}

/// `text` (sympy text by [`sympy_symbol`]) for a reader: every `Symbol('name')` written as
/// its name (`Symbol('E')*x` -> `E*x`), so a column named like a sympy constant (`E`, `I`,
/// `S`, `N`, `Q`) reads by its name in reports and summaries. The sympy text itself keeps
/// the `Symbol` form, which sympy needs. A malformed `Symbol(` is left as it is.
///
/// ```
/// use hxai_symreg::expr::readable_names;
/// assert_eq!(readable_names("2*Symbol('E')*Symbol('Q') + x"), "2*E*Q + x");
/// assert_eq!(readable_names("Symbol('\\u03bcm')"), "\u{3bc}m");
/// ```
pub fn readable_names(text: &str) -> String {
    const OPEN: &str = "Symbol('";
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(OPEN) {
        out.push_str(&rest[..at]);
        let after = &rest[at + OPEN.len()..];
        match symbol_name(after) {
            Some((name, used)) => {
                out.push_str(&name);
                rest = &after[used..];
            }
            None => {
                out.push_str(OPEN);
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// The name of a `Symbol('...')` whose text after the opening quote is `s`, and the bytes
/// of `s` up to and including the closing `')`.
fn symbol_name(s: &str) -> Option<(String, usize)> {
    let mut name = String::new();
    let mut chars = s.char_indices();
    while let Some((i, c)) = chars.next() {
        match c {
            '\'' => return s[i..].starts_with("')").then_some((name, i + 2)),
            '\\' => match chars.next()?.1 {
                '\\' => name.push('\\'),
                '\'' => name.push('\''),
                u @ ('u' | 'U') => {
                    let n = if u == 'u' { 4 } else { 8 };
                    let hex: String = (0..n)
                        .filter_map(|_| chars.next().map(|(_, h)| h))
                        .collect();
                    name.push(char::from_u32(u32::from_str_radix(&hex, 16).ok()?)?);
                }
                _ => return None,
            },
            c => name.push(c),
        }
    }
    None
}
