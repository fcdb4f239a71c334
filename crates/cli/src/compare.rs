//! `hxai compare`: the paper's Table 3 baselines and the symbolic model, fitted on one
//! table and scored on another.
use crate::Global;
use anyhow::{Context, Result};
use hxai_baselines::{Matrix, SymbolicRegressor, table3_models};
use hxai_data::Table;
use hxai_symreg::SearchConfig;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::time::Instant;

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

fn column<'a>(t: &'a Table, name: &str, path: &Path) -> Result<&'a Vec<f64>> {
    let i = t.names.iter().position(|n| n == name).with_context(|| {
        format!(
            "no column `{name}` in {}: the columns are {}",
            path.display(),
            t.names.join(", ")
        )
    })?;
    Ok(&t.columns[i])
}

/// Feature matrix (columns `features`, in that order) and target of a table.
fn xy(t: &Table, features: &[String], target: &str, path: &Path) -> Result<(Matrix, Vec<f64>)> {
    let cols = features
        .iter()
        .map(|f| column(t, f, path).cloned())
        .collect::<Result<Vec<_>>>()?;
    let x = Matrix::from_columns(&cols).with_context(|| format!("bad table {}", path.display()))?;
    Ok((x, column(t, target, path)?.clone()))
}

/// Runs `hxai compare`.
#[allow(clippy::print_stdout)]
pub fn run(args: Args, _g: &Global) -> Result<()> {
    let read = |p: &Path| {
        hxai_data::read_table(p).with_context(|| format!("cannot read the table {}", p.display()))
    };
    let (train, test) = (read(&args.train)?, read(&args.test)?);
    column(&train, &args.target, &args.train)?;
    let features: Vec<String> = train
        .names
        .iter()
        .filter(|n| **n != args.target)
        .cloned()
        .collect();
    anyhow::ensure!(
        !features.is_empty(),
        "{} has no input column besides `{}`",
        args.train.display(),
        args.target
    );
    let (x_train, y_train) = xy(&train, &features, &args.target, &args.train)?;
    let (x_test, y_test) = xy(&test, &features, &args.target, &args.test)?;

    let mut models = table3_models(args.seed);
    let cfg = SearchConfig {
        seed: args.seed,
        ..SearchConfig::default()
    };
    models.push(Box::new(
        SymbolicRegressor::new(cfg).with_names(features.clone()),
    ));

    let mut rows = Vec::new();
    for mut m in models {
        let t0 = Instant::now();
        m.fit(&x_train, &y_train)
            .with_context(|| format!("fitting `{}` failed", m.name()))?;
        let seconds = t0.elapsed().as_secs_f64();
        let pred = m
            .predict(&x_test)
            .with_context(|| format!("predicting with `{}` failed", m.name()))?;
        let s = hxai_eval::score(&y_test, &pred)
            .with_context(|| format!("scoring `{}` failed", m.name()))?;
        rows.push((m.name().to_string(), s, seconds));
    }

    if args.json {
        let models: Vec<_> = rows
            .iter()
            .map(|(name, s, sec)| json!({"name": name, "r2": s.r2, "rmse": s.rmse, "mae": s.mae, "seconds": sec}))
            .collect();
        let doc = json!({
            "models": models,
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
        for (name, s, sec) in &rows {
            println!(
                "{name:<10} {:>10.4} {:>12.5} {:>12.5} {:>10.3}",
                s.r2, s.rmse, s.mae, sec
            );
        }
    }
    Ok(())
}
