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
