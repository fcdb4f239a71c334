//! Proposing candidates, the first layer of the search: the structures each round fits.
//!
//! - `generate`: random programs within the complexity cap, mutation and crossover, drawn
//!   from the operators' and inputs' weights ([`Tables`]);
//! - `field`: the learned probability field path sampling draws structures from;
//! - `strategy`: the internal seam (`SearchStrategy`), what a strategy sees each round
//!   ([`Step`]) and the rounds of an epoch;
//! - `qlattice`: path sampling from the field, with QLattice-style cells of lineages;
//! - `genetic`: island genetic programming with age-regularised evolution;
//! - `combined`: the strategy a configuration names ([`build`]): one of the two, both side
//!   by side, or random search.
//!
//! Nothing here fits or selects: strategies read fits and the archive when they learn.
mod combined;
mod field;
#[doc(hidden)]
pub mod generate;
mod genetic;
mod qlattice;
mod strategy;

pub(crate) use combined::build;
pub(crate) use generate::Tables;
pub(crate) use strategy::{ROUNDS_PER_EPOCH, Step};
