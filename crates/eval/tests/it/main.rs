//! The integration tests of hxai-eval, one module per former test file, linked into one
//! test binary: each binary costs a link of the whole dependency tree, and the tests run
//! in parallel within a binary but one binary after another (issue 51).

mod conformal_reference;
mod properties;
mod reference;
