//! `cargo xtask bench-sr`: symbolic-regression benchmark of hxai against feyn (QLattice),
//! pyoperon and gplearn on AI-Feynman equations (or on one `--csv FILE --target COL` table).
//!
//! Makes the Python venv `.venv-sr` if it is missing (pip: pyoperon feyn gplearn sympy pandas),
//! builds the `hxai` binary, and hands over to `scripts/bench_sr_run.py`, which generates the
//! seeded data, runs every engine, checks exact recovery with sympy, and prints the tables.
//!
//! Options (all forwarded to the script): `--engines hxai,feyn,pyoperon,gplearn`,
//! `--problems N` (first N of 16 equations), `--only I.6.2,I.10.7`, `--noise 0,0.01`,
//! `--rows 1000`, `--seed 42`, `--out target/bench-sr`, `--hxai-args "..."`, `--hxai-label NAME`,
//! `--csv FILE --target COL`.
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn ensure_venv(root: &Path) -> Result<PathBuf> {
    let venv = root.join(".venv-sr");
    let py = venv.join("bin").join("python");
    if !py.exists() {
        let ok = Command::new("python3")
            .arg("-m")
            .arg("venv")
            .arg(&venv)
            .status()
            .context("running python3 -m venv")?;
        if !ok.success() {
            bail!("python3 -m venv {} failed", venv.display());
        }
    }
    let check = Command::new(&py)
        .args(["-c", "import sympy, pandas, numpy"])
        .status()?;
    if !check.success() {
        let ok = Command::new(&py)
            .args([
                "-m", "pip", "install", "-q", "pyoperon", "feyn", "gplearn", "sympy", "pandas",
                "numpy",
            ])
            .status()
            .context("running pip install")?;
        if !ok.success() {
            bail!("pip install into {} failed", venv.display());
        }
    }
    Ok(py)
}

/// Runs the benchmark with the given command-line arguments.
pub fn run(args: &[String]) -> Result<()> {
    let root = root();
    let py = ensure_venv(&root)?;
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
    let status = Command::new(&py)
        .current_dir(&root)
        .arg(root.join("scripts").join("bench_sr_run.py"))
        .arg("--hxai")
        .arg(&hxai)
        .args(args)
        .status()
        .context("running scripts/bench_sr_run.py")?;
    if !status.success() {
        bail!("the benchmark script failed");
    }
    Ok(())
}
