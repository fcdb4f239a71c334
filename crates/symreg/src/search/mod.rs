//! The search: propose model structures, fit their constants in parallel, keep the best per
//! complexity, learn, and finally select.
//!
//! One file per job:
//! - `config`: [`SearchConfig`], [`Strategy`], [`Criterion`] and their checks;
//! - `run`: [`search()`] (one search, or the consensus of [`crate::consensus`]), the main
//!   loop, and [`Progress`];
//! - `fitting`: the rows a search fits on, one candidate's fit, the criterion, the seeds;
//! - `mutual_information`: the inputs' prior weights;
//! - `generate`, `field`, `qlattice`, `genetic`, `strategy`: proposing candidates (path
//!   sampling from a learned field with QLattice-style cells, age-regularised genetic
//!   programming, their combination and random search, behind one internal trait);
//! - `archive`: candidates, fits, and the best fit per complexity;
//! - `selection`: refit on all rows, snap, prune the terms snapping killed, Pareto front,
//!   the criterion's pick
//!   ([`SearchResult`]);
//! - `export`: a fit becomes a [`Model`](crate::Model) naming only the features it uses;
//! - `structure`: [`fit_structure`], one given structure without a search;
//! - `power`: closed-form factor models of the target (products and sums of powers and
//!   other one-column shapes, [`crate::factors`]) offered to selection
//!   ([`SearchConfig::power_laws`]).
//!
//! Every heuristic constant is named and explained where it is used.
mod archive;
mod config;
mod cv;
mod export;
mod field;
mod fitting;
#[doc(hidden)]
pub mod generate;
mod genetic;
mod mutual_information;
mod power;
mod qlattice;
mod run;
mod selection;
mod separable;
mod strategy;
mod structure;
mod symmetry;
mod transform;

pub use config::{
    Criterion, DEFAULT_OPERATORS, ErrorModel, FEW_ROWS, LAW_OPERATORS, PAPER_OPERATORS,
    RandomStart, SearchConfig, Strategy,
};
pub(crate) use run::plain_search;
pub use run::{Progress, search};
pub use selection::{SearchResult, plainness};
pub use structure::fit_structure;
pub(crate) use structure::fit_structure_from;
