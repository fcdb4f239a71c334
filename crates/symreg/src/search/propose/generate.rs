//! Random program generation and variation (mutation, crossover) on postfix code.
//!
//! Internal to the search; public (and hidden from the docs) only so that the property tests
//! and [`crate::bench_programs`] can draw programs the way the search does.
use crate::ops::{Op, OpCosts};
use crate::program::{ComplexityMeasure, Node, Program};
use crate::search::archive::Candidate;
use crate::search::config::SearchConfig;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Prior weight of a binary operator against a unary one (weight 1). QLattice's tables weigh
/// `add`, `multiply` and two-input `gaussian` 5.3 against 1 for unary functions: a binary
/// node joins two inputs, and most laws are products, sums and ratios of their inputs.
pub(crate) const BINARY_OP_WEIGHT: f64 = 5.3;

/// Prior weight of a unary operator.
pub(crate) const UNARY_OP_WEIGHT: f64 = 1.0;

/// Chance that a leaf is a free constant when inputs are affine (`w x + b`). Constants are
/// free under the paper's complexity, and with affine inputs they are rarely needed (only for
/// shifts inside the tree, as in `1 - v^2/c^2`), so they are drawn rarely.
const CONST_LEAF_P_AFFINE: f64 = 0.08;

/// Chance that a leaf is a free constant when inputs are plain: constants then carry every
/// scale and offset, so they are drawn about three times as often.
const CONST_LEAF_P_PLAIN: f64 = 0.25;

/// Chance that [`Tables::grow`] stops at a leaf although its budget allows an operator, so
/// random programs span every size up to the budget instead of filling it.
const EARLY_LEAF_P: f64 = 0.25;

/// Mutation kinds (insert, change, delete, replace a subtree) at a leaf or a binary node:
/// QLattice's 4 : 3 : 1 for insert, change, delete, plus an occasional subtree replacement.
const MUTATION_W_LEAF_OR_BINARY: [f64; 4] = [4.0, 3.0, 1.0, 1.0];

/// Mutation kinds at a unary node: QLattice's 1 : 1 : 1.5, deleting more often so chains
/// of unary functions do not pile up, plus a rarer subtree replacement.
const MUTATION_W_UNARY: [f64; 4] = [1.0, 1.0, 1.5, 0.5];

/// Largest subtree (in nodes) grown by the replace-a-subtree mutation: a local move.
const REPLACEMENT_SUBTREE_MAX: usize = 4;

/// Weighted tables the generators draw from.
#[derive(Debug, Clone)]
pub struct Tables {
    /// Allowed operators.
    pub ops: Vec<Op>,
    /// Weight of each operator.
    pub op_w: Vec<f64>,
    /// Weight of each input column.
    pub in_w: Vec<f64>,
    /// Whether inputs carry affine scalings.
    pub affine: bool,
    /// Complexity measure.
    pub measure: ComplexityMeasure,
    /// Largest complexity allowed.
    pub max_complexity: usize,
    /// Complexity of each operator.
    pub op_costs: OpCosts,
}

/// An index drawn with probability proportional to the weights `w`, or `None` (drawing
/// nothing) when they do not sum to a positive finite total; the caller decides the
/// fallback.
pub(crate) fn roulette(rng: &mut ChaCha8Rng, w: &[f64]) -> Option<usize> {
    let total: f64 = w.iter().sum();
    if total <= 0.0 || !total.is_finite() {
        return None;
    }
    let mut u = rng.gen_range(0.0..total);
    for (i, &x) in w.iter().enumerate() {
        if u < x {
            return Some(i);
        }
        u -= x;
    }
    Some(w.len() - 1)
}

/// [`roulette`], falling back to a uniform draw.
fn pick(rng: &mut ChaCha8Rng, w: &[f64]) -> usize {
    match roulette(rng, w) {
        Some(i) => i,
        None => rng.gen_range(0..w.len().max(1)),
    }
}

