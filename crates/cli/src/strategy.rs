//! The `--strategy` flag, shared by `hxai fit` and `hxai sr`.
use hxai_symreg::Strategy;

/// `--strategy` values: which symbolic-regression search runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum StrategyArg {
    /// QLattice-style path sampling over lineages.
    Qlattice,
    /// Island genetic programming.
    Genetic,
    /// Both, sharing one Pareto archive.
    Combined,
}

impl From<StrategyArg> for Strategy {
    fn from(s: StrategyArg) -> Self {
        match s {
            StrategyArg::Qlattice => Strategy::QLattice,
            StrategyArg::Genetic => Strategy::Genetic,
            StrategyArg::Combined => Strategy::Combined,
        }
    }
}
