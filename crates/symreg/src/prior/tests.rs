//! Tests of the corpus, the tokens and the n-gram model.

use super::feynman::{FEYNMAN, structure_key};
use super::*;
use crate::infix::parse;
use crate::ops::Op;
use crate::program::Node;
use approx::assert_relative_eq;
use std::collections::BTreeSet;

/// The tokens of `text` with `x` and `y` as inputs and every other name a constant.
fn toks(text: &str) -> Vec<Token> {
    match parse(text) {
        Ok(p) => expr_tokens(&p.expr, &["x", "y"]),
        Err(e) => panic!("{text}: {e}"),
    }
}

fn cost(text: &str) -> f64 {
    LawPrior::builtin().codelength_tokens(&toks(text))
}

/// Every law line of the shipped corpus parses (the error names the line), and there are
/// at least 300 of them, each with a source.
#[test]
fn every_corpus_line_parses() {
    let laws = match parse_corpus(BUILTIN_CORPUS) {
        Ok(l) => l,
        Err(e) => panic!("{e}"),
    };
    let lines = BUILTIN_CORPUS
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.trim().starts_with('#'))
        .count();
    assert_eq!(laws.len(), lines);
    assert!(laws.len() >= 300, "{} laws", laws.len());
    let mut names = BTreeSet::new();
    for law in &laws {
        assert!(
            names.insert(law.name.as_str()),
            "line {}: `{}` twice",
            law.line,
            law.name
        );
        assert!(!law.tokens().is_empty(), "line {}", law.line);
    }
    assert_eq!(LawPrior::builtin().laws(), laws.len());
}

/// A malformed line is refused with its line number and name.
#[test]
fn a_bad_line_is_named() {
    let text = "# comment\nok | y = a*x | x | A (2000)\nbad | y = a*foo(x) | x | B (2001)\n";
    match parse_corpus(text) {
        Err(SrError::InvalidConfig(m)) => {
            assert!(
                m.contains("line 3") && m.contains("`bad`") && m.contains("foo"),
                "{m}"
            )
        }
        other => panic!("{other:?}"),
    }
    for bad in [
        "a | y = x | x",
        "a | y x | x | S",
        "a | y = k*x |  | S",
        "a | y = k*x | z | S",
    ] {
        assert!(
            matches!(parse_corpus(bad), Err(SrError::InvalidConfig(_))),
            "{bad}"
        );
    }
    assert!(LawPrior::from_corpus("# nothing\n").is_err());
}

/// Every distribution the model holds sums to 1 over the predicted tokens (1e-9), for
/// each history it has seen and for histories it has not, at orders 1 to 3.
#[test]
fn probabilities_sum_to_one() {
    let laws = parse_corpus(BUILTIN_CORPUS).unwrap_or_default();
    let sentences: Vec<Vec<Token>> = laws.iter().map(Law::tokens).collect();
    let unseen = [
        vec![Token::Op(Op::Gaussian2), Token::Op(Op::Gaussian)],
        vec![Token::Start, Token::Op(Op::Tan)],
        vec![],
    ];
    for order in 1..=3 {
        let prior = match LawPrior::from_sentences(&sentences, order) {
            Ok(p) => p,
            Err(e) => panic!("{e}"),
        };
        let histories: Vec<Vec<Token>> = prior
            .model
            .histories()
            .map(<[Token]>::to_vec)
            .chain(unseen.iter().cloned())
            .collect();
        for h in &histories {
            let sum: f64 = Token::PREDICTED
                .iter()
                .map(|&w| prior.probability(h, w))
                .sum();
            assert!((sum - 1.0).abs() < 1e-9, "order {order}, {h:?}: {sum}");
        }
    }
}

