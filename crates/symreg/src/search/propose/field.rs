//! The learned probability field of path sampling: for each position of an expression tree,
//! a distribution over what stands there (an operator, an input or a constant), seeded by
//! the operators' arity weights and the inputs' mutual-information priors, and pulled each
//! epoch towards what the elite models put at that position.
use super::generate::{Tables, roulette};
use crate::program::{Node, Program};
use crate::search::archive::Fitted;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Positions with their own distribution: the nodes of the top four levels of the tree
/// (root, its 2 children, 4 grandchildren, 8 great-grandchildren) in heap order. Deeper
/// nodes share one more distribution: few laws of complexity <= 20 or so have structure
/// below the fourth level that is not a leaf.
const LEVEL_POSITIONS: usize = 15;
/// [`LEVEL_POSITIONS`] plus the shared distribution of deeper nodes.
const POSITIONS: usize = LEVEL_POSITIONS + 1;
/// Share of a position's weight that stays on leaves at the start (below the root): about
/// [`super::generate`]'s chance of stopping early, so the first samples look like its
/// random programs.
const INITIAL_LEAF_SHARE: f64 = 0.3;
/// Chance that a leaf is a free constant at the start (with affine inputs constants are
/// rarely needed, as in the generator).
const INITIAL_CONST_SHARE: f64 = 0.08;
/// How far one update moves a position's distribution towards the elites' frequencies: a
/// memory of about three updates (`0.7^3 = 0.34`), as the cells' operator boosts.
const LEARNING_RATE: f64 = 0.3;
/// Share of the prior always mixed into the sampling weights, so nothing the elites stopped
/// using becomes impossible.
const PRIOR_FLOOR: f64 = 0.15;
/// The best `1 / ELITE_SHARE` of an update's fits (plus the archive's front) are the
/// elites.
const ELITE_SHARE: usize = 10;

/// A probability field over (position, symbol); symbols are the operators of the tables,
/// then the inputs, then the constant.
#[derive(Debug, Clone)]
pub(crate) struct Field {
    /// Learned weights, one row of `n_symbols` per position (rows sum to 1).
    learned: Vec<Vec<f64>>,
    /// The prior rows (the same at every position below the root).
    prior: Vec<Vec<f64>>,
    ops: Vec<crate::ops::Op>,
    n_ops: usize,
    n_inputs: usize,
}

impl Field {
    /// The prior field of `tables`: operators by their arity weight, inputs by their
    /// mutual-information prior, a constant rarely; the root is always an operator when
    /// there is one.
    pub(crate) fn new(tables: &Tables) -> Self {
        let n_ops = tables.ops.len();
        let n_inputs = tables.in_w.len();
        let op_tot: f64 = tables.op_w.iter().sum();
        let in_tot: f64 = tables.in_w.iter().sum();
        let row = |leaf_share: f64| -> Vec<f64> {
            let mut r: Vec<f64> = tables
                .op_w
                .iter()
                .map(|w| (1.0 - leaf_share) * w / op_tot.max(f64::MIN_POSITIVE))
                .collect();
            let var_share = leaf_share * (1.0 - INITIAL_CONST_SHARE);
            r.extend(
                tables
                    .in_w
                    .iter()
                    .map(|w| var_share * w / in_tot.max(f64::MIN_POSITIVE)),
            );
            r.push(leaf_share * INITIAL_CONST_SHARE);
            normalised(r)
        };
        let root_leaf_share = if n_ops == 0 { 1.0 } else { 0.05 };
        let prior: Vec<Vec<f64>> = (0..POSITIONS)
            .map(|p| {
                if p == 0 {
                    row(root_leaf_share)
                } else {
                    row(INITIAL_LEAF_SHARE)
                }
            })
            .collect();
        Field {
            learned: prior.clone(),
            prior,
            ops: tables.ops.clone(),
            n_ops,
            n_inputs,
        }
    }

