//! Library-level stand-in for `hxai sr --csv FILE --target COL [--seed N] [--epochs N]
//! [--max-complexity N] --json` (same JSON shape), used by the benchmark when the full CLI is
//! not built. Reads a plain numeric CSV with a header.
#![allow(clippy::print_stdout, missing_docs)]
use hxai_symreg::{Model, SearchConfig, Table, search};
use std::error::Error;

fn summary(m: &Model, data: &Table, y: &[f64]) -> Result<serde_json::Value, Box<dyn Error>> {
    let pred = m.predict(data)?;
    let n = y.len() as f64;
    let mean = y.iter().sum::<f64>() / n;
    let sst: f64 = y.iter().map(|v| (v - mean).powi(2)).sum();
    let sse: f64 = y.iter().zip(&pred).map(|(a, b)| (a - b).powi(2)).sum();
    Ok(
        serde_json::json!({"equation": m.equation(), "sympy": m.sympy(), "latex": m.latex(),
        "complexity": m.complexity(), "features": m.features(), "r2": 1.0 - sse / sst, "rmse": (sse / n).sqrt()}),
    )
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().collect();
    let get = |k: &str| {
        args.iter()
            .position(|a| a == k)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let path = get("--csv").ok_or("--csv FILE required")?;
    let target = get("--target").ok_or("--target COL required")?;
    let text = std::fs::read_to_string(&path)?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .ok_or("empty file")?
        .split(',')
        .map(|s| s.trim().to_string())
        .collect();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); header.len()];
    for line in lines.filter(|l| !l.trim().is_empty()) {
        for (c, cell) in cols.iter_mut().zip(line.split(',')) {
            c.push(cell.trim().parse()?);
        }
    }
    let ti = header
        .iter()
        .position(|h| *h == target)
        .ok_or("unknown target column")?;
    let y = cols.remove(ti);
    let mut names = header;
    names.remove(ti);
    let data = Table::new(names, cols)?;
    let mut cfg = SearchConfig::default();
    if let Some(s) = get("--seed") {
        cfg.seed = s.parse()?;
    }
    if let Some(s) = get("--epochs") {
        cfg.epochs = s.parse()?;
    }
    if let Some(s) = get("--max-complexity") {
        cfg.max_complexity = s.parse()?;
    }
    if let Some(s) = get("--operators") {
        cfg.operators = s.split(',').map(|x| x.to_string()).collect();
    }
    let res = search(&data, &y, &cfg, &mut |_| {})?;
    let pareto: Vec<serde_json::Value> = res
        .pareto
        .iter()
        .map(|m| summary(m, &data, &y))
        .collect::<Result<_, _>>()?;
    let doc = serde_json::json!({"best": summary(&res.best, &data, &y)?, "pareto": pareto,
        "evaluations": res.evaluations, "seconds": res.seconds});
    println!("{}", serde_json::to_string_pretty(&doc)?);
    Ok(())
}