/// The toy corpus `x`, `x`, `exp x` at order 2, computed by hand. Its counts of counts
/// (n1 = 2, n2 = 1, n3 = 1) leave no Good-Turing discount in (0, 1), so absolute
/// discounting with D = n1/(n1 + 2 n2) = 1/2 applies; the unigram is (n + 1/2)/(7 + 10).
#[test]
fn toy_corpus_matches_hand_computation() {
    let x = Token::Var;
    let exp = Token::Op(Op::Exp);
    let p = match LawPrior::from_sentences(&[vec![x], vec![x], vec![exp, x]], 2) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    let s = Token::Start;
    let g = Token::Op(Op::Gaussian);
    let cases = [
        // after <s>: x seen 2 of 3, exp 1 of 3; alpha = (1/3) / (1 - 5/17) = 17/36
        (vec![s], x, 1.5 / 3.0),
        (vec![s], exp, 0.5 / 3.0),
        (vec![s], Token::End, 17.0 / 36.0 * 3.5 / 17.0),
        (vec![s], g, 17.0 / 36.0 * 0.5 / 17.0),
        // after x: the end 3 of 3, d = 5/6; alpha = (1/6) / (1 - 3.5/17) = 17/81
        (vec![x], Token::End, 5.0 / 6.0),
        (vec![x], x, 17.0 / 81.0 * 3.5 / 17.0),
        // after exp: x 1 of 1, d = 1/2; alpha = (1/2) / (1 - 3.5/17) = 17/27
        (vec![exp], x, 0.5),
        (vec![exp], Token::End, 17.0 / 27.0 * 3.5 / 17.0),
        // an unseen history backs off to the unigram
        (vec![g], x, 3.5 / 17.0),
    ];
    for (h, w, want) in cases {
        assert_relative_eq!(p.probability(&h, w), want, max_relative = 1e-12);
    }
    let want = -(1.0f64 / 6.0).ln() - 0.5f64.ln() - (5.0f64 / 6.0).ln();
    assert_relative_eq!(p.codelength_tokens(&[exp, x]), want, max_relative = 1e-12);
}

/// An unseen bigram backs off: after `exp` (seen often) the tokens never seen there get
/// `alpha(exp) P(w)`, one ratio to the unigram for all of them, and a finite cost.
#[test]
fn unseen_bigram_backs_off() {
    let laws = parse_corpus(BUILTIN_CORPUS).unwrap_or_default();
    let sentences: Vec<Vec<Token>> = laws.iter().map(Law::tokens).collect();
    let p = match LawPrior::from_sentences(&sentences, 2) {
        Ok(p) => p,
        Err(e) => panic!("{e}"),
    };
    let h = [Token::Op(Op::Exp)];
    let unseen: Vec<Token> = Token::PREDICTED
        .iter()
        .copied()
        .filter(|&w| p.model.count(&h, w) == 0)
        .collect();
    assert!(unseen.contains(&Token::Op(Op::Gaussian)), "{unseen:?}");
    assert!(unseen.len() >= 2);
    let ratio = |w: Token| p.probability(&h, w) / p.probability(&[], w);
    let r0 = ratio(unseen[0]);
    assert!(r0 > 0.0 && r0 < 1.0, "{r0}");
    for &w in &unseen {
        assert_relative_eq!(ratio(w), r0, max_relative = 1e-12);
        assert!(p.cost(&h, w).is_finite());
    }
}

/// An operator the corpus never uses has a finite cost, larger than any operator it uses.
#[test]
fn unseen_operator_has_a_finite_large_cost() {
    let p = LawPrior::builtin();
    assert!(!p.token_counts().contains_key(&Token::Op(Op::Gaussian)));
    let h = [Token::Start, Token::Start];
    let g = p.cost(&h, Token::Op(Op::Gaussian));
    assert!(g.is_finite() && g > 8.0, "{g}");
    for &t in p.token_counts().keys() {
        assert!(p.cost(&h, t) < g, "{t}");
    }
}

/// Laws' shapes cost less than waves and sigmoids: a power law and an Arrhenius term
/// less than `tanh` and `cos`; a line less than a cosine.
#[test]
fn laws_cost_less_than_waves_and_sigmoids() {
    let tanh = cost("c*tanh(c*x + c)");
    let cos = cost("c*cos(c*x + c) + c");
    for law in ["c*x^c", "c*exp(-c/x)"] {
        assert!(cost(law) < tanh, "{law}: {} vs {tanh}", cost(law));
        assert!(cost(law) < cos, "{law}: {} vs {cos}", cost(law));
    }
    assert!(cost("c*x + c") < cos);
    assert!(cost("c*x^c") < cost("c*x^c + c*sin(c*x)"));
}

/// A program costs what the same expression read from text costs, whichever way the
/// power is written.
#[test]
fn program_codelength_equals_text() {
    let (x, c) = (Node::Var(0), Node::Const);
    let op = Node::Op;
    let cases: [(&str, Vec<Node>); 6] = [
        ("c*x^c", vec![c, x, c, op(Op::Pow), op(Op::Mul)]),
        (
            "exp(c*log(x))",
            vec![c, x, op(Op::Log), op(Op::Mul), op(Op::Exp)],
        ),
        (
            "c*exp(-c/x)",
            vec![c, c, x, op(Op::Div), op(Op::Exp), op(Op::Mul)],
        ),
        (
            "c*tanh(c*x + c)",
            vec![
                c,
                c,
                x,
                op(Op::Mul),
                c,
                op(Op::Add),
                op(Op::Tanh),
                op(Op::Mul),
            ],
        ),
        (
            "x^2 + 1/x",
            vec![x, op(Op::Square), x, op(Op::Inverse), op(Op::Add)],
        ),
        (
            "c*x/(c + y)",
            vec![c, x, op(Op::Mul), c, Node::Var(1), op(Op::Add), op(Op::Div)],
        ),
    ];
    let p = LawPrior::builtin();
    for (text, nodes) in cases {
        let program = Program {
            nodes,
            affine: false,
        };
        assert!(program.is_valid(), "{text}");
        assert_eq!(program_tokens(&program), Some(toks(text)), "{text}");
        assert_relative_eq!(
            p.codelength_program(&program),
            cost(text),
            max_relative = 1e-12
        );
    }
    let broken = Program {
        nodes: vec![x, op(Op::Add)],
        affine: false,
    };
    assert_eq!(p.codelength_program(&broken), f64::INFINITY);
}

