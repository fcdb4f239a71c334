//! Island genetic programming: tournament selection, subtree crossover and mutation,
//! age-regularised replacement, migration from the shared archive.
use super::archive::{Archive, Candidate, Fitted};
use super::generate::Tables;
use super::qlattice::same_layout;
use super::strategy::SearchStrategy;
use crate::program::Program;
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
/// Parsimony pressure: criterion units added per unit of complexity in tournaments.
const PARSIMONY: f64 = 2.0;

#[derive(Debug, Clone)]
struct Member {
    program: Program,
    params: Vec<f64>,
    fitness: f64,
    birth: usize,
}

/// The genetic strategy.
#[derive(Debug)]
pub struct Genetic {
    per_epoch: usize,
    islands: Vec<Vec<Member>>,
    epoch: usize,
}

impl Genetic {
    /// A population proposing `per_epoch` children an epoch.
    pub fn new(per_epoch: usize) -> Self {
        Self {
            per_epoch,
            islands: vec![Vec::new(); ISLANDS],
            epoch: 0,
        }
    }

    fn capacity(&self) -> usize {
        (self.per_epoch / ISLANDS).max(MIN_ISLAND)
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

impl SearchStrategy for Genetic {
    fn propose(
        &mut self,
        epoch: usize,
        rng: &mut ChaCha8Rng,
        _archive: &Archive,
        tables: &Tables,
    ) -> Vec<Candidate> {
        self.epoch = epoch;
        let mut out = Vec::with_capacity(self.per_epoch);
        for i in 0..self.per_epoch {
            let isl = i % ISLANDS;
            let pop = &self.islands[isl];
            let tag = isl as u32;
            if pop.len() < 2 || rng.gen_bool(FRESH) {
                out.push(Candidate {
                    program: tables.random_program(rng),
                    params: None,
                    source: 0,
                    tag,
                });
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
                    out.push(Candidate {
                        program,
                        params,
                        source: 0,
                        tag,
                    });
                }
                None => out.push(Candidate {
                    program: tables.random_program(rng),
                    params: None,
                    source: 0,
                    tag,
                }),
            }
        }
        out
    }

    fn update(&mut self, fitted: &[Fitted], archive: &Archive, _rng: &mut ChaCha8Rng) {
        let epoch = self.epoch;
        let cap = self.capacity();
        for f in fitted.iter().filter(|f| f.score.is_finite()) {
            let isl = (f.tag as usize) % ISLANDS;
            self.islands[isl].push(Member {
                program: f.program.clone(),
                params: f.params.clone(),
                fitness: f.score + PARSIMONY * f.complexity as f64,
                birth: epoch,
            });
        }
        // migration: the archive's front and the best model enter every island
        let mut migrants: Vec<&Fitted> = archive.by_complexity.iter().flatten().collect();
        if let Some(b) = &archive.best {
            migrants.push(b);
        }
        for isl in self.islands.iter_mut() {
            for m in &migrants {
                if !isl.iter().any(|x| x.program == m.program) {
                    isl.push(Member {
                        program: m.program.clone(),
                        params: m.params.clone(),
                        fitness: m.score + PARSIMONY * m.complexity as f64,
                        birth: epoch,
                    });
                }
            }
            // age-regularised replacement: drop the oldest (ties: the worst) until within
            // capacity, always keeping the island's best
            if isl.len() > cap {
                let best_i = isl
                    .iter()
                    .enumerate()
                    .min_by(|a, b| a.1.fitness.total_cmp(&b.1.fitness))
                    .map(|(i, _)| i)
                    .unwrap_or(0);
                let best = isl[best_i].clone();
                isl.remove(best_i);
                isl.sort_by(|a, b| b.birth.cmp(&a.birth).then(a.fitness.total_cmp(&b.fitness)));
                isl.truncate(cap - 1);
                isl.push(best);
            }
        }
    }
}
