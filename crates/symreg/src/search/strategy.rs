//! The seam between the loop and the strategies: [`SearchStrategy`], the combined strategy
//! that runs QLattice-style sampling and genetic programming side by side, and random
//! search (the baseline of the ablation).
use super::archive::{Archive, Candidate, Fitted};
use super::config::Strategy;
use super::generate::Tables;
use super::genetic::Genetic;
use super::qlattice::QLattice;
use rand_chacha::ChaCha8Rng;

/// Rounds of proposing, fitting and learning in one epoch. Genetic programming spreads an
/// epoch's children over the rounds, so a 10-epoch run evolves for 50 steady-state steps
/// instead of 10 generations; path sampling and random search propose a whole epoch at
/// once (in the first round) and learn once an epoch, as QLattice does.
pub(crate) const ROUNDS_PER_EPOCH: usize = 5;

/// Where the loop is within an epoch, and what programs are drawn from. (Strategies read the
/// shared archive when they learn, in [`SearchStrategy::update`].)
#[derive(Clone, Copy)]
pub(crate) struct Step<'a> {
    /// Round within the epoch, from 0 to [`ROUNDS_PER_EPOCH`] - 1.
    pub round: usize,
    /// The operators and inputs programs are drawn from, with their weights.
    pub tables: &'a Tables,
}

/// A way of proposing candidates and learning from their fits. Two implementations
/// ([`QLattice`], [`Genetic`]) and their combination; internal, since [`super::search`]
/// chooses one by [`Strategy`].
pub(crate) trait SearchStrategy: Send {
    /// Candidates for this round, drawn from `rng` only (possibly none).
    fn propose(&mut self, step: Step, rng: &mut ChaCha8Rng) -> Vec<Candidate>;
    /// Learns from the fitted candidates of this round (in proposal order; empty when it
    /// proposed none).
    fn update(&mut self, fitted: &[Fitted], archive: &Archive, rng: &mut ChaCha8Rng);
}

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
            .map(|_| Candidate::random(step.tables, rng, 0))
            .collect()
    }

    fn update(&mut self, _fitted: &[Fitted], _archive: &Archive, _rng: &mut ChaCha8Rng) {}
}
