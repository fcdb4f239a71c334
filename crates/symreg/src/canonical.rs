//! The canonical form of an expression, and the structure of a model up to its constants,
//! by equality saturation.
//!
//! # What
//!
//! Two model structures that are equal up to their constants are one structure:
//! `c*x1*x2 + c` and `c + c*x2*x1`, `x*(c*(c*y))` and `c*x*y`, `gaussian(x)` and
//! `exp(-x^2)`, `c*exp(c + x) + c` and `c*exp(x) + c`. [`canonical_expr`] rewrites an
//! [`Expr`] with numeric constants into one canonical form of equal value;
//! [`structure_key`] gives the structure of a [`Program`] as sympy-readable text with
//! every fitted constant written `c` (what [`crate::stability()`] counts), and
//! [`structure_key_expr`] the same for an [`Expr`].
//!
//! # How
//!
//! The expression goes into an e-graph ([`egg`]), an equality saturation engine: the rules
//! below add, for every sub-expression, the forms equal to it, until nothing new appears
//! (saturation) or a limit is hit; then the smallest form is read back. Constants are
//! numbers (`f64`), and an e-graph analysis folds every sub-expression whose operands are all
//! numbers into a number (and keeps only the number in that class), so a rule that moves a
//! constant is an exact identity on numbers: `exp(a + x)` with `a` a number becomes
//! `exp(a) * exp(x)` and `exp(a)` folds. That keeps the whole machinery testable by
//! evaluation: the canonical form of an expression evaluates to its value.
//!
//! Before the rules run, the operators that are shorthands enter in their defining form
//! (exact identities, applied while the expression is built): `a - b` is `a + (-1)*b`,
//! `-a` is `(-1)*a`, `a / b` is `a * inverse(b)`, `gaussian(a)` is `exp(-1*a^2)`,
//! `gaussian2(a, b)` is `exp(-1*(a^2 + b^2))`, and `pow(a, k)` for `k` one of 0, 1, 2,
//! -1, 1/2 is `1`, `a`, `a^2`, `inverse(a)`, `sqrt(a)`. The rules (`c`, `d` numbers,
//! `a`, `b` anything; `+`, `*`, `inverse`, `exp`, `log`, `sqrt`, `square`, `sin`, `cos`,
//! `tanh`, `tan`, `abs` and `pow` are what is left):
//! - commutativity and associativity of `+` and `*`;
//! - units: `a + 0 = a`, `a*1 = a`, `a*0 = 0`;
//! - like terms: `a + a = 2*a`, `c*a + d*a = (c + d)*a`, `a + c*a = (1 + c)*a`,
//!   `a*a = a^2`;
//! - signs and numbers over sums: `-1*(a + b) = -1*a + -1*b` and back;
//!   `c*(a + d) = c*a + c*d` and back, `c*a + d = c*(a + d/c)` (`c` not 0), which lets
//!   `log(c*x + d)` give up a constant;
//! - inverse: `1/(a*b) = (1/a)*(1/b)`, `1/(1/a) = a`, `(1/a)^2 = 1/a^2`;
//! - square, abs, sqrt: `(a*b)^2 = a^2*b^2`, `|a*b| = |a|*|b|`, `||a|| = |a|`,
//!   `|a^2| = a^2`, `|a|^2 = a^2`, `|exp(a)| = exp(a)`, `sqrt(a^2) = |a|`,
//!   `sqrt(c*a) = sqrt(c)*sqrt(a)` for `c > 0` and `sqrt(-c)*sqrt(-a)` for `c < 0`;
//! - exp and log: `exp(c + a) = exp(c)*exp(a)`, `exp(a)*exp(b) = exp(a + b)`,
//!   `log(exp(a)) = a`, `log(c*a) = log(c) + log(a)` for `c > 0` and
//!   `log(-c) + log(-a)` for `c < 0`, `log(1/a) = -log(a)`, `log(sqrt(a)) = log(a)/2`,
//!   `log(a^2) = 2*log(|a|)`;
//! - signs through odd and even functions: `sin(c*a) = -sin(-c*a)` (also `tanh`, `tan`) and
//!   `cos(c*a) = cos(-c*a)` for `c < 0`, and `-sin(a) = sin(-a)` (also `tanh`, `tan`).
//!
//! With the constant folding these give the absorptions a structure needs: `c*(c*x)` is
//! `c*x`, `c + (c + x)` is `c + x`, `(c*x)/(c*y)` is `c*x/y`, `x - (c + y)` is
//! `c + (x - y)`, `log(c*x)` is `c + log(x)`, `sqrt(c*x)` is `c*sqrt(x)`, `(c*x)^2` is
//! `c*x^2`, `1/(c*x)` is `c/x`, `exp(c + x)` is `c*exp(x)`, `c*log(c*x + c) + c` is
//! `c*log(x + c) + c`. Every rule holds for real numbers wherever both sides are defined;
//! where one side is not (a log of a negative number, `0*a` with `a` infinite), the
//! canonical form may be defined where the original was not, never the other way round.
//!
//! # Reading the form back
//!
//! The form read from each e-class is the smallest (fewest nodes), ties broken by a total
//! order on terms (numbers by size then sign, then inputs by name, then operators;
//! children in order), with the operands of `+` and `*` sorted by that order. The cost of
//! a term is its prefix token sequence compared by length, then lexicographically; a
//! prefix code is prefix-free, so that order is monotone in every child, and the cheapest
//! term of each class, computed class by class to a fixpoint, is the cheapest of all the
//! terms the class holds, whatever order the classes were visited in or the e-nodes were
//! added. (egg's own `Extractor` breaks ties by e-node order, which depends on the order of
//! insertion.) So two equal expressions built in different orders read back the same form
//! once both saturate. The form is then printed the usual way: `(-1)*a` is `-a`,
//! `a*(1/b)` is `a/b`, `a + (-1)*b` is `a - b`; in a sum, negated terms come after the
//! others and numbers last, in a product numbers first.
//!
//! # The structure of a program
//!
//! [`structure_key`] gives every parameter of the program a generic value (distinct,
//! positive, between 1.1 and 1.5, from a golden-ratio sequence: never 0 or ±1, and no two
//! of them cancel), canonicalises, and prints every number that is not a small literal (a
//! whole number, half or quarter up to 16: the `-1` of a subtraction, the `2` of `x + x`)
//! as `c`. Structures equal up to their constants then print the same, since the rules look
//! at a number's value only for its sign and for being 0 or 1, and reading back treats
//! every parameter as the same token. [`structure_key_expr`] treats the numbers of an
//! [`Expr`] the same way: small literals stay, every other number is a parameter.
//!
//! # Design decision
//!
//! An e-graph (egg, a well-kept crate that does exactly this) rather than more
//! hand-written rewriting like [`Expr::simplify`]: rules applied in one direction depend on
//! the order they fire in, so two equal expressions can end in different normal forms, and
//! the rules must be ordered with care to terminate; an e-graph keeps every form at once,
//! needs no order, and the smallest form it reads back is a canonical one whenever it
//! saturates. Numbers rather than symbolic constants: a symbolic constant `c` would need
//! rules such as `c + c = c`, which hold for families of functions but not as equalities,
//! and could not be tested by evaluating; with numbers every rule is an identity, the
//! property tests evaluate both sides, and the structure key still cannot see the values,
//! because they are generic and printed `c`. egg's `Runner` is not used: the loop here
//! (search every rule, apply, rebuild) is the same without its time limit and clock.
//!
//! Saturation is bounded by a number of iterations and of e-nodes only, never by time, so
//! the result depends on the input alone. A folded number within 1e-12 (relative) of one
//! already folded is taken to be that one: otherwise `c*(a + d)` and `c*a + c*d`, going
//! back and forth, keep producing constants a few units in the last place apart, each a
//! new e-class, and the e-graph never saturates (before this, 40 % of the affine programs
//! measured did not). The representative is the first value folded near it, so the digits
//! of [`canonical_expr`]'s numbers beyond 1e-12 may depend on the order the operands were
//! written in; structure keys, which print no digits, do not.
//!
//! # Limits
//!
//! - When a limit is hit, the result is still deterministic (the same input gives the same
//!   output, on any machine and thread), but the e-graph does not hold every equal form, so
//!   two equal expressions written differently may read back different forms, and a
//!   structure may be counted twice. [`Canonical::saturated`] says whether it happened.
//!   Measured on the random programs of `bench_programs` with complexity up to 10, with
//!   affine inputs as in a search: 160 of 165 saturate under [`Effort::Full`] (mean 0.92
//!   ms per call, median about 0.4 ms), 164 of 165 under [`Effort::Fast`] (mean 73 us,
//!   median about 55 us); `cargo bench -p hxai-symreg --bench canonical`.
//! - The rules know nothing of trigonometric identities (`sin(x + pi/2)` is not
//!   `cos(x)`; [`Expr::simplify`] handles that one in reports), of `exp(log(a)) = a` (it
//!   holds for positive `a` only), of a sign pulled out of a sum inside an even or odd
//!   function (`cos(x - y)` and `cos(y - x)` stay two forms) or of expanding products of
//!   sums (`x*(y + z)` and `x*y + x*z` stay two structures: expanding blows up the e-graph).
//! - Signs: the generic values are positive, so a constant has the sign its structure
//!   forces (`x - c` has a negative one). A constant that can take either sign for the same
//!   structure (`c1 - c2`, `cos(c)`) takes the sign its generic values happen to give, and
//!   `log`/`sqrt` of it split by that sign: such rare structures may get two keys. The key
//!   keeps a sign that a constant of either sign would absorb inside `log` and `sqrt`:
//!   `log(c - x)` and `log(c + x)` are two keys, though with a free scale on `x` they are
//!   one family.
//! - A model input named `c` prints like a constant in the key.
use crate::expr::Expr;
use crate::ops::Op;
use crate::program::{Node, Program};
use egg::{Analysis, DidMerge, EGraph, Id, Language, Rewrite, Subst, define_language, rewrite};
use std::cmp::Ordering;
use std::fmt;
use std::str::FromStr;
use std::sync::OnceLock;

