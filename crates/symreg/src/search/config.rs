//! Search settings: which strategy, which selection criterion, and every knob with its
//! default and its check.
use crate::consensus::MAX_CONSENSUS_RUNS;
pub use crate::enclosure::{DEFINED_BOXES, DEFINED_MARGIN};
use crate::nesting::{Nesting, NestingRules};
use crate::ops::{Op, OpCosts, parse_operators};
use crate::program::ComplexityMeasure;
use crate::{Par, SrError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Largest `max_complexity` accepted. The paper searches up to 10; 60 leaves room for
/// larger laws while keeping every candidate's Levenberg-Marquardt system (about two
/// parameters per leaf) small enough for the dense Cholesky solve of [`crate::fit`].
pub(crate) const MAX_COMPLEXITY_LIMIT: usize = 60;

/// Most runners-up kept at each complexity ([`SearchConfig::runners_up`]): each is refitted
/// on all rows and cross-validated at the end of a search.
pub(crate) const MAX_RUNNERS_UP: usize = 20;

/// Fewest rows a search runs on: a two-constant law on five rows keeps three residual
/// degrees of freedom. Below [`FEW_ROWS`] a candidate may have at most `n - 2` fitted
/// constants, and the command line warns how few rows there are.
pub(crate) const MIN_ROWS: usize = 5;

/// Rows below which a search is on "few rows" (the smallest `max_fit_rows`, too): the
/// simplest model has four parameters before simplification (output scale and offset, one
/// input's weight and bias), and twice that many rows leaves the fit residual degrees of
/// freedom, so a criterion can tell models apart. Engineers' calibration tables are often
/// smaller (six or seven points), so such tables are searched with the constants capped at
/// `n - 2` (issue 47).
pub const FEW_ROWS: usize = 8;

/// The default operators: the paper's (arithmetic, `sin`, `cos`, the one- and two-input
/// gaussians, `log`, `abs`) and feyn's (`exp`, `sqrt`, `square`, `inverse`, `tanh`).
pub const DEFAULT_OPERATORS: [&str; 15] = [
    "add",
    "sub",
    "mul",
    "div",
    "sin",
    "cos",
    "gaussian",
    "gaussian2",
    "log",
    "abs",
    "exp",
    "sqrt",
    "square",
    "inverse",
    "tanh",
];

/// The paper's operators (arithmetic, `sin`, `cos`, the one- and two-input gaussians, `log`,
/// `abs`) plus `exp`, the first eleven of [`DEFAULT_OPERATORS`]: the set hybrid corrections search by default ([`SearchConfig::paper`]).
/// A correction is a small term over many features; the wider [`DEFAULT_OPERATORS`] serve
/// laws such as AI Feynman's, but on the hybrid cases they cost accuracy (measured with
/// `cargo xtask reproduce`, see docs/benchmarks.md).
pub const PAPER_OPERATORS: &[&str] = DEFAULT_OPERATORS.split_at(11).0;

/// The operators of the laws engineers write down for a process (Taylor's tool life,
/// Kienzle's force, Archard's wear, Arrhenius): arithmetic, `exp` and `log`, so power laws
/// (`exp(a*log(x))`), exponentials and quotients, and no periodic function, gaussian or
/// `abs`. What a table hybrid's correction searches by default ([`SearchConfig::laws`]);
/// widen it with `--operators` where the process has, say, a periodic effect.
pub const LAW_OPERATORS: [&str; 6] = ["add", "sub", "mul", "div", "exp", "log"];

/// Which search strategy runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Strategy {
    /// Path sampling: structures sampled from a learned probability field over (tree
    /// position, operator or input), alongside QLattice-style cells of lineages. Serialised
    /// as `qlattice`, the spelling of the `--strategy` flag (`q_lattice`, the derived
    /// snake-case name, is read).
    #[serde(rename = "qlattice", alias = "q_lattice")]
    QLattice,
    /// Island genetic programming with age-regularised evolution (the oldest leave).
    Genetic,
    /// Both, sharing a Pareto archive (default).
    #[default]
    Combined,
    /// Random programs from the generator, without learning: the baseline of the ablation
    /// (same evaluation budget as the others).
    Random,
}

