//! `cargo xtask bench-sr`: symbolic-regression benchmark of hxai against feyn (QLattice),
//! pyoperon and gplearn on AI-Feynman equations (or on one `--csv FILE --target COL` table).
//!
//! Makes the Python venv `.venv-sr` if it is missing (pip, pinned in
//! `scripts/bench_sr_requirements.txt`: pyoperon feyn gplearn sympy pandas numpy), builds the
//! `hxai` binary, and hands over to `scripts/bench_sr_run.py` (the 16 hand-copied equations),
//! which generates the seeded data, runs every engine, checks exact recovery with sympy, and
//! prints the tables.
//!
//! `--suite feynman` runs `scripts/bench_sr_suite.py` instead: all 100 equations of the AI
//! Feynman database (`--db`, default `../shared/data/feynman100.csv` beside the repository),
//! each engine a subprocess with a time limit, results written row by row (`--resume`); see
//! that script's `--help` and docs/benchmarks.md. `--suite nguyen|keijzer|korns|livermore|strogatz`
//! runs the same script on a held-out suite built from its published formulas (issue 24; the
//! script's default `--db` is `scripts/suites/NAME.csv`, sources in `scripts/suites/README.md`,
//! results in `target/bench-sr/NAME/`); `--check-suite` only parses and samples a suite.
//!
//! `--suite real-laws` runs `scripts/bench_real_laws.py` instead (issue 47): `hxai sr` alone on
//! the seven real tables of `testdata/real/`, each scored against the law the literature fits
//! to it (`testdata/real/laws.json`), with the `hxai` built here (the dev profile; a later
//! `--hxai PATH` wins); the venv then needs only sympy, numpy, scipy and pandas.
//! Its options: `--only NAME,...`, `--extra "HXAI-SR-ARGS"` (or the arguments after `--`),
//! `--out FILE` (default `target/bench-sr/real-laws/results.jsonl`), `--seed N` (of the scoring
//! points), `--self-test` (checks the scorer, runs no hxai).
//!
//! Options of the other suites (all forwarded to the script): `--engines hxai,feyn,pyoperon,gplearn`,
//! `--problems N` (first N of 16 equations), `--only I.6.2,I.10.7`, `--noise 0,0.01`,
//! `--rows 1000`, `--seed 42`, `--out target/bench-sr`, `--hxai-args "..."`, `--hxai-label NAME`,
//! `--csv FILE --target COL`.
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The venv's interpreter, after `pip install` of the pinned requirements if any module of
/// `imports` (a Python import list) is missing.
fn ensure_venv(root: &Path, imports: &str) -> Result<PathBuf> {
    let venv = root.join(".venv-sr");
    let py = crate::venv::create(&venv, "python3")?;
    let check = Command::new(&py)
        .args(["-c", &format!("import {imports}")])
        .status()?;
    if !check.success() {
        let requirements = root.join("scripts").join("bench_sr_requirements.txt");
        crate::venv::pip_install(&py, &requirements, &venv)?;
    }
    Ok(py)
}

/// The value of `--suite NAME` (or `--suite=NAME`) among the arguments, if the option is there
/// (empty when `--suite` ends the line: the script then says what is missing).
fn suite_name(args: &[String]) -> Option<String> {
    args.iter().enumerate().find_map(|(i, a)| {
        if a == "--suite" {
            Some(args.get(i + 1).cloned().unwrap_or_default())
        } else {
            a.strip_prefix("--suite=").map(str::to_string)
        }
    })
}

/// The arguments without `--suite NAME` or `--suite=NAME`.
fn without_suite(args: &[String]) -> Vec<String> {
    let mut kept = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if a == "--suite" {
            it.next();
        } else if !a.starts_with("--suite=") {
            kept.push(a.clone());
        }
    }
    kept
}

/// Runs the benchmark with the given command-line arguments.
pub fn run(args: &[String]) -> Result<()> {
    let root = root();
    let suite = suite_name(args);
    let real_laws = suite.as_deref() == Some("real-laws");
    let py = if real_laws {
        ensure_venv(&root, "sympy, pandas, numpy, scipy")?
    } else {
        ensure_venv(&root, "sympy, pandas, numpy, pyoperon, gplearn, feyn")?
    };
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let ok = Command::new(&cargo)
        .current_dir(&root)
        .args(["build", "-p", "hxai-cli"])
        .status()
        .context("building hxai")?;
    if !ok.success() {
        bail!("cargo build -p hxai-cli failed");
    }
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| root.join("target"));
    let hxai = target.join("debug").join("hxai");
    let script = if real_laws {
        "bench_real_laws.py"
    } else if suite.is_some() {
        "bench_sr_suite.py"
    } else {
        "bench_sr_run.py"
    };
    // bench_real_laws.py has one suite and takes no `--suite`
    let args = if real_laws {
        without_suite(args)
    } else {
        args.to_vec()
    };
    let mut cmd = Command::new(&py);
    cmd.current_dir(&root)
        .arg(root.join("scripts").join(script))
        .arg("--hxai")
        .arg(&hxai);
    // the AI Feynman database lives beside the repository; the held-out suites' CSVs are the
    // script's own default (scripts/suites/NAME.csv)
    let db_given = args.iter().any(|a| a == "--db" || a.starts_with("--db="));
    if suite.as_deref() == Some("feynman") && !db_given {
        let db = root
            .join("..")
            .join("shared")
            .join("data")
            .join("feynman100.csv");
        cmd.arg("--db").arg(db);
    }
    let status = cmd
        .args(&args)
        .status()
        .with_context(|| format!("running scripts/{script}"))?;
    if !status.success() {
        bail!("the benchmark script failed");
    }
    Ok(())
}