/// The bits of an `f64`, the numbers of the e-graph (ordered by bits: the e-graph only needs
/// some total order; reading back orders by value).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
struct Bits(u64);

impl Bits {
    fn value(self) -> f64 {
        f64::from_bits(self.0)
    }
}

impl fmt::Display for Bits {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.value())
    }
}

impl FromStr for Bits {
    type Err = std::num::ParseFloatError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let v: f64 = s.parse()?;
        Ok(Bits(v.to_bits()))
    }
}

/// An input, by its rank among the sorted names of the expression's inputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
struct VarId(u32);

impl fmt::Display for VarId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "v{}", self.0)
    }
}

impl FromStr for VarId {
    type Err = ();
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        s.strip_prefix('v')
            .and_then(|d| d.parse().ok())
            .map(VarId)
            .ok_or(())
    }
}

define_language! {
    /// The core operators: the search's, less the shorthands (see the module docs).
    enum Math {
        "+" = Add([Id; 2]),
        "*" = Mul([Id; 2]),
        "pow" = Pow([Id; 2]),
        "inv" = Inv(Id),
        "exp" = Exp(Id),
        "log" = Log(Id),
        "sqrt" = Sqrt(Id),
        "square" = Square(Id),
        "sin" = Sin(Id),
        "cos" = Cos(Id),
        "tanh" = Tanh(Id),
        "tan" = Tan(Id),
        "abs" = Abs(Id),
        Num(Bits),
        Var(VarId),
    }
}

