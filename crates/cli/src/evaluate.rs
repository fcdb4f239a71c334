//! `hxai evaluate` (placeholder until its issue lands).
use crate::Global;
use anyhow::Result;

/// Arguments of `hxai evaluate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `hxai evaluate`.
pub fn run(_args: Args, _g: &Global) -> Result<()> {
    anyhow::bail!("`hxai evaluate` is not implemented yet")
}
