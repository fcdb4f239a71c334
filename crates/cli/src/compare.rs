//! `hxai compare`: the paper's Table 3 baselines, gradient boosting (scikit-learn's
//! `HistGradientBoostingRegressor` defaults) and the symbolic model, fitted on one table and
//! scored on another.
use crate::Global;
use anyhow::{Context, Result};
use hxai_baselines::{GradientBoosting, SymbolicRegressor, table3_models};
use hxai_symreg::SearchConfig;
use serde_json::json;
use std::path::{Path, PathBuf};

/// Arguments of `hxai compare`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Training table (CSV or Parquet, every column numeric).
    #[arg(long)]
    pub train: PathBuf,
    /// Test table with the same columns (extra columns are ignored).
    #[arg(long)]
    pub test: PathBuf,
    /// Column to predict; every other column of the training table is an input.
    #[arg(long)]
    pub target: String,
    /// Seed of the forest and the symbolic search.
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// Print one JSON document on stdout instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Runs `hxai compare`.
#[allow(clippy::print_stdout)]
pub fn run(args: Args, _g: &Global) -> Result<()> {
    let read = |p: &Path| {
        hxai_data::read_table(p).with_context(|| format!("cannot read the table {}", p.display()))
    };
    let (mut x_train, test) = (read(&args.train)?, read(&args.test)?);
    let y_train = x_train.remove_column(&args.target).with_context(|| {
        format!(
            "cannot take column `{}` of {} as the target: it must be there, besides at least \
             one input column (the columns are {})",
            args.target,
            args.train.display(),
            x_train.names().join(", ")
        )
    })?;
    let in_test = |what: &str| format!("{what} of {}", args.test.display());
    let x_test = test
        .select_columns(x_train.names())
        .with_context(|| in_test("the training table's input columns"))?;
    let y_test = test
        .require(&args.target)
        .with_context(|| in_test("the target column"))?;

    anyhow::ensure!(
        y_test.len() >= 2,
        "{}: the test table has {} row(s); R² and the other scores need at least 2",
        args.test.display(),
        y_test.len()
    );
    /// Every input column and the target, as slices of the tables (no copies).
    fn columns<'a>(x: &'a hxai_symreg::Table, y: &'a [f64]) -> Vec<&'a [f64]> {
        let mut c: Vec<&[f64]> = x.columns().iter().map(Vec::as_slice).collect();
        c.push(y);
        c
    }
    let shared = hxai_eval::shared_rows(&columns(&x_train, &y_train), &columns(&x_test, y_test));
    if shared > 0 {
        crate::safety::warn(&[format!(
            "{shared} of the {} test rows repeat a training row (every input and the target \
             equal): the test scores overstate how well the models predict new rows",
            y_test.len()
        )]);
    }

    let mut models = table3_models(args.seed);
    // the black box an engineer reaches for beside the paper's (issue 48)
    models.push(Box::new(GradientBoosting::with_seed(args.seed)));
    let cfg = SearchConfig {
        seed: args.seed,
        ..SearchConfig::paper()
    };
    models.push(Box::new(SymbolicRegressor::new(cfg)));
    let bar = crate::progress::styled(
        models.len() as u64,
        "{bar:30} {pos}/{len} models fitted [{elapsed}]",
    );
    let rows = hxai_baselines::compare(models, &x_train, &y_train, &x_test, y_test, &mut |p| {
        bar.set_position(p.done as u64);
    })
    .context("the comparison failed")?;
    bar.finish_and_clear();

    if args.json {
        let doc = json!({
            "models": rows,
            "target": args.target,
            "n_train": y_train.len(),
            "n_test": y_test.len(),
            "seed": args.seed,
        });
        println!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        println!(
            "{} train rows, {} test rows, target `{}`, seed {}",
            y_train.len(),
            y_test.len(),
            args.target,
            args.seed
        );
        println!(
            "{:<10} {:>10} {:>12} {:>12} {:>10}",
            "model", "R^2", "RMSE", "MAE", "seconds"
        );
        for c in &rows {
            let s = &c.metrics;
            println!(
                "{:<10} {:>10.4} {:>12.5} {:>12.5} {:>10.3}",
                c.name, s.r2, s.rmse, s.mae, c.seconds
            );
        }
    }
    Ok(())
}