/// How the selected model is chosen.
///
/// With `Bic` and `Aic`, `k` counts fitted parameters: constants snapped to exact values
/// (0, +-1, integers, halves) are not counted, and the selected model is the simplest one
/// whose criterion is within one parameter's charge (`lambda ln n`, or `2 lambda`) of the
/// lowest. Snapping constants to exact values is judged by the same charge (BIC's under
/// `ParetoScore`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Criterion {
    /// Bayesian information criterion `n ln(MSE/var + 1e-12) + lambda k ln n` (default).
    #[default]
    Bic,
    /// Akaike information criterion `n ln(MSE/var + 1e-12) + 2 lambda k`.
    Aic,
    /// PySR's rule: on the Pareto front, among models with loss within 1.5x of the best,
    /// the largest drop of log-loss per unit of complexity.
    ParetoScore,
    /// K-fold cross-validation (`cv_folds` folds, seeded by `seed`): each candidate's
    /// structure is refitted on K-1 folds and scored by its mean squared error on the
    /// held-out fold; the pick is the simplest model whose mean held-out error is within
    /// one standard error of the lowest (the one-standard-error rule). Constants are still
    /// snapped by BIC's charge. Serialised as `cv`.
    #[serde(rename = "cv")]
    CrossValidation,
    /// Description length: BIC's score plus a charge for writing the structure down,
    /// `2 c ln(B)` for a model of complexity `c` over an alphabet of `B` symbols (the
    /// search's operators and the inputs), after Bartlett, Desmond and Ferreira's exhaustive
    /// symbolic regression (2023), whose description length codes a function's tree in
    /// `c ln(B)` nats. BIC charges the constants only, so among thousands of structures one
    /// with five more operators wins on a few tenths of a percent of R^2; this charge does
    /// not grow with the rows, so it decides on a few dozen rows and fades on thousands.
    /// The pick is the simplest model within one parameter's charge of the lowest, as with
    /// BIC. Serialised as `mdl`.
    Mdl,
}

pub use crate::prior::Prior;
/// How the criterion of [`Criterion::Bic`], [`Criterion::Aic`] and [`Criterion::Mdl`]
/// reads the scatter of a positive target: as an error of fixed size (additive, the
/// least-squares likelihood) or in proportion to the value (multiplicative: a normal error
/// of `ln y`, so a power law fitted to a target spanning decades is judged on every row,
/// not on its largest few). The constants are least-squares fits on the target's scale
/// either way; only the pick among the fitted models changes.
///
/// The two likelihoods are compared as Box and Cox (1964) compare transforms: the
/// multiplicative error's `-2 ln L` on the scale of `y` is `n ln(g^2 MSE_log)`, `g` the
/// target's geometric mean and `MSE_log` the mean squared difference of `ln y` and
/// `ln y_hat` (the Jacobian of `ln`), so it enters the criterion as the loss
/// `g^2 MSE_log` in place of the MSE.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorModel {
    /// The least-squares likelihood (every model's and hybrid correction's default).
    #[default]
    Additive,
    /// The multiplicative likelihood; a target that is not positive on every row is
    /// refused.
    Multiplicative,
    /// Whichever of the two gives the lower criterion for the best model under it, where
    /// the target is positive on every row (additive otherwise): `hxai sr`'s and
    /// `SymbolicRegressor`'s default.
    Auto,
}

impl ErrorModel {
    /// Whether this is [`ErrorModel::Additive`] (files leave the default out).
    pub fn is_additive(&self) -> bool {
        *self == Self::Additive
    }
}

