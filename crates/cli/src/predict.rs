//! `hxai predict` (placeholder until its issue lands).
use crate::Global;
use anyhow::Result;

/// Arguments of `hxai predict`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `hxai predict`.
pub fn run(_args: Args, _g: &Global) -> Result<()> {
    anyhow::bail!("`hxai predict` is not implemented yet")
}
