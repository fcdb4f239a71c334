//! The parser: recursive descent over the tokens, one function per precedence level, as
//! Python binds its operators.

use super::Parsed;
use super::lexer::{Tok, describe, err, function, lex};
use crate::SrError;
use crate::expr::Expr;
use crate::ops::Op;

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
