//! Printing an [`Expr`] as presentation MathML (`hxai report`, issue 50): what every current
//! browser renders without a script, so a report needs no network to show its equations.
//! The layout follows the LaTeX printer (the same parentheses, signs and fractions).

use super::Expr;
use super::print::{fmt_number, signed_right};
use super::simplify::half_pi_multiple;
use crate::ops::Op;

/// `s` with the characters XML gives a meaning to escaped.
pub fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

fn paren(inner: &str) -> String {
    format!("<mrow><mo>(</mo>{inner}<mo>)</mo></mrow>")
}

fn func(name: &str, arg: &str) -> String {
    format!(
        "<mrow><mi>{name}</mi><mo>&#x2061;</mo>{}</mrow>",
        paren(arg)
    )
}

/// A name: `f12` as `f` with subscript 12, others as one identifier.
fn name(n: &str) -> String {
    let i = n.find(|c: char| c.is_ascii_digit()).unwrap_or(n.len());
    let (head, tail) = (&n[..i], &n[i..]);
    if head.chars().count() == 1 && !tail.is_empty() && tail.chars().all(|c| c.is_ascii_digit()) {
        format!("<msub><mi>{}</mi><mn>{tail}</mn></msub>", xml_escape(head))
    } else if n.chars().count() == 1 {
        format!("<mi>{}</mi>", xml_escape(n))
    } else {
        format!("<mi mathvariant=\"normal\">{}</mi>", xml_escape(n))
    }
}

fn number(v: f64, digits: usize) -> String {
    if let Some(k) = half_pi_multiple(v) {
        let pi = "<mi>&#x3C0;</mi>";
        let sign = if k < 0 { "<mo>&#x2212;</mo>" } else { "" };
        let k = k.abs();
        return match (k % 2 == 0, k) {
            (true, 2) => format!("<mrow>{sign}{pi}</mrow>"),
            (true, _) => format!("<mrow>{sign}<mn>{}</mn><mo>&#x2062;</mo>{pi}</mrow>", k / 2),
            (false, 1) => format!("<mrow>{sign}<mfrac>{pi}<mn>2</mn></mfrac></mrow>"),
            (false, _) => format!(
                "<mrow>{sign}<mfrac><mrow><mn>{k}</mn><mo>&#x2062;</mo>{pi}</mrow><mn>2</mn></mfrac></mrow>"
            ),
        };
    }
    let s = fmt_number(v, Some(digits));
    let (sign, s) = match s.strip_prefix('-') {
        Some(rest) => ("<mo>&#x2212;</mo>", rest.to_string()),
        None => ("", s),
    };
    match s.split_once('e') {
        Some((m, e)) => format!(
            "<mrow>{sign}<mn>{m}</mn><mo>&#xB7;</mo><msup><mn>10</mn><mn>{}</mn></msup></mrow>",
            e.trim_start_matches('+')
        ),
        None if sign.is_empty() => format!("<mn>{s}</mn>"),
        None => format!("<mrow>{sign}<mn>{s}</mn></mrow>"),
    }
}

