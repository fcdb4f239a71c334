//! Expectations shared by the tests of the table hybrid: the library's own tests here,
//! and the CLI's and reproduce's, which include this file by path (`hxai hybrid compare`
//! and the section "Beyond the paper" show what `tables::compare` computes, so all expect
//! the same list).
#![allow(dead_code)]

/// The models `tables::compare` scores, in the order it reports them.
pub const COMPARE_MODELS: [&str; 6] = [
    "physics",
    "physics_calibrated",
    "symbolic",
    "physics_forest",
    "boosting",
    "hybrid",
];
