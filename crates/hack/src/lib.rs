//! Feature unification only: no code. `xtask` and the Python module depend on this crate so
//! that Cargo builds their third-party dependencies with the same features as
//! `cargo test --workspace`, and the artifacts of one build serve the others (issue 51).
//! The reason and the list are in `Cargo.toml` and docs/architecture.md.
