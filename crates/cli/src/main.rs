//! The `hxai` command line.
fn main() {}
