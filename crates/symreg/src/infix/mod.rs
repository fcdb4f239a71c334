//! Equations written by people: an infix parser and a compiler to [`Program`] form.
//!
//! The hybrid layer (`hxai hybrid ...`) takes a physics equation as text, such as
//! `kc*b*h^(1-mc)` or `f^2/(32*r)`. [`parse`] reads it into an [`Expr`]; [`compile`] turns
//! that into a postfix [`Program`] over named inputs whose named parameters and numbers are
//! constant leaves, so a physics law is evaluated and differentiated by the same
//! [`Evaluator`] as every symbolic-regression candidate, and its
//! parameters are calibrated by the same Levenberg-Marquardt machinery.
//!
//! Syntax: `+ - * /`, `^` and `**` (right-associative, binding tighter than unary minus, as
//! in Python: `-x^2` is `-(x^2)`, `2^-1` is `1/2`), unary minus and plus, parentheses,
//! numbers (`3`, `0.5`, `.5`, `1e-3`), `pi`, and the functions `exp log ln sqrt sin cos tan
//! tanh abs` (`Abs` too, so sympy's output parses back). Names are identifiers
//! (`[A-Za-z_][A-Za-z0-9_]*`) or any text in backquotes (`` `v c [m/min]` ``). `x^2` with a
//! literal 2 becomes the `square` operator; any other power is [`Op::Pow`].
//!
//! Errors name the character position (1-based) and what was found there.
//!
//! ```
//! use hxai_symreg::infix::{compile, parse};
//! use std::collections::BTreeMap;
//! let parsed = parse("kc*b*h^(1-mc)")?;
//! assert_eq!(parsed.names(), vec!["kc", "b", "h", "mc"]);
//! let consts = BTreeMap::from([("kc".to_string(), 1500.0), ("mc".to_string(), 0.25)]);
//! let c = compile(&parsed, &["b".into(), "h".into()], &consts)?;
//! let v = c.eval_row(&[2.0, 0.16]);
//! assert!((v - 1500.0 * 2.0 * 0.16f64.powf(0.75)).abs() < 1e-9);
//! # Ok::<(), hxai_symreg::SrError>(())
//! ```
//!
//! Files by job: `lexer.rs` the tokens, `parser.rs` recursive descent into [`Parsed`],
//! `compiler.rs` the [`Compiled`] program; this file the parsed form and the tests.
//!
//! [`Program`]: crate::Program
//! [`Evaluator`]: crate::eval::Evaluator
//! [`Op::Pow`]: crate::Op::Pow

mod compiler;
mod lexer;
mod parser;

pub use compiler::{Compiled, compile, compile_text};
pub use parser::{parse, parse_with_slots};

use crate::expr::Expr;

/// A learned slot in a physics equation, `f(T, v)`: a function the data are to write
/// ([`parse_with_slots`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SlotCall {
    /// The slot's name (`f`).
    pub name: String,
    /// The columns it reads, as listed.
    pub columns: Vec<String>,
    /// 1-based character position of its first call.
    pub position: usize,
}

/// A parsed equation: the expression and where each name first appears.
#[derive(Clone, Debug, PartialEq)]
pub struct Parsed {
    /// The expression; names are [`Expr::Var`].
    pub expr: Expr,
    /// Each distinct name with the 1-based character position of its first use, in order
    /// of first use.
    pub positions: Vec<(String, usize)>,
}

impl Parsed {
    /// Distinct names in order of first use.
    pub fn names(&self) -> Vec<&str> {
        self.positions.iter().map(|(n, _)| n.as_str()).collect()
    }

