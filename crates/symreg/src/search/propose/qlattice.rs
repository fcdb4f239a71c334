//! QLattice-style path sampling: new structures sampled from a learned probability field over
//! (tree position, operator or input) seeded by the mutual-information priors, alongside
//! cells of lineages that mutate their kept models with decaying operator and input boosts
//! and retire them by age. Both learn from the shared archive too, so what genetic
//! programming finds in the combined strategy feeds the field and the cells.
use super::field::Field;
use super::generate::{Tables, same_layout};
use super::strategy::{SearchStrategy, Step};
use crate::program::{Node, Program};
use crate::search::archive::{Archive, Candidate, Fitted};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Cells (independent lineage pools), as in QLattice.
const N_CELLS: usize = 25;
/// Models a cell keeps between epochs, as in QLattice.
const KEEP: usize = 6;
/// Weight of the old operator and input boosts when the epoch's credit is mixed in: the
/// distributions follow what wins with a memory of about three epochs (`0.7^3 = 0.34`).
const DECAY: f64 = 0.7;
/// Added to every boost before it multiplies a prior weight, so an operator or input the
/// best models stopped using keeps a fifth of its chance and can come back.
const BOOST_FLOOR: f64 = 0.2;
/// QLattice's retirement age `MAX_AGE_TOP * exp(-rank / MAX_AGE_RANK_SCALE) + MAX_AGE_MIN`
/// (rank within its cell): a cell's best lineage may survive about 50 epochs, the sixth
/// (rank 5) about 36, so older lineages must keep winning to stay.
const MAX_AGE_TOP: f64 = 50.0;
/// See [`MAX_AGE_TOP`].
const MAX_AGE_RANK_SCALE: f64 = 14.4;
/// See [`MAX_AGE_TOP`]: every lineage lives at least one more epoch.
const MAX_AGE_MIN: f64 = 1.0;
/// Chance that a cell forgets a lineage other than its best at each update, so cells do not
/// settle on one family and keep room for fresh programs.
const FORGET_P: f64 = 0.1;
/// The best `1 / CREDIT_SHARE` of an epoch's fits credit their operators and inputs.
const CREDIT_SHARE: usize = 10;

#[derive(Debug, Clone)]
struct Kept {
    program: Program,
    params: Vec<f64>,
    score: f64,
    age: usize,
}

/// The QLattice-like strategy.
#[derive(Debug)]
pub struct QLattice {
    per_epoch: usize,
    cells: Vec<Vec<Kept>>,
    op_boost: Vec<f64>,
    in_boost: Vec<f64>,
    ops: Vec<crate::ops::Op>,
    field: Field,
    updates: usize,
}

impl QLattice {
    /// A sampler proposing about `per_epoch` candidates an epoch.
    pub fn new(per_epoch: usize, tables: &Tables) -> Self {
        Self {
            per_epoch,
            cells: vec![Vec::new(); N_CELLS],
            op_boost: vec![1.0; tables.ops.len()],
            in_boost: vec![1.0; tables.in_w.len()],
            ops: tables.ops.clone(),
            field: Field::new(tables),
            updates: 0,
        }
    }

    fn local_tables(&self, t: &Tables) -> Tables {
        let mut l = t.clone();
        for (w, b) in l.op_w.iter_mut().zip(&self.op_boost) {
            *w *= BOOST_FLOOR + b;
        }
        // inputs are 16x more likely than operators below the root in QLattice; our grower
        // decides leaf-vs-operator by budget, so only relative input weights matter here.
        for (w, b) in l.in_w.iter_mut().zip(&self.in_boost) {
            *w *= BOOST_FLOOR + b;
        }
        l
    }
}

