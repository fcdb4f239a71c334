//! `hxai sr` (placeholder until its issue lands).
use crate::Global;
use anyhow::Result;

/// Arguments of `hxai sr`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `hxai sr`.
pub fn run(_args: Args, _g: &Global) -> Result<()> {
    anyhow::bail!("`hxai sr` is not implemented yet")
}