    /// 1-based character position of the first use of `name`.
    pub fn position(&self, name: &str) -> Option<usize> {
        self.positions
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, p)| *p)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::SrError;
    use std::collections::BTreeMap;

    fn at(text: &str, vars: &[(&str, f64)]) -> f64 {
        let c = compile_text(text, &BTreeMap::new()).unwrap();
        let row: Vec<f64> = c
            .inputs
            .iter()
            .map(|n| vars.iter().find(|(m, _)| m == n).unwrap().1)
            .collect();
        c.eval_row(&row)
    }

    /// Precedence and associativity follow Python: `-x^2 = -(x^2)`, `2^3^2 = 2^9`,
    /// `a/b/c = (a/b)/c`, `a-b-c = (a-b)-c`; all exact in f64 for these values.
    #[test]
    fn precedence_matches_python() {
        let x = [("x", 3.0), ("a", 8.0), ("b", 4.0), ("c", 2.0)];
        assert_eq!(at("-x^2", &x), -9.0);
        assert_eq!(at("-x**2", &x), -9.0);
        assert_eq!(at("(-x)^2", &x), 9.0);
        assert_eq!(at("c^3^c", &x), 512.0);
        assert_eq!(at("a/b/c", &x), 1.0);
        assert_eq!(at("a-b-c", &x), 2.0);
        assert_eq!(at("a - -b", &x), 12.0);
        assert_eq!(at("c^-1", &x), 0.5);
        assert_eq!(at("1e-3*a + 2.5E2 + .5", &x), 250.508);
        assert_eq!(at("+a*(b+c)", &x), 48.0);
    }

    /// `Symbol('...')` reads back every name `sympy_symbol` writes that way (sympy's own
    /// names, spaces, quotes, backslashes, non-ASCII), and malformed ones are refused.
    #[test]
    fn sympy_symbols_read_back() {
        for name in [
            "Q",
            "E",
            "a b",
            "it's",
            "back\\slash",
            "\u{3bc}m",
            "\u{1d70e}",
        ] {
            let text = format!("2*{}", crate::expr::sympy_symbol(name));
            let c = compile_text(&text, &BTreeMap::new()).unwrap();
            assert_eq!(c.inputs, [name.to_string()], "{text}");
            assert_eq!(c.eval_row(&[3.0]), 6.0);
        }
        // a named constant given as Symbol('Q') is a constant, not an input
        let k = BTreeMap::from([("Q".to_string(), 4.0)]);
        let c = compile_text("Symbol('Q')*x", &k).unwrap();
        assert_eq!(c.inputs, ["x".to_string()]);
        for bad in ["Symbol('Q'", "Symbol('Q", "Symbol('')", "Symbol('\\u00')"] {
            assert!(
                matches!(
                    compile_text(bad, &BTreeMap::new()),
                    Err(SrError::Parse { .. })
                ),
                "{bad}"
            );
        }
    }

    /// Functions and `pi` evaluate like std's (1e-15 relative: vmath kernels).
    #[test]
    fn functions_and_pi() {
        let x = [("x", 0.7)];
        let cases: [(&str, f64); 9] = [
            ("exp(x)", 0.7f64.exp()),
            ("log(x)", 0.7f64.ln()),
            ("ln(x)", 0.7f64.ln()),
            ("sqrt(x)", 0.7f64.sqrt()),
            ("sin(pi*x)", (std::f64::consts::PI * 0.7).sin()),
            ("cos(x)", 0.7f64.cos()),
            ("tan(x)", 0.7f64.tan()),
            ("tanh(x)", 0.7f64.tanh()),
            ("abs(-x) + Abs(x)", 1.4),
        ];
        for (t, want) in cases {
            let got = at(t, &x);
            assert!(
                (got - want).abs() <= 1e-15 * want.abs(),
                "{t}: {got} vs {want}"
            );
        }
    }

    /// Errors name the position and the offending token or name.
    #[test]
    fn errors_point_at_the_character() {
        let e = parse("f^2/(32*r").unwrap_err();
        assert_eq!(
            e,
            SrError::Parse {
                position: 10,
                message:
                    "expected `)` to close the `(` at character 5 but found the end of the equation"
                        .into()
            }
        );
        let e = parse("a + * b").unwrap_err().to_string();
        assert!(e.contains("character 5") && e.contains("`*`"), "{e}");
        let e = parse("foo(x)").unwrap_err().to_string();
        assert!(e.contains("character 1") && e.contains("`foo`"), "{e}");
        let e = parse("a $ b").unwrap_err().to_string();
        assert!(e.contains("character 3") && e.contains("`$`"), "{e}");
        let e = parse("a b").unwrap_err().to_string();
        assert!(e.contains("character 3") && e.contains("`b`"), "{e}");
        assert!(matches!(parse("  ").unwrap_err(), SrError::Parse { .. }));
        let p = parse("k*x + k2").unwrap();
        let e = compile(&p, &["x".into()], &BTreeMap::from([("k".into(), 1.0)])).unwrap_err();
        assert_eq!(
            e,
            SrError::UnknownSymbol {
                name: "k2".into(),
                position: 7
            }
        );
    }

    /// A constant used twice owns two leaves that `set` moves together; backquoted names
    /// may hold any character.
    #[test]
    fn shared_constants_and_backquotes() {
        let p = parse("C*`v c` + C").unwrap();
        assert_eq!(p.names(), vec!["C", "v c"]);
        let mut c = compile(&p, &["v c".into()], &BTreeMap::from([("C".into(), 2.0)])).unwrap();
        assert_eq!(c.slots["C"].len(), 2);
        assert_eq!(c.eval_row(&[3.0]), 8.0);
        c.set("C", 1.0);
        assert_eq!(c.eval_row(&[3.0]), 4.0);
        assert_eq!(c.get("C"), Some(1.0));
    }

    /// Printing a compiled equation (sympy form, full precision) and parsing it back gives
    /// the same values (1e-12 relative), powers and negative exponents included.
    #[test]
    fn printed_form_parses_back() {
        let consts = BTreeMap::from([("C".into(), 350.0), ("n".into(), 0.25)]);
        for text in [
            "(C/v)^(1/n)",
            "-f^2/(32*r) + tan(f)",
            "v^-0.5*exp(-(f-1)^2)",
        ] {
            let c = compile_text(text, &consts).unwrap();
            let printed = c.expr().to_text(None, true);
            let back = compile_text(&printed, &BTreeMap::new()).unwrap();
            for row in [[120.0, 0.8, 0.4], [200.0, 0.3, 1.2]] {
                let get = |names: &[String]| -> Vec<f64> {
                    names
                        .iter()
                        .map(|n| match n.as_str() {
                            "v" => row[0],
                            "f" => row[1],
                            _ => row[2],
                        })
                        .collect()
                };
                let a = c.eval_row(&get(&c.inputs));
                let b = back.eval_row(&get(&back.inputs));
                assert!(
                    (a - b).abs() <= 1e-12 * a.abs(),
                    "{text} -> {printed}: {a} vs {b}"
                );
            }
        }
    }

    /// A call of an unknown name is a learned slot only under `parse_with_slots`: its
    /// columns are names the equation reads, the slot is a variable, and a slot called over
    /// two sets of columns, an argument that is not a name, or a slot in plain `parse` are
    /// refused by position.
    #[test]
    fn slots_are_calls_of_unknown_names() {
        let (p, slots) = parse_with_slots("A*exp(-((E - E0)/w)^2)*f(C) + g(T, `v c`)").unwrap();
        assert_eq!(
            slots,
            vec![
                SlotCall {
                    name: "f".into(),
                    columns: vec!["C".into()],
                    position: 24
                },
                SlotCall {
                    name: "g".into(),
                    columns: vec!["T".into(), "v c".into()],
                    position: 31
                }
            ]
        );
        assert_eq!(p.names(), vec!["A", "E", "E0", "w", "C", "T", "v c"]);
        assert_eq!(p.expr.to_text(None, false), "A*exp(-((E - E0)/w)**2)*f + g");
        assert!(parse_with_slots("f(C)*2 + f(C)").is_ok());
        for (text, at, says) in [
            ("f(C) + f(D)", 8, "one set of columns"),
            ("f(2*C)", 3, "column names"),
            ("f(C D)", 5, "expected `,` or `)`"),
            ("f(C, C)", 6, "twice"),
            ("f()", 3, "column names"),
        ] {
            match parse_with_slots(text) {
                Err(SrError::Parse { position, message }) => {
                    assert_eq!(position, at, "{text}: {message}");
                    assert!(message.contains(says), "{text}: {message}");
                }
                other => panic!("{text}: {other:?}"),
            }
        }
        assert!(matches!(
            parse("2*f(C)"),
            Err(SrError::Parse { position: 3, .. })
        ));
        assert!(matches!(parse("f(C, D)"), Err(SrError::Parse { .. })));
    }
}
