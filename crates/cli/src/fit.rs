//! `hxai fit` (placeholder until its issue lands).
use crate::Global;
use anyhow::Result;

/// Arguments of `hxai fit`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `hxai fit`.
pub fn run(_args: Args, _g: &Global) -> Result<()> {
    anyhow::bail!("`hxai fit` is not implemented yet")
}
