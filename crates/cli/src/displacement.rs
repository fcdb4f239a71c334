//! `hxai displacement` (placeholder until its issue lands).
use crate::Global;
use anyhow::Result;

/// Arguments of `hxai displacement`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `hxai displacement`.
pub fn run(_args: Args, _g: &Global) -> Result<()> {
    anyhow::bail!("`hxai displacement` is not implemented yet")
}
