//! Selecting, the last layer of the search: the reported models made final and the one the
//! criterion picks.
//!
//! - `selection`: [`select`]: the archive's front and the extra candidates refitted,
//!   rescored under the error model, one per structure, the Pareto front and the pick
//!   ([`SearchResult`]);
//! - `refine`: one model refitted on all rows, shortened, snapped, pruned and folded;
//! - `cv`: cross-validated loss over seeded folds, the one-standard-error rule and the
//!   models within one standard error of the best;
//! - `pick`: the simplest of models the criterion cannot tell apart ([`plainness`]), the
//!   Pareto front, BIC's and AIC's margin, PySR's score;
//! - `export`: a fit becomes a [`Model`](crate::Model) naming only the features it uses.
//!
//! Structures are told apart by [`crate::canonical::structure_of`].
mod cv;
mod export;
mod pick;
mod refine;
mod selection;

pub use pick::plainness;
pub use selection::SearchResult;
pub(crate) use selection::{Counts, Finalists, select};