/// Laws whose structure is that of an AI Feynman equation, reviewed one by one: each is a
/// monomial (a product of two to four symbols, some divided or squared), a shape every
/// product of measured quantities has, and a different law from the equation it shares it
/// with (Ohm's `R*I` and the friction `mu*N` of I.12.1; Archard's `K*F*s/H` and the
/// `Y*A*x/d` of II.38.3). A structure with a sum, a difference or a function is never
/// accepted here.
const REVIEWED_MONOMIALS: [&str; 15] = [
    "Ohm's law",
    "Henry's law",
    "Preston polishing rate",
    "Bolt tightening torque",
    "Wiedemann-Franz law",
    "Wien displacement law",
    "Critical radius of insulation",
    "Film theory mass transfer",
    "Welding heat input",
    "Archard wear",
    "Corrosion rate from current",
    "Mass-action incidence",
    "Two-suffix Margules",
    "Joule heating",
    "Hazen effective-size permeability",
];

/// No law of the corpus is an AI Feynman equation: the structure keys (names renamed to
/// one symbol, sums and products sorted, quotients and roots as powers) differ, except for
/// the monomials reviewed in [`REVIEWED_MONOMIALS`]; and no law is named after one of
/// them. When
/// `/work/shared/data/feynman100.csv` is present, the embedded list is checked against it.
#[test]
fn no_ai_feynman_equation_in_corpus() {
    let feynman: Vec<(&str, String)> = FEYNMAN
        .iter()
        .filter_map(|(id, f)| parse(f).ok().map(|p| (*id, structure_key(&p.expr))))
        .collect();
    // the four with arcsin or arccos do not parse, and no law uses those
    assert!(feynman.len() >= 96, "{}", feynman.len());
    let laws = parse_corpus(BUILTIN_CORPUS).unwrap_or_default();
    let mut matches = Vec::new();
    for law in &laws {
        let key = structure_key(&law.parsed.expr);
        for (id, k) in &feynman {
            if *k == key && !REVIEWED_MONOMIALS.contains(&law.name.as_str()) {
                matches.push(format!(
                    "line {} `{}` has the shape of {id}",
                    law.line, law.name
                ));
            }
        }
    }
    assert!(matches.is_empty(), "{}", matches.join("\n"));
    for name in REVIEWED_MONOMIALS {
        let Some(law) = laws.iter().find(|l| l.name == name) else {
            panic!("reviewed law `{name}` is not in the corpus");
        };
        let key = structure_key(&law.parsed.expr);
        let rest = key.replace("mul(", "").replace("pow(", "");
        assert!(
            key.starts_with("mul(") && rest.chars().all(|c| "s,()-.0123456789".contains(c)),
            "`{name}` is not a monomial: {key}"
        );
    }
    let banned = [
        "planck",
        "shockley",
        "barometric",
        "ideal gas",
        "hooke",
        "bose",
        "doppler",
        "snell",
        "coulomb's law",
        "fourier's law",
        "larmor",
        "lorentz",
        "langevin",
        "lensmaker",
    ];
    for law in &laws {
        let name = law.name.to_lowercase();
        assert!(
            !banned.iter().any(|b| name.contains(b)),
            "line {}: {}",
            law.line,
            law.name
        );
    }
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/feynman100.csv");
    if let Ok(csv) = std::fs::read_to_string(path) {
        let formulas: Vec<&str> = csv
            .lines()
            .skip(1)
            .filter_map(|l| l.split(',').nth(3))
            .collect();
        let embedded: Vec<&str> = FEYNMAN.iter().map(|(_, f)| *f).collect();
        assert_eq!(formulas, embedded);
    }
}

