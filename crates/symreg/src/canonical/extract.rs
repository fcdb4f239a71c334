//! Reading the form back: the cheapest term of every e-class as prefix tokens, by length
//! and then a total order on tokens, so the form read does not depend on the order the
//! e-graph was built in.

use super::is_literal;
use super::language::{Bits, Graph, Math, order_key};
use egg::{Id, Language};
use std::cmp::Ordering;

/// One token of a term in prefix order. The derived order is the tie-break of reading back:
/// parameters (all equal) in structure keys, then numbers by size and sign, then inputs by
/// name, then operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum Tok {
    /// A parameter, in a structure key.
    Gen,
    /// A number: the total-order key of its magnitude, then 0 for positive and 1 for
    /// negative (so `cos(2*x)` reads back rather than its equal `cos(-2*x)`).
    Num(u64, u8),
    /// An input.
    Var(u32),
    /// An operator, by [`tag`].
    Op(u8),
}

/// The token of a number (see [`Tok::Num`]).
pub(super) fn num_tok(v: f64) -> Tok {
    Tok::Num(order_key(v.abs()), u8::from(v.is_sign_negative()))
}

/// Operators' tags (their order among themselves) and arities.
pub(super) const TAGS: [(u8, usize); 13] = [
    (0, 2),  // +
    (1, 2),  // *
    (2, 2),  // pow
    (3, 1),  // inv
    (4, 1),  // exp
    (5, 1),  // log
    (6, 1),  // sqrt
    (7, 1),  // square
    (8, 1),  // sin
    (9, 1),  // cos
    (10, 1), // tanh
    (11, 1), // tan
    (12, 1), // abs
];

fn tag(n: &Math) -> Option<u8> {
    Some(match n {
        Math::Add(_) => 0,
        Math::Mul(_) => 1,
        Math::Pow(_) => 2,
        Math::Inv(_) => 3,
        Math::Exp(_) => 4,
        Math::Log(_) => 5,
        Math::Sqrt(_) => 6,
        Math::Square(_) => 7,
        Math::Sin(_) => 8,
        Math::Cos(_) => 9,
        Math::Tanh(_) => 10,
        Math::Tan(_) => 11,
        Math::Abs(_) => 12,
        Math::Num(_) | Math::Var(_) => return None,
    })
}

/// Cost order of two token sequences: length (node count), then lexicographic.
fn cost_cmp(a: &[Tok], b: &[Tok]) -> Ordering {
    a.len().cmp(&b.len()).then_with(|| a.cmp(b))
}

/// Cost order of two terms of one class with `fewest`: length, then the fewer parameters
/// ([`Tok::Gen`]), then lexicographic. Of two forms of one length the one with fewer
/// constants is the absorbed one: `-sqrt(c*x)` and `c*sqrt(c*x)` are both `c*sqrt(-x)` (a
/// form the second's e-graph holds too), where the token order alone would read back the
/// second, whose two constants only one program can fill. Monotone in every child, as
/// [`cost_cmp`] is: a parent's length and parameter count are sums of its children's.
fn class_cmp(a: &[Tok], b: &[Tok], fewest: bool) -> Ordering {
    let gens = |t: &[Tok]| t.iter().filter(|k| **k == Tok::Gen).count();
    a.len()
        .cmp(&b.len())
        .then_with(|| {
            if fewest {
                gens(a).cmp(&gens(b))
            } else {
                Ordering::Equal
            }
        })
        .then_with(|| a.cmp(b))
}

/// The cheapest term of every class, as its prefix tokens (see the module docs), read from
/// the class of `root`; with `fewest`, of two terms of one length the one with fewer
/// parameters ([`class_cmp`]).
pub(super) fn extract(g: &Graph, root: Id, key: bool, fewest: bool) -> Vec<Tok> {
    let slots = g
        .classes()
        .map(|c| usize::from(c.id) + 1)
        .max()
        .unwrap_or(0);
    let mut best: Vec<Option<Vec<Tok>>> = vec![None; slots];
    let tok_of = |b: Bits| {
        let v = b.value();
        if key && !is_literal(v) {
            Tok::Gen
        } else {
            num_tok(v)
        }
    };
    let mut cand: Vec<Tok> = Vec::new();
    loop {
        let mut changed = false;
        for class in g.classes() {
            let slot = usize::from(class.id);
            for node in &class.nodes {
                cand.clear();
                match node {
                    Math::Num(b) => cand.push(tok_of(*b)),
                    Math::Var(v) => cand.push(Tok::Var(v.0)),
                    _ => {
                        let ch = node.children();
                        let mut kids: [&[Tok]; 2] = [&[], &[]];
                        let mut known = true;
                        for (k, c) in kids.iter_mut().zip(ch) {
                            match &best[usize::from(g.find(*c))] {
                                Some(t) => *k = t,
                                None => known = false,
                            }
                        }
                        if !known {
                            continue;
                        }
                        let kids = &mut kids[..ch.len()];
                        let len = 1 + kids.iter().map(|k| k.len()).sum::<usize>();
                        if best[slot].as_ref().is_some_and(|cur| cur.len() < len) {
                            continue;
                        }
                        if matches!(node, Math::Add(_) | Math::Mul(_)) {
                            kids.sort_by(|a, b| cost_cmp(a, b));
                        }
                        cand.push(Tok::Op(tag(node).unwrap_or(0)));
                        for k in kids.iter() {
                            cand.extend_from_slice(k);
                        }
                    }
                }
                let better = best[slot]
                    .as_ref()
                    .is_none_or(|cur| class_cmp(&cand, cur, fewest) == Ordering::Less);
                if better {
                    best[slot] = Some(cand.clone());
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    best.get_mut(usize::from(g.find(root)))
        .and_then(Option::take)
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::canonical::language::from_order_key;

    #[test]
    fn order_keys_follow_total_order() {
        let vs = [
            f64::NEG_INFINITY,
            -2.0,
            -0.0,
            0.0,
            1e-300,
            3.0,
            f64::INFINITY,
        ];
        for w in vs.windows(2) {
            assert!(order_key(w[0]) < order_key(w[1]));
        }
        for v in vs {
            assert_eq!(from_order_key(order_key(v)).to_bits(), v.to_bits());
        }
    }
}
