//! The search flags shared by `hxai sr`, `hxai fit` and `hxai hybrid fit`: `--strategy` and
//! `--criterion`.
use hxai_symreg::{Criterion, Strategy};

/// `--strategy` values: which symbolic-regression search runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum StrategyArg {
    /// Path sampling from a learned field, with QLattice-style lineages.
    Qlattice,
    /// Island genetic programming with age-regularised evolution.
    Genetic,
    /// Both, sharing one Pareto archive.
    Combined,
    /// Random search (the baseline: random programs, no learning).
    Random,
}

impl From<StrategyArg> for Strategy {
    fn from(s: StrategyArg) -> Self {
        match s {
            StrategyArg::Qlattice => Strategy::QLattice,
            StrategyArg::Genetic => Strategy::Genetic,
            StrategyArg::Combined => Strategy::Combined,
            StrategyArg::Random => Strategy::Random,
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

/// Parses `--operator-complexity` entries (`sqrt=2`, `exp=2`) into the search's
/// `operator_complexity` map; the search checks the operator names and values.
///
/// # Errors
/// An entry that is not `NAME=INTEGER`, or names one operator twice.
pub fn operator_complexity(
    entries: &[String],
) -> anyhow::Result<std::collections::BTreeMap<String, usize>> {
    let mut out = std::collections::BTreeMap::new();
    for e in entries.iter().filter(|e| !e.trim().is_empty()) {
        let (name, value) = e.split_once('=').ok_or_else(|| {
            anyhow::anyhow!("--operator-complexity entry `{e}` is not NAME=INTEGER (e.g. sqrt=2)")
        })?;
        let c: usize = value.trim().parse().map_err(|_| {
            anyhow::anyhow!(
                "--operator-complexity entry `{e}`: `{}` is not a whole number (e.g. sqrt=2)",
                value.trim()
            )
        })?;
        let key = name.trim().to_ascii_lowercase();
        anyhow::ensure!(
            out.insert(key.clone(), c).is_none(),
            "--operator-complexity names `{key}` twice"
        );
    }
    Ok(out)
}
