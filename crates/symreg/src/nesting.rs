//! Nesting constraints: which operator may appear inside which, and how often.
//!
//! A correction an engineer can read has no exponential inside an exponential and no
//! logarithm inside a gaussian: a sign or the size of an effect can be read off
//! `c * exp(-c*v)` or `c * f^a`, not off `exp(-(exp(-x^2))^2)`. PySR calls this
//! `nested_constraints` and reports that it "helps a lot with finding interpretable
//! expressions"; hxai takes the same form.
//!
//! A [`Nesting`] maps an *outer* operator to the *inner* operators limited beneath it, each
//! with the most times the inner operator may occur on any path from the outer operator down
//! to a leaf (the outer node itself not counted). `exp: {exp: 0}` forbids `exp(.. exp(..) ..)`
//! at any depth; `sin: {sin: 1}` allows `sin(sin(x))` but not `sin(sin(sin(x)))`. Pairs not
//! named are free. The search never fits a candidate that breaks a constraint, so every
//! model it returns keeps them (a structure given to [`crate::fit_structure`] is the user's
//! own and is not checked).
//!
//! [`Nesting::readable()`] is the default of hybrid corrections ([`crate::SearchConfig::paper`]):
//! no transcendental function (`exp`, `log`, `sin`, `cos`, `tanh`, `gaussian`, `gaussian2`)
//! inside another, with one exception, `log` directly inside `exp` once: `exp(a log(x) + b)`
//! is the power law `e^b x^a` (Taylor's tool life, Kienzle's force, Archard's wear), which
//! prints as a power. A gaussian of a sum or product of inputs (`gaussian2(x*y, z)`) is one
//! transcendental, as QLattice counts it. [`Nesting::strict()`] adds that `sin` and `cos`
//! take only a sum of inputs: the default of `hxai sr` and `SymbolicRegressor` since issue
//! 47, where the free search ([`Nesting::none()`], the library's
//! [`crate::SearchConfig::default()`]) returned periodic and nested tangles on small real
//! tables.
//!
//! Text form (CLI `--nesting`, Python `nesting=` as a string): a comma-separated list of
//! items read left to right, each either a preset (`none`, `readable`, `strict`) or a rule
//! `OUTER:INNER=MAX`; a later item overrides an earlier one, so
//! `readable,exp:log=0` is the readable preset without power laws.
use crate::SrError;
use crate::ops::Op;
use crate::program::{Node, Program};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Number of operators ([`Op`] has 17 variants).
const N_OPS: usize = 17;

/// Largest limit a rule may give (a path in a model of complexity at most 60 holds fewer
/// operators than this).
pub const MAX_NESTING: usize = 60;

/// Nesting constraints by operator name: outer -> inner -> most occurrences of inner on any
/// path below outer (see the module docs). Serialised as that map (JSON
/// `{"exp": {"exp": 0, "log": 1}}`); the empty map constrains nothing. Read from the map or
/// from the text form (`"readable"`, `"none"`, `"readable,exp:log=0"`).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(transparent)]
pub struct Nesting(pub BTreeMap<String, BTreeMap<String, usize>>);

impl<'de> Deserialize<'de> for Nesting {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Form {
            Text(String),
            Map(BTreeMap<String, BTreeMap<String, usize>>),
        }
        match Form::deserialize(d)? {
            Form::Text(t) => Nesting::parse(&t).map_err(serde::de::Error::custom),
            Form::Map(m) => Ok(Nesting(m)),
        }
    }
}

impl Nesting {
    /// No constraint.
    pub fn none() -> Self {
        Self::default()
    }

    /// No transcendental inside a transcendental, except one `log` inside `exp` (a power
    /// law); see the module docs.
    pub fn readable() -> Self {
        // the search's operators that are transcendental ([`Op::ALL`] leaves out the users'
        // `pow` and `tan`)
        let transcendental = || Op::ALL.into_iter().filter(|op| op.is_transcendental());
        let mut rules: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
        for outer in transcendental() {
            let inner = rules.entry(outer.name().to_string()).or_default();
            for op in transcendental() {
                let max = usize::from(outer == Op::Exp && op == Op::Log);
                inner.insert(op.name().to_string(), max);
            }
        }
        Nesting(rules)
    }

    /// [`Nesting::readable()`], and a periodic function (`sin`, `cos`) of an affine function
    /// of the inputs only: nothing but `add` and `sub` beneath it, so `sin(a*x + b*y + c)`
    /// and never `sin(x/cos(y))` or `cos(x*y)`. The default of `hxai sr` and
    /// `SymbolicRegressor` (text form `strict`): on small real tables the unconstrained
    /// search returned periodic and nested tangles that fit the rows and not the law
    /// (issue 47, docs/benchmarks.md).
    pub fn strict() -> Self {
        let mut out = Self::readable();
        for outer in [Op::Sin, Op::Cos] {
            let inner = out.0.entry(outer.name().to_string()).or_default();
            for op in Op::ALL {
                if !matches!(op, Op::Add | Op::Sub) {
                    inner.insert(op.name().to_string(), 0);
                }
            }
        }
        out
    }