/// Where the constants of a new candidate's fit start during the search.
///
/// Every new candidate is first fitted from its canonical start (inputs scaled to unit
/// RMS with their sign, constants 1, the output map by least squares); a candidate that
/// inherits its parent's constants starts from those alone, whatever this says.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RandomStart {
    /// Also fit from a seeded random perturbation of it and keep the better fit (the
    /// default).
    #[default]
    Always,
    /// Fit from the random start only when the canonical start gives no finite loss:
    /// measured on the AI Feynman 100 with `hxai sr`, a fifth less time, as many laws at
    /// noise 0 and two fewer at 1 % (docs/benchmarks.md, "One start per candidate").
    OnFailure,
}

/// Search settings. `Default` gives the paper's set-up (seed 42, 10 epochs, complexity at
/// most 10 whatever the number of inputs, BIC with lambda 1) with the paper's and feyn's
/// operators ([`DEFAULT_OPERATORS`]). `hxai sr` lets the cap grow by 2 with each input
/// beyond the first (`complexity_per_input = 2`, see [`SearchConfig::complexity_cap`]):
/// a hybrid model's correction keeps the paper's fixed cap, which keeps it readable.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default)]
pub struct SearchConfig {
    /// Seed of every random choice.
    pub seed: u64,
    /// Number of epochs (each proposes `candidates_per_epoch` models).
    pub epochs: usize,
    /// Largest complexity of a model over one input; see [`SearchConfig::complexity_cap`]
    /// for more inputs.
    pub max_complexity: usize,
    /// Complexity the cap grows by with each input beyond the first (see
    /// [`SearchConfig::complexity_cap`]); 0 (the paper's fixed cap) by default.
    pub complexity_per_input: usize,
    /// Complexity of operators by name (`{"sqrt": 2, "exp": 2}`); operators not listed
    /// count 1, the paper's count. Names as in `operators`; each value 1 to
    /// [`crate::ops::MAX_OPERATOR_COMPLEXITY`].
    pub operator_complexity: BTreeMap<String, usize>,
    /// Allowed operator names (see [`Op::parse`]).
    pub operators: Vec<String>,
    /// Search strategy.
    pub strategy: Strategy,
    /// Model selection criterion.
    pub criterion: Criterion,
    /// Weight lambda of the parameter penalty in BIC/AIC.
    pub complexity_penalty: f64,
    /// Folds of [`Criterion::CrossValidation`] (2 or more; ignored by the other criteria).
    pub cv_folds: usize,
    /// Stop after this many seconds (checked between batches of candidates; a run that hits
    /// it depends on timing).
    pub time_limit_s: Option<f64>,
    /// Stop after this many fitted models.
    pub max_evaluations: Option<u64>,
    /// Inputs enter as `w x + b` (QLattice) when true.
    pub affine_inputs: bool,
    /// How complexity is counted.
    pub complexity_measure: ComplexityMeasure,
    /// Candidates proposed per epoch.
    pub candidates_per_epoch: usize,
    /// Rows used to fit candidates during the search (a seeded subsample when the data has
    /// more); the reported models are refitted on all rows.
    pub max_fit_rows: usize,
    /// Levenberg-Marquardt iterations per candidate.
    pub lm_iterations: usize,
    /// Whether a new candidate is also fitted from a random start ([`RandomStart`]).
    pub random_start: RandomStart,
    /// Snap constants to simple values in reported models when the loss barely changes.
    pub snap_constants: bool,
    /// Relative loss increase allowed when a constant is rounded to 1-3 significant digits
    /// (snaps to exact values such as 0, 1 or 1/2 are judged by the criterion instead).
    pub snap_tolerance: f64,
    /// Snap constants also to the irrationals a physicist writes (`sqrt(2)`, `1/sqrt(2 pi)`,
    /// `1/(4 pi)`, ...; judged by the criterion like every exact snap): true for `hxai sr`
    /// (laws), false for hybrid corrections ([`SearchConfig::paper`]), where a factor that
    /// happens to lie near `1/sqrt(pi)` is a fitted number, not a claim about physics.
    /// Thirds and quarters are tried either way.
    pub named_constants: bool,
    /// Test the most accurate model for separability (`f = g(xA) + h(xB)` or
    /// `f = g(xA) h(xB)`, by mixed differences) and, where it holds, search the parts
    /// apart and offer their join to selection (`search::decompose`). False by default:
    /// on the AI Feynman 100 it recovered one more law at noise 0 and none at 1 % for
    /// about 40 % more CPU time (docs/benchmarks.md, "Separability").
    pub separability: bool,
    /// Offer selection closed-form factor models of the target ([`crate::factors`]): a
    /// product `C prod_j f_j(x_j)` and a sum `c + sum_j a_j s_j(x_j)` of one-column shapes
    /// (a power `x^p` with a fitted exponent first, then the shapes whose operators are
    /// allowed: linear, `exp`, `log`, a pole or a saturation with `div` or `inverse`) and
    /// at most one `x^p y^q` interaction, chosen by cross-validation. The power primitive
    /// of `hxai sr` (issue 47): a product of powers is one candidate, not a search through
    /// `exp(a log(x) + b log(y))`. Only on tables of at most 300 rows (larger ones reach a
    /// power law through the search itself; measured on the AI Feynman 100, see
    /// `search::power`). False by default (hybrid corrections have their own `--form
    /// factors`); `hxai sr` and `SymbolicRegressor` turn it on.
    pub power_laws: bool,
    /// How the criterion reads the target's scatter ([`ErrorModel`]): additive by default,
    /// [`ErrorModel::Auto`] in `hxai sr` and `SymbolicRegressor`.
    pub error_model: ErrorModel,
    /// Which operator may appear inside which ([`Nesting`]): none constrained by default,
    /// [`Nesting::readable()`] for hybrid corrections ([`SearchConfig::paper`]),
    /// [`Nesting::strict()`] in `hxai sr` and `SymbolicRegressor`.
    /// Candidates that break a constraint are never fitted.
    pub nesting: Nesting,
    /// Consensus selection over this many bootstrap searches ([`crate::consensus`]); 0
    /// (the default) runs one search and selects by `criterion`.
    pub consensus_runs: usize,
    /// Skip a candidate whose structure is algebraically equal to one already fitted in
    /// this search (same [`crate::canonical::Effort::Fast`] structure key), giving it the
    /// earlier fit: true by default. False fits it again (the search before this setting;
    /// [`SearchResult::duplicate_structures`](crate::SearchResult::duplicate_structures)
    /// counts such candidates either way).
    pub skip_equivalent: bool,
    /// The largest program (in nodes: inputs, constants and operators) whose structure key
    /// the search computes: a new candidate of more nodes is fitted without one, so it is
    /// neither skipped as an equivalent nor counted as one. `None` (the default, and the
    /// hybrid corrections') keys every new candidate; `hxai sr` uses 14. The keys of long
    /// programs cost the most (equality saturation grows with the program) and they are
    /// rarely equal to a structure fitted before: on the AI Feynman 100, 14 took about a
    /// fifth less CPU time than `None` with as many laws, 10 about 40 % less with a few
    /// laws fewer (docs/benchmarks.md, "Keys for the short programs only").
    pub max_key_nodes: Option<usize>,
    /// Return a reported model as its canonical form when the algebra proves it equal to a
    /// shorter one with no more fitted constants ([`crate::canonical::canonical_program`];
    /// docs/interfaces.md, "Simplification after the search"): true by default. False
    /// reports the programs as the search wrote them (for measuring what it changes:
    /// [`SearchResult::simplified`](crate::SearchResult::simplified)).
    pub simplify: bool,
    /// Distinct programs kept at each complexity besides the one that fits best, and
    /// offered to selection with it: 0 for `hxai sr` (one model per complexity), 3 for
    /// hybrid corrections ([`SearchConfig::paper`]), where several short structures fit
    /// alike within the noise and selection then prefers the one with the fewest degrees
    /// of freedom ([`crate::canonical::degrees_of_freedom`]), then the plainest
    /// ([`crate::search::plainness`]), instead of the one that happened to fit a little
    /// better on these rows. At most 20.
    pub runners_up: usize,
    /// No pole beside the data (issue 64): a candidate not proven defined and finite over
    /// the box of its input columns, each widened by this share of its range (not below 0
    /// for a column that never is), is rejected ([`crate::enclosure::defined_over`]), and a
    /// reported one seen to blow up there is not selected ([`crate::search::BLOW_UP_RANGES`]).
    /// `Some(0.1)` by default; `None` keeps any candidate that is finite on the rows.
    pub defined_margin: Option<f64>,
    /// The prior over structures ([`Prior`]): what [`Criterion::Mdl`] charges, and how
    /// [`Criterion::CrossValidation`] picks within one standard error (shortest description
    /// or lowest complexity). [`Prior::Laws`]; [`Prior::Uniform`] in [`SearchConfig::laws`]
    /// (no better there on real tables: docs/benchmarks.md, issue 65).
    #[serde(default)]
    pub prior: Prior,
    /// Harmonics only where declared (issue 64): the columns a `sin` or `cos` may read (a
    /// candidate with one over another column is rejected unfitted); `None` (the default):
    /// any. Set by the hybrid from its `--periodic` columns, which its files keep instead.
    #[serde(skip)]
    pub harmonic_inputs: Option<Vec<String>>,
    /// Threads of the search (and of [`crate::stability()`]'s runs): [`Par::Current`] by
    /// default, the caller's pool. Not part of any file (`serde(skip)`): the result never
    /// depends on it.
    #[serde(skip)]
    pub par: Par,
}

