//! A prior over structures learned from written laws: how many nats a structure costs
//! given how physicists and engineers write their laws.
//!
//! The MDL criterion charges every operator alike, so a `tanh`, a `cos` or a gaussian costs
//! what a power costs, and one that fits a little better wins. Written laws are not uniform
//! over operators: powers, products, quotients and exponentials of ratios are everywhere,
//! `tanh` is rare, sines belong to waves. Following Bartlett, Desmond and Ferreira
//! ("Priors for symbolic regression", 2023), a structure's codelength is `-ln P` of its
//! operator tokens in prefix order under a back-off n-gram model of a corpus of laws.
//!
//! Main items: [`LawPrior`] (the model; [`LawPrior::builtin`] is trained once on
//! `testdata/laws/laws.txt`, embedded in the library), [`Token`], [`parse_corpus`] and
//! [`Law`]. Files by job: `corpus.rs` reads the corpus, `tokens.rs` turns a written law or a
//! [`Program`] into tokens (the rules are under "Tokens" below), `ngram.rs` is the Katz
//! model ("The model" below), `tests.rs` the tests, with the checks that no AI Feynman
//! equation and no law of the real-law suite is in the corpus (`feynman.rs` holds the AI
//! Feynman list).
//!
//! Design decision: a written law and a search program pass through the same tree and the
//! same rules, so the prior of a program is the prior of the law it would print as; and the
//! tokens follow the search's own forms (`pow x c`, `square`, `inverse`, constants folded,
//! the outer `c*r + c` dropped because every program has its own output scale and
//! offset), so the model learns how often each operator follows each other in laws written
//! the way the search writes them.
//!
//! This module only prices structures; the search charges by it under `Criterion::Mdl` with
//! `SearchConfig::prior = Prior::Laws` (the default; `hxai sr --prior laws|uniform`).
//!
//! ```
//! use hxai_symreg::infix::parse;
//! use hxai_symreg::prior::{LawPrior, expr_tokens};
//! let prior = LawPrior::builtin();
//! let cost = |text: &str| {
//!     let e = parse(text).map(|p| p.expr).unwrap_or(hxai_symreg::expr::Expr::Num(0.0));
//!     prior.codelength_tokens(&expr_tokens(&e, &["x"]))
//! };
//! assert!(cost("c*x^c") < cost("c*tanh(c*x + c)"));
//! assert!(cost("c*x + c") < cost("c*cos(c*x + c) + c"));
//! ```
//!
//! # The model
//!
//! A Katz back-off n-gram model with Good-Turing discounts (Katz 1987, IEEE Trans. ASSP
//! 35). For a history `h` and a token `w` seen `r` times after it,
//! `P(w | h) = d_r r / c(h)`; an unseen `w` gets `alpha(h) P(w | h')`, `h'` being `h`
//! without its oldest token, with `alpha(h)` chosen so that every distribution sums to 1.
//! Counts above [`KATZ_K`] are not discounted; smaller ones by Good-Turing, or by absolute
//! discounting where the counts of counts have gaps. The floor for unseen tokens is the
//! unigram, the Krichevsky-Trofimov estimate `(n(w) + 1/2) / (N + 10)` over the 20
//! predicted tokens: an operator the corpus never uses (`gaussian`) costs about
//! `ln(2N + 20)`, 9.6 nats for the built-in corpus's 7,235 tokens, plus the back-off
//! weights above it (21.7 nats for `gaussian(c*x + c)` in all). A history whose
//! continuations are all frequent keeps at least [`MIN_BACKOFF_MASS`]` / (c(h) + 1)` for the
//! tokens never seen after it, so no cost is infinite.
//!
//! # Tokens
//!
//! A written law and a program go through one tree and one set of rules, so a program and
//! the same expression read from text give the same tokens ([`expr_tokens`],
//! [`program_tokens`]):
//!
//! 1. Leaves: a measured input is `x`, a fitted constant `c`, and so is a fixed number
//!    (`2` in `2*g*h`, `0.023` in Dittus-Boelter): a program's constants are all fitted
//!    (the search snaps them to simple numbers afterwards), so a literal is a constant leaf
//!    in the form the search would write it, and a separate literal token would put
//!    probability on tokens no program can produce.
//! 2. A subtree without an input is one constant (`1/n`, `Ea/R`, `2*pi`, `log(10)`): the
//!    search has no way to write it but as a constant leaf.
//! 3. Powers as the search writes them: `a^2` is `square a` (the parser already does this),
//!    `a^0.5` `sqrt a`, `a^-1` `inverse a`, `a^-2` `inverse square a`, `a^-0.5`
//!    `inverse sqrt a`; any other constant exponent is `pow a c` (the power primitive's
//!    form, `SearchConfig::power_laws`), and so is the tree search's `exp(c*log(a))`. A
//!    constant raised to an input (`Q10^((T - T0)/10)`, `10^(A - B/(C + T))`) is
//!    `exp(c*e)`, the only way the search writes it.
//! 4. A negation `-a` of an input-dependent `a` is `mul c a` (the compiler writes `-1*a`);
//!    `1/a` with a literal 1 is `inverse a`, the search's operator (`k/a` stays `div c a`).
//! 5. The outer affine map is dropped: a program's output is `scale * root + offset` with
//!    both parameters outside its nodes, so the root's `c*r`, `r/c`, `r + c`, `c - r` and
//!    `-r` are `r` (repeatedly: `c*x + c` is `x`), `c/r` is `inverse r`, and
//!    `inverse pow a c` is `pow a c`.
//!
//! Nothing else is simplified: a law keeps the shape its handbook gives it
//! (`Ea/(R*T)` stays `div c mul c x`).
//!
//! # The built-in prior
//!
//! Trained on the 726 laws of `testdata/laws/laws.txt` (trigram, [`LawPrior::ORDER`]).
//! Every token the corpus uses, by count (end marks included, one per law; 17 of the 20:
//! `abs`, `gaussian` and `gaussian2` never occur, and cost the unigram floor):
//!
//! | token | count | token | count |
//! |---|---|---|---|
//! | `c` | 1769 | `square` | 145 |
//! | `x` | 1539 | `sqrt` | 103 |
//! | `mul` | 1077 | `inverse` | 88 |
//! | `</s>` | 726 | `log` | 79 |
//! | `div` | 542 | `sin` | 12 |
//! | `pow` | 351 | `cos` | 12 |
//! | `add` | 313 | `tanh` | 7 |
//! | `sub` | 299 | `tan` | 3 |
//! | `exp` | 170 |  |  |
//!
//! Codelengths in nats (`LawPrior::builtin().codelength_tokens`, end mark included; the
//! text is read with `x` (and `y`) as the inputs and every other name a constant):
//!
//! | structure | written | tokens | nats |
//! |---|---|---|---|
//! | power law | `c*x^c` | `pow x c` | 3.38 |
//! | power law in two inputs | `c*x^c*y^c` | `mul mul c pow x c pow x c` | 8.56 |
//! | exponential | `c*exp(c*x)` | `exp mul c x` | 4.23 |
//! | Arrhenius | `c*exp(-c/x)` | `exp div c x` | 5.82 |
//! | Michaelis-Menten | `c*x/(c + x)` | `div mul c x add c x` | 8.64 |
//! | pole (viscometer) | `c*x/(y - c)` | `div mul c x sub x c` | 8.43 |
//! | line | `c*x + c` | `x` | 3.29 |
//! | quadratic | `c*x^2 + c*x + c` | `add mul c square x mul c x` | 11.83 |
//! | logistic | `c/(1 + exp(-c*(x - c)))` | `inverse add c exp mul c sub x c` | 14.56 |
//! | tanh | `c*tanh(c*x + c)` | `tanh add mul c x c` | 17.06 |
//! | cos | `c*cos(c*x + c) + c` | `cos add mul c x c` | 14.56 |
//! | Gaussian, written | `c*exp(-(x - c)^2/c)` | `exp div mul c square sub x c c` | 13.85 |
//! | Gaussian, search operator | `gaussian(c*x + c)` | `gaussian add mul c x c` | 21.74 |

