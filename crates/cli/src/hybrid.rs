//! `hxai hybrid fit | predict | evaluate | compare`: hybrid models of any process on a table
//! (a physics equation over the columns, its error learned by symbolic regression).
//!
//! This module parses options, reads and writes files and prints; every computation is
//! `hxai_hybrid::process`.
use crate::Global;
use anyhow::{Context, Result, bail};
use hxai_hybrid::IntervalMethod;
use hxai_hybrid::process::{
    Comparison, CorrectionForm, ProcessConfig, ProcessModel, ProcessProgress, compare_process,
    fit_process,
};
use hxai_symreg::Table;
use indicatif::{ProgressBar, ProgressStyle};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Arguments of `hxai hybrid`.
#[derive(Debug, clap::Args)]
pub struct Args {
    #[command(subcommand)]
    command: Sub,
}

#[derive(Debug, clap::Subcommand)]
enum Sub {
    /// Calibrate a physics equation, learn its correction, write the model file.
    Fit(FitArgs),
    /// Physics, correction and hybrid for every row of a table.
    Predict(PredictArgs),
    /// Physics vs hybrid on the rows of a table (needs the target column).
    Evaluate(EvaluateArgs),
    /// Physics, calibrated physics, symbolic regression, physics + forest and the hybrid on
    /// the same splits, with k-fold CV and paired t-tests.
    Compare(CompareArgs),
}

/// `--correction` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum CorrectionArg {
    /// y = f_p + delta.
    Additive,
    /// y = f_p (1 + delta).
    Multiplicative,
    /// y = f_p exp(delta), delta found on the log scale: for scatter that grows with the
    /// quantity (log-normal) and power-law corrections. Target and physics must be positive.
    Log,
}

/// `--interval-method` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub(crate) enum IntervalMethodArg {
    /// CV+ over the folds of the fit, scores normalised by the local scale (the default
    /// where the model file stores its calibration).
    Conformal,
    /// Split conformal: one fold's model, calibrated on that fold's rows.
    Split,
    /// The delta method with a constant residual variance (the default for model files
    /// without conformal calibration).
    Delta,
}

impl From<IntervalMethodArg> for IntervalMethod {
    fn from(m: IntervalMethodArg) -> Self {
        match m {
            IntervalMethodArg::Conformal => IntervalMethod::Conformal,
            IntervalMethodArg::Split => IntervalMethod::Split,
            IntervalMethodArg::Delta => IntervalMethod::Delta,
        }
    }
}

/// The method asked for, else the model's default at `level` (conformal where it stores
/// the calibration with enough scores, else delta).
fn method_of(asked: Option<IntervalMethodArg>, model: &ProcessModel, level: f64) -> IntervalMethod {
    asked
        .map(IntervalMethod::from)
        .or_else(|| model.default_interval_method(level))
        .unwrap_or(IntervalMethod::Delta)
}

