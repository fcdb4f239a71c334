//! The integration tests of hxai-baselines, one module per former test file, linked into one
//! test binary: each binary costs a link of the whole dependency tree, and the tests run
//! in parallel within a binary but one binary after another (issue 51).

mod boosting;
mod properties;
mod reference;