/// The suite laws whose shape written laws share by the dozen: `mammals`' power law
/// `a*x^b` (Hollomon, Paris, Norton, Freundlich, ...) and `hills`' sum of two proportional
/// terms. The laws themselves (allometry of brain and body, Naismith's rule) are left out
/// by name; the shape cannot be, or the prior would not know a power law.
const SHARED_SUITE_SHAPES: [&str; 2] = ["mammals", "hills"];

/// Nothing from the real-law suite (`testdata/real/laws.json`) is in the corpus: no law
/// has the structure of the five suite laws with a shape of their own (asymptotic growth,
/// the logistic, the four-parameter logistic, the bi-exponential, the asymptotic
/// exponential), and no law is named after any of the seven.
#[test]
fn no_real_law_suite_entry_in_corpus() {
    let suite: serde_json::Value =
        match serde_json::from_str(include_str!("../../../../testdata/real/laws.json")) {
            Ok(v) => v,
            Err(e) => panic!("{e}"),
        };
    let keys: Vec<(String, String)> = suite
        .as_object()
        .into_iter()
        .flatten()
        .filter_map(|(name, entry)| {
            let law = entry.get("law")?.as_str()?;
            parse(law)
                .ok()
                .map(|p| (name.clone(), structure_key(&p.expr)))
        })
        .collect();
    assert_eq!(keys.len(), 7);
    let laws = parse_corpus(BUILTIN_CORPUS).unwrap_or_default();
    let banned = [
        "naismith",
        "logistic",
        "verhulst",
        "allometr",
        "biexponential",
        "bi-exponential",
        "two-compartment",
        "four-parameter",
        "asymptotic regression",
        "mitscherlich",
    ];
    let mut found = Vec::new();
    for law in &laws {
        let key = structure_key(&law.parsed.expr);
        for (name, k) in &keys {
            if *k == key && !SHARED_SUITE_SHAPES.contains(&name.as_str()) {
                found.push(format!(
                    "line {} `{}` is the suite's {name}",
                    law.line, law.name
                ));
            }
        }
        let lower = law.name.to_lowercase();
        if banned.iter().any(|b| lower.contains(b)) {
            found.push(format!(
                "line {} `{}` is named after a suite law",
                law.line, law.name
            ));
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

/// The tables in the module docs are the built-in prior's (regenerate: copy them from
/// this test's failure message).
#[test]
fn docs_tables_are_current() {
    let p = LawPrior::builtin();
    let mut counts: Vec<(Token, usize)> = p.token_counts().iter().map(|(&t, &n)| (t, n)).collect();
    counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let top: Vec<String> = counts
        .iter()
        .take(20)
        .map(|(t, n)| format!("`{t}` | {n}"))
        .collect();
    let (left, right) = top.split_at(top.len().div_ceil(2));
    let rows: Vec<String> = left
        .iter()
        .zip(right.iter().map(Some).chain(std::iter::repeat(None)))
        .map(|(l, r)| format!("//! | {l} | {} |", r.map_or(" | ", |r| r.as_str())))
        .collect();
    let structures: [(&str, &str); 12] = [
        ("power law", "c*x^c"),
        ("power law in two inputs", "c*x^c*y^c"),
        ("exponential", "c*exp(c*x)"),
        ("Arrhenius", "c*exp(-c/x)"),
        ("Michaelis-Menten", "c*x/(c + x)"),
        ("pole (viscometer)", "c*x/(y - c)"),
        ("line", "c*x + c"),
        ("quadratic", "c*x^2 + c*x + c"),
        ("logistic", "c/(1 + exp(-c*(x - c)))"),
        ("tanh", "c*tanh(c*x + c)"),
        ("cos", "c*cos(c*x + c) + c"),
        ("Gaussian, written", "c*exp(-(x - c)^2/c)"),
    ];
    let row = |name: &str, written: &str, t: &[Token]| {
        let names: Vec<&str> = t.iter().map(|t| t.name()).collect();
        format!(
            "//! | {name} | `{written}` | `{}` | {:.2} |",
            names.join(" "),
            p.codelength_tokens(t)
        )
    };
    let mut costs: Vec<String> = structures
        .iter()
        .map(|(name, text)| row(name, text, &toks(text)))
        .collect();
    let gaussian_op = [
        Token::Op(Op::Gaussian),
        Token::Op(Op::Add),
        Token::Op(Op::Mul),
        Token::Const,
        Token::Var,
        Token::Const,
    ];
    costs.push(row(
        "Gaussian, search operator",
        "gaussian(c*x + c)",
        &gaussian_op,
    ));
    let (rows, costs) = (rows.join("\n"), costs.join("\n"));
    let docs = include_str!("mod.rs");
    assert!(
        docs.contains(&rows) && docs.contains(&costs),
        "the module docs' tables are stale; they are now:\n{rows}\n\n{costs}"
    );
}