impl Tables {
    /// The tables of a search: the allowed operators weighted by arity
    /// ([`BINARY_OP_WEIGHT`], [`UNARY_OP_WEIGHT`]) and the inputs by their prior `in_w`,
    /// the complexity capped by [`SearchConfig::complexity_cap`] for as many inputs.
    pub(crate) fn for_search(
        ops: Vec<Op>,
        in_w: Vec<f64>,
        cfg: &SearchConfig,
        op_costs: OpCosts,
    ) -> Self {
        Tables {
            op_w: ops
                .iter()
                .map(|o| {
                    if o.arity() == 2 {
                        BINARY_OP_WEIGHT
                    } else {
                        UNARY_OP_WEIGHT
                    }
                })
                .collect(),
            ops,
            max_complexity: cfg.complexity_cap(in_w.len()),
            in_w,
            affine: cfg.affine_inputs,
            measure: cfg.complexity_measure,
            op_costs,
        }
    }

    fn leaf(&self, rng: &mut ChaCha8Rng) -> Node {
        let p_const = if self.affine {
            CONST_LEAF_P_AFFINE
        } else {
            CONST_LEAF_P_PLAIN
        };
        if rng.gen_bool(p_const) {
            Node::Const
        } else {
            Node::Var(pick(rng, &self.in_w) as u16)
        }
    }

    fn op_of_arity(&self, rng: &mut ChaCha8Rng, arity: Option<usize>) -> Option<Op> {
        let w: Vec<f64> = self
            .ops
            .iter()
            .zip(&self.op_w)
            .map(|(o, &w)| {
                if arity.is_none_or(|a| o.arity() == a) {
                    w
                } else {
                    0.0
                }
            })
            .collect();
        if w.iter().sum::<f64>() <= 0.0 {
            return None;
        }
        Some(self.ops[pick(rng, &w)])
    }

    /// A random expression of at most `budget` complexity (every node counting at least 1,
    /// an operator its cost), appended to `out`.
    pub fn grow(&self, rng: &mut ChaCha8Rng, budget: usize, out: &mut Vec<Node>) {
        if budget <= 1 || rng.gen_bool(EARLY_LEAF_P) {
            out.push(self.leaf(rng));
            return;
        }
        let arity = if budget >= 3 { None } else { Some(1) };
        let op = self.op_of_arity(rng, arity);
        // an operator whose cost leaves no room for its arguments becomes a leaf
        let rest = op.map_or(0, |o| budget.saturating_sub(self.op_costs.of(o)));
        match op {
            Some(op) if op.arity() == 1 && rest >= 1 => {
                self.grow(rng, rest, out);
                out.push(Node::Op(op));
            }
            Some(op) if op.arity() == 2 && rest >= 2 => {
                let left = rng.gen_range(1..rest);
                let before = out.len();
                self.grow(rng, left, out);
                let used = self.size(&out[before..]);
                self.grow(rng, rest - used, out);
                out.push(Node::Op(op));
            }
            _ => out.push(self.leaf(rng)),
        }
    }

    /// The budget `nodes` used in [`Tables::grow`]: 1 per leaf, each operator's cost.
    fn size(&self, nodes: &[Node]) -> usize {
        nodes
            .iter()
            .map(|n| match n {
                Node::Op(op) => self.op_costs.of(*op),
                _ => 1,
            })
            .sum()
    }

    /// A proposal of a fresh random program ([`Tables::random_program`]), tagged `tag`.
    pub(crate) fn random_candidate(&self, rng: &mut ChaCha8Rng, tag: u32) -> Candidate {
        Candidate::new(self.random_program(rng), None, tag)
    }

    /// A random program within the complexity limit.
    pub fn random_program(&self, rng: &mut ChaCha8Rng) -> Program {
        let size = rng.gen_range(1..=self.max_complexity.max(1));
        let mut nodes = Vec::new();
        self.grow(rng, size, &mut nodes);
        Program {
            nodes,
            affine: self.affine,
        }
    }

