//! `hxai sr`: symbolic regression of one column of a table on the others.
use crate::Global;
use crate::strategy::{CriterionArg, RandomStartArg, StrategyArg};
use anyhow::{Context, Result};
use hxai_symreg::SearchConfig;
use std::path::PathBuf;

/// Rows `hxai sr` fits its candidates on by default (`--max-fit-rows`); Python's
/// `SymbolicRegressor` has the same default.
pub const SR_MAX_FIT_ROWS: usize = 500;

/// The largest candidate (in nodes) `hxai sr` computes a structure key for by default
/// (`--max-key-nodes`); Python's `SymbolicRegressor` has the same default. The library's
/// default keys every candidate.
pub const SR_MAX_KEY_NODES: usize = 14;

/// `--max-key-nodes`: a number of nodes, or `all` (`None`: every candidate keyed).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct KeyNodes(pub Option<usize>);

impl KeyNodes {
    fn parse(s: &str) -> Result<Self, String> {
        if s.trim() == "all" {
            return Ok(KeyNodes(None));
        }
        s.trim()
            .parse::<usize>()
            .map(|n| KeyNodes(Some(n)))
            .map_err(|_| format!("`{s}` is not a number of nodes (0 or more) or `all`"))
    }
}

impl std::fmt::Display for KeyNodes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.0 {
            Some(n) => write!(f, "{n}"),
            None => f.write_str("all"),
        }
    }
}

