//! `hxai sr`: symbolic regression of one column of a table on the others.
use crate::Global;
use crate::strategy::StrategyArg;
use anyhow::{Context, Result};
use hxai_symreg::{Criterion, Model, SearchConfig, Table, search};
use serde_json::{Value, json};
use std::path::PathBuf;

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
    /// Largest complexity (input leaves + operators).
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
    /// Complexity of operators, as comma-separated NAME=INTEGER (e.g. `sqrt=2,exp=2`);
    /// operators not named count 1.
    #[arg(long, value_delimiter = ',')]
    pub operator_complexity: Vec<String>,
    /// Complexity the cap grows by with each input beyond the first (default: the
    /// search's default).
    #[arg(long)]
    pub complexity_per_input: Option<usize>,
    /// Stop after this many fitted models.
    #[arg(long)]
    pub max_evaluations: Option<u64>,
    /// Search strategy.
    #[arg(long, value_enum, default_value_t = StrategyArg::Combined)]
    pub strategy: StrategyArg,
    /// How the reported model is chosen: BIC or AIC (the simplest model within one
    /// parameter's charge of the lowest), or PySR's score along the Pareto front.
    #[arg(long, value_enum, default_value_t = CriterionArg::Bic)]
    pub criterion: CriterionArg,
    /// Multiplier lambda of the criterion's charge per fitted parameter.
    #[arg(long, default_value_t = 1.0)]
    pub complexity_penalty: f64,
    /// Print one JSON document on stdout instead of text.
    #[arg(long)]
    pub json: bool,
}

/// `--criterion` values.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum CriterionArg {
    /// Bayesian information criterion.
    Bic,
    /// Akaike information criterion.
    Aic,
    /// PySR's score along the Pareto front.
    Pareto,
}

/// A model's forms and its training scores (`null` when a score cannot be computed, e.g. a
/// non-finite prediction).
fn summary(m: &Model, data: &Table, y: &[f64]) -> Result<Value> {
    let scores = hxai_eval::score(y, &m.predict(data)?).ok();
    Ok(json!({
        "equation": m.equation(),
        "sympy": m.sympy(),
        "latex": m.latex(),
        "complexity": m.complexity(),
        "features": m.features(),
        "r2": scores.map(|s| s.r2),
        "rmse": scores.map(|s| s.rmse),
    }))
}

/// Runs `hxai sr`.
#[allow(clippy::print_stdout)]
pub fn run(args: Args, _g: &Global) -> Result<()> {
    let mut data = hxai_data::read_table(&args.csv)
        .with_context(|| format!("cannot read the table {}", args.csv.display()))?;
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
        max_complexity: args.max_complexity,
        epochs: args.epochs,
        time_limit_s: args.time_limit_s,
        max_evaluations: args.max_evaluations,
        strategy: args.strategy.into(),
        criterion: match args.criterion {
            CriterionArg::Bic => Criterion::Bic,
            CriterionArg::Aic => Criterion::Aic,
            CriterionArg::Pareto => Criterion::ParetoScore,
        },
        complexity_penalty: args.complexity_penalty,
        ..SearchConfig::default()
    };
    if let Some(ops) = args.operators {
        cfg.operators = ops;
    }
    cfg.operator_complexity = crate::strategy::operator_complexity(&args.operator_complexity)?;
    if let Some(c) = args.complexity_per_input {
        cfg.complexity_per_input = c;
    }
    let bar = if args.json {
        indicatif::ProgressBar::hidden()
    } else {
        let b = indicatif::ProgressBar::new(cfg.epochs as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:30} epoch {pos}/{len} {msg} [{elapsed}]")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    };
    let res = search(&data, &y, &cfg, &mut |p| {
        bar.set_position(p.epoch as u64);
        bar.set_message(format!(
            "models {} best loss {:.4e}",
            p.evaluations, p.best_loss
        ));
    })?;
    bar.finish_and_clear();
    let best = summary(&res.best, &data, &y)?;
    let pareto = res
        .pareto
        .iter()
        .map(|m| summary(m, &data, &y))
        .collect::<Result<Vec<_>>>()?;
    if args.json {
        let doc = json!({
            "best": best,
            "pareto": pareto,
            "evaluations": res.evaluations,
            "seconds": res.seconds,
        });
        println!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        println!(
            "best (complexity {}): {}",
            res.best.complexity(),
            res.best.equation()
        );
        let num = |v: &Value, k: &str| v[k].as_f64().unwrap_or(f64::NAN);
        println!(
            "  R^2 {:.6}  RMSE {:.6e}  features {}",
            num(&best, "r2"),
            num(&best, "rmse"),
            res.best.features().join(", ")
        );
        println!("Pareto front:");
        for (m, s) in res.pareto.iter().zip(&pareto) {
            println!(
                "  {:>3}  R^2 {:.6}  {}",
                m.complexity(),
                num(s, "r2"),
                m.equation()
            );
        }
        println!("{} models in {:.2} s", res.evaluations, res.seconds);
    }
    Ok(())
}