impl Expr {
    /// Presentation MathML of the expression with `digits` significant digits (the inner
    /// content: wrap it in `<math>`), as the LaTeX form lays it out.
    pub fn to_mathml(&self, digits: usize) -> String {
        let wrap = |e: &Expr, min: u8| {
            let s = e.to_mathml(digits);
            if e.prec() < min { paren(&s) } else { s }
        };
        let wrap_right = |e: &Expr, min: u8| {
            if e.leads_with_minus() {
                paren(&e.to_mathml(digits))
            } else {
                wrap(e, min)
            }
        };
        match self {
            Expr::Num(v) => number(*v, digits),
            Expr::Var(n) => name(n),
            Expr::Neg(a) => format!("<mrow><mo>&#x2212;</mo>{}</mrow>", wrap(a, 3)),
            Expr::Un(op, a) => {
                let s = a.to_mathml(digits);
                match op {
                    Op::Square => format!("<msup>{}<mn>2</mn></msup>", wrap(a, 9)),
                    Op::Inverse => format!("<mfrac><mn>1</mn>{s}</mfrac>"),
                    Op::Abs => format!("<mrow><mo>|</mo>{s}<mo>|</mo></mrow>"),
                    Op::Sqrt => format!("<msqrt>{s}</msqrt>"),
                    Op::Exp => format!("<msup><mi>e</mi>{s}</msup>"),
                    Op::Gaussian => format!(
                        "<msup><mi>e</mi><mrow><mo>&#x2212;</mo><msup>{}<mn>2</mn></msup></mrow></msup>",
                        wrap(a, 9)
                    ),
                    Op::Log => func("log", &s),
                    Op::Sin => func("sin", &s),
                    Op::Cos => func("cos", &s),
                    Op::Tanh => func("tanh", &s),
                    Op::Tan => func("tan", &s),
                    _ => func(op.name(), &s),
                }
            }
            Expr::Bin(op, a, b) => match op {
                Op::Add | Op::Sub => {
                    let (sign, right, min) = signed_right(*op, b);
                    let sign = if sign == "-" { "&#x2212;" } else { "+" };
                    format!(
                        "<mrow>{}<mo>{sign}</mo>{}</mrow>",
                        wrap(a, 1),
                        wrap_right(&right, min)
                    )
                }
                Op::Mul => {
                    let (l, r) = (wrap(a, 2), wrap_right(b, 2));
                    // juxtaposed numbers would read as one (2 · 3), and a number or a name
                    // against a word runs together (0.013 · speed): a visible dot there
                    let lead = |x: &str| {
                        let mut x = x;
                        while let Some(rest) = ["<msup>", "<msub>", "<mrow>"]
                            .iter()
                            .find_map(|t| x.strip_prefix(t))
                        {
                            x = rest;
                        }
                        x.to_string()
                    };
                    let (rl, ll) = (lead(&r), lead(&l));
                    let times = if rl.starts_with("<mn>")
                        || rl.starts_with("<mi mathvariant")
                        || ll.starts_with("<mi mathvariant")
                    {
                        "&#xB7;"
                    } else {
                        "&#x2062;"
                    };
                    format!("<mrow>{l}<mo>{times}</mo>{r}</mrow>")
                }
                Op::Div => format!(
                    "<mfrac>{}{}</mfrac>",
                    a.to_mathml(digits),
                    b.to_mathml(digits)
                ),
                Op::Gaussian2 => format!(
                    "<msup><mi>e</mi><mrow><mo>&#x2212;</mo>{}</mrow></msup>",
                    paren(&format!(
                        "<msup>{}<mn>2</mn></msup><mo>+</mo><msup>{}<mn>2</mn></msup>",
                        wrap(a, 4),
                        wrap(b, 4)
                    ))
                ),
                Op::Pow => format!("<msup>{}{}</msup>", wrap(a, 9), b.to_mathml(digits)),
                _ => func(
                    op.name(),
                    &format!("{}<mo>,</mo>{}", a.to_mathml(digits), b.to_mathml(digits)),
                ),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn var(n: &str) -> Box<Expr> {
        Box::new(Expr::Var(n.into()))
    }

    /// The forms an engineer's law takes: a power, a quotient, an exponential, a
    /// difference with a negative term, a name with a subscript and one to escape.
    #[test]
    fn laws_print_as_mathml() {
        let power = Expr::Bin(Op::Pow, var("f"), Box::new(Expr::Num(0.5)));
        assert_eq!(power.to_mathml(4), "<msup><mi>f</mi><mn>0.5</mn></msup>");
        let q = Expr::Bin(Op::Div, var("x1"), var("d"));
        assert_eq!(
            q.to_mathml(4),
            "<mfrac><msub><mi>x</mi><mn>1</mn></msub><mi>d</mi></mfrac>"
        );
        let e = Expr::Un(Op::Exp, Box::new(Expr::Neg(var("T"))));
        assert_eq!(
            e.to_mathml(4),
            "<msup><mi>e</mi><mrow><mo>&#x2212;</mo><mi>T</mi></mrow></msup>"
        );
        let d = Expr::Bin(
            Op::Add,
            var("a"),
            Box::new(Expr::Bin(Op::Mul, Box::new(Expr::Num(-2.0)), var("b"))),
        );
        assert_eq!(
            d.to_mathml(4),
            "<mrow><mi>a</mi><mo>&#x2212;</mo><mrow><mn>2</mn><mo>&#x2062;</mo><mi>b</mi></mrow></mrow>"
        );
        let speed = Expr::Bin(Op::Mul, Box::new(Expr::Num(0.5)), var("speed"));
        assert_eq!(
            speed.to_mathml(4),
            "<mrow><mn>0.5</mn><mo>&#xB7;</mo><mi mathvariant=\"normal\">speed</mi></mrow>"
        );
        assert_eq!(
            Expr::Var("v<c".into()).to_mathml(4),
            "<mi mathvariant=\"normal\">v&lt;c</mi>"
        );
        assert_eq!(
            Expr::Num(1.5e-7).to_mathml(3),
            "<mrow><mn>1.50</mn><mo>&#xB7;</mo><msup><mn>10</mn><mn>-7</mn></msup></mrow>"
        );
    }
}