/// Arguments of `hxai sr`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Table to read (CSV or Parquet): every column numeric.
    #[arg(long)]
    pub csv: PathBuf,
    /// Column to model; every other column is an input.
    #[arg(long)]
    pub target: String,
    /// Seed of every random choice.
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// Largest complexity (input leaves + operators) of a model over one input (see
    /// `--complexity-per-input`).
    #[arg(long, default_value_t = 10)]
    pub max_complexity: usize,
    /// Number of epochs.
    #[arg(long, default_value_t = 10)]
    pub epochs: usize,
    /// Stop after this many seconds (results then depend on timing).
    #[arg(long)]
    pub time_limit_s: Option<f64>,
    /// Comma-separated operators, from: add sub mul div exp log sqrt square inverse sin cos
    /// tanh abs gaussian gaussian2 (default: all of them, the paper's and feyn's sets).
    #[arg(long, value_delimiter = ',')]
    pub operators: Option<Vec<String>>,
    /// Which operator may appear inside which: `strict` (the default of `sr`: `readable`,
    /// and `sin`/`cos` only of a sum of inputs), `readable` (no exp, log, sin, cos, tanh or
    /// gaussian inside another, except a power law `exp(a*log(x))`), `none` (free nesting,
    /// the default before issue 47), or rules `OUTER:INNER=MAX` (e.g. `strict,sin:mul=1`).
    #[arg(long)]
    pub nesting: Option<String>,
    /// Consensus selection: also search N bootstrap resamples of the rows and select the
    /// structure most of them give back among their near-best models, refitted on all rows
    /// (0, the default, selects by --criterion from one search).
    #[arg(long, default_value_t = 0)]
    pub consensus: usize,
    /// Fit a candidate again when an algebraically equal structure (same canonical form)
    /// was fitted earlier in the search; by default it takes the earlier fit. For
    /// measuring what the skip saves (`duplicate_structures` in `--json`).
    #[arg(long)]
    pub refit_equivalent: bool,
    /// Compute the structure key (to skip a candidate whose structure was fitted before)
    /// only for candidates of at most N nodes (inputs, constants and operators), and fit
    /// longer ones without one; `all` keys every candidate (the library's default), 0 none.
    /// The keys of long programs cost the most and they are rarely equal to one fitted
    /// before: on the AI Feynman 100, N = 14 took about a fifth less CPU time than `all`
    /// with as many laws recovered (docs/benchmarks.md, "Keys for the short programs
    /// only").
    #[arg(long, default_value_t = KeyNodes(Some(SR_MAX_KEY_NODES)), value_parser = KeyNodes::parse)]
    pub max_key_nodes: KeyNodes,
    /// Report the models as the search wrote them, not in the shorter form the algebra
    /// proves them equal to (for measuring what the simplification changes: `simplified`
    /// in `--json` counts the models it shortened).
    #[arg(long)]
    pub no_simplify: bool,
    /// Leave out AI Feynman's tools (on by default): the most accurate model tested as an
    /// oracle for a sum or product of parts, a pair of inputs that enters as one, and an
    /// input that enters as a power, the smaller problems searched apart; and a polynomial
    /// of a transformed target on searches of up to three inputs. Measured on the AI
    /// Feynman 100 and the held-out suites (docs/benchmarks.md), they recover more laws for
    /// about 40 % more time.
    #[arg(long, conflicts_with = "separability")]
    pub no_separability: bool,
    /// Leave out the power primitive (on by default): closed-form factor models of the
    /// target, a product `C x^a y^b ...` and a sum of one-column terms (powers with fitted
    /// exponents first, then the allowed operators' shapes), chosen by cross-validation and
    /// offered to selection beside the search's models (docs/interfaces.md).
    #[arg(long)]
    pub no_power_laws: bool,
    /// The tools `--no-separability` leaves out: the default since they measured better; kept
    /// so that command lines written when they were opt-in still run.
    #[arg(long, hide = true)]
    pub separability: bool,
    /// Complexity of operators, as comma-separated NAME=INTEGER (e.g. `sqrt=2,exp=2`);
    /// operators not named count 1.
    #[arg(long, value_delimiter = ',')]
    pub operator_complexity: Vec<String>,
    /// Complexity the cap grows by with each input beyond the first: the cap is
    /// `max_complexity + complexity_per_input * (inputs - 1)`, so a law using every input
    /// once fits (0 keeps the cap fixed).
    #[arg(long, default_value_t = 2)]
    pub complexity_per_input: usize,
    /// Stop after this many fitted models.
    #[arg(long)]
    pub max_evaluations: Option<u64>,
    /// Candidates proposed and fitted per epoch.
    #[arg(long, default_value_t = SearchConfig::default().candidates_per_epoch)]
    pub candidates_per_epoch: usize,
    /// Rows the search fits its candidates on (a seeded sample when the table has more);
    /// the reported models are refitted on every row. 500 in `hxai sr` (the library's
    /// default, and the hybrid corrections', is 2000): measured on the AI Feynman 100 at
    /// 1,000 rows, as many laws for about 27 % less time (docs/benchmarks.md).
    #[arg(long, default_value_t = SR_MAX_FIT_ROWS)]
    pub max_fit_rows: usize,
    /// Levenberg-Marquardt iterations per candidate's fit during the search.
    #[arg(long, default_value_t = SearchConfig::default().lm_iterations)]
    pub lm_iterations: usize,
    /// Whether each new candidate is also fitted from a seeded random start besides its
    /// canonical one. `on-failure` fits from the random start only when the canonical one
    /// gives no finite loss: measured on the AI Feynman 100, a fifth less time, as many laws
    /// at noise 0 and two fewer at 1 % (docs/benchmarks.md, "One start per candidate").
    #[arg(long, value_enum, default_value_t = RandomStartArg::Always)]
    pub random_start: RandomStartArg,
    /// Search strategy.
    #[arg(long, value_enum, default_value_t = StrategyArg::Combined)]
    pub strategy: StrategyArg,
    /// How the reported model is chosen: `mdl` (the default: BIC plus a charge for writing
    /// the structure down, which decides on small tables and fades on large ones), BIC or
    /// AIC (the simplest model within one parameter's charge of the lowest), PySR's score
    /// along the Pareto front, or k-fold cross-validated loss (the simplest within one
    /// standard error of the lowest).
    #[arg(long, value_enum, default_value_t = CriterionArg::Mdl)]
    pub criterion: CriterionArg,
    /// The prior over structures: `laws` (the default: the codelength of the structure's
    /// operators under a back-off n-gram model of 726 written laws, testdata/laws/) or
    /// `uniform` (every operator alike). `--criterion mdl` charges by it; under `cv` the
    /// one-standard-error rule picks the shortest description by it (`uniform`: the lowest
    /// complexity).
    #[arg(long, value_enum, default_value_t = crate::strategy::PriorArg::Laws)]
    pub prior: crate::strategy::PriorArg,
    /// Folds of `--criterion cv`.
    #[arg(long, default_value_t = 5)]
    pub cv_folds: usize,
    /// How `mdl`, `bic` and `aic` read the scatter of the target: `auto` (the default)
    /// compares an additive error with a multiplicative one (in proportion to the value,
    /// for a positive target) by their likelihoods and uses the likelier; the constants are
    /// least-squares fits either way.
    #[arg(long, value_enum, default_value_t = crate::strategy::ErrorModelArg::Auto)]
    pub error_model: crate::strategy::ErrorModelArg,
    /// Multiplier lambda of the criterion's charge per fitted parameter.
    #[arg(long, default_value_t = 1.0)]
    pub complexity_penalty: f64,
    /// Also rerun the search on N seeded bootstrap resamples of the rows and report how
    /// often each feature and each structure (constants ignored) is selected, and the
    /// spread of R^2 on the rows each resample left out (JSON `stability`).
    #[arg(long)]
    pub stability: Option<usize>,
    /// Units of every column, as comma-separated COLUMN=UNIT (e.g.
    /// `F=N,m=kg,a=m/s^2`; `1` for a dimensionless column): the inputs are reduced to
    /// dimensionless groups (Buckingham pi), the search runs on those, and every model is
    /// consistent in its units (docs/interfaces.md, "Units"). `--units row` reads them
    /// from the CSV's first row under the header instead (one unit per column).
    #[arg(long, value_delimiter = ',')]
    pub units: Vec<String>,
    /// Empty cells: `refuse` (the default; the message names the column, its count and the
    /// two other choices), `drop` (drop the rows with an empty cell) or `impute` (fill an
    /// input's empty cells with its median; rows with an empty target are dropped). What
    /// was done goes to stderr and the JSON's `warnings`, the medians to its `missing`.
    #[arg(long, default_value = "refuse", value_parser = hxai_data::MissingPolicy::parse)]
    pub missing: hxai_data::MissingPolicy,
    /// Print one JSON document on stdout instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Reads `hxai sr`'s table: every cell a number, or, under `--missing drop|impute` (and