/// Options shared by `fit` and `compare`.
#[derive(Debug, clap::Args)]
struct Common {
    /// Table (CSV or Parquet, by extension).
    #[arg(long)]
    data: PathBuf,
    /// Column to model.
    #[arg(long)]
    target: String,
    /// Physics equation over column and parameter names, e.g. "kc*b*h^(1-mc)".
    #[arg(long)]
    physics: String,
    /// Parameters fitted on the training rows (comma-separated).
    #[arg(long, value_delimiter = ',')]
    calibrate: Vec<String>,
    /// Starting values of calibrated parameters: P1=V,P2=V (default 1).
    #[arg(long, value_delimiter = ',')]
    init: Vec<String>,
    /// Values of parameters that are not calibrated: P=V (repeat or comma-separate).
    #[arg(long, value_delimiter = ',')]
    set: Vec<String>,
    /// Feature columns of the correction (default: every column except target and group).
    #[arg(long, value_delimiter = ',', conflicts_with = "exclude")]
    features: Option<Vec<String>>,
    /// Columns left out of the default feature set.
    #[arg(long, value_delimiter = ',')]
    exclude: Vec<String>,
    /// How the correction enters the hybrid.
    #[arg(long, value_enum, default_value_t = CorrectionArg::Additive)]
    correction: CorrectionArg,
    /// Rows sharing this column's value stay on one side of every split.
    #[arg(long)]
    group: Option<String>,
    /// Share of rows (or groups) held out for testing.
    #[arg(long, default_value_t = 0.2)]
    test_fraction: f64,
    /// Test on the rows with the top --test-fraction of this column (train low, test high).
    #[arg(long)]
    extrapolate: Option<String>,
    /// Seed of the split and the search.
    #[arg(long, default_value_t = 42)]
    seed: u64,
    /// Epochs of the symbolic-regression search.
    #[arg(long, default_value_t = 10)]
    epochs: usize,
    /// Largest complexity of the correction (input leaves + operators).
    #[arg(long, default_value_t = 10)]
    max_complexity: usize,
    /// Comma-separated operators of the correction's search, from: add sub mul div exp log
    /// sqrt square inverse sin cos tanh abs gaussian gaussian2 (default: the law operators,
    /// add sub mul div exp log: power laws, exponentials and quotients).
    #[arg(long, value_delimiter = ',')]
    operators: Option<Vec<String>>,
    /// Which operator may appear inside which: `readable` (the default of corrections: no
    /// exp, log, sin, cos, tanh or gaussian inside another, except a power law
    /// `exp(a*log(x))`), `none`, or rules `OUTER:INNER=MAX` (e.g. `readable,exp:log=0`).
    #[arg(long)]
    nesting: Option<String>,
    /// Consensus selection: also search N bootstrap resamples of the rows and select the
    /// structure most of them give back among their near-best models, refitted on all rows
    /// (0, the default, selects by --criterion from one search).
    #[arg(long)]
    consensus: Option<usize>,
    /// How the correction's equation is chosen among the search's candidates (see
    /// `hxai sr --help`; default `cv`, the library's for table hybrids).
    #[arg(long, value_enum)]
    criterion: Option<crate::strategy::CriterionArg>,
    /// Folds of `--criterion cv`.
    #[arg(long, default_value_t = 5)]
    cv_folds: usize,
    /// Refit physics parameters and correction constants together once the correction's
    /// structure is chosen (the two-stage values are reported too).
    #[arg(long)]
    joint: bool,
    /// Folds of the CV+ calibration of conformal prediction intervals, stored in the model
    /// file (each fold refits the hybrid's constants, not its structure); 0 fits without
    /// them (the delta method is then the only interval).
    #[arg(long, default_value_t = hxai_hybrid::conformal::DEFAULT_CONFORMAL_FOLDS)]
    conformal_folds: usize,
    /// Print one JSON document on stdout instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(Debug, clap::Args)]
struct FitArgs {
    #[command(flatten)]
    common: Common,
    /// Where to write the model file (JSON).
    #[arg(long)]
    out: PathBuf,
    /// Also rerun the correction's search on N seeded bootstrap resamples of the training
    /// rows; the model file gets `stability` (feature and structure shares, out-of-bag R^2).
    #[arg(long)]
    stability: Option<usize>,
}

#[derive(Debug, clap::Args)]
struct CompareArgs {
    #[command(flatten)]
    common: Common,
    /// Folds of the cross-validation (0 to skip it).
    #[arg(long, default_value_t = 5)]
    folds: usize,
    /// Nominal level of the hybrid's prediction intervals whose coverage on the test rows
    /// is reported.
    #[arg(long, default_value_t = hxai_hybrid::DEFAULT_INTERVAL)]
    interval: f64,
    /// How the prediction intervals are made (default: conformal where the model has it).
    #[arg(long, value_enum)]
    interval_method: Option<IntervalMethodArg>,
}

#[derive(Debug, clap::Args)]
struct PredictArgs {
    /// Model file written by `hxai hybrid fit`.
    #[arg(long)]
    model: PathBuf,
    /// Table (CSV or Parquet).
    #[arg(long)]
    data: PathBuf,
    /// Output table (CSV or Parquet): columns physics, correction, hybrid (and hybrid_lo,
    /// hybrid_hi with --interval).
    #[arg(long)]
    out: PathBuf,
    /// Add the hybrid's prediction interval at this level (e.g. 0.95) as the columns
    /// hybrid_lo and hybrid_hi.
    #[arg(long)]
    interval: Option<f64>,
    /// How the prediction intervals are made (default: conformal where the model file
    /// stores its calibration, else delta).
    #[arg(long, value_enum, requires = "interval")]
    interval_method: Option<IntervalMethodArg>,
}

#[derive(Debug, clap::Args)]
struct EvaluateArgs {
    /// Model file written by `hxai hybrid fit`.
    #[arg(long)]
    model: PathBuf,
    /// Table (CSV or Parquet) with the target column.
    #[arg(long)]
    data: PathBuf,
    /// Nominal level of the prediction intervals whose coverage is reported.
    #[arg(long, default_value_t = hxai_hybrid::DEFAULT_INTERVAL)]
    interval: f64,
    /// How the prediction intervals are made (default: conformal where the model file
    /// stores its calibration, else delta).
    #[arg(long, value_enum)]
    interval_method: Option<IntervalMethodArg>,
    /// Print one JSON document on stdout instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs `hxai hybrid ...`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    match args.command {
        Sub::Fit(a) => fit(a),
        Sub::Predict(a) => predict(a),
        Sub::Evaluate(a) => evaluate(a),
        Sub::Compare(a) => compare(a),
    }
}