mod corpus;
mod ngram;
mod precision;
mod tokens;

#[cfg(test)]
mod feynman;
#[cfg(test)]
mod tests;

pub use corpus::{Law, parse_corpus};
pub use ngram::{KATZ_K, MIN_BACKOFF_MASS};
pub use precision::Codelengths;
pub use tokens::{Token, expr_tokens, program_tokens};

use crate::SrError;
use crate::program::Program;
use ngram::Ngram;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The prior over structures that [`crate::Criterion::Mdl`] charges a structure's description by
/// (issue 65). Serialised as `laws` or `uniform`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Prior {
    /// `2 L` for a structure whose operator tokens cost `L` nats under the back-off n-gram
    /// model of written laws ([`LawPrior::builtin`]): a power, a product or
    /// an exponential of a ratio is cheap, a `tanh`, a `cos` or a Gaussian dear, as in the
    /// handbooks (the default).
    #[default]
    Laws,
    /// `2 c ln(B)` for a structure of complexity `c` over an alphabet of `B` symbols: every
    /// operator alike.
    Uniform,
}

impl Prior {
    /// `laws` or `uniform`.
    pub fn name(self) -> &'static str {
        match self {
            Prior::Laws => "laws",
            Prior::Uniform => "uniform",
        }
    }
}