/// Relative distance under which two folded numbers are one (see the module docs).
const SNAP: f64 = 1e-12;

/// Constant folding: the value of a class whose every term is a number.
#[derive(Debug, Default)]
struct Fold {
    /// The numbers folded so far, as [`order_key`]s: a new one within [`SNAP`] of one of
    /// them is taken to be it, and only one that is not enters.
    seen: std::collections::BTreeSet<u64>,
}

impl Fold {
    /// `v`, or the smallest number already seen within [`SNAP`] of it.
    fn snap(&mut self, v: f64) -> f64 {
        let d = SNAP * v.abs();
        let (lo, hi) = (order_key(v - d), order_key(v + d));
        if let Some(k) = self.seen.range(lo..=hi).next() {
            return from_order_key(*k);
        }
        self.seen.insert(order_key(v));
        v
    }
}

type Graph = EGraph<Math, Fold>;

impl Analysis<Math> for Fold {
    type Data = Option<f64>;

    fn make(egraph: &mut Graph, enode: &Math, _id: Id) -> Self::Data {
        let c = |i: &Id| egraph[*i].data;
        let v = match enode {
            Math::Num(b) => b.value(),
            Math::Var(_) => return None,
            Math::Add([a, b]) => c(a)? + c(b)?,
            Math::Mul([a, b]) => c(a)? * c(b)?,
            Math::Pow([a, b]) => Op::Pow.apply2(c(a)?, c(b)?),
            Math::Inv(a) => 1.0 / c(a)?,
            Math::Exp(a) => Op::Exp.apply1(c(a)?),
            Math::Log(a) => Op::Log.apply1(c(a)?),
            Math::Sqrt(a) => c(a)?.sqrt(),
            Math::Square(a) => c(a)? * c(a)?,
            Math::Sin(a) => Op::Sin.apply1(c(a)?),
            Math::Cos(a) => Op::Cos.apply1(c(a)?),
            Math::Tanh(a) => Op::Tanh.apply1(c(a)?),
            Math::Tan(a) => Op::Tan.apply1(c(a)?),
            Math::Abs(a) => c(a)?.abs(),
        };
        v.is_finite().then(|| egraph.analysis.snap(v))
    }

