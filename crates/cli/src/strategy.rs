//! The search flags shared by `hxai sr`, `hxai fit` and `hxai hybrid fit`: `--strategy` and
//! `--criterion`; `hxai sr`'s `--random-start`; and [`SearchFlags`], the settings every
//! command that searches applies to its search configuration in one place.
use hxai_symreg::{Criterion, RandomStart, SearchConfig, Strategy};

/// The search settings the commands that search share (`hxai sr`, `hxai fit`, `hxai hybrid
/// fit | compare`), each `None` (or empty) where the command's own default stands:
/// [`SearchFlags::apply`] writes them into a command's search configuration, so every
/// command reads the same flag the same way.
#[derive(Debug, Default)]
pub(crate) struct SearchFlags<'a> {
    /// `--epochs`.
    pub(crate) epochs: Option<usize>,
    /// `--max-complexity`.
    pub(crate) max_complexity: Option<usize>,
    /// `--criterion`.
    pub(crate) criterion: Option<Criterion>,
    /// `--cv-folds`.
    pub(crate) cv_folds: Option<usize>,
    /// `--operators` (each name trimmed).
    pub(crate) operators: Option<&'a [String]>,
    /// `--nesting`.
    pub(crate) nesting: Option<&'a str>,
    /// `--consensus`.
    pub(crate) consensus: Option<usize>,
    /// `--prior`.
    pub(crate) prior: Option<hxai_symreg::Prior>,
    /// `--operator-complexity` entries `NAME=INTEGER`.
    pub(crate) operator_complexity: &'a [String],
    /// `--complexity-per-input`.
    pub(crate) complexity_per_input: Option<usize>,
}

impl SearchFlags<'_> {
    /// Writes the flags given into `cfg`.
    ///
    /// # Errors
    /// A `--nesting` or `--operator-complexity` that does not parse.
    pub(crate) fn apply(&self, cfg: &mut SearchConfig) -> anyhow::Result<()> {
        if let Some(e) = self.epochs {
            cfg.epochs = e;
        }
        if let Some(c) = self.max_complexity {
            cfg.max_complexity = c;
        }
        if let Some(c) = self.criterion {
            cfg.criterion = c;
        }
        if let Some(k) = self.cv_folds {
            cfg.cv_folds = k;
        }
        if let Some(ops) = self.operators {
            cfg.operators = ops.iter().map(|o| o.trim().to_string()).collect();
        }
        if let Some(n) = self.nesting {
            cfg.nesting = hxai_symreg::Nesting::parse(n)?;
        }
        if let Some(b) = self.consensus {
            cfg.consensus_runs = b;
        }
        if let Some(p) = self.prior {
            cfg.prior = p;
        }
        if !self.operator_complexity.is_empty() {
            cfg.operator_complexity = operator_complexity(self.operator_complexity)?;
        }
        if let Some(c) = self.complexity_per_input {
            cfg.complexity_per_input = c;
        }
        Ok(())
    }
}

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
    /// Description length: BIC plus a charge for writing the structure down (under
    /// `--prior`: its tokens' codelength under a model of written laws, or `2 ln B` per
    /// unit of complexity), so a structure must pay for itself on small tables.
    Mdl,
}

impl From<CriterionArg> for Criterion {
    fn from(c: CriterionArg) -> Self {
        match c {
            CriterionArg::Bic => Criterion::Bic,
            CriterionArg::Aic => Criterion::Aic,
            CriterionArg::Pareto => Criterion::ParetoScore,
            CriterionArg::Cv => Criterion::CrossValidation,
            CriterionArg::Mdl => Criterion::Mdl,
        }
    }
}

/// `--prior` values: the prior over structures `--criterion mdl` charges by, and by which
/// `--criterion cv` picks among the models within one standard error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PriorArg {
    /// Learned from 726 written laws (testdata/laws/): a power or an exponential of a ratio
    /// is cheap, a tanh, a cosine or a Gaussian dear.
    Laws,
    /// Every operator alike: `2 ln B` per unit of complexity.
    Uniform,
}

impl From<PriorArg> for hxai_symreg::Prior {
    fn from(p: PriorArg) -> Self {
        match p {
            PriorArg::Laws => hxai_symreg::Prior::Laws,
            PriorArg::Uniform => hxai_symreg::Prior::Uniform,
        }
    }
}

