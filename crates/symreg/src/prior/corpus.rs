//! Reading the corpus of written laws (`testdata/laws/laws.txt`): one law per line,
//! `name | target = expression | variables | source`.

use super::tokens::{Token, expr_tokens};
use crate::SrError;
use crate::infix::{Parsed, parse};

/// One law of the corpus, parsed.
#[derive(Clone, Debug, PartialEq)]
pub struct Law {
    /// 1-based line number in the corpus text.
    pub line: usize,
    /// The law's name (`Taylor tool life`).
    pub name: String,
    /// The name of what the law gives (left of `=`).
    pub target: String,
    /// The expression as written (right of `=`).
    pub expression: String,
    /// The measured inputs; every other name in the expression is a fitted constant.
    pub variables: Vec<String>,
    /// Where the law is written down.
    pub source: String,
    /// The parsed expression.
    pub parsed: Parsed,
}

impl Law {
    /// The law's prefix token sequence over the search's vocabulary
    /// (the [`prior`](super) docs, "Tokens", say how a written law becomes tokens).
    pub fn tokens(&self) -> Vec<Token> {
        let vars: Vec<&str> = self.variables.iter().map(String::as_str).collect();
        expr_tokens(&self.parsed.expr, &vars)
    }
}

fn malformed(line: usize, name: &str, what: impl std::fmt::Display) -> SrError {
    SrError::InvalidConfig(format!("laws corpus line {line} (`{name}`): {what}"))
}

/// Parses one non-comment line.
fn parse_line(line: usize, text: &str) -> Result<Law, SrError> {
    let fields: Vec<&str> = text.split(" | ").map(str::trim).collect();
    let name = fields.first().copied().unwrap_or("");
    let [name, equation, variables, source] = fields[..] else {
        return Err(malformed(
            line,
            name,
            format!(
                "{} fields; write `name | target = expression | variables | source`",
                fields.len()
            ),
        ));
    };
    let Some((target, expression)) = equation.split_once('=') else {
        return Err(malformed(line, name, "no `=`: write `target = expression`"));
    };
    let (target, expression) = (target.trim(), expression.trim());
    if target.is_empty() || source.is_empty() {
        return Err(malformed(line, name, "empty target or source"));
    }
    let parsed = parse(expression).map_err(|e| malformed(line, name, e))?;
    let variables: Vec<String> = variables
        .split(',')
        .map(|v| v.trim().to_string())
        .filter(|v| !v.is_empty())
        .collect();
    if variables.is_empty() {
        return Err(malformed(
            line,
            name,
            "no variables: name the measured inputs",
        ));
    }
    let names = parsed.names();
    if let Some(v) = variables.iter().find(|v| !names.contains(&v.as_str())) {
        return Err(malformed(
            line,
            name,
            format!("variable `{v}` is not in the expression"),
        ));
    }
    Ok(Law {
        line,
        name: name.to_string(),
        target: target.to_string(),
        expression: expression.to_string(),
        variables,
        source: source.to_string(),
        parsed,
    })
}

/// Parses a corpus: every line that is neither blank nor a `#` comment is a law.
///
/// # Errors
/// [`SrError::InvalidConfig`] naming the first line that is malformed: not four fields
/// separated by ` | `, no `=`, an expression the infix parser refuses, no variables, or a
/// variable the expression does not use.
pub fn parse_corpus(text: &str) -> Result<Vec<Law>, SrError> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| {
            let l = l.trim();
            !l.is_empty() && !l.starts_with('#')
        })
        .map(|(i, l)| parse_line(i + 1, l))
        .collect()
}