    /// The smaller value (by total order) when two constant classes merge: their values can
    /// differ by rounding; the choice must not depend on the order of the merges.
    fn merge(&mut self, to: &mut Self::Data, from: Self::Data) -> DidMerge {
        match (*to, from) {
            (None, None) => DidMerge(false, false),
            (None, Some(y)) => {
                *to = Some(y);
                DidMerge(true, false)
            }
            (Some(_), None) => DidMerge(false, true),
            (Some(x), Some(y)) => match y.total_cmp(&x) {
                Ordering::Less => {
                    *to = Some(y);
                    DidMerge(true, true)
                }
                Ordering::Equal => DidMerge(false, false),
                Ordering::Greater => DidMerge(false, true),
            },
        }
    }

    /// A constant class keeps its numbers only: nothing else about it matters, and pruning
    /// keeps the rules from rearranging constant sub-expressions.
    fn modify(egraph: &mut Graph, id: Id) {
        if let Some(v) = egraph[id].data {
            let n = egraph.add(Math::Num(Bits(v.to_bits())));
            egraph.union(id, n);
            egraph[id].nodes.retain(|n| n.is_leaf());
        }
    }
}

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

/// How hard [`canonical_expr`] and the structure keys try: the rules and the limits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Effort {
    /// Every rule of the module docs, up to 30 iterations and 5,000 e-nodes.
    #[default]
    Full,
    /// Every rule but the six that multiply the forms of sums and products (a number or a
    /// sign over a sum and back, `(a*b)^2` for `a` not a number, `exp(a)*exp(b)`), up to 12
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

/// Whether `v` is a small literal rather than a parameter: a whole number, half or quarter
/// (exactly, to the last bit) of size at most 16.
fn is_literal(v: f64) -> bool {
    v.is_finite() && v.abs() <= 16.0 && (4.0 * v).fract() == 0.0
}

/// The generic value of parameter `i`: `1.1 + 0.4 frac((i + 1) phi)` with `phi` the golden
/// ratio's fractional part, rounded to 40 bits. Distinct for distinct `i`, in `[1.1, 1.5)`
/// (where `log`, `sin`, `cos`, `tanh` and `tan` are all positive, so a constant computed
/// from one parameter has the sign a person would give it), never a small literal.
fn generic(i: usize) -> f64 {
    const PHI: f64 = 0.618_033_988_749_894_9;
    let f = ((i + 1) as f64 * PHI).fract();
    1.1 + 0.4 * f
}

