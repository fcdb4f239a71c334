//! The Python virtual environments of `bench-sr` and `refs`.
use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The interpreter of the venv at `venv`, made with `python -m venv` if it is missing.
pub fn create(venv: &Path, python: &str) -> Result<PathBuf> {
    let py = venv.join("bin").join("python");
    if !py.exists() {
        let ok = Command::new(python)
            .args(["-m", "venv"])
            .arg(venv)
            .status()
            .with_context(|| format!("running {python} -m venv"))?;
        if !ok.success() {
            bail!("{python} -m venv {} failed", venv.display());
        }
    }
    Ok(py)
}

/// `pip install -r requirements` with the venv's interpreter `py` (the venv `venv`, for the
/// message).
pub fn pip_install(py: &Path, requirements: &Path, venv: &Path) -> Result<()> {
    let ok = Command::new(py)
        .args(["-m", "pip", "install", "-q", "-r"])
        .arg(requirements)
        .status()
        .context("running pip install")?;
    if !ok.success() {
        bail!(
            "pip install -r {} into {} failed",
            requirements.display(),
            venv.display()
        );
    }
    Ok(())
}