/// The corpus the built-in prior is trained on.
pub const BUILTIN_CORPUS: &str = include_str!("../../../../testdata/laws/laws.txt");

/// A back-off n-gram model of the prefix tokens of written laws: the codelength of a
/// structure in nats.
#[derive(Clone, Debug, PartialEq)]
pub struct LawPrior {
    model: Ngram,
    laws: usize,
    counts: BTreeMap<Token, usize>,
}

impl LawPrior {
    /// The order of the built-in model and of [`LawPrior::from_corpus`]: trigrams (an
    /// operator given its parent and grandparent in prefix order), backing off to bigrams
    /// and to the unigram floor.
    pub const ORDER: usize = 3;

    /// Trains a trigram model on a corpus in the format of `testdata/laws/laws.txt`.
    ///
    /// # Errors
    /// [`SrError::InvalidConfig`] naming the first malformed line ([`parse_corpus`]), or
    /// for a corpus without laws.
    pub fn from_corpus(text: &str) -> Result<Self, SrError> {
        let laws = parse_corpus(text)?;
        let sentences: Vec<Vec<Token>> = laws.iter().map(Law::tokens).collect();
        Self::from_sentences(&sentences, Self::ORDER)
    }

    /// Trains a model of the given order (1 to 6) on token sentences (start and end marks
    /// are added; any in the sentences are ignored).
    ///
    /// # Errors
    /// [`SrError::InvalidConfig`] for no sentences or an order outside 1 to 6.
    pub fn from_sentences(sentences: &[Vec<Token>], order: usize) -> Result<Self, SrError> {
        if sentences.is_empty() {
            return Err(SrError::InvalidConfig(
                "the laws corpus has no laws: add lines `name | target = expression | variables | source`".into(),
            ));
        }
        if !(1..=6).contains(&order) {
            return Err(SrError::InvalidConfig(format!(
                "n-gram order {order}: choose 1 to 6"
            )));
        }
        let mut counts = BTreeMap::new();
        for s in sentences {
            for &t in s.iter().chain([&Token::End]) {
                if t != Token::Start {
                    *counts.entry(t).or_insert(0) += 1;
                }
            }
        }
        Ok(LawPrior {
            model: Ngram::train(sentences, order),
            laws: sentences.len(),
            counts,
        })
    }

    /// The prior trained once on the corpus embedded in the library
    /// ([`BUILTIN_CORPUS`], `testdata/laws/laws.txt`).
    ///
    /// # Panics
    /// Never for the corpus shipped: the crate's tests parse every line of it.
    #[allow(clippy::expect_used)]
    pub fn builtin() -> &'static LawPrior {
        static PRIOR: OnceLock<LawPrior> = OnceLock::new();
        PRIOR.get_or_init(|| {
            LawPrior::from_corpus(BUILTIN_CORPUS).expect("the built-in laws corpus parses")
        })
    }

    /// The model's order `n`.
    pub fn order(&self) -> usize {
        self.model.order()
    }

    /// Number of laws trained on.
    pub fn laws(&self) -> usize {
        self.laws
    }

    /// How often each token occurs in the training sentences (end marks included).
    pub fn token_counts(&self) -> &BTreeMap<Token, usize> {
        &self.counts
    }

    /// `P(token | history)`: the history is the tokens before it, oldest first, starting
    /// with [`Token::Start`] marks (the model uses the last `order - 1`).
    pub fn probability(&self, history: &[Token], token: Token) -> f64 {
        self.model.prob(token, history)
    }

    /// `-ln P(token | history)` in nats ([`LawPrior::probability`]).
    pub fn cost(&self, history: &[Token], token: Token) -> f64 {
        -self.probability(history, token).ln()
    }

    /// The codelength in nats of a whole prefix token sequence: the sum of each token's cost
    /// given the ones before it, from the start marks to the end mark (added here; leave
    /// them out of `tokens`).
    pub fn codelength_tokens(&self, tokens: &[Token]) -> f64 {
        let pad = self.order() - 1;
        let mut seq = vec![Token::Start; pad];
        seq.extend(
            tokens
                .iter()
                .copied()
                .filter(|t| *t != Token::Start && *t != Token::End),
        );
        seq.push(Token::End);
        (pad..seq.len()).map(|i| self.cost(&seq[..i], seq[i])).sum()
    }

    /// The codelength in nats of a search program's structure ([`program_tokens`]);
    /// infinite for nodes that are not one well-formed expression.
    pub fn codelength_program(&self, program: &Program) -> f64 {
        program_tokens(program).map_or(f64::INFINITY, |t| self.codelength_tokens(&t))
    }
}