impl Default for SearchConfig {
    fn default() -> Self {
        Self {
            seed: 42,
            epochs: 10,
            max_complexity: 10,
            complexity_per_input: 0,
            operator_complexity: BTreeMap::new(),
            operators: DEFAULT_OPERATORS.iter().map(|s| s.to_string()).collect(),
            strategy: Strategy::Combined,
            criterion: Criterion::Bic,
            complexity_penalty: 1.0,
            cv_folds: 5,
            time_limit_s: None,
            max_evaluations: None,
            affine_inputs: true,
            complexity_measure: ComplexityMeasure::FeaturesPlusOperators,
            candidates_per_epoch: 1000,
            max_fit_rows: 2000,
            lm_iterations: 25,
            random_start: RandomStart::Always,
            snap_constants: true,
            snap_tolerance: 1e-3,
            named_constants: true,
            separability: false,
            power_laws: false,
            error_model: ErrorModel::Additive,
            nesting: Nesting::none(),
            consensus_runs: 0,
            skip_equivalent: true,
            max_key_nodes: None,
            simplify: true,
            runners_up: 0,
            defined_margin: Some(DEFINED_MARGIN),
            prior: Prior::Laws,
            harmonic_inputs: None,
            par: Par::Current,
        }
    }
}

impl SearchConfig {
    /// The defaults with the paper's operators ([`PAPER_OPERATORS`]), no transcendental
    /// function inside another ([`Nesting::readable()`]) and no snapping to named
    /// irrationals (`named_constants`): what hybrid corrections (`hxai
    /// fit`, `hxai hybrid`, `hxai compare`, the reproduction) search with.
    pub fn paper() -> Self {
        Self {
            operators: PAPER_OPERATORS.iter().map(|s| s.to_string()).collect(),
            nesting: Nesting::readable(),
            runners_up: 3,
            named_constants: false,
            ..Self::default()
        }
    }

