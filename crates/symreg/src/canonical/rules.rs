//! The rewrite rules of the module docs, [`Effort`] (which rules, and the limits of
//! iterations and e-nodes), and the loop that runs them to saturation.

use super::language::{Fold, Graph, Math};
use egg::{Id, Language, Rewrite, Subst, rewrite};
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
    /// three that cancel (`a*(1/a)`, `a^2*(1/a)`, `sqrt(a)^2`), the three powers of an
    /// exponential (`1/exp(a)`, `exp(a)^2`, `sqrt(exp(a))`), and reading back without the
    /// tie-break by fewer parameters, up to 12
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

/// The rules [`Effort::Full`] adds: the ones that multiply the forms of sums and products,
/// the cancelling ones and the powers of an exponential (out of `Fast`, whose keys steer
/// the search).
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
        // powers of an exponential are exponentials: `c/exp(c*x)` is `c*exp(c*x)`
        rewrite!("inv-exp"; "(inv (exp ?a))" => "(exp (* -1.0 ?a))"),
        rewrite!("square-exp"; "(square (exp ?a))" => "(exp (* 2.0 ?a))"),
        rewrite!("sqrt-exp"; "(sqrt (exp ?a))" => "(exp (* 0.5 ?a))"),
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

/// The matches of every rule in one iteration, rule by rule.
type Matches = Vec<Vec<egg::SearchMatches<'static, Math>>>;

/// Runs the rules of `effort` to saturation or to its limits; true if saturated.
///
/// Each iteration searches only the e-classes where a match can be new: those whose
/// e-nodes or constant changed in the previous iteration (or are new), and their parents
/// and grandparents, since no pattern here looks deeper than a grandchild (`(exp (+ ?c ?a))`
/// with `?c` a number). A match that involves no changed class was there one iteration
/// earlier and was applied then, so applying it again adds nothing: the e-graph grows as
/// if every class were searched, in the same order, at a fraction of the cost.
pub(super) fn saturate(g: &mut Graph, effort: Effort) -> bool {
    let mut dirty = Dirty::default();
    saturate_with(g, effort, |g, rules| {
        dirty.update(g);
        (!dirty.list.is_empty()).then(|| rules.iter().map(|r| dirty.search(r, g)).collect())
    })
}

/// [`saturate`] as it was before it searched only the changed classes: every class, every
/// iteration (the reference its tests compare with).
#[cfg(test)]
pub(super) fn saturate_searching_all(g: &mut Graph, effort: Effort) -> bool {
    saturate_with(g, effort, |g, rules| {
        Some(rules.iter().map(|r| r.search(g)).collect())
    })
}

/// The saturation loop: each iteration takes the matches `search` finds (`None`: nothing
/// can match anew, so the e-graph is saturated), applies them rule by rule and rebuilds,
/// until nothing changes or a limit of `effort` is hit.
fn saturate_with(
    g: &mut Graph,
    effort: Effort,
    mut search: impl FnMut(&Graph, &'static [Rewrite<Math, Fold>]) -> Option<Matches>,
) -> bool {
    g.rebuild();
    let rules = rules(effort);
    for _ in 0..effort.iterations() {
        let before = (g.total_size(), g.number_of_classes());
        let Some(matches) = search(g, rules) else {
            return true;
        };
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

/// The e-classes to search in an iteration, from what each class held at the last one.
#[derive(Default)]
struct Dirty {
    /// What each class held at the last update, by id: its e-nodes (a range of `nodes`)
    /// and its constant.
    seen: Vec<Option<Held>>,
    /// The e-nodes of every class at the last update, one after the other.
    nodes: Vec<Math>,
    /// Whether each id is to be searched.
    mark: Vec<bool>,
    /// The ids marked.
    list: Vec<Id>,
}

/// A class's e-nodes, as a range of [`Dirty::nodes`], and its constant's bits.
#[derive(Clone, Copy, PartialEq)]
struct Held {
    start: usize,
    len: usize,
    data: Option<u64>,
}

impl Dirty {
    /// Marks the classes whose e-nodes or constant changed since the last update (new ones
    /// included), with their parents and grandparents.
    fn update(&mut self, g: &Graph) {
        for id in self.list.drain(..) {
            self.mark[usize::from(id)] = false;
        }
        let mut seen = vec![None; self.seen.len()];
        let mut nodes = Vec::with_capacity(g.total_size());
        for class in g.classes() {
            let i = usize::from(class.id);
            if i >= seen.len() {
                seen.resize(i + 1, None);
                self.mark.resize(i + 1, false);
            }
            let now = Held {
                start: nodes.len(),
                len: class.nodes.len(),
                data: class.data.map(f64::to_bits),
            };
            nodes.extend_from_slice(&class.nodes);
            let same = self.seen.get(i).copied().flatten().is_some_and(|was| {
                was.len == now.len
                    && was.data == now.data
                    && self.nodes[was.start..was.start + was.len] == class.nodes[..]
            });
            if !same {
                self.mark[i] = true;
                self.list.push(class.id);
            }
            seen[i] = Some(now);
        }
        self.seen = seen;
        self.nodes = nodes;
        let mut from = 0;
        for _ in 0..2 {
            let to = self.list.len();
            for k in from..to {
                let id = self.list[k];
                for p in g[id].parents() {
                    let p = g.find(p);
                    let i = usize::from(p);
                    if !self.mark[i] {
                        self.mark[i] = true;
                        self.list.push(p);
                    }
                }
            }
            from = to;
        }
    }

    /// The matches of `rule` rooted in the marked classes, in the order a search of the
    /// whole e-graph finds them.
    fn search<'r>(
        &self,
        rule: &'r Rewrite<Math, Fold>,
        g: &Graph,
    ) -> Vec<egg::SearchMatches<'r, Math>> {
        let found = |id: Id| {
            if self.mark[usize::from(id)] {
                rule.searcher.search_eclass(g, id)
            } else {
                None
            }
        };
        let root = match rule.searcher.get_pattern_ast().map(|a| a.as_ref().last()) {
            Some(Some(egg::ENodeOrVar::ENode(e))) => Some(e.discriminant()),
            _ => None,
        };
        match root {
            Some(op) => match g.classes_for_op(&op) {
                Some(ids) => ids.filter_map(found).collect(),
                None => Vec::new(),
            },
            None => g.classes().map(|c| c.id).filter_map(found).collect(),
        }
    }
}
