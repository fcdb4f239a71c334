//! Reproduction of the paper's tables and figures.
#![deny(missing_docs)]

pub mod figures;
