//! `hxai simulate` (placeholder until its issue lands).
use crate::Global;
use anyhow::Result;

/// Arguments of `hxai simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `hxai simulate`.
pub fn run(_args: Args, _g: &Global) -> Result<()> {
    anyhow::bail!("`hxai simulate` is not implemented yet")
}
