//! The rewrite rules of the module docs, [`Effort`] (which rules, and the limits of
//! iterations and e-nodes), and the loop that runs them to saturation.

use super::language::{Fold, Graph, Math};
use egg::{Id, Rewrite, Subst, rewrite};
use std::sync::OnceLock;

fn var(name: &str) -> egg::Var {
    name.parse().expect("a pattern variable")
}

fn is_const(v: &str) -> impl Fn(&mut Graph, Id, &Subst) -> bool + use<> {
    let v = var(v);
    move |g, _, s| g[s[v]].data.is_some()
}

fn is_pos(v: &str) -> impl Fn(&mut Graph, Id, &Subst) -> bool + use<> {
    let v = var(v);
    move |g, _, s| g[s[v]].data.is_some_and(|x| x > 0.0)
}

fn is_neg(v: &str) -> impl Fn(&mut Graph, Id, &Subst) -> bool + use<> {
    let v = var(v);
    move |g, _, s| g[s[v]].data.is_some_and(|x| x < 0.0)
}

fn is_nonzero_const(v: &str) -> impl Fn(&mut Graph, Id, &Subst) -> bool + use<> {
    let v = var(v);
    move |g, _, s| g[s[v]].data.is_some_and(|x| x != 0.0)
}

/// How hard [`canonical_expr`](super::canonical_expr) and the structure keys try: the rules
/// and the limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Effort {
    /// Every rule of the module docs, up to 30 iterations and 5,000 e-nodes.
    #[default]
    Full,
    /// Every rule but the six that multiply the forms of sums and products (a number or a
    /// sign over a sum and back, `(a*b)^2` for `a` not a number, `exp(a)*exp(b)`) and the
    /// three that cancel (`a*(1/a)`, `a^2*(1/a)`, `sqrt(a)^2`), up to 12
    /// iterations and 2,000 e-nodes: reordering, the shorthands, constant absorption in
    /// sums, products, `exp`, `log`, `sqrt`, squares and inverses, at a tenth of the cost
    /// (mean 73 us against 0.92 ms per call on programs of complexity up to 10 with affine
    /// inputs; docs/benchmarks.md).
    /// For use inside a search; it tells apart some structures `Full` identifies
    /// (`c*(x + c)` and `c*x + c`, `x - (y + z)` and `x - y - z`).
    Fast,
}

impl Effort {
    fn iterations(self) -> usize {
        match self {
            Effort::Full => 30,
            Effort::Fast => 12,
        }
    }

    fn nodes(self) -> usize {
        match self {
            Effort::Full => 5_000,
            Effort::Fast => 2_000,
        }
    }
}

#[rustfmt::skip]
fn fast_rules() -> Vec<Rewrite<Math, Fold>> {
    vec![
        rewrite!("add-comm"; "(+ ?a ?b)" => "(+ ?b ?a)"),
        rewrite!("mul-comm"; "(* ?a ?b)" => "(* ?b ?a)"),
        rewrite!("add-assoc"; "(+ ?a (+ ?b ?c))" => "(+ (+ ?a ?b) ?c)"),
        rewrite!("mul-assoc"; "(* ?a (* ?b ?c))" => "(* (* ?a ?b) ?c)"),
        rewrite!("add-0"; "(+ ?a 0.0)" => "?a"),
        rewrite!("mul-1"; "(* ?a 1.0)" => "?a"),
        rewrite!("mul-0"; "(* ?a 0.0)" => "0.0"),
        rewrite!("add-same"; "(+ ?a ?a)" => "(* 2.0 ?a)"),
        rewrite!("add-like"; "(+ (* ?c ?a) (* ?d ?a))" => "(* (+ ?c ?d) ?a)"
            if is_const("?c") if is_const("?d")),
        rewrite!("add-like-1"; "(+ ?a (* ?c ?a))" => "(* (+ 1.0 ?c) ?a)" if is_const("?c")),
        rewrite!("mul-same"; "(* ?a ?a)" => "(square ?a)"),
        rewrite!("inv-mul"; "(inv (* ?a ?b))" => "(* (inv ?a) (inv ?b))"),
        rewrite!("inv-inv"; "(inv (inv ?a))" => "?a"),
        rewrite!("square-inv"; "(square (inv ?a))" => "(inv (square ?a))"),
        rewrite!("square-mul-const"; "(square (* ?c ?a))" => "(* (square ?c) (square ?a))"
            if is_const("?c")),
        rewrite!("abs-mul"; "(abs (* ?a ?b))" => "(* (abs ?a) (abs ?b))"),
        rewrite!("abs-abs"; "(abs (abs ?a))" => "(abs ?a)"),
        rewrite!("abs-square"; "(abs (square ?a))" => "(square ?a)"),
        rewrite!("square-abs"; "(square (abs ?a))" => "(square ?a)"),
        rewrite!("abs-exp"; "(abs (exp ?a))" => "(exp ?a)"),
        rewrite!("sqrt-square"; "(sqrt (square ?a))" => "(abs ?a)"),
        rewrite!("sqrt-mul-pos"; "(sqrt (* ?c ?a))" => "(* (sqrt ?c) (sqrt ?a))" if is_pos("?c")),
        rewrite!("sqrt-mul-neg"; "(sqrt (* ?c ?a))" => "(* (sqrt (* -1.0 ?c)) (sqrt (* -1.0 ?a)))"
            if is_neg("?c")),
        rewrite!("exp-add-const"; "(exp (+ ?c ?a))" => "(* (exp ?c) (exp ?a))" if is_const("?c")),
        rewrite!("log-exp"; "(log (exp ?a))" => "?a"),
        rewrite!("log-mul-pos"; "(log (* ?c ?a))" => "(+ (log ?c) (log ?a))" if is_pos("?c")),
        rewrite!("log-mul-neg"; "(log (* ?c ?a))" => "(+ (log (* -1.0 ?c)) (log (* -1.0 ?a)))"
            if is_neg("?c")),
        rewrite!("log-inv"; "(log (inv ?a))" => "(* -1.0 (log ?a))"),
        rewrite!("log-sqrt"; "(log (sqrt ?a))" => "(* 0.5 (log ?a))"),
        rewrite!("log-square"; "(log (square ?a))" => "(* 2.0 (log (abs ?a)))"),
        rewrite!("sin-neg"; "(sin (* ?c ?a))" => "(* -1.0 (sin (* (* -1.0 ?c) ?a)))" if is_neg("?c")),
        rewrite!("tanh-neg"; "(tanh (* ?c ?a))" => "(* -1.0 (tanh (* (* -1.0 ?c) ?a)))" if is_neg("?c")),
        rewrite!("tan-neg"; "(tan (* ?c ?a))" => "(* -1.0 (tan (* (* -1.0 ?c) ?a)))" if is_neg("?c")),
        rewrite!("cos-neg"; "(cos (* ?c ?a))" => "(cos (* (* -1.0 ?c) ?a))" if is_neg("?c")),
        rewrite!("neg-sin"; "(* -1.0 (sin ?a))" => "(sin (* -1.0 ?a))"),
        rewrite!("neg-tanh"; "(* -1.0 (tanh ?a))" => "(tanh (* -1.0 ?a))"),
        rewrite!("neg-tan"; "(* -1.0 (tan ?a))" => "(tan (* -1.0 ?a))"),
    ]
}

