//! `cargo xtask`: project automation.
//!
//! - `cargo xtask reproduce [--quick] [--check] [--out DIR]`: the paper's tables and figures
//!   into `docs/results/` (or `DIR`); `--check` writes nothing and fails when the committed
//!   files differ from what the code produces now.
//! - `cargo xtask bench-sr [...]`: symbolic regression side by side with peer engines, and
//!   `--suite real-laws`: `hxai sr` against the laws of real tables (issue 47).
//! - `cargo xtask check-docs`: fails when `README.md` or `docs/` name a path that does not
//!   exist, when a module is missing from the code map of `docs/architecture.md`, when a
//!   folder's files use each other in a circle, a hand-written file is over 600 lines, or
//!   `cargo xtask` would build a dependency without a feature the tests turn on (CI runs it).
//! - `cargo xtask refs`: regenerates the reference vectors under `testdata/` with the pinned
//!   Python tools of `scripts/requirements.txt` (in a venv under `target/`; not run by CI).
#![allow(clippy::print_stdout, clippy::print_stderr)]

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

mod bench_sr;
mod check_docs;
mod code_shape;
mod features;
mod refs;
mod reproduce;
mod rust_paths;
mod venv;

const USAGE: &str = "usage: cargo xtask <command>

commands:
  reproduce [--quick] [--check] [--out DIR]
      simulate, fit and evaluate; write the paper's tables and figures to docs/results/
      --quick   reduced data and epochs (CI smoke run), written to target/reproduce-quick/
      --check   write nothing; fail if the committed docs/results/ differ from a fresh run
      --out DIR write somewhere else
  bench-sr [--suite feynman|nguyen|keijzer|korns|livermore|strogatz|real-laws] [--help]
      hxai vs feyn, pyoperon and gplearn on AI-Feynman problems (creates .venv-sr);
      --suite real-laws: hxai sr on the real tables of testdata/real/ against their laws
  check-docs
      fail when README.md or docs/ name a repository path that does not exist,
      or when a module is missing from the code map of docs/architecture.md;
      fail on a circle of use among a folder's files or a file over 600 lines
  refs [--python PY]
      regenerate testdata/ reference vectors with the versions pinned in
      scripts/requirements.txt (venv in target/refs-venv; needs network for pip)";

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

/// The workspace root (the xtask crate's parent folder).
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

fn run() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((cmd, rest)) = args.split_first() else {
        println!("{USAGE}");
        return Ok(());
    };
    match cmd.as_str() {
        "reproduce" => reproduce::run(rest).context("cargo xtask reproduce"),
        "bench-sr" => bench_sr::run(rest).context("cargo xtask bench-sr"),
        "check-docs" => check_docs::run(rest).context("cargo xtask check-docs"),
        "refs" => refs::run(rest).context("cargo xtask refs"),
        "-h" | "--help" | "help" => {
            println!("{USAGE}");
            Ok(())
        }
        other => bail!("unknown command `{other}`\n\n{USAGE}"),
    }
}
