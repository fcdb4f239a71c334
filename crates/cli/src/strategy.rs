//! The search flags shared by `hxai sr`, `hxai fit` and `hxai hybrid fit`: `--strategy` and
//! `--criterion`.
use hxai_symreg::{Criterion, Strategy};

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

/// `--criterion` values: how the reported model is chosen among the search's candidates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CriterionArg {
    /// Bayesian information criterion (the simplest model within one parameter's charge of
    /// the lowest).
    Bic,
    /// Akaike information criterion (likewise).
    Aic,
    /// PySR's score along the Pareto front.
    Pareto,
    /// K-fold cross-validated loss (`--cv-folds`), with the one-standard-error rule.
    Cv,
}

impl From<CriterionArg> for Criterion {
    fn from(c: CriterionArg) -> Self {
        match c {
            CriterionArg::Bic => Criterion::Bic,
            CriterionArg::Aic => Criterion::Aic,
            CriterionArg::Pareto => Criterion::ParetoScore,
            CriterionArg::Cv => Criterion::CrossValidation,
        }
    }
}