/// to say what to do when `refuse` meets an empty cell), the gaps resolved; the report of
/// what was done when anything was.
pub(crate) fn read_with_missing(
    path: &std::path::Path,
    target: &str,
    policy: hxai_data::MissingPolicy,
) -> Result<(hxai_data::Table, Option<hxai_data::MissingReport>)> {
    let cannot = || format!("cannot read the table {}", path.display());
    if policy == hxai_data::MissingPolicy::Refuse {
        match hxai_data::read_table(path) {
            Ok(t) => return Ok((t, None)),
            Err(hxai_data::DataError::MissingValue { .. }) => {}
            Err(e) => return Err(e).with_context(cannot),
        }
    }
    let gappy = hxai_data::read_gappy_table(path).with_context(cannot)?;
    let (mixed, report) = gappy
        .resolve(policy, Some(target), &[], &[], None)
        .with_context(cannot)?;
    let (table, text) = mixed.numeric().with_context(cannot)?;
    anyhow::ensure!(
        text.is_empty(),
        "{}: column(s) {} hold text; hxai sr reads numbers only",
        path.display(),
        text.join(", ")
    );
    Ok((table, Some(report)))
}

/// How a model was selected, in lines: its structure's share over resamples when measured,
/// and the alternatives the data cannot tell apart from it (`hxai sr`, `fit`, `hybrid fit`
/// and `explain` print these).
pub fn selection_lines(sel: &hxai_symreg::SelectionReport) -> Vec<String> {
    let share = |s: Option<f64>| s.map(|v| format!("{:.0} %", 100.0 * v));
    let mut lines = vec![match (share(sel.share), sel.runs) {
        (Some(s), Some(runs)) => format!(
            "selected by {}: structure {} (given back by {s} of {runs} resamples)",
            sel.method, sel.structure
        ),
        _ => format!("selected by {}: structure {}", sel.method, sel.structure),
    }];
    if !sel.alternatives.is_empty() {
        lines.push(
            "the data cannot tell these apart from it (cross-validated loss within one SE):".into(),
        );
        for a in &sel.alternatives {
            let s = share(a.share)
                .map(|s| format!("  [{s}]"))
                .unwrap_or_default();
            lines.push(format!(
                "  {:>3}{}  {}{s}",
                a.complexity,
                codelength_column(a.codelength.as_ref()),
                a.equation
            ));
        }
    }
    lines
}

