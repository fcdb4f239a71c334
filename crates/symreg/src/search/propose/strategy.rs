//! The seam between the loop and the strategies: [`SearchStrategy`], what a strategy is
//! told each round ([`Step`]) and the rounds of an epoch. The strategies implement it
//! (`qlattice`, `genetic`) and `combined` builds the one a configuration names.
use super::generate::Tables;
use crate::search::archive::{Archive, Candidate, Fitted};
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
/// (`QLattice`, `Genetic`) and their combination; internal, since [`crate::search()`]
/// chooses one by [`Strategy`](crate::Strategy).
pub(crate) trait SearchStrategy: Send {
    /// Candidates for this round, drawn from `rng` only (possibly none).
    fn propose(&mut self, step: Step, rng: &mut ChaCha8Rng) -> Vec<Candidate>;
    /// Learns from the fitted candidates of this round (in proposal order; empty when it
    /// proposed none).
    fn update(&mut self, fitted: &[Fitted], archive: &Archive, rng: &mut ChaCha8Rng);
}
