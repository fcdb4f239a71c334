//! `hxai dynamic fit | predict | compare`: grey-box dynamic models on a long table (one row
//! per sample), the engineer's ODE calibrated through its trajectories with a learned
//! correction inside the derivative (docs/dynamic.md).

use anyhow::{Context, Result};
use clap::{Args as ClapArgs, Subcommand, ValueEnum};
use hxai_hybrid::dynamic::{DynamicConfig, DynamicModel, Initial, TestSplit};
use hxai_hybrid::tables::{CorrectionForm, Form};
use std::path::PathBuf;

#[derive(Debug, ClapArgs)]
pub(crate) struct Args {
    #[command(subcommand)]
    sub: Sub,
}

#[derive(Debug, Subcommand)]
enum Sub {
    /// Calibrate the ODE through its trajectories, learn its correction, write the model.
    Fit(FitArgs),
    /// Simulate every run of a table from its first reading with a fitted model.
    Predict(PredictArgs),
    /// Physics, calibrated physics, hybrid and a NARX boosting by free-run error on
    /// held-out runs.
    Compare(CompareArgs),
}

/// `--correction` values.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum CorrectionArg {
    /// `x' = f + c`.
    Additive,
    /// `x' = f (1 + c)`.
    Multiplicative,
}

/// `--form` values.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum FormArg {
    /// None, factors or free, by cross-validation over runs.
    Auto,
    /// No correction: the calibrated physics.
    None,
    /// One closed-form factor per column.
    Factors,
    /// Free-form symbolic regression.
    Free,
}

/// `--initial` values.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum InitialArg {
    /// Each run from its first reading.
    First,
    /// Each run's initial state calibrated with the parameters.
    Estimate,
}

#[derive(Debug, ClapArgs)]
struct Common {
    /// The long table (CSV or Parquet), one row per sample.
    #[arg(long)]
    data: PathBuf,
    /// The time column.
    #[arg(long)]
    time: String,
    /// The run column (default: the table is one run).
    #[arg(long)]
    run: Option<String>,
    /// The measured state columns, comma-separated; each has one equation in --ode.
    #[arg(long, value_delimiter = ',', required = true)]
    state: Vec<String>,
    /// Input columns, comma-separated, held from each sample to the next.
    #[arg(long, value_delimiter = ',')]
    inputs: Vec<String>,
    /// The ODE, one `NAME' = expression` per state, `;` between them.
    #[arg(long)]
    ode: String,
    /// Parameters calibrated on the training runs, comma-separated.
    #[arg(long, value_delimiter = ',')]
    calibrate: Vec<String>,
    /// Starting values of calibrated parameters, `P=V` comma-separated (default 1).
    #[arg(long, value_delimiter = ',')]
    init: Vec<String>,
    /// Values of fixed parameters, `P=V` comma-separated.
    #[arg(long, value_delimiter = ',')]
    set: Vec<String>,
    /// How the correction enters the derivative.
    #[arg(long, value_enum, default_value = "additive")]
    correction: CorrectionArg,
    /// The correction's form.
    #[arg(long, value_enum, default_value = "auto")]
    form: FormArg,
    /// Each run's initial state.
    #[arg(long, value_enum, default_value = "first")]
    initial: InitialArg,
    /// Columns a harmonic (sin, cos) may use in the correction.
    #[arg(long, value_delimiter = ',')]
    periodic: Vec<String>,
    /// Window of the derivatives' local quadratic (samples, odd is best).
    #[arg(long, default_value_t = hxai_hybrid::dynamic::DEFAULT_SMOOTH)]
    smooth: usize,
    /// Seed of the search and of the default split.
    #[arg(long, default_value_t = 42)]
    seed: u64,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
}

#[derive(Debug, ClapArgs)]
struct FitArgs {
    #[command(flatten)]
    common: Common,
    /// Folds over runs of the conformal bands (0: none).
    #[arg(long, default_value_t = 5)]
    conformal_folds: usize,
    /// The model file to write.
    #[arg(long)]
    out: PathBuf,
}

#[derive(Debug, ClapArgs)]
struct PredictArgs {
    /// The model file (`hxai dynamic fit --out`).
    #[arg(long)]
    model: PathBuf,
    /// The long table: the runs to simulate, with their inputs and first readings.
    #[arg(long)]
    data: PathBuf,
    /// Also write a conformal band holding a whole run's trajectory at this level (0.9).
    #[arg(long)]
    interval: Option<f64>,
    /// The predictions (CSV or Parquet).
    #[arg(long)]
    out: PathBuf,
}