/// A table read for the hybrid: numeric columns, plus the group column (text groups are
/// numbered in order of first appearance) and its original cells for `predict`'s output.
pub(crate) struct Loaded {
    pub(crate) table: Table,
    group_cells: Option<hxai_data::Column>,
    /// Text columns left out (other than the group column), with their cells.
    text: Vec<(String, Vec<String>)>,
    /// Warnings about the table, said once the command has succeeded.
    warnings: Vec<String>,
}

impl Loaded {
    /// Refuses a text column where numbers are needed (the library would only see it as
    /// missing): one named by the target, `--features`, `--extrapolate` or the physics, and
    /// one that would be a default feature but is numbers with an empty cell (a gap in the
    /// data, not a text column: the row is named). A real text column left out of the
    /// default features gets a warning instead of silence.
    fn check_numeric(&mut self, c: &Common) -> Result<()> {
        let mut named: Vec<String> = vec![c.target.clone()];
        named.extend(c.features.iter().flatten().cloned());
        named.extend(c.extrapolate.iter().cloned());
        if let Ok(p) = hxai_symreg::infix::parse(&c.physics) {
            named.extend(p.names().into_iter().map(str::to_string));
        }
        let default_feature = |n: &str| {
            c.features.is_none()
                && !c.exclude.iter().any(|e| e.trim() == n)
                && c.group.as_deref() != Some(n)
        };
        let mut left_out = Vec::new();
        for (n, cells) in &self.text {
            if !named.contains(n) && !default_feature(n) {
                continue;
            }
            let numbers_with_gaps = cells
                .iter()
                .all(|v| v.trim().is_empty() || v.trim().parse::<f64>().is_ok());
            if numbers_with_gaps && let Some(row) = cells.iter().position(|v| v.trim().is_empty()) {
                bail!(
                    "{}: row {}, column `{n}`: the cell is empty; hxai hybrid needs a number in every row of a column it uses (fill it, remove the row, or --exclude {n})",
                    c.data.display(),
                    row + 1
                );
            }
            // true/false (a Parquet boolean, or such words in a CSV) is not text to a reader
            let flags = cells.iter().all(|v| {
                let t = v.trim();
                t.is_empty() || t.eq_ignore_ascii_case("true") || t.eq_ignore_ascii_case("false")
            });
            let holds = if flags {
                "true/false values (write them as 1/0 to use them)"
            } else {
                "text"
            };
            if named.contains(n) {
                bail!(
                    "column `{n}` of {} holds {holds}, not numbers: hxai hybrid needs numeric columns (text is allowed only in the --group column)",
                    c.data.display()
                );
            }
            left_out.push(format!(
                "column `{n}` holds {holds} and is left out of the correction's features (--exclude {n} to say so)"
            ));
        }
        self.warnings.extend(left_out);
        Ok(())
    }
}

