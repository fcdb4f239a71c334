//! The tokens of an infix equation, each with its 1-based character position.

use crate::SrError;
use crate::ops::Op;

#[derive(Clone, Debug, PartialEq)]
pub(super) enum Tok {
    Num(f64),
    Name(String),
    Plus,
    Minus,
    Star,
    Slash,
    Pow,
    LParen,
    RParen,
    /// `,`: only between the columns of a learned slot, `f(T, v)`.
    Comma,
    End,
}

pub(super) fn describe(t: &Tok) -> String {
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
        Tok::Comma => "`,`".into(),
        Tok::End => "the end of the equation".into(),
    }
}

pub(super) fn err(position: usize, message: String) -> SrError {
    SrError::Parse { position, message }
}

/// Splits the text into tokens with their 1-based character positions.
/// The name inside `Symbol('...')`, read from `chars[at..]` (just after the opening quote)
/// with the escapes [`crate::expr::sympy_symbol`] writes (`\\`, `\'`, `\uXXXX`,
/// `\UXXXXXXXX`), and the index after the closing `)`.
fn symbol_literal(chars: &[char], at: usize, pos: usize) -> Result<(String, usize), SrError> {
    let mut name = String::new();
    let mut i = at;
    loop {
        match chars.get(i) {
            None => return Err(err(pos, "the Symbol('...') name is not closed".into())),
            Some('\'') => break,
            Some('\\') => {
                let hex = |n: usize| -> Result<char, SrError> {
                    let digits: String =
                        chars.get(i + 2..i + 2 + n).unwrap_or(&[]).iter().collect();
                    u32::from_str_radix(&digits, 16)
                        .ok()
                        .filter(|_| digits.len() == n)
                        .and_then(char::from_u32)
                        .ok_or_else(|| {
                            err(pos, format!("bad escape `\\{digits}` in Symbol('...')"))
                        })
                };
                match chars.get(i + 1) {
                    Some(&c @ ('\\' | '\'')) => {
                        name.push(c);
                        i += 2;
                    }
                    Some('u') => {
                        name.push(hex(4)?);
                        i += 6;
                    }
                    Some('U') => {
                        name.push(hex(8)?);
                        i += 10;
                    }
                    _ => return Err(err(pos, "bad escape in Symbol('...')".into())),
                }
            }
            Some(&c) => {
                name.push(c);
                i += 1;
            }
        }
    }
    if chars.get(i + 1) != Some(&')') {
        return Err(err(pos, "Symbol('...') must end with `')`".into()));
    }
    if name.is_empty() {
        return Err(err(pos, "empty Symbol('') name".into()));
    }
    Ok((name, i + 2))
}

pub(super) fn lex(text: &str) -> Result<Vec<(Tok, usize)>, SrError> {
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
            ',' => Some(Tok::Comma),
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
            let word: String = chars[start..i].iter().collect();
            if word == "Symbol" && chars.get(i) == Some(&'(') && chars.get(i + 1) == Some(&'\'') {
                // sympy's `Symbol('name')`, as [`crate::expr::sympy_symbol`] writes a name
                // sympy would read as something else
                let (name, next) = symbol_literal(&chars, i + 2, pos)?;
                out.push((Tok::Name(name), pos));
                i = next;
                continue;
            }
            out.push((Tok::Name(word), pos));
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

pub(super) fn function(name: &str) -> Option<Op> {
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