/// Builds the core form of an expression into an e-graph (see the module docs for the
/// shorthands).
struct Builder<'a> {
    g: &'a mut Graph,
    /// Sorted input names: `Var(i)` is `names[i]`.
    names: Vec<String>,
}

impl Builder<'_> {
    fn num(&mut self, v: f64) -> Id {
        self.g.add(Math::Num(Bits(v.to_bits())))
    }

    fn neg(&mut self, a: Id) -> Id {
        let m1 = self.num(-1.0);
        self.g.add(Math::Mul([m1, a]))
    }

    fn var(&mut self, name: &str) -> Id {
        let i = self.names.binary_search_by(|n| n.as_str().cmp(name));
        let i = i.unwrap_or_else(|i| i); // every name was collected first
        self.g.add(Math::Var(VarId(i as u32)))
    }

    fn un(&mut self, op: Op, a: Id) -> Id {
        let n = match op {
            Op::Exp => Math::Exp(a),
            Op::Log => Math::Log(a),
            Op::Sqrt => Math::Sqrt(a),
            Op::Square => Math::Square(a),
            Op::Inverse => Math::Inv(a),
            Op::Sin => Math::Sin(a),
            Op::Cos => Math::Cos(a),
            Op::Tanh => Math::Tanh(a),
            Op::Tan => Math::Tan(a),
            Op::Abs => Math::Abs(a),
            Op::Gaussian => {
                let s = self.g.add(Math::Square(a));
                let n = self.neg(s);
                Math::Exp(n)
            }
            // a binary operator with one operand has no value
            _ => return self.num(f64::NAN),
        };
        self.g.add(n)
    }

    fn bin(&mut self, op: Op, a: Id, b: Id, b_num: Option<f64>) -> Id {
        let n = match op {
            Op::Add => Math::Add([a, b]),
            Op::Sub => {
                let nb = self.neg(b);
                Math::Add([a, nb])
            }
            Op::Mul => Math::Mul([a, b]),
            Op::Div => {
                let ib = self.g.add(Math::Inv(b));
                Math::Mul([a, ib])
            }
            Op::Gaussian2 => {
                let sa = self.g.add(Math::Square(a));
                let sb = self.g.add(Math::Square(b));
                let s = self.g.add(Math::Add([sa, sb]));
                let n = self.neg(s);
                Math::Exp(n)
            }
            Op::Pow => match b_num {
                Some(0.0) => return self.num(1.0),
                Some(1.0) => return a,
                Some(2.0) => Math::Square(a),
                Some(-1.0) => Math::Inv(a),
                Some(0.5) => Math::Sqrt(a),
                _ => Math::Pow([a, b]),
            },
            _ => return self.num(f64::NAN),
        };
        self.g.add(n)
    }

    /// Adds `e`, its numbers mapped by `num`.
    fn expr(&mut self, e: &Expr, num: &mut dyn FnMut(f64) -> f64) -> Id {
        match e {
            Expr::Num(v) => {
                let v = num(*v);
                self.num(v)
            }
            Expr::Var(n) => self.var(n),
            Expr::Neg(a) => {
                let a = self.expr(a, num);
                self.neg(a)
            }
            Expr::Un(op, a) => {
                let a = self.expr(a, num);
                self.un(*op, a)
            }
            Expr::Bin(op, a, b) => {
                let ia = self.expr(a, num);
                let ib = self.expr(b, num);
                let b_num = self.g[ib].data;
                self.bin(*op, ia, ib, b_num)
            }
        }
    }
}

fn collect_names(e: &Expr, out: &mut Vec<String>) {
    match e {
        Expr::Num(_) => {}
        Expr::Var(n) => out.push(n.clone()),
        Expr::Neg(a) | Expr::Un(_, a) => collect_names(a, out),
        Expr::Bin(_, a, b) => {
            collect_names(a, out);
            collect_names(b, out);
        }
    }
}