pub(crate) fn read(path: &Path, group: Option<&str>) -> Result<Loaded> {
    let mixed = hxai_data::read_mixed_table(path)
        .with_context(|| format!("cannot read the table {}", path.display()))?;
    let mut names = Vec::new();
    let mut columns = Vec::new();
    let mut group_cells = None;
    let mut text = Vec::new();
    for (n, c) in mixed.names.iter().zip(&mixed.columns) {
        if Some(n.as_str()) == group {
            group_cells = Some(c.clone());
        }
        match c {
            hxai_data::Column::Number(v) => {
                names.push(n.clone());
                columns.push(v.clone());
            }
            hxai_data::Column::Text(cells) if Some(n.as_str()) == group => {
                let mut ids: BTreeMap<&str, usize> = BTreeMap::new();
                let mut next = 0usize;
                let codes = cells
                    .iter()
                    .map(|s| {
                        *ids.entry(s.as_str()).or_insert_with(|| {
                            next += 1;
                            next - 1
                        }) as f64
                    })
                    .collect();
                names.push(n.clone());
                columns.push(codes);
            }
            hxai_data::Column::Text(cells) => text.push((n.clone(), cells.clone())),
        }
    }
    let table = Table::new(names, columns)
        .with_context(|| format!("the table {} has no usable numeric column", path.display()))?;
    Ok(Loaded {
        table,
        group_cells,
        text,
        warnings: Vec::new(),
    })
}

fn pairs(list: &[String], flag: &str) -> Result<BTreeMap<String, f64>> {
    let mut out = BTreeMap::new();
    for item in list {
        let Some((k, v)) = item.split_once('=') else {
            bail!("--{flag} `{item}`: write NAME=VALUE");
        };
        let v: f64 = v
            .trim()
            .parse()
            .with_context(|| format!("--{flag} `{item}`: `{}` is not a number", v.trim()))?;
        if out.insert(k.trim().to_string(), v).is_some() {
            bail!("--{flag} names `{}` twice", k.trim());
        }
    }
    Ok(out)
}

fn config(c: &Common) -> Result<ProcessConfig> {
    let mut cfg = ProcessConfig::new(&c.target, &c.physics);
    cfg.calibrate = c.calibrate.iter().map(|s| s.trim().to_string()).collect();
    cfg.init = pairs(&c.init, "init")?;
    cfg.set = pairs(&c.set, "set")?;
    cfg.features = c
        .features
        .as_ref()
        .map(|f| f.iter().map(|s| s.trim().to_string()).collect());
    cfg.exclude = c.exclude.iter().map(|s| s.trim().to_string()).collect();
    cfg.correction = match c.correction {
        CorrectionArg::Additive => CorrectionForm::Additive,
        CorrectionArg::Multiplicative => CorrectionForm::Multiplicative,
        CorrectionArg::Log => CorrectionForm::Log,
    };
    cfg.group = c.group.clone();
    cfg.test_fraction = c.test_fraction;
    cfg.extrapolate = c.extrapolate.clone();
    cfg.seed = c.seed;
    cfg.joint = c.joint;
    cfg.conformal_folds = c.conformal_folds;
    cfg.search.epochs = c.epochs;
    cfg.search.max_complexity = c.max_complexity;
    if let Some(crit) = c.criterion {
        cfg.search.criterion = crit.into();
    }
    cfg.search.cv_folds = c.cv_folds;
    if let Some(ops) = &c.operators {
        cfg.search.operators = ops.iter().map(|o| o.trim().to_string()).collect();
    }
    if let Some(n) = &c.nesting {
        cfg.search.nesting = hxai_symreg::Nesting::parse(n)?;
    }
    if let Some(b) = c.consensus {
        cfg.search.consensus_runs = b;
    }
    Ok(cfg)
}