    /// Whether `p` respects the limits.
    pub fn fits(&self, p: &Program) -> bool {
        p.is_valid()
            && p.complexity_with(self.measure, &self.op_costs) <= self.max_complexity
            && !p.nodes.is_empty()
    }

    /// One random mutation: change, insert or delete at one position, or replace a subtree.
    /// Returns `None` when the result breaks the limits.
    pub fn mutate(&self, rng: &mut ChaCha8Rng, p: &Program) -> Option<Program> {
        let n = p.nodes.len();
        let pos = rng.gen_range(0..n);
        let node = p.nodes[pos];
        let is_unary = matches!(node, Node::Op(op) if op.arity() == 1);
        let w = if is_unary {
            MUTATION_W_UNARY
        } else {
            MUTATION_W_LEAF_OR_BINARY
        };
        let mut nodes = p.nodes.clone();
        match pick(rng, &w) {
            0 => {
                // insert an operator above the subtree rooted at pos
                let op = self.op_of_arity(rng, None)?;
                let mut ins = vec![];
                if op.arity() == 2 {
                    ins.push(self.leaf(rng));
                }
                ins.push(Node::Op(op));
                let at = pos + 1;
                if op.arity() == 2 && rng.gen_bool(0.5) {
                    // new leaf on the left: put it before the subtree
                    let start = p.subtree_start(pos);
                    nodes.insert(start, ins[0]);
                    nodes.insert(at + 1, Node::Op(op));
                } else {
                    for (i, x) in ins.into_iter().enumerate() {
                        nodes.insert(at + i, x);
                    }
                }
            }
            1 => {
                nodes[pos] = match node {
                    Node::Var(_) | Node::Const => self.leaf(rng),
                    Node::Op(op) => Node::Op(self.op_of_arity(rng, Some(op.arity()))?),
                };
            }
            2 => {
                // delete: replace the subtree at pos by one of its children (or a leaf)
                match node {
                    Node::Op(op) => {
                        let ch = p.children();
                        let c = ch[pos][if op.arity() == 2 && rng.gen_bool(0.5) {
                            1
                        } else {
                            0
                        }];
                        let start = p.subtree_start(pos);
                        let cs = p.subtree_start(c);
                        let sub: Vec<Node> = p.nodes[cs..=c].to_vec();
                        nodes.splice(start..=pos, sub);
                    }
                    _ => nodes[pos] = self.leaf(rng),
                }
            }
            _ => {
                let start = p.subtree_start(pos);
                let mut sub = Vec::new();
                let size = rng.gen_range(1..=REPLACEMENT_SUBTREE_MAX);
                self.grow(rng, size, &mut sub);
                nodes.splice(start..=pos, sub);
            }
        }
        let q = Program {
            nodes,
            affine: p.affine,
        };
        if self.fits(&q) { Some(q) } else { None }
    }

    /// Subtree crossover: a random subtree of `a` replaced by a random subtree of `b`.
    pub fn crossover(&self, rng: &mut ChaCha8Rng, a: &Program, b: &Program) -> Option<Program> {
        let pa = rng.gen_range(0..a.nodes.len());
        let pb = rng.gen_range(0..b.nodes.len());
        let sa = a.subtree_start(pa);
        let sb = b.subtree_start(pb);
        let mut nodes = a.nodes.clone();
        nodes.splice(sa..=pa, b.nodes[sb..=pb].iter().copied());
        let q = Program {
            nodes,
            affine: a.affine,
        };
        if self.fits(&q) { Some(q) } else { None }
    }
}

/// Whether two programs have the same parameter layout (leaf sequence).
pub(crate) fn same_layout(a: &Program, b: &Program) -> bool {
    let la = a.nodes.iter().filter(|n| !matches!(n, Node::Op(_)));
    let lb = b.nodes.iter().filter(|n| !matches!(n, Node::Op(_)));
    a.affine == b.affine
        && la
            .map(|n| a.node_params(n))
            .eq(lb.map(|n| b.node_params(n)))
}