#[derive(Debug, ClapArgs)]
struct CompareArgs {
    #[command(flatten)]
    common: Common,
    /// Held-out runs, comma-separated, as the run column writes them (default: a seeded
    /// quarter of the runs).
    #[arg(long, value_delimiter = ',', conflicts_with = "test_after")]
    test_runs: Vec<String>,
    /// Hold out every run's samples after this time instead.
    #[arg(long)]
    test_after: Option<f64>,
}

pub(crate) fn run(a: Args, _g: &crate::Global) -> Result<()> {
    match a.sub {
        Sub::Fit(a) => fit(a),
        Sub::Predict(a) => predict(a),
        Sub::Compare(a) => compare(a),
    }
}

fn config(c: &Common) -> Result<DynamicConfig> {
    Ok(DynamicConfig {
        time: c.time.clone(),
        run: c.run.clone(),
        states: c.state.clone(),
        inputs: c.inputs.clone(),
        ode: c.ode.clone(),
        calibrate: c.calibrate.clone(),
        init: crate::strategy::pairs(&c.init, "--init", "a number")?,
        set: crate::strategy::pairs(&c.set, "--set", "a number")?,
        correction: match c.correction {
            CorrectionArg::Additive => CorrectionForm::Additive,
            CorrectionArg::Multiplicative => CorrectionForm::Multiplicative,
        },
        form: match c.form {
            FormArg::Auto => Form::Auto,
            FormArg::None => Form::None,
            FormArg::Factors => Form::Factors,
            FormArg::Free => Form::Free,
        },
        initial: match c.initial {
            InitialArg::First => Initial::First,
            InitialArg::Estimate => Initial::Estimate,
        },
        periodic: c.periodic.clone(),
        smooth: c.smooth,
        seed: c.seed,
        ..DynamicConfig::default()
    })
}

fn read(c: &Common) -> Result<hxai_symreg::Table> {
    Ok(crate::hybrid::read(&c.data, c.run.as_deref())?.table)
}

/// The distinct cells of a text run column in order of first appearance: the run column's
/// numbers are their positions (as the table reader numbers a text group).
fn run_names(cells: Option<&hxai_data::Column>) -> Option<Vec<String>> {
    match cells {
        Some(hxai_data::Column::Text(t)) => {
            let mut names: Vec<String> = Vec::new();
            for c in t {
                if !names.contains(c) {
                    names.push(c.clone());
                }
            }
            Some(names)
        }
        _ => None,
    }
}

/// `--test-runs` as the run column's numbers: names of a text run column, numbers otherwise.
fn run_codes(asked: &[String], names: Option<&[String]>) -> Result<Vec<f64>> {
    asked
        .iter()
        .map(|r| match names {
            Some(n) => n
                .iter()
                .position(|x| x == r.trim())
                .map(|i| i as f64)
                .ok_or_else(|| {
                    anyhow::anyhow!("--test-runs: there is no run {r} (runs: {})", n.join(", "))
                }),
            None => r.trim().parse::<f64>().map_err(|_| {
                anyhow::anyhow!("--test-runs: {r:?} is not a run of the (numeric) run column")
            }),
        })
        .collect()
}

/// A progress line per phase, with the time since the start.
fn reporter() -> (indicatif::ProgressBar, impl FnMut(&str)) {
    let b = crate::progress::styled(1, "{msg} [{elapsed}]");
    let bb = b.clone();
    (b, move |m: &str| bb.set_message(m.to_string()))
}

#[allow(clippy::print_stdout)]
fn fit(a: FitArgs) -> Result<()> {
    crate::safety::check_output(
        &a.out,
        &[crate::safety::input(&a.common.data, "the table (--data)")],
    )?;
    let mut cfg = config(&a.common)?;
    cfg.conformal_folds = a.conformal_folds;
    cfg.check()?;
    let table = read(&a.common)?;
    let (b, mut progress) = reporter();
    let model = hxai_hybrid::dynamic::fit(&table, &cfg, &mut progress)?;
    b.finish_and_clear();
    crate::safety::warn(&model.warnings);
    let json = model.to_json();
    let cannot = || format!("cannot write the model to {}", a.out.display());
    let staged = hxai_data::stage_text(&a.out, &json).with_context(cannot)?;
    if a.common.json {
        crate::safety::print_document(&json)?;
        return staged.commit().with_context(cannot);
    }
    staged.commit().with_context(cannot)?;
    print_model(&model);
    println!("model written to {}", a.out.display());
    Ok(())
}