/// What `fit` and `compare` start from: the configuration, the table (checked for text
/// where numbers are needed) and the progress bar of the search.
fn prepare(c: &Common) -> Result<(ProcessConfig, Loaded, ProgressBar)> {
    let mut cfg = config(c)?;
    let mut loaded = read(&c.data, cfg.group.as_deref())?;
    loaded.check_numeric(c)?;
    // A text column is never a feature: excluding it is allowed and needs no word to the
    // library, which sees the numeric columns only.
    cfg.exclude
        .retain(|e| !loaded.text.iter().any(|(n, _)| n == e));
    let b = bar(c.json, cfg.search.epochs);
    Ok((cfg, loaded, b))
}

fn bar(hidden: bool, epochs: usize) -> ProgressBar {
    if hidden {
        return ProgressBar::hidden();
    }
    let b = crate::progress::bar(epochs as u64);
    b.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg} [{elapsed}]")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    b
}

fn on_progress(b: &ProgressBar) -> impl FnMut(&ProcessProgress) + '_ {
    move |p: &ProcessProgress| {
        let e = p.search.epochs as u64;
        b.set_length(p.tasks as u64 * e);
        b.set_position((p.task as u64 - 1) * e + p.search.epoch as u64);
        b.set_message(format!("{} epoch {}/{}", p.label, p.search.epoch, e));
    }
}

fn fmt_se(se: Option<&Option<f64>>) -> String {
    match se {
        Some(Some(s)) => format!(" +- {s:.4e}"),
        Some(None) => " +- (undefined)".into(),
        None => String::new(),
    }
}

#[allow(clippy::print_stdout)]
fn print_model(m: &ProcessModel) {
    println!("physics: {}", m.physics.equation);
    for (name, v) in &m.physics.parameters {
        let tag = if m.physics.calibrated.contains(name) {
            "calibrated"
        } else {
            "set"
        };
        let ci = m
            .physics
            .params
            .get(name)
            .and_then(|p| p.ci95)
            .map(|[lo, hi]| format!(", 95 % CI [{lo:.6e}, {hi:.6e}]"))
            .unwrap_or_default();
        println!(
            "  {name} = {v:.6e}{}{ci} ({tag})",
            fmt_se(m.physics.standard_errors.get(name))
        );
    }
    println!(
        "correction ({}, complexity {}): {}",
        m.correction.kind.name(),
        m.correction.forms.complexity,
        m.correction.forms.equation
    );
    println!("hybrid: {} = {}", m.target, m.hybrid.equation);
    if let Some(j) = &m.joint {
        println!(
            "joint refit: train RMSE {:.6e} -> {:.6e} (two-stage correction: {})",
            j.sequential_train_rmse, j.joint_train_rmse, j.sequential_correction
        );
    }
    let s = &m.scores;
    println!(
        "train ({} rows): physics RMSE {:.6e} R^2 {:.4}, hybrid RMSE {:.6e} R^2 {:.4}",
        m.split.train.len(),
        s.train.physics.rmse,
        s.train.physics.r2,
        s.train.hybrid.rmse,
        s.train.hybrid.r2
    );
    if let Some(t) = &s.test {
        println!(
            "test  ({} rows, {} split): physics RMSE {:.6e} R^2 {:.4}, hybrid RMSE {:.6e} R^2 {:.4}",
            m.split.test.len(),
            m.split.kind,
            t.physics.rmse,
            t.physics.r2,
            t.hybrid.rmse,
            t.hybrid.r2
        );
    }
}

