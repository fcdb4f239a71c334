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
use crate::SrError;
use crate::eval::Evaluator;
use crate::expr::Expr;
use crate::ops::Op;
use crate::program::{Node, Program};
use std::collections::BTreeMap;

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

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Num(f64),
    Name(String),
    Plus,
    Minus,
    Star,
    Slash,
    Pow,
    LParen,
    RParen,
    End,
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(v) => format!("number {v}"),
        Tok::Name(n) => format!("`{n}`"),
        Tok::Plus => "`+`".into(),
        Tok::Minus => "`-`".into(),
        Tok::Star => "`*`".into(),
        Tok::Slash => "`/`".into(),
        Tok::Pow => "a power operator".into(),
        Tok::LParen => "`(`".into(),
        Tok::RParen => "`)`".into(),
        Tok::End => "the end of the equation".into(),
    }
}

fn err(position: usize, message: String) -> SrError {
    SrError::Parse { position, message }
}

/// Splits the text into tokens with their 1-based character positions.
fn lex(text: &str) -> Result<Vec<(Tok, usize)>, SrError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let pos = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        let simple = match c {
            '+' => Some(Tok::Plus),
            '-' => Some(Tok::Minus),
            '/' => Some(Tok::Slash),
            '^' => Some(Tok::Pow),
            '(' => Some(Tok::LParen),
            ')' => Some(Tok::RParen),
            '*' => {
                if chars.get(i + 1) == Some(&'*') {
                    i += 1;
                    Some(Tok::Pow)
                } else {
                    Some(Tok::Star)
                }
            }
            _ => None,
        };
        if let Some(t) = simple {
            out.push((t, pos));
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let s: String = chars[start..i].iter().collect();
            let v: f64 = s
                .parse()
                .map_err(|_| err(pos, format!("`{s}` is not a number")))?;
            out.push((Tok::Num(v), pos));
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push((Tok::Name(chars[start..i].iter().collect()), pos));
            continue;
        }
        if c == '`' {
            let start = i + 1;
            let mut j = start;
            while j < chars.len() && chars[j] != '`' {
                j += 1;
            }
            if j >= chars.len() {
                return Err(err(pos, "the backquoted name is not closed".into()));
            }
            let name: String = chars[start..j].iter().collect();
            if name.is_empty() {
                return Err(err(pos, "empty backquoted name".into()));
            }
            out.push((Tok::Name(name), pos));
            i = j + 1;
            continue;
        }
        return Err(err(pos, format!("unexpected character `{c}`")));
    }
    out.push((Tok::End, chars.len() + 1));
    Ok(out)
}

fn function(name: &str) -> Option<Op> {
    Some(match name {
        "exp" => Op::Exp,
        "log" | "ln" => Op::Log,
        "sqrt" => Op::Sqrt,
        "sin" => Op::Sin,
        "cos" => Op::Cos,
        "tan" => Op::Tan,
        "tanh" => Op::Tanh,
        "abs" | "Abs" => Op::Abs,
        _ => return None,
    })
}

struct Parser {
    toks: Vec<(Tok, usize)>,
    i: usize,
    positions: Vec<(String, usize)>,
}

impl Parser {
    fn peek(&self) -> &Tok {
        &self.toks[self.i].0
    }

    fn pos(&self) -> usize {
        self.toks[self.i].1
    }

    fn next(&mut self) -> (Tok, usize) {
        let t = self.toks[self.i].clone();
        if self.i + 1 < self.toks.len() {
            self.i += 1;
        }
        t
    }

    /// One left-associative level of binary operators, `operand (op operand)*`: `op_of`
    /// gives the operator of a token (`None` ends the level).
    fn left_assoc(
        &mut self,
        op_of: fn(&Tok) -> Option<Op>,
        operand: fn(&mut Self) -> Result<Expr, SrError>,
    ) -> Result<Expr, SrError> {
        let mut e = operand(self)?;
        while let Some(op) = op_of(self.peek()) {
            self.next();
            let r = operand(self)?;
            e = Expr::Bin(op, Box::new(e), Box::new(r));
        }
        Ok(e)
    }

    fn expr(&mut self) -> Result<Expr, SrError> {
        self.left_assoc(
            |t| match t {
                Tok::Plus => Some(Op::Add),
                Tok::Minus => Some(Op::Sub),
                _ => None,
            },
            Self::term,
        )
    }

