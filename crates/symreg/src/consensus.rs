//! Consensus selection: the structure the data gives back most often.
//!
//! One search picks one structure, and on noisy data a resample of the rows often picks
//! another that fits as well: the choice among the near-best is a draw. Consensus selection
//! ([`SearchConfig::consensus_runs`](crate::SearchConfig::consensus_runs) = B > 0) turns the
//! draw into a vote:
//! 1. the search runs once on all rows (its Pareto front and its near-best models are
//!    reported as usual);
//! 2. it runs again on B bootstrap resamples of the rows (run `r` draws its rows from a
//!    generator seeded by the seed and `r`, and searches with seed `seed + r + 1`, as
//!    [`crate::stability()`] does), one after the other, each search parallel inside;
//! 3. each run nominates the structures it found: its selected model, its
//!    [`SearchResult::alternatives`](crate::SearchResult::alternatives) and every member
//!    of its Pareto front, each structure once per run
//!    ([`crate::stability::structure_of`]);
//! 4. the structures nominated by at least half the runs ([`STABLE_SHARE`]) are the stable
//!    ones; each is refitted on all rows (the all-rows search's own fit when it found the
//!    structure, else the constants of the run that nominated it first, refitted from
//!    there) and scored by the criterion on all rows; the best-scoring stable structure
//!    wins (ties: the simpler, then by text). When no structure is stable, the most
//!    nominated one wins. The report names the structure of the winner as refitted (snapping
//!    may shorten it), with its own share where the runs nominated it too.
//!
//! The report ([`Consensus`]) gives the winner's share (runs nominating it / B) and the
//! most nominated structures. This is stability selection (Meinshausen and Bühlmann 2010)
//! applied to whole structures: first keep what the data gives back, then choose by fit
//! among what is kept. A structure that only one draw of the rows supports cannot win
//! however well it fits that draw; the price is accuracy where the true correction is more
//! complex than anything the resamples agree on. It costs B + 1 searches.
//!
//! This module holds the report and its limits; the search runs the consensus
//! (`search/vote.rs`), since [`crate::search()`] is what runs it.
use crate::bootstrap::StructureShare;
use serde::{Deserialize, Serialize};

/// Most structures a [`Consensus`] report lists besides the winner.
pub const MAX_LISTED: usize = 5;

/// Share of the runs that must nominate a structure for it to count as stable.
pub const STABLE_SHARE: f64 = 0.5;

/// Largest number of consensus runs accepted.
pub const MAX_CONSENSUS_RUNS: usize = 1000;

/// What consensus selection reports (JSON `consensus` in a search result).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Consensus {
    /// Bootstrap runs (B).
    pub runs: usize,
    /// The winning structure, every constant written `c`.
    pub structure: String,
    /// Share of runs that nominated it (0 to 1).
    pub share: f64,
    /// The winner, then the most nominated other structures (at most [`MAX_LISTED`]);
    /// shares do not sum to 1, since a run nominates every structure it found.
    pub nominated: Vec<StructureShare>,
}
