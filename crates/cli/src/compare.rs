//! `hxai compare` (placeholder until its issue lands).
use crate::Global;
use anyhow::Result;

/// Arguments of `hxai compare`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `hxai compare`.
pub fn run(_args: Args, _g: &Global) -> Result<()> {
    anyhow::bail!("`hxai compare` is not implemented yet")
}