/// A model's two codelengths as a column of the text output (`  L 12.3 + 4.5 nats`:
/// structure, then constants), empty when the criterion charged none.
fn codelength_column(c: Option<&hxai_symreg::prior::Codelengths>) -> String {
    c.map(|c| format!("  L {:>5.1} + {:>5.1} nats", c.structure, c.parameters))
        .unwrap_or_default()
}

/// Prints [`selection_lines`].
#[allow(clippy::print_stdout)]
pub fn print_selection(sel: &hxai_symreg::SelectionReport) {
    for line in selection_lines(sel) {
        println!("{line}");
    }
}

/// Prints a stability report: the five most frequent structures, the features used, the
/// out-of-bag R^2.
#[allow(clippy::print_stdout)]
pub fn print_stability(st: &hxai_symreg::Stability) {
    println!("stability over {} bootstrap runs:", st.runs);
    for s in st.structures.iter().take(5) {
        println!("  {:>5.1} %  {}", 100.0 * s.share, s.template);
    }
    let used: Vec<String> = st
        .features
        .iter()
        .filter(|(_, v)| **v > 0.0)
        .map(|(k, v)| format!("{k} {:.0} %", 100.0 * v))
        .collect();
    println!("  features: {}", used.join(", "));
    if let Some(sets) = &st.factor_sets {
        for s in sets.iter().take(3) {
            println!(
                "  factor columns {:>5.1} %  {}",
                100.0 * s.share,
                s.template
            );
        }
    }
    if let Some(factors) = &st.factors {
        for (col, shapes) in factors {
            let mut v: Vec<(&String, &f64)> = shapes.iter().collect();
            v.sort_by(|a, b| b.1.total_cmp(a.1).then(a.0.cmp(b.0)));
            let shown: Vec<String> = v
                .iter()
                .map(|(t, s)| format!("{t} {:.0} %", 100.0 * **s))
                .collect();
            println!("  factor of {col}: {}", shown.join(", "));
        }
    }
    if let Some(r2) = st.r2 {
        println!("  out-of-bag R^2 {:.4} +- {:.4}", r2.mean, r2.sd);
    }
}