    /// Whether nothing is constrained.
    pub fn is_empty(&self) -> bool {
        self.0.values().all(BTreeMap::is_empty)
    }

    /// Parses the text form of the module docs.
    ///
    /// # Errors
    /// [`SrError::InvalidConfig`] for an item that is neither a preset nor `OUTER:INNER=MAX`
    /// (naming the item), [`SrError::UnknownOperator`] for an operator name
    /// [`Op::parse`] does not know.
    pub fn parse(text: &str) -> Result<Self, SrError> {
        let mut out = Nesting::none();
        let items: Vec<&str> = text.split(',').map(str::trim).collect();
        if items.iter().all(|s| s.is_empty()) {
            return Err(SrError::InvalidConfig(
                "--nesting is empty: give `none`, `readable`, `strict` or rules like `exp:exp=0`"
                    .into(),
            ));
        }
        for item in items {
            match item.to_ascii_lowercase().as_str() {
                "" => continue,
                "none" => out = Nesting::none(),
                "readable" => out = Nesting::readable(),
                "strict" => out = Nesting::strict(),
                _ => {
                    let bad = || {
                        SrError::InvalidConfig(format!(
                            "--nesting item `{item}` is not `none`, `readable`, `strict` or \
                             OUTER:INNER=MAX (for example `exp:exp=0`)"
                        ))
                    };
                    let (pair, max) = item.split_once('=').ok_or_else(bad)?;
                    let (outer, inner) = pair.split_once(':').ok_or_else(bad)?;
                    let max: usize = max.trim().parse().map_err(|_| bad())?;
                    let outer = Op::parse(outer)?;
                    let inner = Op::parse(inner)?;
                    out.0
                        .entry(outer.name().to_string())
                        .or_default()
                        .insert(inner.name().to_string(), max);
                }
            }
        }
        out.rules()?;
        Ok(out)
    }

    /// The constraints as a table for [`NestingRules::allows`].
    ///
    /// # Errors
    /// [`SrError::UnknownOperator`] for a name [`Op::parse`] does not know,
    /// [`SrError::InvalidConfig`] for a limit above [`MAX_NESTING`].
    pub fn rules(&self) -> Result<NestingRules, SrError> {
        let mut limit = [[u8::MAX; N_OPS]; N_OPS];
        let mut any = false;
        for (outer, inner) in &self.0 {
            let o = Op::parse(outer)?;
            for (name, &max) in inner {
                let i = Op::parse(name)?;
                if max > MAX_NESTING {
                    return Err(SrError::InvalidConfig(format!(
                        "nesting of `{name}` inside `{outer}` is {max}: choose 0 to \
                         {MAX_NESTING}"
                    )));
                }
                limit[o as usize][i as usize] = max as u8;
                any = true;
            }
        }
        Ok(NestingRules { limit, any })
    }
}

/// [`Nesting`] compiled to a table indexed by operator.
#[derive(Clone, Debug)]
pub struct NestingRules {
    /// `limit[outer][inner]`, `u8::MAX` where free.
    limit: [[u8; N_OPS]; N_OPS],
    /// Whether any pair is limited.
    any: bool,
}

