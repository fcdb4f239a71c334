//! The integration tests of hxai-symreg, one module per former test file, linked into one
//! test binary: each binary costs a link of the whole dependency tree, and the tests run
//! in parallel within a binary but one binary after another (issue 51).

mod common;

mod canonical;
mod canonical_properties;
mod consensus;
mod cv_selection;
mod error_model;
mod eval_programs;
mod nesting;
mod prior;
mod properties;
mod search;
mod stability;
mod sympy_export;
mod uncertainty;
mod vmath;