    /// The symbol of a node.
    fn symbol(&self, n: &Node) -> Option<usize> {
        match n {
            Node::Op(op) => self.ops.iter().position(|o| o == op),
            Node::Var(j) => ((*j as usize) < self.n_inputs).then_some(self.n_ops + *j as usize),
            Node::Const => Some(self.n_ops + self.n_inputs),
        }
    }

    /// Samples a program of at most `tables.max_complexity` from the field.
    pub(crate) fn sample(&self, tables: &Tables, rng: &mut ChaCha8Rng) -> Program {
        let budget = rng.gen_range(1..=tables.max_complexity.max(1));
        let mut nodes = Vec::new();
        self.grow(tables, rng, 0, budget, &mut nodes);
        Program {
            nodes,
            affine: tables.affine,
        }
    }

    fn grow(
        &self,
        tables: &Tables,
        rng: &mut ChaCha8Rng,
        pos: usize,
        budget: usize,
        out: &mut Vec<Node>,
    ) {
        let row = pos;
        let n_sym = self.n_ops + self.n_inputs + 1;
        let w: Vec<f64> = (0..n_sym)
            .map(|s| {
                let allowed = if s < self.n_ops {
                    let op = tables.ops[s];
                    let cost = tables.op_costs.of(op);
                    budget >= cost + op.arity()
                } else {
                    true
                };
                if allowed {
                    PRIOR_FLOOR * self.prior[row][s] + (1.0 - PRIOR_FLOOR) * self.learned[row][s]
                } else {
                    0.0
                }
            })
            .collect();
        let s = pick(rng, &w);
        if s >= self.n_ops {
            out.push(if s < self.n_ops + self.n_inputs {
                Node::Var((s - self.n_ops) as u16)
            } else {
                Node::Const
            });
            return;
        }
        let op = tables.ops[s];
        let rest = budget - tables.op_costs.of(op);
        let (left_pos, right_pos) = (child_pos(pos, 0), child_pos(pos, 1));
        if op.arity() == 1 {
            self.grow(tables, rng, left_pos, rest, out);
        } else {
            let left = rng.gen_range(1..rest);
            let before = out.len();
            self.grow(tables, rng, left_pos, left, out);
            let used: usize = out[before..]
                .iter()
                .map(|n| match n {
                    Node::Op(o) => tables.op_costs.of(*o),
                    _ => 1,
                })
                .sum();
            self.grow(
                tables,
                rng,
                right_pos,
                rest.saturating_sub(used).max(1),
                out,
            );
        }
        out.push(Node::Op(op));
    }

    /// Pulls every position's distribution towards the symbols the elites put there: the
    /// best tenth of `fitted` (by criterion) and the models of `front`.
    pub(crate) fn update(&mut self, fitted: &[Fitted], front: &[Fitted]) {
        let mut ranked: Vec<&Fitted> = fitted.iter().filter(|f| f.score.is_finite()).collect();
        ranked.sort_by(|a, b| a.score.total_cmp(&b.score).then(a.program.cmp(&b.program)));
        ranked.truncate((ranked.len() / ELITE_SHARE).max(1));
        ranked.extend(front.iter());
        if ranked.is_empty() {
            return;
        }
        let n_sym = self.n_ops + self.n_inputs + 1;
        let mut counts = vec![vec![0.0; n_sym]; POSITIONS];
        for f in ranked {
            let p = &f.program;
            if p.nodes.is_empty() {
                continue;
            }
            let ch = p.children();
            let mut stack = vec![(p.nodes.len() - 1, 0usize)];
            while let Some((i, pos)) = stack.pop() {
                if let Some(s) = self.symbol(&p.nodes[i]) {
                    counts[pos][s] += 1.0;
                }
                for (k, &c) in ch[i].iter().enumerate() {
                    if c != usize::MAX {
                        stack.push((c, child_pos(pos, k)));
                    }
                }
            }
        }
        for (row, c) in self.learned.iter_mut().zip(counts) {
            let tot: f64 = c.iter().sum();
            if tot > 0.0 {
                for (w, x) in row.iter_mut().zip(&c) {
                    *w = (1.0 - LEARNING_RATE) * *w + LEARNING_RATE * x / tot;
                }
            }
        }
    }
}

