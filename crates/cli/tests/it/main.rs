//! The integration tests of the `hxai` command line, one module per former test file,
//! linked into one test binary: each binary costs a link of the whole dependency tree, and
//! the tests run in parallel within a binary but one binary after another (issue 51).

mod common;

mod bad_input;
mod dynamic_cli;
mod explain_cli;
mod generated_csv;
mod hostile;
mod hybrid_cli;
mod hybrid_table_cli;
mod signals;
mod simulate_case_cli;
mod sr_cli;
mod stream_cli;