impl SearchStrategy for QLattice {
    fn propose(&mut self, step: Step, rng: &mut ChaCha8Rng) -> Vec<Candidate> {
        let tables = step.tables;
        // a whole epoch at once, learning once an epoch (as QLattice)
        if step.round != 0 {
            return Vec::new();
        }
        let t = self.local_tables(tables);
        let per_cell = (self.per_epoch / N_CELLS).max(1);
        let mut out = Vec::with_capacity(self.per_epoch);
        for (c, kept) in self.cells.iter().enumerate() {
            let each = per_cell / (kept.len() + 1);
            let mut made = 0;
            for k in kept {
                for _ in 0..each {
                    let mut p = t.mutate(rng, &k.program);
                    if p.is_none() {
                        p = t.mutate(rng, &k.program);
                    }
                    if let Some(program) = p {
                        let params = same_layout(&k.program, &program).then(|| k.params.clone());
                        out.push(Candidate::new(program, params, c as u32));
                        made += 1;
                    }
                }
            }
            // the rest of the cell's share: new structures sampled from the field
            while made < per_cell {
                out.push(Candidate::new(
                    self.field.sample(tables, rng),
                    None,
                    c as u32,
                ));
                made += 1;
            }
        }
        out
    }

    fn update(&mut self, fitted: &[Fitted], archive: &Archive, rng: &mut ChaCha8Rng) {
        if fitted.is_empty() {
            return;
        }
        self.updates += 1;
        for (c, kept) in self.cells.iter_mut().enumerate() {
            let mut pool: Vec<Kept> = kept
                .drain(..)
                .map(|mut k| {
                    k.age += 1;
                    k
                })
                .collect();
            for f in fitted
                .iter()
                .filter(|f| f.tag as usize == c && f.score.is_finite())
            {
                pool.push(Kept {
                    program: f.program.clone(),
                    params: f.params.clone(),
                    score: f.score,
                    age: 0,
                });
            }
            pool.sort_by(|a, b| a.score.total_cmp(&b.score).then(a.program.cmp(&b.program)));
            let mut next: Vec<Kept> = Vec::new();
            for (rank, k) in pool.into_iter().enumerate() {
                let max_age =
                    MAX_AGE_TOP * (-(rank as f64) / MAX_AGE_RANK_SCALE).exp() + MAX_AGE_MIN;
                if (k.age as f64) > max_age || next.iter().any(|n| n.program == k.program) {
                    continue;
                }
                // forgetting: weaker lineages are dropped at random
                if !next.is_empty() && rng.gen_bool(FORGET_P) {
                    continue;
                }
                next.push(k);
                if next.len() >= KEEP {
                    break;
                }
            }
            *kept = next;
        }
        // the shared archive's best (whichever strategy found it) becomes a lineage of one
        // cell in turn
        if let Some(b) = &archive.best {
            let cell = &mut self.cells[self.updates % N_CELLS];
            if !cell.iter().any(|k| k.program == b.program) {
                if cell.len() >= KEEP {
                    cell.pop();
                }
                cell.push(Kept {
                    program: b.program.clone(),
                    params: b.params.clone(),
                    score: b.score,
                    age: 0,
                });
            }
        }
        self.field.update(fitted, &archive.front());
        // decaying distributions over operators and inputs, credited by the best tenth
        let mut ranked: Vec<&Fitted> = fitted.iter().filter(|f| f.score.is_finite()).collect();
        ranked.sort_by(|a, b| a.score.total_cmp(&b.score));
        let top = &ranked[..(ranked.len() / CREDIT_SHARE).max(1).min(ranked.len())];
        if top.is_empty() {
            return;
        }
        let mut op_c = vec![0.0; self.op_boost.len()];
        let mut in_c = vec![0.0; self.in_boost.len()];
        for f in top {
            for n in &f.program.nodes {
                match n {
                    Node::Var(j) => {
                        if let Some(x) = in_c.get_mut(*j as usize) {
                            *x += 1.0;
                        }
                    }
                    Node::Op(op) => {
                        if let Some(i) = self.ops.iter().position(|o| o == op) {
                            op_c[i] += 1.0;
                        }
                    }
                    Node::Const => {}
                }
            }
        }
        let tot_op: f64 = op_c.iter().sum();
        if tot_op > 0.0 {
            let k = op_c.len() as f64;
            for (b, c) in self.op_boost.iter_mut().zip(&op_c) {
                *b = DECAY * *b + (1.0 - DECAY) * k * c / tot_op;
            }
        }
        let tot_in: f64 = in_c.iter().sum();
        if tot_in > 0.0 {
            let k = in_c.len() as f64;
            for (b, c) in self.in_boost.iter_mut().zip(&in_c) {
                *b = DECAY * *b + (1.0 - DECAY) * k * c / tot_in;
            }
        }
    }
}