    /// The defaults of a table hybrid's correction (`hxai hybrid`, `HybridRegressor`): the
    /// law operators ([`LAW_OPERATORS`]), readable nesting, three runners-up per complexity,
    /// and selection by cross-validated loss with the one-standard-error rule. Measured
    /// against [`SearchConfig::paper`] on bootstrap resamples of the three process tables of
    /// `hxai_sim::cases` (docs/benchmarks.md, "Equations that explain: the law operators
    /// and cross-validated selection"): the structure the resamples agree on most often is
    /// more frequent, the hybrid's test error as low or lower.
    pub fn laws() -> Self {
        Self {
            operators: LAW_OPERATORS.iter().map(|s| s.to_string()).collect(),
            criterion: Criterion::CrossValidation,
            prior: Prior::Uniform,
            ..Self::paper()
        }
    }

    /// The largest complexity of a search over `n_inputs` inputs:
    /// `max_complexity + complexity_per_input * (n_inputs - 1)`, at most
    /// 60, the largest `max_complexity` accepted (and never below `max_complexity`).
    ///
    /// A law over `n` inputs that uses each once needs `n` leaves and `n - 1` binary
    /// operators to join them, `2n - 1` in all: with `complexity_per_input = 2` every
    /// further input brings the room to place it and join it, and the room `max_complexity`
    /// leaves for other operators stays the same however many inputs there are.
    pub fn complexity_cap(&self, n_inputs: usize) -> usize {
        let grown = self.max_complexity.saturating_add(
            self.complexity_per_input
                .saturating_mul(n_inputs.saturating_sub(1)),
        );
        grown.min(MAX_COMPLEXITY_LIMIT.max(self.max_complexity))
    }

