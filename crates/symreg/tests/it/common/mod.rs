//! Helpers shared by symreg's integration tests.
//!
//! Every test file compiles this module on its own and uses only part of it.
#![allow(dead_code)]

use hxai_symreg::{Node, Op, Program};

/// The affine program written in postfix: `x0`, `x1`, ... are the inputs, `c` a fitted
/// constant, any other word an operator name as [`Op::parse`] reads it; so
/// `affine_program("x0 x1 mul")` is `Var(0) Var(1) Op(Mul)` with affine inputs.
///
/// # Panics
/// On a word that is neither an input, `c` nor an operator (a typo in the test itself).
pub fn affine_program(postfix: &str) -> Program {
    let nodes = postfix
        .split_whitespace()
        .map(|word| {
            if let Some(Ok(i)) = word.strip_prefix('x').map(str::parse) {
                Node::Var(i)
            } else if word == "c" {
                Node::Const
            } else {
                Node::Op(Op::parse(word).unwrap_or_else(|e| panic!("`{word}` in `{postfix}`: {e}")))
            }
        })
        .collect();
    Program {
        nodes,
        affine: true,
    }
}

/// `hxai sr`'s defaults that the selection tests depend on (strict nesting, the power
/// primitive, the description-length criterion, two units of complexity per input, keys for
/// candidates of at most 14 nodes), the rest the library's.
pub fn sr_defaults() -> hxai_symreg::SearchConfig {
    hxai_symreg::SearchConfig {
        criterion: hxai_symreg::Criterion::Mdl,
        nesting: hxai_symreg::Nesting::strict(),
        power_laws: true,
        complexity_per_input: 2,
        max_key_nodes: Some(14),
        ..hxai_symreg::SearchConfig::default()
    }
}