/// Runs the rules of `effort` to saturation or to its limits; true if saturated.
fn saturate(g: &mut Graph, effort: Effort) -> bool {
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

/// One token of a term in prefix order. The derived order is the tie-break of reading back:
/// parameters (all equal) in structure keys, then numbers by size and sign, then inputs by
/// name, then operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Tok {
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
fn num_tok(v: f64) -> Tok {
    Tok::Num(order_key(v.abs()), u8::from(v.is_sign_negative()))
}

/// `f64::total_cmp` as an unsigned key.
fn order_key(v: f64) -> u64 {
    let b = v.to_bits();
    if b >> 63 == 1 { !b } else { b | (1 << 63) }
}

fn from_order_key(k: u64) -> f64 {
    f64::from_bits(if k >> 63 == 1 { k & !(1 << 63) } else { !k })
}

/// Operators' tags (their order among themselves) and arities.
const TAGS: [(u8, usize); 13] = [
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

/// The cheapest term of every class, as its prefix tokens (see the module docs), read from
/// the class of `root`.
fn extract(g: &Graph, root: Id, key: bool) -> Vec<Tok> {
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
                    .is_none_or(|cur| cost_cmp(&cand, cur) == Ordering::Less);
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

/// A term read back from tokens.
enum Term {
    Gen,
    Num(f64),
    Var(u32),
    Op(u8, Vec<Term>),
}

fn decode(toks: &[Tok], at: &mut usize) -> Term {
    let t = toks.get(*at).copied().unwrap_or(num_tok(f64::NAN));
    *at += 1;
    match t {
        Tok::Gen => Term::Gen,
        Tok::Num(k, s) => {
            let v = from_order_key(k);
            Term::Num(if s == 1 { -v } else { v })
        }
        Tok::Var(i) => Term::Var(i),
        Tok::Op(o) => {
            let arity = TAGS.get(o as usize).map_or(1, |t| t.1);
            Term::Op(o, (0..arity).map(|_| decode(toks, at)).collect())
        }
    }
}

const UNARY: [(u8, Op); 10] = [
    (3, Op::Inverse),
    (4, Op::Exp),
    (5, Op::Log),
    (6, Op::Sqrt),
    (7, Op::Square),
    (8, Op::Sin),
    (9, Op::Cos),
    (10, Op::Tanh),
    (11, Op::Tan),
    (12, Op::Abs),
];

/// Prints a term the usual way (see the module docs); in a key, parameters are `c`.
struct Pretty<'a> {
    names: &'a [String],
    key: bool,
}

impl Pretty<'_> {
    fn flatten<'t>(op: u8, t: &'t Term, out: &mut Vec<&'t Term>) {
        match t {
            Term::Op(o, ch) if *o == op => {
                for c in ch {
                    Self::flatten(op, c, out);
                }
            }
            other => out.push(other),
        }
    }

    fn expr(&self, t: &Term) -> Expr {
        match t {
            Term::Gen => Expr::Var("c".into()),
            Term::Num(v) => {
                if self.key && !is_literal(*v) {
                    Expr::Var("c".into())
                } else {
                    Expr::Num(*v)
                }
            }
            Term::Var(i) => Expr::Var(
                self.names
                    .get(*i as usize)
                    .cloned()
                    .unwrap_or_else(|| format!("x{i}")),
            ),
            Term::Op(0, _) => self.sum(t),
            Term::Op(1, _) => self.product(t),
            Term::Op(2, ch) if ch.len() == 2 => Expr::Bin(
                Op::Pow,
                Box::new(self.expr(&ch[0])),
                Box::new(self.expr(&ch[1])),
            ),
            Term::Op(o, ch) => {
                let op = UNARY.iter().find(|u| u.0 == *o).map_or(Op::Exp, |u| u.1);
                let a = ch.first().map_or(Expr::Num(f64::NAN), |c| self.expr(c));
                Expr::Un(op, Box::new(a))
            }
        }
    }

    /// Terms of a sum: inputs and functions first, negated terms next, numbers last.
    fn sum(&self, t: &Term) -> Expr {
        let mut terms = Vec::new();
        Self::flatten(0, t, &mut terms);
        let mut pos = Vec::new();
        let mut neg = Vec::new();
        let mut nums = Vec::new();
        for term in terms {
            match self.expr(term) {
                Expr::Neg(x) => neg.push(*x),
                e @ (Expr::Num(_) | Expr::Var(_)) if matches!(term, Term::Num(_) | Term::Gen) => {
                    nums.push(e)
                }
                e => pos.push(e),
            }
        }
        let mut acc: Option<Expr> = None;
        for e in pos {
            acc = Some(match acc {
                None => e,
                Some(a) => Expr::Bin(Op::Add, Box::new(a), Box::new(e)),
            });
        }
        for e in neg {
            acc = Some(match acc {
                None => Expr::Neg(Box::new(e)),
                Some(a) => Expr::Bin(Op::Sub, Box::new(a), Box::new(e)),
            });
        }
        for e in nums {
            acc = Some(match acc {
                None => e,
                Some(a) => Expr::Bin(Op::Add, Box::new(a), Box::new(e)),
            });
        }
        acc.unwrap_or(Expr::Num(0.0))
    }

    /// Factors of a product: a factor -1 is a sign, numbers come first, inverses are
    /// divisors.
    fn product(&self, t: &Term) -> Expr {
        let mut factors = Vec::new();
        Self::flatten(1, t, &mut factors);
        let mut negative = false;
        let mut numbers: Vec<Expr> = Vec::new();
        let mut num: Vec<Expr> = Vec::new();
        let mut den: Vec<Expr> = Vec::new();
        for f in factors {
            match f {
                Term::Num(v) if *v == -1.0 => negative = !negative,
                Term::Num(_) | Term::Gen => numbers.push(self.expr(f)),
                Term::Op(3, ch) if ch.len() == 1 => den.push(self.expr(&ch[0])),
                other => num.push(self.expr(other)),
            }
        }
        numbers.append(&mut num);
        let num = numbers;
        let prod = |v: Vec<Expr>| {
            v.into_iter()
                .reduce(|a, b| Expr::Bin(Op::Mul, Box::new(a), Box::new(b)))
        };
        let e = match (prod(num), prod(den)) {
            (Some(n), Some(d)) => Expr::Bin(Op::Div, Box::new(n), Box::new(d)),
            (Some(n), None) => n,
            (None, Some(d)) => Expr::Un(Op::Inverse, Box::new(d)),
            (None, None) => Expr::Num(1.0),
        };
        if negative { Expr::Neg(Box::new(e)) } else { e }
    }
}