    /// The complexity of each operator ([`SearchConfig::operator_complexity`] checked).
    ///
    /// # Errors
    /// [`SrError::UnknownOperator`] or [`SrError::InvalidConfig`] for a bad entry.
    pub fn op_costs(&self) -> Result<OpCosts, SrError> {
        OpCosts::parse(&self.operator_complexity)
    }

    /// Checks the settings once and keeps what the check derives: the operators, their
    /// costs, the nesting rules and the complexity cap, which the search, its sub-searches
    /// and the consensus runs take ([`ValidSearch`], as linfa's `check() -> Valid`).
    ///
    /// # Errors
    /// [`SrError::UnknownOperator`] or [`SrError::InvalidConfig`].
    pub fn check(&self) -> Result<ValidSearch, SrError> {
        let ops = parse_operators(&self.operators)?;
        let op_costs = self.op_costs()?;
        let nesting = self.nesting.rules()?;
        if self.max_complexity == 0 || self.max_complexity > MAX_COMPLEXITY_LIMIT {
            return Err(SrError::InvalidConfig(format!(
                "max_complexity is {}: choose 1 to {MAX_COMPLEXITY_LIMIT}",
                self.max_complexity
            )));
        }
        if self.epochs == 0 {
            return Err(SrError::InvalidConfig(
                "epochs is 0: run at least one epoch".into(),
            ));
        }
        if !(self.complexity_penalty.is_finite() && self.complexity_penalty >= 0.0) {
            return Err(SrError::InvalidConfig(
                "complexity_penalty must be finite and >= 0".into(),
            ));
        }
        if self.criterion == Criterion::CrossValidation && self.cv_folds < 2 {
            return Err(SrError::InvalidConfig(format!(
                "cv_folds is {}: cross-validation needs at least 2 folds",
                self.cv_folds
            )));
        }
        self.check_time_limit()?;
        if self.consensus_runs > MAX_CONSENSUS_RUNS {
            return Err(SrError::InvalidConfig(format!(
                "consensus_runs is {}: choose 0 (one search) to {MAX_CONSENSUS_RUNS}",
                self.consensus_runs,
            )));
        }
        if self.runners_up > MAX_RUNNERS_UP {
            return Err(SrError::InvalidConfig(format!(
                "runners_up is {}: choose 0 to {MAX_RUNNERS_UP}",
                self.runners_up
            )));
        }
        self.check_max_evaluations()?;
        if self.candidates_per_epoch == 0 {
            return Err(SrError::InvalidConfig(
                "candidates_per_epoch is 0: propose at least one model per epoch".into(),
            ));
        }
        if self.max_fit_rows < FEW_ROWS {
            return Err(SrError::InvalidConfig(format!(
                "max_fit_rows is {}: fit on at least {FEW_ROWS} rows",
                self.max_fit_rows
            )));
        }
        if self.lm_iterations == 0 {
            return Err(SrError::InvalidConfig(
                "lm_iterations is 0: allow at least one iteration of the constants' fit".into(),
            ));
        }
        Ok(ValidSearch {
            cfg: self.clone(),
            ops,
            op_costs,
            nesting,
        })
    }

