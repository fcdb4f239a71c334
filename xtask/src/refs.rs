//! `cargo xtask refs`: regenerates the reference vectors under `testdata/` that come from
//! Python (numpy, scipy, scikit-learn).
//!
//! Makes the virtual environment `target/refs-venv` if it is missing, installs exactly the
//! versions pinned in `scripts/requirements.txt`, and runs every `scripts/ref_*.py` with it,
//! in name order. Each script writes its files atomically and records the versions it used.
//! Not run by CI (it needs the network for pip); afterwards `git diff testdata/` shows what
//! changed and `cargo test` checks the crates against the new vectors. The two Rust-made
//! files (`testdata/sim/records.json`, `testdata/symreg/eval_programs.json`) have their own
//! commands, listed in `testdata/README.md`.
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Runs the command with its arguments (`--python PY` picks the interpreter that makes the
/// venv; default `python3` from `PATH`).
pub fn run(args: &[String]) -> Result<()> {
    let mut python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--python" => {
                python = it
                    .next()
                    .context("--python needs an interpreter, e.g. --python python3.11")?
                    .clone();
            }
            other => bail!("unknown option `{other}` (refs takes only --python PY)"),
        }
    }
    let root = crate::root();
    let py = ensure_venv(&root, &python)?;
    let scripts = ref_scripts(&root)?;
    if scripts.is_empty() {
        bail!("no scripts/ref_*.py found under {}", root.display());
    }
    for script in &scripts {
        let shown = script.strip_prefix(&root).unwrap_or(script).display();
        println!("== {shown}");
        let ok = Command::new(&py)
            .current_dir(&root)
            .arg(script)
            .status()
            .with_context(|| format!("running {shown}"))?;
        if !ok.success() {
            bail!("{shown} failed");
        }
    }
    println!(
        "regenerated the Python reference vectors; review `git diff testdata/` and run the tests"
    );
    Ok(())
}

/// `target/refs-venv` with the pinned requirements installed; returns its interpreter.
fn ensure_venv(root: &Path, python: &str) -> Result<PathBuf> {
    let venv = root.join("target").join("refs-venv");
    let py = crate::venv::create(&venv, python)?;
    crate::venv::pip_install(&py, &root.join("scripts").join("requirements.txt"), &venv)?;
    Ok(py)
}

/// `scripts/ref_*.py`, sorted by name.
fn ref_scripts(root: &Path) -> Result<Vec<PathBuf>> {
    let dir = root.join("scripts");
    let mut out: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("listing {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("ref_") && n.ends_with(".py"))
        })
        .collect();
    out.sort();
    Ok(out)
}