/// `--error-model` values: how the criterion reads the scatter of a positive target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ErrorModelArg {
    /// Whichever of the two below gives the lower criterion (additive unless the target is
    /// positive on every row).
    Auto,
    /// Scatter of one size on every row (least squares).
    Additive,
    /// Scatter in proportion to the value (a normal error of `ln y`): a target that spans
    /// decades is judged on every row, not on its largest few.
    Multiplicative,
}

impl From<ErrorModelArg> for hxai_symreg::ErrorModel {
    fn from(e: ErrorModelArg) -> Self {
        match e {
            ErrorModelArg::Auto => Self::Auto,
            ErrorModelArg::Additive => Self::Additive,
            ErrorModelArg::Multiplicative => Self::Multiplicative,
        }
    }
}

/// `--random-start` values: whether a new candidate is also fitted from a random start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RandomStartArg {
    /// Also from a seeded random start, keeping the better fit.
    Always,
    /// From the random start only when the canonical start gives no finite loss.
    OnFailure,
}

impl From<RandomStartArg> for RandomStart {
    fn from(r: RandomStartArg) -> Self {
        match r {
            RandomStartArg::Always => RandomStart::Always,
            RandomStartArg::OnFailure => RandomStart::OnFailure,
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
    let entries: Vec<String> = entries.iter().map(|e| e.to_ascii_lowercase()).collect();
    pairs(
        &entries,
        "--operator-complexity",
        "a whole number (e.g. sqrt=2)",
    )
}

/// Parses `NAME=VALUE` entries of the option `flag` (the one parser of such lists: `--set`,
/// `--init`, `--operator-complexity`). Blank entries are skipped; names are trimmed.
///
/// # Errors
/// An entry without `=` (the message says to write `NAME=VALUE`), a value that does not
/// parse (`what` says what it must be), or a name given twice.
pub fn pairs<T: std::str::FromStr>(
    entries: &[String],
    flag: &str,
    what: &str,
) -> anyhow::Result<std::collections::BTreeMap<String, T>> {
    let mut out = std::collections::BTreeMap::new();
    for e in entries.iter().filter(|e| !e.trim().is_empty()) {
        let (name, value) = e.split_once('=').ok_or_else(|| {
            anyhow::anyhow!(
                "{flag} entry `{e}` is not NAME=VALUE; write NAME=VALUE with VALUE {what}"
            )
        })?;
        let v: T = value
            .trim()
            .parse()
            .map_err(|_| anyhow::anyhow!("{flag} entry `{e}`: `{}` is not {what}", value.trim()))?;
        let key = name.trim().to_string();
        anyhow::ensure!(
            out.insert(key.clone(), v).is_none(),
            "{flag} names `{key}` twice"
        );
    }
    Ok(out)
}

/// `--interval-method` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum IntervalMethodArg {
    /// CV+ over the folds of the fit, scores normalised by the local scale (the default
    /// where the model file stores its calibration).
    Conformal,
    /// Split conformal: one fold's model, calibrated on that fold's rows.
    Split,
    /// The delta method with a constant residual variance (the default for model files
    /// without conformal calibration).
    Delta,
}

impl From<IntervalMethodArg> for hxai_hybrid::IntervalMethod {
    fn from(m: IntervalMethodArg) -> Self {
        match m {
            IntervalMethodArg::Conformal => hxai_hybrid::IntervalMethod::Conformal,
            IntervalMethodArg::Split => hxai_hybrid::IntervalMethod::Split,
            IntervalMethodArg::Delta => hxai_hybrid::IntervalMethod::Delta,
        }
    }
}

/// The interval method asked for, else the model's default (`model_default`, from its
/// `default_interval_method`), else the delta method.
pub fn interval_method(
    asked: Option<IntervalMethodArg>,
    model_default: Option<hxai_hybrid::IntervalMethod>,
) -> hxai_hybrid::IntervalMethod {
    asked
        .map(hxai_hybrid::IntervalMethod::from)
        .or(model_default)
        .unwrap_or(hxai_hybrid::IntervalMethod::Delta)
}