#[allow(clippy::print_stdout)]
fn fit(a: FitArgs) -> Result<()> {
    // The output is checked before any work: a fit that cannot be written is not started.
    crate::safety::check_output(
        &a.out,
        &[crate::safety::input(&a.common.data, "the table (--data)")],
    )?;
    let (cfg, loaded, b) = prepare(&a.common)?;
    let mut model = fit_process(&loaded.table, &cfg, &mut on_progress(&b))?;
    b.finish_and_clear();
    crate::safety::warn(&loaded.warnings);
    crate::safety::warn(&model.warnings);
    if let Some(runs) = a.stability {
        let sb = if a.common.json {
            ProgressBar::hidden()
        } else {
            crate::progress::bar(runs as u64)
        };
        let sbb = sb.clone();
        model.stability = Some(hxai_hybrid::process::process_stability(
            &loaded.table,
            &cfg,
            &model,
            runs,
            &mut move |done, _| sbb.set_position(done as u64),
        )?);
        sb.finish_and_clear();
        if let (Some(st), Some(sel)) = (&model.stability, model.correction.selection.take()) {
            model.correction.selection = Some(sel.with_stability(st));
        }
    }
    let json = model.to_json();
    hxai_data::write_text(&a.out, &json)
        .with_context(|| format!("cannot write the model to {}", a.out.display()))?;
    if a.common.json {
        println!("{json}");
    } else {
        print_model(&model);
        if let Some(sel) = &model.correction.selection {
            crate::sr::print_selection(sel);
        }
        if let Some(st) = &model.stability {
            crate::sr::print_stability(st);
        }
        println!("model written to {}", a.out.display());
    }
    Ok(())
}

fn load_model(path: &Path) -> Result<ProcessModel> {
    let text = hxai_data::read_text(path)
        .with_context(|| format!("cannot read the model {}", path.display()))?;
    ProcessModel::from_json(&text)
        .with_context(|| format!("cannot load the model {}", path.display()))
}

#[allow(clippy::print_stdout)]
fn predict(a: PredictArgs) -> Result<()> {
    crate::safety::check_output(
        &a.out,
        &[
            crate::safety::input(&a.data, "the table (--data)"),
            crate::safety::input(&a.model, "the model (--model)"),
        ],
    )?;
    crate::safety::check_table_path(&a.out)?;
    if let Some(level) = a.interval {
        crate::safety::check_level(level, "--interval")?;
    }
    let model = load_model(&a.model)?;
    let loaded = read(&a.data, model.group.as_deref())?;
    let p = model.predict(&loaded.table)?;
    crate::safety::warn(&model.range_warnings(&loaded.table));
    let bounds = match a.interval {
        Some(level) => Some(model.intervals_with(
            &loaded.table,
            level,
            method_of(a.interval_method, &model, level),
        )?),
        None => None,
    };
    let mut t = hxai_data::MixedTable::default();
    if let (Some(g), Some(cells)) = (&model.group, loaded.group_cells) {
        t.names.push(g.clone());
        t.columns.push(cells);
    }
    for (n, v) in [
        ("physics", p.physics),
        ("correction", p.correction),
        ("hybrid", p.hybrid),
    ] {
        t.names.push(n.to_string());
        t.columns.push(hxai_data::Column::Number(v));
    }
    if let Some(b) = bounds {
        let (lo, hi): (Vec<f64>, Vec<f64>) = b.into_iter().unzip();
        for (n, v) in [("hybrid_lo", lo), ("hybrid_hi", hi)] {
            t.names.push(n.to_string());
            t.columns.push(hxai_data::Column::Number(v));
        }
    }
    hxai_data::write_mixed_table(&a.out, &t)
        .with_context(|| format!("cannot write the predictions to {}", a.out.display()))?;
    println!(
        "{} rows written to {}",
        loaded.table.n_rows(),
        a.out.display()
    );
    Ok(())
}