    fn term(&mut self) -> Result<Expr, SrError> {
        self.left_assoc(
            |t| match t {
                Tok::Star => Some(Op::Mul),
                Tok::Slash => Some(Op::Div),
                _ => None,
            },
            Self::unary,
        )
    }

    fn unary(&mut self) -> Result<Expr, SrError> {
        match self.peek() {
            Tok::Minus => {
                self.next();
                Ok(match self.unary()? {
                    Expr::Num(v) => Expr::Num(-v),
                    e => Expr::Neg(Box::new(e)),
                })
            }
            Tok::Plus => {
                self.next();
                self.unary()
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Expr, SrError> {
        let base = self.atom()?;
        if *self.peek() != Tok::Pow {
            return Ok(base);
        }
        self.next();
        let exponent = self.unary()?;
        Ok(match exponent {
            Expr::Num(2.0) => Expr::Un(Op::Square, Box::new(base)),
            e => Expr::Bin(Op::Pow, Box::new(base), Box::new(e)),
        })
    }

    fn atom(&mut self) -> Result<Expr, SrError> {
        let (tok, pos) = self.next();
        match tok {
            Tok::Num(v) => Ok(Expr::Num(v)),
            Tok::LParen => {
                let e = self.expr()?;
                self.close(pos)?;
                Ok(e)
            }
            Tok::Name(name) => {
                if *self.peek() == Tok::LParen {
                    let Some(op) = function(&name) else {
                        return Err(err(
                            pos,
                            format!(
                                "unknown function `{name}`: use exp, log, sqrt, sin, cos, tan, tanh or abs"
                            ),
                        ));
                    };
                    let open = self.pos();
                    self.next();
                    let a = self.expr()?;
                    self.close(open)?;
                    return Ok(Expr::Un(op, Box::new(a)));
                }
                if name == "pi" {
                    return Ok(Expr::Num(std::f64::consts::PI));
                }
                if function(&name).is_some() {
                    return Err(err(
                        pos,
                        format!("`{name}` is a function: write `{name}(...)`"),
                    ));
                }
                if !self.positions.iter().any(|(n, _)| *n == name) {
                    self.positions.push((name.clone(), pos));
                }
                Ok(Expr::Var(name))
            }
            other => Err(err(
                pos,
                format!(
                    "expected a number, a name or `(` but found {}",
                    describe(&other)
                ),
            )),
        }
    }

    fn close(&mut self, open: usize) -> Result<(), SrError> {
        let (t, pos) = self.next();
        if t == Tok::RParen {
            Ok(())
        } else {
            Err(err(
                pos,
                format!(
                    "expected `)` to close the `(` at character {open} but found {}",
                    describe(&t)
                ),
            ))
        }
    }
}

/// Parses an infix equation.
///
/// # Errors
/// [`SrError::Parse`] with the 1-based character position: an unexpected character or
/// token, an unclosed parenthesis, an unknown function, an empty equation.
pub fn parse(text: &str) -> Result<Parsed, SrError> {
    let toks = lex(text)?;
    let mut p = Parser {
        toks,
        i: 0,
        positions: Vec::new(),
    };
    if *p.peek() == Tok::End {
        return Err(err(1, "the equation is empty".into()));
    }
    let expr = p.expr()?;
    let (t, pos) = p.next();
    if t != Tok::End {
        return Err(err(
            pos,
            format!("unexpected {} after a complete expression", describe(&t)),
        ));
    }
    Ok(Parsed {
        expr,
        positions: p.positions,
    })
}

/// A compiled equation: a program over `inputs` whose numbers and named constants are
/// constant leaves with their values in `params`.
#[derive(Clone, Debug, PartialEq)]
pub struct Compiled {
    /// The program (no affine inputs; output scale 1 and offset 0 in `params[0..2]`).
    pub program: Program,
    /// Parameter vector in the program's layout.
    pub params: Vec<f64>,
    /// Input names; `Node::Var(i)` is `inputs[i]`.
    pub inputs: Vec<String>,
    /// For each named constant, the indices into `params` of its leaves (a name used twice
    /// has two leaves that must move together).
    pub slots: BTreeMap<String, Vec<usize>>,
}

impl Compiled {
    /// Sets every leaf of the named constant to `value` (no-op for an unknown name).
    pub fn set(&mut self, name: &str, value: f64) {
        if let Some(slots) = self.slots.get(name) {
            for &i in slots {
                self.params[i] = value;
            }
        }
    }

    /// Current value of a named constant.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.slots
            .get(name)
            .and_then(|s| s.first())
            .map(|&i| self.params[i])
    }

    /// Evaluates on columns given in the order of `inputs`.
    pub fn eval_columns(&self, cols: &[&[f64]], n_rows: usize) -> Vec<f64> {
        let mut out = Vec::new();
        Evaluator::new(&self.program).predict(&self.program, &self.params, cols, n_rows, &mut out);
        out
    }

    /// Evaluates at one row given in the order of `inputs`.
    pub fn eval_row(&self, row: &[f64]) -> f64 {
        let cols: Vec<&[f64]> = row.iter().map(std::slice::from_ref).collect();
        self.eval_columns(&cols, 1)
            .first()
            .copied()
            .unwrap_or(f64::NAN)
    }

    /// The equation with every constant's value substituted, as a reporting expression.
    pub fn expr(&self) -> Expr {
        Expr::from_program(&self.program, &self.params, &self.inputs)
    }
}

fn emit(
    e: &Expr,
    inputs: &[String],
    constants: &BTreeMap<String, f64>,
    parsed: &Parsed,
    nodes: &mut Vec<Node>,
    values: &mut Vec<f64>,
    named: &mut Vec<(String, usize)>,
) -> Result<(), SrError> {
    let constant = |v: f64, nodes: &mut Vec<Node>, values: &mut Vec<f64>| {
        nodes.push(Node::Const);
        values.push(v);
    };
    match e {
        Expr::Num(v) => constant(*v, nodes, values),
        Expr::Var(name) => {
            if let Some(j) = inputs.iter().position(|n| n == name) {
                let j = u16::try_from(j).map_err(|_| {
                    SrError::InvalidConfig("an equation may use at most 65535 inputs".into())
                })?;
                nodes.push(Node::Var(j));
            } else if let Some(v) = constants.get(name) {
                named.push((name.clone(), values.len()));
                constant(*v, nodes, values);
            } else {
                return Err(SrError::UnknownSymbol {
                    name: name.clone(),
                    position: parsed.position(name).unwrap_or(0),
                });
            }
        }
        Expr::Neg(a) => {
            constant(-1.0, nodes, values);
            emit(a, inputs, constants, parsed, nodes, values, named)?;
            nodes.push(Node::Op(Op::Mul));
        }
        Expr::Un(op, a) => {
            emit(a, inputs, constants, parsed, nodes, values, named)?;
            nodes.push(Node::Op(*op));
        }
        Expr::Bin(op, a, b) => {
            emit(a, inputs, constants, parsed, nodes, values, named)?;
            emit(b, inputs, constants, parsed, nodes, values, named)?;
            nodes.push(Node::Op(*op));
        }
    }
    Ok(())
}

/// Compiles a parsed equation: names in `inputs` become inputs, names in `constants` become
/// constant leaves with those values, numbers become constant leaves.
///
/// # Errors
/// [`SrError::UnknownSymbol`] for a name in neither list.
pub fn compile(
    parsed: &Parsed,
    inputs: &[String],
    constants: &BTreeMap<String, f64>,
) -> Result<Compiled, SrError> {
    let mut nodes = Vec::new();
    let mut values = Vec::new();
    let mut named = Vec::new();
    emit(
        &parsed.expr,
        inputs,
        constants,
        parsed,
        &mut nodes,
        &mut values,
        &mut named,
    )?;
    let program = Program {
        nodes,
        affine: false,
    };
    // Constants own one parameter each, in node order, after the output scale and offset.
    let mut params = vec![1.0, 0.0];
    params.extend_from_slice(&values);
    let mut slots: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (name, k) in named {
        slots.entry(name).or_default().push(k + 2);
    }
    Ok(Compiled {
        program,
        params,
        inputs: inputs.to_vec(),
        slots,
    })
}

/// Parses and compiles in one step, treating every name that is not a constant as an
/// input (in order of first use).
///
/// # Errors
/// As [`parse`].
pub fn compile_text(text: &str, constants: &BTreeMap<String, f64>) -> Result<Compiled, SrError> {
    let parsed = parse(text)?;
    let inputs: Vec<String> = parsed
        .names()
        .into_iter()
        .filter(|n| !constants.contains_key(*n))
        .map(str::to_string)
        .collect();
    compile(&parsed, &inputs, constants)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

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
}
