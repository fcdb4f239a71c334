//! Island genetic programming with age-regularised evolution (Real et al. 2019, as in
//! PySR): each round, children of tournament winners (subtree crossover or mutation) join
//! their island and the oldest members leave, whatever their fitness; the shared archive
//! sends its best models in as migrants.
use super::generate::same_layout;
use super::strategy::{ROUNDS_PER_EPOCH, SearchStrategy, Step};
use crate::program::Program;
use crate::search::archive::{Archive, Candidate, Fitted};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Islands (sub-populations that evolve apart and meet through migration), one per
/// candidate index modulo 4.
const ISLANDS: usize = 4;
/// Tournament size: moderate selection pressure (the best of 5 random members).
const TOURNAMENT: usize = 5;
/// Share of children made by crossover; the rest are mutants.
const CROSSOVER: f64 = 0.3;
/// Share of fresh random programs, to keep the islands diverse.
const FRESH: f64 = 0.05;
/// Smallest island capacity, whatever `candidates_per_epoch`, so tournaments have a pool.
const MIN_ISLAND: usize = 20;
/// An island holds this many rounds' worth of children: a member lives this many rounds
/// (unless it is re-entered as a migrant), so it can parent several rounds of children
/// before age retires it.
const LIFETIME_ROUNDS: usize = 3;
/// Models of the archive's front (best scores first) sent to one island each round.
const MIGRANTS: usize = 3;
/// Parsimony pressure: criterion units added per unit of complexity in tournaments.
const PARSIMONY: f64 = 2.0;

#[derive(Debug, Clone)]
struct Member {
    program: Program,
    params: Vec<f64>,
    fitness: f64,
    /// Order of arrival (the oldest leaves first).
    birth: u64,
}

/// The genetic strategy.
#[derive(Debug)]
pub struct Genetic {
    per_epoch: usize,
    islands: Vec<Vec<Member>>,
    births: u64,
    updates: usize,
}

impl Genetic {
    /// A population proposing `per_epoch` children an epoch.
    pub fn new(per_epoch: usize) -> Self {
        Self {
            per_epoch,
            islands: vec![Vec::new(); ISLANDS],
            births: 0,
            updates: 0,
        }
    }

    /// Children in round `round` of an epoch (the epoch's share spread evenly, the
    /// remainder in the first rounds).
    fn per_round(&self, round: usize) -> usize {
        self.per_epoch / ROUNDS_PER_EPOCH + usize::from(round < self.per_epoch % ROUNDS_PER_EPOCH)
    }

    fn capacity(&self) -> usize {
        (LIFETIME_ROUNDS * self.per_epoch / ROUNDS_PER_EPOCH / ISLANDS).max(MIN_ISLAND)
    }

    fn admit(&mut self, isl: usize, program: &Program, params: &[f64], fitness: f64) {
        self.births += 1;
        self.islands[isl].push(Member {
            program: program.clone(),
            params: params.to_vec(),
            fitness,
            birth: self.births,
        });
    }
}

fn tournament<'a>(rng: &mut ChaCha8Rng, pop: &'a [Member]) -> &'a Member {
    let mut best = &pop[rng.gen_range(0..pop.len())];
    for _ in 1..TOURNAMENT {
        let m = &pop[rng.gen_range(0..pop.len())];
        if m.fitness < best.fitness {
            best = m;
        }
    }
    best
}

fn fitness(f: &Fitted) -> f64 {
    f.score + PARSIMONY * f.complexity as f64
}

impl SearchStrategy for Genetic {
    fn propose(&mut self, step: Step, rng: &mut ChaCha8Rng) -> Vec<Candidate> {
        let tables = step.tables;
        let n = self.per_round(step.round);
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let isl = i % ISLANDS;
            let pop = &self.islands[isl];
            let tag = isl as u32;
            if pop.len() < 2 || rng.gen_bool(FRESH) {
                out.push(tables.random_candidate(rng, tag));
                continue;
            }
            let a = tournament(rng, pop);
            let child = if rng.gen_bool(CROSSOVER) {
                let b = tournament(rng, pop);
                tables.crossover(rng, &a.program, &b.program)
            } else {
                tables.mutate(rng, &a.program)
            };
            match child {
                Some(program) => {
                    let params = same_layout(&a.program, &program).then(|| a.params.clone());
                    out.push(Candidate::new(program, params, tag));
                }
                None => out.push(tables.random_candidate(rng, tag)),
            }
        }
        out
    }

    fn update(&mut self, fitted: &[Fitted], archive: &Archive, _rng: &mut ChaCha8Rng) {
        if fitted.is_empty() {
            return;
        }
        self.updates += 1;
        for f in fitted.iter().filter(|f| f.score.is_finite()) {
            self.admit(
                (f.tag as usize) % ISLANDS,
                &f.program,
                &f.params,
                fitness(f),
            );
        }
        // migration: the archive's best-scoring models (whichever strategy found them)
        // enter one island in turn, unless already there
        let mut front: Vec<Fitted> = archive.front();
        front.sort_by(|a, b| a.score.total_cmp(&b.score).then(a.program.cmp(&b.program)));
        let isl = self.updates % ISLANDS;
        for m in front.iter().take(MIGRANTS) {
            if !self.islands[isl].iter().any(|x| x.program == m.program) {
                self.admit(isl, &m.program, &m.params, fitness(m));
            }
        }
        // age-regularised replacement: the oldest leave, whatever their fitness
        let cap = self.capacity();
        for pop in self.islands.iter_mut() {
            if pop.len() > cap {
                pop.sort_by_key(|m| m.birth);
                pop.drain(..pop.len() - cap);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::ops::Op;
    use crate::program::Node;
    use rand::SeedableRng;

    fn fitted(k: u16, score: f64, tag: u32) -> Fitted {
        Fitted {
            program: Program {
                nodes: vec![Node::Var(k), Node::Var(k), Node::Op(Op::Mul)],
                affine: true,
            },
            params: Vec::new(),
            mse: 1.0,
            score,
            complexity: 3,
            source: 0,
            tag,
        }
    }

    // Age-regularised replacement: an island over capacity loses its oldest members,
    // whatever their fitness; the best, if old, leaves too.
    #[test]
    fn the_oldest_leave_whatever_their_fitness() {
        let mut g = Genetic::new(100); // capacity max(3 * 100 / 5 / 4, 20) = 20 per island
        assert_eq!(g.capacity(), 20);
        let archive = Archive::default();
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        // first round: 20 members on island 0, the first the best by far
        let first: Vec<Fitted> = (0..20)
            .map(|k| fitted(k, if k == 0 { -1e9 } else { k as f64 }, 0))
            .collect();
        g.update(&first, &archive, &mut rng);
        assert_eq!(g.islands[0].len(), 20);
        // second round: 5 newcomers, all worse than everyone
        let second: Vec<Fitted> = (100..105).map(|k| fitted(k, 1e9, 0)).collect();
        g.update(&second, &archive, &mut rng);
        let isl = &g.islands[0];
        assert_eq!(isl.len(), 20);
        let kept: Vec<u16> = isl
            .iter()
            .map(|m| match m.program.nodes[0] {
                Node::Var(k) => k,
                _ => u16::MAX,
            })
            .collect();
        // the five oldest (0..5, the best among them) left; every newcomer stayed
        assert!(!kept.contains(&0) && !kept.contains(&4), "{kept:?}");
        assert!((100..105).all(|k| kept.contains(&k)), "{kept:?}");
    }
}
