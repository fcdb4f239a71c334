//! `hxai features` (placeholder until its issue lands).
use crate::Global;
use anyhow::Result;

/// Arguments of `hxai features`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Runs `hxai features`.
pub fn run(_args: Args, _g: &Global) -> Result<()> {
    anyhow::bail!("`hxai features` is not implemented yet")
}
