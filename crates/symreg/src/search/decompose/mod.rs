//! Decomposing, the second layer of the search: questions put to the search's most accurate
//! model about the law, and the smaller problems they leave (AI Feynman's tools, Udrescu and
//! Tegmark 2020; issue 24 item 2). Each tool offers selection one more candidate, refitted
//! and judged like every other model.
//!
//! - `oracle`: the most accurate model as an [`oracle::Oracle`] on any points, and the mixed
//!   differences that split the inputs into groups that only add or multiply (union-find);
//! - `separable`: [`decompositions`]: the groups searched apart and joined, or, when nothing
//!   splits, a symmetric pair replaced by one input; the sub-search is the loop's own, passed
//!   in as a closure (`SubSearch`), so nothing here calls the loop by name;
//! - `join`: the parts of a sum or a product joined back into one program;
//! - `symmetry`: a pair that enters as a difference, ratio, product or sum, an input that
//!   enters as a power, and a sub-model written back over the inputs;
//! - `transform`: [`polynomials`]: a polynomial of a transformed target (`1/y`, `ln y`, ...)
//!   on problems of a few inputs.
mod join;
mod oracle;
mod separable;
mod symmetry;
mod transform;

pub(crate) use separable::{Spent, decompositions};
pub(crate) use transform::polynomials;
