//! The search: propose model structures, fit their constants in parallel, keep the best per
//! complexity, learn, decompose, and finally select.
//!
//! In layers, each a folder that uses the files above it and none below (`cargo xtask
//! check-docs` fails on a circle of `use` among a folder's files):
//! - `config`: [`SearchConfig`], [`Strategy`], [`Criterion`] and their checks;
//! - `progress`: [`Progress`], what a search reports after every epoch;
//! - `archive`: candidates, fits, and the best fit per complexity;
//! - `fitting`: the rows a search fits on, one candidate's fit (and a refit of given
//!   constants), the criterion, the seeds;
//! - `mutual_information`: the inputs' prior weights;
//! - `propose/`: proposing candidates (`generate`, `field`, `qlattice`, `genetic`,
//!   `strategy`, `combined`: path sampling from a learned field with QLattice-style cells,
//!   age-regularised genetic programming, their combination and random search, behind one
//!   internal trait);
//! - `decompose/`: the most accurate model as an oracle (`oracle`) and the tools it serves,
//!   each offering selection one more candidate: separability (`separable`, `join`),
//!   symmetries and powers (`symmetry`), a polynomial of a transformed target
//!   (`transform`); the sub-searches are the loop's own, passed in as a closure;
//! - `power`: closed-form factor models of the target (products and sums of powers and
//!   other one-column shapes, [`crate::factors`]) offered to selection
//!   ([`SearchConfig::power_laws`]);
//! - `select/`: refit on all rows, snap, prune the terms snapping killed, Pareto front,
//!   cross-validation, the criterion's pick ([`SearchResult`]); `export` makes a fit a
//!   [`Model`](crate::Model) naming only the features it uses;
//! - `structure`: [`fit_structure`], one given structure without a search (fitting, then
//!   selection);
//! - `vote`: the consensus of [`crate::consensus`] over B + 1 searches, each passed in as a
//!   closure (the loop's own, or `crate::units`' search on the dimensionless groups);
//! - `run`: [`search()`] (one search, or the consensus of `vote`) and the main loop over
//!   all of the above.
//!
//! Every heuristic constant is named and explained where it is used.
mod archive;
mod beside;
mod config;
mod decompose;
mod fitting;
mod mutual_information;
mod power;
mod progress;
mod propose;
mod run;
mod select;
mod structure;
mod vote;

#[doc(hidden)]
pub use beside::BLOW_UP_RANGES;
pub use config::{
    Criterion, DEFAULT_OPERATORS, DEFINED_BOXES, DEFINED_MARGIN, ErrorModel, FEW_ROWS,
    LAW_OPERATORS, PAPER_OPERATORS, Prior, RandomStart, SearchConfig, Strategy, ValidSearch,
};
pub use progress::Progress;
pub use propose::generate;
pub use run::{search, search_checked};
pub use select::{SearchResult, plainness};
pub use structure::fit_structure;
pub(crate) use vote::search_with;