/// What one canonicalisation gives: the form, and whether the e-graph saturated.
#[derive(Clone, Debug, PartialEq)]
pub struct Canonical {
    /// The canonical form.
    pub expr: Expr,
    /// Whether the rules ran to saturation (see the module docs' limits when not).
    pub saturated: bool,
    /// E-nodes in the e-graph at the end.
    pub nodes: usize,
}

fn run(e: &Expr, effort: Effort, key: bool) -> Canonical {
    let mut names = Vec::new();
    collect_names(e, &mut names);
    names.sort();
    names.dedup();
    let mut g = Graph::new(Fold::default());
    let mut b = Builder { g: &mut g, names };
    let mut k = 0;
    let mut num = |v: f64| {
        if key && !is_literal(v) {
            k += 1;
            generic(k - 1)
        } else {
            v
        }
    };
    let root = b.expr(e, &mut num);
    let names = b.names;
    finish(g, root, &names, effort, key)
}

fn finish(mut g: Graph, root: Id, names: &[String], effort: Effort, key: bool) -> Canonical {
    let saturated = saturate(&mut g, effort);
    let toks = extract(&g, root, key);
    let term = decode(&toks, &mut 0);
    let expr = Pretty { names, key }.expr(&term);
    Canonical {
        expr,
        saturated,
        nodes: g.total_size(),
    }
}

/// The canonical form of `e` (see the module docs): equal in value to `e` wherever both are
/// finite (up to rounding: folded constants carry 40 bits), and the same for any two
/// expressions the rules prove equal, whatever order their operands were written in.
pub fn canonical_expr(e: &Expr) -> Expr {
    run(e, Effort::Full, false).expr
}