/// The rules [`Effort::Full`] adds: the ones that multiply the forms of sums and products.
#[rustfmt::skip]
fn more_rules() -> Vec<Rewrite<Math, Fold>> {
    vec![
        rewrite!("square-mul"; "(square (* ?a ?b))" => "(* (square ?a) (square ?b))"),
        rewrite!("distribute-neg"; "(* -1.0 (+ ?a ?b))" => "(+ (* -1.0 ?a) (* -1.0 ?b))"),
        rewrite!("factor-neg"; "(+ (* -1.0 ?a) (* -1.0 ?b))" => "(* -1.0 (+ ?a ?b))"),
        rewrite!("distribute-const"; "(* ?c (+ ?a ?d))" => "(+ (* ?c ?a) (* ?c ?d))"
            if is_const("?c") if is_const("?d")),
        rewrite!("factor-const"; "(+ (* ?c ?a) ?d)" => "(* ?c (+ ?a (* ?d (inv ?c))))"
            if is_nonzero_const("?c") if is_const("?d")),
        rewrite!("exp-mul"; "(* (exp ?a) (exp ?b))" => "(exp (+ ?a ?b))"),
        // cancelling: for the reported forms (a units composition's `m2/m1*m1^2`); left
        // out of `Fast`, whose keys steer the search (with them there, the search's path
        // changed on 165 of the 200 AI Feynman rows for no gain: docs/benchmarks.md)
        rewrite!("mul-inv-same"; "(* ?a (inv ?a))" => "1.0"),
        rewrite!("square-over"; "(* (square ?a) (inv ?a))" => "?a"),
        rewrite!("square-sqrt"; "(square (sqrt ?a))" => "?a"),
    ]
}

fn rules(effort: Effort) -> &'static [Rewrite<Math, Fold>] {
    static FAST: OnceLock<Vec<Rewrite<Math, Fold>>> = OnceLock::new();
    static FULL: OnceLock<Vec<Rewrite<Math, Fold>>> = OnceLock::new();
    match effort {
        Effort::Fast => FAST.get_or_init(fast_rules),
        Effort::Full => FULL.get_or_init(|| {
            let mut r = fast_rules();
            r.extend(more_rules());
            r
        }),
    }
}

/// Runs the rules of `effort` to saturation or to its limits; true if saturated.
pub(super) fn saturate(g: &mut Graph, effort: Effort) -> bool {
    g.rebuild();
    let rules = rules(effort);
    for _ in 0..effort.iterations() {
        let before = (g.total_size(), g.number_of_classes());
        let matches: Vec<_> = rules.iter().map(|r| r.search(g)).collect();
        let mut changed = false;
        for (r, m) in rules.iter().zip(&matches) {
            changed |= !r.apply(g, m).is_empty();
            if g.total_size() > effort.nodes() {
                g.rebuild();
                return false;
            }
        }
        g.rebuild();
        if !changed && before == (g.total_size(), g.number_of_classes()) {
            return true;
        }
    }
    false
}