/// Runs `hxai sr`.
#[allow(clippy::print_stdout, clippy::print_stderr)]
pub fn run(args: Args, _g: &Global) -> Result<()> {
    let units_row = args.units.len() == 1 && args.units[0] == "row";
    anyhow::ensure!(
        !(units_row && args.missing != hxai_data::MissingPolicy::Refuse),
        "--units row and --missing {} cannot be combined: give the units with --units",
        args.missing.name()
    );
    let mut missing: Option<hxai_data::MissingReport> = None;
    let (mut data, row_units) = if units_row {
        let (t, u) = hxai_data::read_table_with_units(&args.csv)
            .with_context(|| format!("cannot read the table {}", args.csv.display()))?;
        (t, Some(u))
    } else {
        let (t, report) = read_with_missing(&args.csv, &args.target, args.missing)?;
        missing = report;
        (t, None)
    };
    // the units row, as the pairs --units takes, before the target leaves the table
    let row_pairs: Option<Vec<(String, String)>> = row_units.map(|u| {
        data.names()
            .iter()
            .cloned()
            .zip(u)
            .collect::<Vec<(String, String)>>()
    });
    anyhow::ensure!(
        data.index_of(&args.target).is_some(),
        "no column `{}` in {}: the columns are {}",
        args.target,
        args.csv.display(),
        data.names().join(", ")
    );
    anyhow::ensure!(
        data.n_cols() > 1,
        "{}: no input column besides `{}`",
        args.csv.display(),
        args.target
    );
    let y = data.remove_column(&args.target)?;
    let mut cfg = SearchConfig {
        seed: args.seed,
        time_limit_s: args.time_limit_s,
        max_evaluations: args.max_evaluations,
        candidates_per_epoch: args.candidates_per_epoch,
        max_fit_rows: args.max_fit_rows,
        lm_iterations: args.lm_iterations,
        random_start: args.random_start.into(),
        strategy: args.strategy.into(),
        complexity_penalty: args.complexity_penalty,
        skip_equivalent: !args.refit_equivalent,
        max_key_nodes: args.max_key_nodes.0,
        simplify: !args.no_simplify,
        separability: !args.no_separability,
        power_laws: !args.no_power_laws,
        error_model: args.error_model.into(),
        prior: args.prior.into(),
        nesting: hxai_symreg::Nesting::strict(),
        ..SearchConfig::default()
    };
    crate::strategy::SearchFlags {
        epochs: Some(args.epochs),
        max_complexity: Some(args.max_complexity),
        criterion: Some(args.criterion.into()),
        cv_folds: Some(args.cv_folds),
        operators: args.operators.as_deref(),
        nesting: args.nesting.as_deref(),
        consensus: Some(args.consensus),
        prior: None,
        operator_complexity: &args.operator_complexity,
        complexity_per_input: Some(args.complexity_per_input),
    }
    .apply(&mut cfg)?;
    let reduction = if args.units.is_empty() {
        None
    } else {
        let given: Vec<(String, String)> = match row_pairs {
            Some(pairs) => pairs,
            None => {
                crate::strategy::pairs::<String>(&args.units, "--units", "a unit such as m/s^2")?
                    .into_iter()
                    .collect()
            }
        };
        let (dims, target) = hxai_symreg::units::dimensions(data.names(), &args.target, &given)?;
        Some(hxai_symreg::units::Reduction::of(
            data.names(),
            &dims,
            target,
        )?)
    };
    let bar = crate::progress::styled(
        cfg.epochs as u64,
        "{bar:30} epoch {pos}/{len} {msg} [{elapsed}]",
    );
    let mut on_progress = |p: &hxai_symreg::Progress| {
        bar.set_position(p.epoch as u64);
        bar.set_message(format!(
            "models {} best loss {:.4e}",
            p.evaluations, p.best_loss
        ));
    };
    let res = hxai_symreg::units::search(&data, &y, reduction.as_ref(), &cfg, &mut on_progress)?;
    bar.finish_and_clear();
    let stability = match args.stability {
        Some(runs) => {
            let b = crate::progress::styled(runs as u64, "{bar:30} {pos}/{len} {msg} [{elapsed}]");
            b.set_message("stability runs");
            let bb = b.clone();
            let mut tick = move |done: usize, _: usize| bb.set_position(done as u64);
            let s = hxai_symreg::units::stability(
                &data,
                &y,
                reduction.as_ref(),
                &cfg,
                runs,
                &mut tick,
            )?;
            b.finish_and_clear();
            Some(s)
        }
        None => None,
    };
    let unc = res.best.uncertainty(&data, &y)?;
    let mut report = hxai_symreg::SearchReport::of(&res, &cfg, (&data, &y), &unc, true, stability)?;
    report.dimensional_groups = reduction.as_ref().map(|r| r.describe(&args.target));
    // the cells --missing-codes emptied, then what --missing did with them
    report.warnings.extend(hxai_data::take_missing_code_notes());
    if let Some(m) = &missing {
        report.warnings.extend(m.lines());
    }
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    if args.json {
        let mut doc = serde_json::to_value(&report)?;
        if let (Some(m), Some(obj)) = (&missing, doc.as_object_mut()) {
            obj.insert("missing".into(), serde_json::to_value(m)?);
        }
        println!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        let num = |v: Option<f64>| v.unwrap_or(f64::NAN);
        println!(
            "best (complexity {}{}): {}",
            res.best.complexity(),
            report
                .best
                .codelength
                .map(|c| format!(", L {:.1} + {:.1} nats", c.structure, c.parameters))
                .unwrap_or_default(),
            res.best.equation()
        );
        println!(
            "  R^2 {:.6}  RMSE {:.6e}  features {}",
            num(report.best.r2),
            num(report.best.rmse),
            res.best.features().join(", ")
        );
        println!("Pareto front:");
        for (m, s) in res.pareto.iter().zip(&report.pareto) {
            println!(
                "  {:>3}  R^2 {:.6}{}  {}",
                m.complexity(),
                num(s.r2),
                codelength_column(s.codelength.as_ref()),
                m.equation()
            );
        }
        println!("{} models in {:.2} s", res.evaluations, res.seconds);
        if res.error_model == hxai_symreg::ErrorModel::Multiplicative {
            println!(
                "selected with a multiplicative error (scatter in proportion to the target, \
                 likelier here than a fixed one; --error-model additive reads it as fixed)"
            );
        }
        if let Some(groups) = &report.dimensional_groups {
            println!("searched on the dimensionless groups:");
            for line in groups {
                println!("  {line}");
            }
        }
        print_selection(&report.selection);
        if let Some(st) = &report.stability {
            print_stability(st);
        }
    }
    Ok(())
}