/// [`canonical_expr`] with a chosen [`Effort`], and whether the e-graph saturated.
pub fn canonicalize(e: &Expr, effort: Effort) -> Canonical {
    run(e, effort, false)
}

/// The structure of an expression: its numbers that are not small literals taken as
/// parameters (see the module docs), canonicalised and printed as sympy-readable text with
/// every parameter written `c`.
pub fn structure_key_expr(e: &Expr) -> String {
    structure_expr_with(e, Effort::Full)
        .expr
        .to_text(None, true)
}

/// [`structure_key_expr`] with a chosen [`Effort`]; the form has every parameter as the
/// input `c`.
pub fn structure_expr_with(e: &Expr, effort: Effort) -> Canonical {
    run(e, effort, true)
}

/// The structure of a program over inputs named `names`: `scale * root + offset` with every
/// parameter generic, canonicalised and printed as sympy-readable text with every
/// parameter written `c` (see the module docs). Programs equal up to their constants give
/// the same text.
pub fn structure_key(program: &Program, names: &[String]) -> String {
    structure_with(program, names, Effort::Full)
        .expr
        .to_text(None, true)
}

/// [`structure_key`] with a chosen [`Effort`]; the form has every parameter as the input
/// `c`.
pub fn structure_with(program: &Program, names: &[String], effort: Effort) -> Canonical {
    let name = |j: u16| {
        names
            .get(j as usize)
            .cloned()
            .unwrap_or_else(|| format!("x{j}"))
    };
    let mut sorted: Vec<String> = program.vars().into_iter().map(name).collect();
    sorted.sort();
    sorted.dedup();
    let mut g = Graph::new(Fold::default());
    let mut b = Builder {
        g: &mut g,
        names: sorted,
    };
    let offs = program.param_offsets();
    let mut stack: Vec<Id> = Vec::with_capacity(program.nodes.len());
    for (k, n) in program.nodes.iter().enumerate() {
        let id = match n {
            Node::Var(j) => {
                let x = b.var(&name(*j));
                if program.affine {
                    let w = b.num(generic(offs[k]));
                    let c = b.num(generic(offs[k] + 1));
                    let wx = b.g.add(Math::Mul([w, x]));
                    b.g.add(Math::Add([wx, c]))
                } else {
                    x
                }
            }
            Node::Const => b.num(generic(offs[k])),
            Node::Op(op) => {
                if op.arity() == 2 {
                    let nan = b.num(f64::NAN);
                    let y = stack.pop().unwrap_or(nan);
                    let x = stack.pop().unwrap_or(nan);
                    let y_num = b.g[y].data;
                    b.bin(*op, x, y, y_num)
                } else {
                    let nan = b.num(f64::NAN);
                    let x = stack.pop().unwrap_or(nan);
                    b.un(*op, x)
                }
            }
        };
        stack.push(id);
    }
    let nan = b.num(f64::NAN);
    let root = stack.pop().unwrap_or(nan);
    let s = b.num(generic(0));
    let o = b.num(generic(1));
    let sr = b.g.add(Math::Mul([s, root]));
    let root = b.g.add(Math::Add([sr, o]));
    let names = b.names;
    finish(g, root, &names, effort, true)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generic_values_are_distinct_and_not_literal() {
        let mut seen = std::collections::HashSet::new();
        for i in 0..10_000 {
            let v = generic(i);
            assert!((1.1..1.5).contains(&v), "{v}");
            assert!(!is_literal(v), "{v}");
            assert!(seen.insert(v.to_bits()), "{i}");
        }
        for v in [0.0, 1.0, -1.0, 2.0, 0.5, -0.5, 16.0, 0.75, 2.5] {
            assert!(is_literal(v), "{v}");
        }
        for v in [17.0, 0.1, 1.0 / 3.0, 1.3, std::f64::consts::PI, f64::NAN] {
            assert!(!is_literal(v), "{v}");
        }
    }

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
