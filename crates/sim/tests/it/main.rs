//! The integration tests of hxai-sim, one module per former test file, linked into one
//! test binary: each binary costs a link of the whole dependency tree, and the tests run
//! in parallel within a binary but one binary after another (issue 51).

mod common;

mod calibration;
mod cases;
mod linear;
mod properties;
mod regression;
mod spindle;
