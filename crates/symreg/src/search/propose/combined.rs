//! The strategies a configuration names ([`Strategy`]): QLattice-style sampling, genetic
//! programming, both side by side sharing one archive ([`Combined`]), and random search
//! (the baseline of the ablation).
use super::generate::Tables;
use super::genetic::Genetic;
use super::qlattice::QLattice;
use super::strategy::{SearchStrategy, Step};
use crate::search::archive::{Archive, Candidate, Fitted};
use crate::search::config::Strategy;
use rand_chacha::ChaCha8Rng;

/// The strategy `which`, proposing `per_epoch` candidates an epoch. The combined strategy
/// gives each part half (QLattice the smaller half when `per_epoch` is odd).
pub(crate) fn build(which: Strategy, per_epoch: usize, tables: &Tables) -> Box<dyn SearchStrategy> {
    match which {
        Strategy::QLattice => Box::new(QLattice::new(per_epoch, tables)),
        Strategy::Genetic => Box::new(Genetic::new(per_epoch)),
        Strategy::Random => Box::new(RandomSearch { per_epoch }),
        Strategy::Combined => Box::new(Combined {
            parts: vec![
                Box::new(QLattice::new(per_epoch / 2, tables)),
                Box::new(Genetic::new(per_epoch - per_epoch / 2)),
            ],
        }),
    }
}

/// Several strategies sharing one archive: each proposes in turn (its candidates tagged
/// with its index as `source`) and learns only from its own candidates' fits.
struct Combined {
    parts: Vec<Box<dyn SearchStrategy>>,
}

impl SearchStrategy for Combined {
    fn propose(&mut self, step: Step, rng: &mut ChaCha8Rng) -> Vec<Candidate> {
        let mut out = Vec::new();
        for (i, p) in self.parts.iter_mut().enumerate() {
            for mut c in p.propose(step, rng) {
                c.source = i as u8;
                out.push(c);
            }
        }
        out
    }

    fn update(&mut self, fitted: &[Fitted], archive: &Archive, rng: &mut ChaCha8Rng) {
        for (i, p) in self.parts.iter_mut().enumerate() {
            let mine: Vec<Fitted> = fitted
                .iter()
                .filter(|f| f.source as usize == i)
                .cloned()
                .collect();
            p.update(&mine, archive, rng);
        }
    }
}

/// Random search: an epoch's worth of random programs (the generator's, without learning),
/// the baseline every strategy must beat at the same number of evaluations.
struct RandomSearch {
    per_epoch: usize,
}

impl SearchStrategy for RandomSearch {
    fn propose(&mut self, step: Step, rng: &mut ChaCha8Rng) -> Vec<Candidate> {
        if step.round != 0 {
            return Vec::new();
        }
        (0..self.per_epoch)
            .map(|_| step.tables.random_candidate(rng, 0))
            .collect()
    }

    fn update(&mut self, _fitted: &[Fitted], _archive: &Archive, _rng: &mut ChaCha8Rng) {}
}
