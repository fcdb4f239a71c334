//! The integration tests of hxai-hybrid, one module per former test file, linked into one
//! test binary: each binary costs a link of the whole dependency tree, and the tests run
//! in parallel within a binary but one binary after another (issue 51).
//! `tests/memory.rs` stays a binary of its own: its counting allocator sees every thread,
//! so nothing else may run beside it.

mod common;

mod beside;
mod conformal;
mod correction_per;
mod design;
mod dynamic;
mod end_to_end;
mod factor_pictures;
mod json_shape;
mod monotone;
mod per_class;
mod process;
mod properties;
mod saves;
mod search_sample;
mod stream;