impl NestingRules {
    /// Whether `program` keeps every constraint. Linear in the program's length: each node
    /// carries, per operator, the most occurrences on a path down from it.
    pub fn allows(&self, program: &Program) -> bool {
        if !self.any {
            return true;
        }
        let mut stack: Vec<[u8; N_OPS]> = Vec::with_capacity(program.nodes.len());
        for n in &program.nodes {
            let below = match n {
                Node::Var(_) | Node::Const => {
                    stack.push([0; N_OPS]);
                    continue;
                }
                Node::Op(op) => {
                    let mut below = stack.pop().unwrap_or([0; N_OPS]);
                    if op.arity() == 2 {
                        let a = stack.pop().unwrap_or([0; N_OPS]);
                        for (b, a) in below.iter_mut().zip(a) {
                            *b = (*b).max(a);
                        }
                    }
                    let limits = &self.limit[*op as usize];
                    if below.iter().zip(limits).any(|(&count, &max)| count > max) {
                        return false;
                    }
                    below[*op as usize] = below[*op as usize].saturating_add(1);
                    below
                }
            };
            stack.push(below);
        }
        true
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn prog(nodes: Vec<Node>) -> Program {
        Program {
            nodes,
            affine: true,
        }
    }

    #[test]
    fn readable_forbids_a_transcendental_inside_another_at_any_depth() {
        let r = Nesting::readable().rules().unwrap();
        let x = Node::Var(0);
        let y = Node::Var(1);
        let op = Node::Op;
        // exp(exp(x))
        assert!(!r.allows(&prog(vec![x, op(Op::Exp), op(Op::Exp)])));
        // gaussian(x + log(y)): a log inside a gaussian, one level down
        assert!(!r.allows(&prog(vec![
            x,
            y,
            op(Op::Log),
            op(Op::Add),
            op(Op::Gaussian)
        ])));
        // sin(sqrt(exp(x))): depth does not hide it
        assert!(!r.allows(&prog(vec![x, op(Op::Exp), op(Op::Sqrt), op(Op::Sin)])));
        // exp(log(x)): the power law is allowed, once
        assert!(r.allows(&prog(vec![x, op(Op::Log), op(Op::Exp)])));
        // exp(log(x) * log(y)): two logs side by side are one per path
        assert!(r.allows(&prog(vec![
            x,
            op(Op::Log),
            y,
            op(Op::Log),
            op(Op::Mul),
            op(Op::Exp)
        ])));
        // exp(log(log(x))): a log inside the log is not
        assert!(!r.allows(&prog(vec![x, op(Op::Log), op(Op::Log), op(Op::Exp)])));
        // strict: sin(x + y) is allowed, sin(x * y) and cos(x / cos(y)) are not, and
        // everything readable forbids stays forbidden
        let s = Nesting::strict().rules().unwrap();
        assert!(s.allows(&prog(vec![x, y, op(Op::Add), op(Op::Sin)])));
        assert!(!s.allows(&prog(vec![x, y, op(Op::Mul), op(Op::Sin)])));
        assert!(!s.allows(&prog(vec![x, y, op(Op::Cos), op(Op::Div), op(Op::Cos)])));
        assert!(!s.allows(&prog(vec![x, op(Op::Exp), op(Op::Exp)])));
        assert!(s.allows(&prog(vec![x, op(Op::Log), op(Op::Exp)])));
        assert_eq!(Nesting::parse("strict").unwrap(), Nesting::strict());
        // gaussian2(x*y, z) * exp(x): side by side, not nested
        assert!(r.allows(&prog(vec![
            x,
            y,
            op(Op::Mul),
            Node::Var(2),
            op(Op::Gaussian2),
            x,
            op(Op::Exp),
            op(Op::Mul)
        ])));
    }

    #[test]
    fn none_allows_everything_and_limits_count_occurrences() {
        let x = Node::Var(0);
        let sss = prog(vec![
            x,
            Node::Op(Op::Sin),
            Node::Op(Op::Sin),
            Node::Op(Op::Sin),
        ]);
        assert!(Nesting::none().rules().unwrap().allows(&sss));
        let one = Nesting::parse("sin:sin=1").unwrap().rules().unwrap();
        assert!(!one.allows(&sss));
        assert!(one.allows(&prog(vec![x, Node::Op(Op::Sin), Node::Op(Op::Sin)])));
    }

    #[test]
    fn the_text_form_reads_presets_and_rules_left_to_right() {
        let n = Nesting::parse("readable, exp:log=0").unwrap();
        assert_eq!(n.0["exp"]["log"], 0);
        assert_eq!(n.0["sin"]["exp"], 0);
        assert_eq!(Nesting::parse("readable,none").unwrap(), Nesting::none());
        assert_eq!(Nesting::parse("EXP:Exp=2").unwrap().0["exp"]["exp"], 2);
        for bad in ["", "exp", "exp:exp", "exp:exp=-1", "exp=0", "readble"] {
            let e = Nesting::parse(bad).unwrap_err().to_string();
            assert!(e.contains("nesting"), "{bad}: {e}");
        }
        assert!(matches!(
            Nesting::parse("exp:pow2=0"),
            Err(SrError::UnknownOperator(_))
        ));
        assert!(Nesting::parse("exp:exp=61").is_err());
    }

    #[test]
    fn the_map_round_trips_through_json() {
        let n = Nesting::readable();
        let text = serde_json::to_string(&n).unwrap();
        assert!(text.starts_with("{\"cos\":{"), "{text}");
        assert_eq!(serde_json::from_str::<Nesting>(&text).unwrap(), n);
        assert_eq!(serde_json::from_str::<Nesting>("\"readable\"").unwrap(), n);
        assert!(serde_json::from_str::<Nesting>("\"exp:exp\"").is_err());
    }
}
