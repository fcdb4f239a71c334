//! Empty: it exists so that Cargo builds this crate's build-dependency `syn` (on the host,
//! with the features `cargo test --workspace` turns on; see `Cargo.toml`).
fn main() {}