/// Heap position of child `k` (0 left, 1 right) of the node at `pos`; every node below the
/// top levels shares the last position.
fn child_pos(pos: usize, k: usize) -> usize {
    if pos >= LEVEL_POSITIONS {
        LEVEL_POSITIONS
    } else {
        (2 * pos + 1 + k).min(LEVEL_POSITIONS)
    }
}

fn normalised(mut r: Vec<f64>) -> Vec<f64> {
    let t: f64 = r.iter().sum();
    if t > 0.0 {
        for x in &mut r {
            *x /= t;
        }
    }
    r
}

/// [`roulette`]; when no weight is usable, the last symbol (only leaves are always allowed:
/// fall back to the constant).
fn pick(rng: &mut ChaCha8Rng, w: &[f64]) -> usize {
    roulette(rng, w).unwrap_or(w.len() - 1)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::ops::{Op, OpCosts};
    use crate::program::ComplexityMeasure;
    use rand::SeedableRng;

    fn tables() -> Tables {
        Tables {
            ops: vec![Op::Add, Op::Mul, Op::Sqrt, Op::Exp],
            op_w: vec![5.3, 5.3, 1.0, 1.0],
            in_w: vec![1.0, 0.5, 0.1],
            affine: true,
            measure: ComplexityMeasure::FeaturesPlusOperators,
            max_complexity: 9,
            op_costs: OpCosts::parse([(&"sqrt".to_string(), &3)]).unwrap(),
        }
    }

    fn fitted(nodes: Vec<Node>, score: f64) -> Fitted {
        Fitted {
            program: Program {
                nodes,
                affine: true,
            },
            params: Vec::new(),
            mse: 1.0,
            score,
            complexity: 3,
            source: 0,
            tag: 0,
        }
    }

    // Every sample is a valid program within the cap, operator costs counted.
    #[test]
    fn samples_respect_the_cap_and_costs() {
        let t = tables();
        let f = Field::new(&t);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..2000 {
            let p = f.sample(&t, &mut rng);
            assert!(t.fits(&p), "{p:?}");
        }
    }

    // Elites that put `mul` at the root and input 2 below it pull the field there: the elites
    // are the best tenth of the batch (the `mul` model and one `exp` model) and the front (the
    // `mul` model), so `mul` holds 2/3 of the root's count and input 2 2/3 of the first
    // child's; three updates at rate 0.3 move a row 1 - 0.7^3 = 66 % of the way there, from
    // 0.40 to 0.58 for the root's `mul` and from 0.02 to 0.44 for the child's input 2.
    #[test]
    fn the_field_learns_the_elites_positions() {
        let t = tables();
        let mut f = Field::new(&t);
        let (mul, x2) = (1, t.ops.len() + 2);
        let (root0, child0) = (f.learned[0][mul], f.learned[1][x2]);
        let elite = fitted(vec![Node::Var(2), Node::Var(2), Node::Op(Op::Mul)], -10.0);
        let other = fitted(vec![Node::Var(0), Node::Op(Op::Exp)], 5.0);
        let mut batch = vec![elite.clone()];
        batch.extend(std::iter::repeat_n(other, 20));
        for _ in 0..3 {
            f.update(&batch, std::slice::from_ref(&elite));
        }
        assert!(
            f.learned[0][mul] > root0 + 0.15,
            "{} -> {}",
            root0,
            f.learned[0][mul]
        );
        assert!(
            f.learned[1][x2] > child0 + 0.3,
            "{} -> {}",
            child0,
            f.learned[1][x2]
        );
        // rows stay distributions (sum 1 within 1e-12)
        for row in &f.learned {
            assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        }
    }
}
