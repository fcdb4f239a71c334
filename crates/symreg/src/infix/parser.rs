//! The parser: recursive descent over the tokens, one function per precedence level, as
//! Python binds its operators.

use super::lexer::{Tok, describe, err, function, lex};
use super::{Parsed, SlotCall};
use crate::SrError;
use crate::expr::Expr;
use crate::ops::Op;

/// Most tokens an equation may have: far beyond any physical law (Kienzle's force is about
/// 15), small enough that the expression tree stays shallow for the recursive walks that
/// evaluate, simplify and print it (a flat chain of 60,000 terms overflowed the stack).
pub const MAX_TOKENS: usize = 10_000;

/// Deepest nesting an equation may have (parentheses, functions, signs and powers, and the
/// length of a chain of one operator, which nests to the left): far beyond any physical
/// law, shallow enough for every recursive walk on a 2 MB worker-thread stack.
pub const MAX_DEPTH: usize = 1_000;

struct Parser {
    toks: Vec<(Tok, usize)>,
    i: usize,
    positions: Vec<(String, usize)>,
    depth: usize,
    /// `Some` when calls of unknown names are learned slots ([`parse_with_slots`]).
    slots: Option<Vec<SlotCall>>,
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

    /// Every nesting of the grammar passes through here (parentheses and function calls
    /// through `expr`, signs and exponents directly), so the recursion is bounded here.
    fn unary(&mut self) -> Result<Expr, SrError> {
        if self.depth >= MAX_DEPTH {
            return Err(err(
                self.pos(),
                format!("the equation nests deeper than {MAX_DEPTH} levels; write it flatter"),
            ));
        }
        self.depth += 1;
        let e = self.unary_inner();
        self.depth -= 1;
        e
    }

    fn unary_inner(&mut self) -> Result<Expr, SrError> {
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
                    if function(&name).is_none() && self.slots.is_some() {
                        return self.slot(name, pos);
                    }
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

    /// A learned slot `name(col, ...)`: its columns, recorded, and the slot's name as a
    /// variable in the expression.
    fn slot(&mut self, name: String, pos: usize) -> Result<Expr, SrError> {
        let (_, open) = self.next();
        let mut columns = Vec::new();
        loop {
            let (t, at) = self.next();
            match t {
                Tok::Name(c) if function(&c).is_none() && c != "pi" => {
                    if columns.contains(&c) {
                        return Err(err(at, format!("the slot `{name}` lists `{c}` twice")));
                    }
                    columns.push(c);
                }
                other => {
                    return Err(err(
                        at,
                        format!(
                            "the learned slot `{name}(...)` takes column names separated by \
                             commas, but found {}",
                            describe(&other)
                        ),
                    ));
                }
            }
            let (t, at) = self.next();
            match t {
                Tok::Comma => {}
                Tok::RParen => break,
                other => {
                    return Err(err(
                        at,
                        format!(
                            "expected `,` or `)` to close the `(` at character {open} but found {}",
                            describe(&other)
                        ),
                    ));
                }
            }
        }
        let slots = self.slots.get_or_insert_with(Vec::new);
        if let Some(s) = slots.iter().find(|s| s.name == name) {
            if s.columns != columns {
                return Err(err(
                    pos,
                    format!(
                        "the slot `{name}` is called over ({}) here and over ({}) before: one \
                         learned function has one set of columns",
                        columns.join(", "),
                        s.columns.join(", ")
                    ),
                ));
            }
        } else {
            slots.push(SlotCall {
                name: name.clone(),
                columns,
                position: pos,
            });
        }
        Ok(Expr::Var(name))
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
    Ok(parse_inner(text, false)?.0)
}

/// [`parse`] of a physics equation with learned slots: a call of a name that is not a
/// known function (`f(C)`, `g(T, v)`) is a learned function of the listed columns. Each
/// slot is a variable of its own name in the expression; the slots are returned in order
/// of first use, and their columns are among [`Parsed::positions`] (the equation reads
/// them), their names are not.
///
/// # Errors
/// [`parse`]'s, a slot whose arguments are not names, that lists one twice, or that is
/// called over two different sets of columns.
pub fn parse_with_slots(text: &str) -> Result<(Parsed, Vec<SlotCall>), SrError> {
    let (parsed, slots) = parse_inner(text, true)?;
    Ok((parsed, slots.unwrap_or_default()))
}

fn parse_inner(text: &str, slots: bool) -> Result<(Parsed, Option<Vec<SlotCall>>), SrError> {
    let toks = lex(text)?;
    // Checked before any tree is built: the tree of a longer chain could not even be dropped
    // without deep recursion.
    if toks.len() > MAX_TOKENS + 1 {
        return Err(err(
            toks[MAX_TOKENS].1,
            format!(
                "the equation has {} tokens, more than the {MAX_TOKENS} accepted; is this the \
                 equation you meant?",
                toks.len() - 1
            ),
        ));
    }
    let mut p = Parser {
        toks,
        i: 0,
        positions: Vec::new(),
        depth: 0,
        slots: slots.then(Vec::new),
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
    let depth = tree_depth(&expr);
    if depth > MAX_DEPTH {
        return Err(err(
            1,
            format!(
                "the equation nests {depth} levels deep (a chain of one operator nests once per \
                 term), more than the {MAX_DEPTH} accepted; write it flatter"
            ),
        ));
    }
    let mut positions = p.positions;
    if let Some(calls) = &p.slots {
        // a slot's columns are names the equation reads
        for s in calls {
            for c in &s.columns {
                if !positions.iter().any(|(n, _)| n == c) {
                    positions.push((c.clone(), s.position));
                }
            }
        }
    }
    Ok((Parsed { expr, positions }, p.slots))
}

/// The depth of a tree, without recursion.
fn tree_depth(e: &Expr) -> usize {
    let mut deepest = 0;
    let mut stack = vec![(e, 1usize)];
    while let Some((e, d)) = stack.pop() {
        deepest = deepest.max(d);
        match e {
            Expr::Num(_) | Expr::Var(_) => {}
            Expr::Neg(a) | Expr::Un(_, a) => stack.push((a, d + 1)),
            Expr::Bin(_, a, b) => {
                stack.push((a, d + 1));
                stack.push((b, d + 1));
            }
        }
    }
    deepest
}

#[cfg(test)]
mod limits {
    use super::*;

    /// No text can overflow the stack: deep nesting of every kind and long flat chains are
    /// refused with a parse error naming the limit; the largest accepted ones parse.
    #[test]
    fn deep_and_long_equations_are_refused_by_name() {
        let cases = [
            format!("{}x{}", "(".repeat(20_000), ")".repeat(20_000)),
            format!("{}x{}", "abs(".repeat(10_000), ")".repeat(10_000)),
            format!("{}x", "-".repeat(50_000)),
            format!("x{}", "^x".repeat(30_000)),
            vec!["x"; 60_000].join("+"),
            vec!["x"; 15_000].join("*"),
            vec!["x"; 1_500].join("+"),
        ];
        for text in &cases {
            match parse(text) {
                Err(SrError::Parse { message, .. }) => assert!(
                    message.contains("nests") || message.contains("tokens"),
                    "{}...: {message}",
                    &text[..20]
                ),
                other => panic!("{}...: {other:?}", &text[..20]),
            }
        }
        assert!(parse(&vec!["x"; 900].join("+")).is_ok());
        assert!(parse(&format!("{}x{}", "(".repeat(900), ")".repeat(900))).is_ok());
    }
}