#[allow(clippy::print_stdout)]
fn print_model(m: &DynamicModel) {
    println!("physics: {}", m.ode);
    for (p, e) in &m.physics_calibrated {
        match e.ci95 {
            Some([lo, hi]) => println!("  {p} = {:.6} (95 % interval {lo:.6} to {hi:.6})", e.value),
            None => println!("  {p} = {:.6}", e.value),
        }
    }
    for c in &m.corrections {
        println!(
            "correction of {}' ({}, {}): {}",
            c.state,
            m.correction_kind.name(),
            c.form.name(),
            c.equation
        );
    }
    println!("hybrid: {}", m.hybrid_equation);
    let r = |k: &str| m.train_rmse.get(k).copied().unwrap_or(f64::NAN);
    println!(
        "free-run RMSE on the {} training run(s): physics {:.4}, calibrated physics {:.4}, hybrid {:.4}",
        m.training.runs.len(),
        r("physics"),
        r("physics_calibrated"),
        r("hybrid")
    );
}

#[allow(clippy::print_stdout)]
fn predict(a: PredictArgs) -> Result<()> {
    crate::safety::check_predict(&a.out, &a.data, &a.model, a.interval)?;
    let text = std::fs::read_to_string(&a.model)
        .with_context(|| format!("cannot read the model {}", a.model.display()))?;
    let model = DynamicModel::from_json(&text).with_context(|| a.model.display().to_string())?;
    let view = crate::hybrid::read(&a.data, model.run.as_deref())?;
    let p = model.predict(&view.table, a.interval)?;
    crate::safety::warn(&p.warnings);
    let mut t = hxai_data::MixedTable::default();
    if let (Some(r), Some(cells)) = (&model.run, view.group_cells) {
        t.push(r, cells);
    }
    if let Some(time) = view.table.column(&model.time) {
        t.push(&model.time, hxai_data::Column::Number(time.to_vec()));
    }
    for (j, s) in model.states.iter().enumerate() {
        t.push(
            &format!("{s}_physics"),
            hxai_data::Column::Number(p.physics[j].clone()),
        );
        t.push(
            &format!("{s}_hybrid"),
            hxai_data::Column::Number(p.hybrid[j].clone()),
        );
        if let (Some(lo), Some(hi)) = (&p.lower, &p.upper) {
            t.push(&format!("{s}_lo"), hxai_data::Column::Number(lo[j].clone()));
            t.push(&format!("{s}_hi"), hxai_data::Column::Number(hi[j].clone()));
        }
    }
    hxai_data::write_mixed_table(&a.out, &t)
        .with_context(|| format!("cannot write the predictions to {}", a.out.display()))?;
    println!(
        "{} rows written to {}",
        view.table.n_rows(),
        a.out.display()
    );
    Ok(())
}

#[allow(clippy::print_stdout)]
fn compare(a: CompareArgs) -> Result<()> {
    let cfg = config(&a.common)?;
    cfg.check()?;
    let view = crate::hybrid::read(&a.common.data, a.common.run.as_deref())?;
    let names = run_names(view.group_cells.as_ref());
    let split = TestSplit {
        test_runs: run_codes(&a.test_runs, names.as_deref())?,
        test_after: a.test_after,
    };
    let table = view.table;
    let (b, mut progress) = reporter();
    let c = hxai_hybrid::dynamic::compare(&table, &cfg, &split, &mut progress)?;
    b.finish_and_clear();
    crate::safety::warn(&c.warnings);
    if a.common.json {
        return crate::safety::emit(&serde_json::to_string_pretty(&c)?);
    }
    match c.test_after {
        Some(t) => println!(
            "free-run RMSE after time {t} on {} run(s), trained before it",
            c.test_runs.len()
        ),
        None => println!(
            "free-run RMSE on held-out run(s) {} (trained on {} run(s))",
            c.test_runs
                .iter()
                .map(|&r| names
                    .as_ref()
                    .and_then(|n| n.get(r as usize).cloned())
                    .unwrap_or_else(|| r.to_string()))
                .collect::<Vec<_>>()
                .join(", "),
            c.train_runs.len()
        ),
    }
    for m in &c.models {
        println!(
            "  {:<20} {:>12}   p (hybrid vs this) {}",
            m.name,
            m.rmse.map_or("not finite".into(), |v| format!("{v:.5}")),
            m.p_value.map_or("-".into(), |p| format!("{p:.3e}"))
        );
    }
    if let Some(n) = &c.t_test_note {
        println!("  ({n})");
    }
    println!("correction: {}", c.hybrid.correction.equation);
    println!("hybrid: {}", c.hybrid.equation);
    Ok(())
}