#[allow(clippy::print_stdout)]
fn evaluate(a: EvaluateArgs) -> Result<()> {
    crate::safety::check_level(a.interval, "--interval")?;
    let model = load_model(&a.model)?;
    let loaded = read(&a.data, model.group.as_deref())?;
    let e = match (a.interval_method, model.default_interval_method(a.interval)) {
        (None, None) => model.evaluate_at(&loaded.table, a.interval)?,
        (asked, _) => model.evaluate_with(
            &loaded.table,
            a.interval,
            method_of(asked, &model, a.interval),
        )?,
    };
    crate::safety::warn(&e.warnings);
    if a.json {
        println!("{}", serde_json::to_string_pretty(&e)?);
    } else {
        println!(
            "{} rows: physics RMSE {:.6e} R^2 {:.4}; hybrid RMSE {:.6e} R^2 {:.4}; improvement {:.2} %; paired t-test p = {:.3e}",
            e.n_samples,
            e.physics.rmse,
            e.physics.r2,
            e.hybrid.rmse,
            e.hybrid.r2,
            e.improvement_pct,
            e.t_test.p_value
        );
        if let Some(iv) = e.interval {
            print_interval(&iv, "rows");
        }
    }
    Ok(())
}

#[allow(clippy::print_stdout)]
fn print_interval(iv: &hxai_hybrid::IntervalReport, what: &str) {
    println!(
        "prediction intervals ({}) at {:.1} %: coverage {:.1} % of {} {what}, median width {}",
        iv.method.name(),
        100.0 * iv.nominal,
        100.0 * iv.coverage,
        iv.n,
        iv.median_width
            .map_or_else(|| "(none)".to_string(), |w| format!("{w:.4e}"))
    );
}

#[allow(clippy::print_stdout)]
fn print_comparison(c: &Comparison) {
    println!(
        "{} split: {} train rows, {} test rows",
        c.split, c.n_train, c.n_test
    );
    println!("{:<20} {:>10} {:>14} {:>14}", "model", "R^2", "RMSE", "MAE");
    for m in &c.models {
        println!(
            "{:<20} {:>10.4} {:>14.6e} {:>14.6e}",
            m.name, m.metrics.r2, m.metrics.rmse, m.metrics.mae
        );
    }
    if !c.cv.is_empty() {
        println!(
            "{}-fold CV, R^2 mean +- sd [95 % Student-t interval]:",
            c.folds
        );
        for s in &c.cv {
            println!(
                "{:<20} {:>8.4} +- {:.4} [{:.4}, {:.4}]",
                s.name, s.r2_mean, s.r2_sd, s.r2_ci[0], s.r2_ci[1]
            );
        }
    }
    for t in &c.t_tests {
        println!(
            "paired t-test {} vs {} (squared errors): t = {:.3}, p = {:.3e}",
            t.model, t.baseline, t.test.statistic, t.test.p_value
        );
    }
    if let Some(iv) = &c.interval {
        print_interval(iv, "test rows");
    }
    println!("hybrid: {} = {}", c.target, c.hybrid.hybrid.equation);
}

#[allow(clippy::print_stdout)]
fn compare(a: CompareArgs) -> Result<()> {
    crate::safety::check_level(a.interval, "--interval")?;
    let (cfg, loaded, b) = prepare(&a.common)?;
    let mut c = compare_process(&loaded.table, &cfg, a.folds, &mut on_progress(&b))?;
    b.finish_and_clear();
    crate::safety::warn(&c.hybrid.warnings);
    if a.interval_method.is_some() || a.interval != hxai_hybrid::DEFAULT_INTERVAL {
        let method = method_of(a.interval_method, &c.hybrid, a.interval);
        c.interval = c.hybrid.test_interval(&loaded.table, a.interval, method)?;
    }
    crate::safety::warn(&loaded.warnings);
    if a.common.json {
        println!("{}", serde_json::to_string_pretty(&c)?);
    } else {
        print_comparison(&c);
    }
    Ok(())
}