    fn check_time_limit(&self) -> Result<(), SrError> {
        if let Some(t) = self.time_limit_s
            && !(t.is_finite() && t > 0.0)
        {
            return Err(SrError::InvalidConfig(
                "time_limit_s must be a positive number of seconds".into(),
            ));
        }
        Ok(())
    }

    fn check_max_evaluations(&self) -> Result<(), SrError> {
        if self.max_evaluations == Some(0) {
            return Err(SrError::InvalidConfig(
                "max_evaluations is 0: allow at least one model to be fitted".into(),
            ));
        }
        Ok(())
    }
}

/// A [`SearchConfig`] that passed [`SearchConfig::check`], with what the check derived: the
/// operators, their costs, the nesting rules; and the complexity cap. Reads as the
/// configuration it was made from (it dereferences to it), so the settings have one name.
/// Only [`SearchConfig::check`] makes one, and the search's own copies (a sub-search's
/// share of the budget, a consensus run's seed) change only the settings that need no other
/// check, or check again those that do.
#[derive(Clone, Debug)]
pub struct ValidSearch {
    cfg: SearchConfig,
    ops: Vec<Op>,
    op_costs: OpCosts,
    nesting: NestingRules,
}

impl ValidSearch {
    /// The configuration checked.
    pub fn config(&self) -> &SearchConfig {
        &self.cfg
    }

    /// The operators, parsed from [`SearchConfig::operators`].
    pub fn operators(&self) -> &[Op] {
        &self.ops
    }

    /// Each operator's complexity ([`SearchConfig::operator_complexity`]).
    pub fn op_costs(&self) -> &OpCosts {
        &self.op_costs
    }

    /// The nesting rules ([`SearchConfig::nesting`]).
    pub fn nesting(&self) -> &NestingRules {
        &self.nesting
    }

    /// The complexity cap of a search over `n_inputs` inputs
    /// ([`SearchConfig::complexity_cap`]).
    pub fn complexity_cap(&self, n_inputs: usize) -> usize {
        self.cfg.complexity_cap(n_inputs)
    }

    /// This configuration with another seed and thread pool (every other setting as checked,
    /// consensus included): one bootstrap run of [`crate::stability()`].
    pub(crate) fn with_seed_par(&self, seed: u64, par: crate::Par) -> Self {
        let mut out = self.clone();
        out.cfg.seed = seed;
        out.cfg.par = par;
        out
    }

    /// This configuration with another seed and without consensus: one run of a consensus
    /// (every other setting as checked).
    pub(crate) fn one_run(&self, seed: u64) -> Self {
        let mut out = self.clone();
        out.cfg.seed = seed;
        out.cfg.consensus_runs = 0;
        out
    }

    /// A sub-search's configuration: another seed, its share of the budget and time, no
    /// consensus; the budget and time checked again, as a new configuration would be.
    ///
    /// # Errors
    /// [`SrError::InvalidConfig`] for a time limit that is not positive or a budget of 0.
    pub(crate) fn sub_search(
        &self,
        seed: u64,
        max_evaluations: Option<u64>,
        time_limit_s: Option<f64>,
    ) -> Result<Self, SrError> {
        let mut out = self.one_run(seed);
        out.cfg.max_evaluations = max_evaluations;
        out.cfg.time_limit_s = time_limit_s;
        out.cfg.check_time_limit()?;
        out.cfg.check_max_evaluations()?;
        Ok(out)
    }
}

impl std::ops::Deref for ValidSearch {
    type Target = SearchConfig;

    fn deref(&self) -> &SearchConfig {
        &self.cfg
    }
}
