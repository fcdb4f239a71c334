//! `hxai hybrid design`: the settings of the next runs (issue 49, first part;
//! `hxai_hybrid::tables::design`).
use anyhow::{Context, Result};
use hxai_hybrid::tables::design::{Candidates, DesignGoal, candidates, design, parse_space};
use std::path::PathBuf;

/// What the next runs should settle.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub(crate) enum GoalArg {
    /// Separate the selected correction from the alternatives the data cannot tell apart
    /// (the default; `precision` when the model file has none, `coverage` when it has no
    /// covariance either).
    Discriminate,
    /// Where the prediction interval is widest and the runs are sparse.
    Coverage,
    /// Ds-optimal for the physics parameters, the correction's constants as nuisance
    /// parameters (from the model file's covariance): the runs that narrow the parameters'
    /// joint interval most.
    Precision,
}

/// Arguments of `hxai hybrid design`.
#[derive(Debug, clap::Args)]
pub(crate) struct DesignArgs {
    /// Model file written by `hxai hybrid fit`.
    #[arg(long)]
    pub(crate) model: PathBuf,
    /// The settings that can be run: ranges `col=lo:hi[:step],col=a|b` covering every
    /// input column of the model, or a CSV (or Parquet) file of feasible settings.
    #[arg(long)]
    pub(crate) space: String,
    /// How many runs to propose.
    #[arg(long)]
    pub(crate) n: usize,
    /// The CSV of proposed runs: the space's columns, `predicted`, `spread`, `reason`.
    #[arg(long)]
    pub(crate) out: PathBuf,
    /// What the runs should settle.
    #[arg(long, value_enum, default_value_t = GoalArg::Discriminate)]
    pub(crate) goal: GoalArg,
    /// Seed of the random candidates drawn from ranges.
    #[arg(long, default_value_t = 42)]
    pub(crate) seed: u64,
    /// Print one JSON document on stdout (the runs, each equation's predictions there).
    #[arg(long)]
    pub(crate) json: bool,
}

/// Runs `hxai hybrid design`.
#[allow(clippy::print_stdout)]
pub(crate) fn run(a: DesignArgs) -> Result<()> {
    let space_path = PathBuf::from(&a.space);
    let from_file = !a.space.contains('=') && space_path.exists();
    let mut inputs = vec![crate::safety::input(&a.model, "the model (--model)")];
    if from_file {
        inputs.push(crate::safety::input(&space_path, "the space (--space)"));
    }
    crate::safety::check_output(&a.out, &inputs)?;
    let model = super::load_model(&a.model)?;
    let Candidates { mut table, text } = if from_file {
        let view = super::read(&space_path, None)
            .with_context(|| format!("cannot read the space {}", space_path.display()))?;
        Candidates {
            table: view.table,
            text: view.text,
        }
    } else {
        candidates(&parse_space(&a.space)?, a.seed)?
    };
    // the settings as given (numbers, then text), before the model's level indicators
    let numeric_names: Vec<String> = table.names().to_vec();
    model.add_levels(&mut table, &text).with_context(|| {
        format!(
            "cannot design runs over the space {} (give a level column as `COL=A|B` or a \
             column of the settings)",
            a.space
        )
    })?;
    let goal = match a.goal {
        GoalArg::Discriminate => DesignGoal::Discriminate,
        GoalArg::Coverage => DesignGoal::Coverage,
        GoalArg::Precision => DesignGoal::Precision,
    };
    let p = design(&model, &table, a.n, goal).with_context(|| {
        format!(
            "cannot design runs over the space {} (it must give every input column of the model)",
            a.space
        )
    })?;
    if p.left_out > 0 {
        crate::safety::warn(&[&format!(
            "{} of the {} candidate settings left out: the model has no finite value there (its \
             physics or correction is outside its domain)",
            p.left_out,
            p.left_out + p.n_candidates
        )]);
    }
    if goal == DesignGoal::Discriminate && p.goal != goal {
        crate::safety::warn(&[&format!(
            "--goal discriminate: the model file has no alternative the data could not tell \
             apart from its correction, so the runs are chosen for {}",
            p.goal.name()
        )]);
    }
    // the settings' numeric columns (not the level indicators added for the model)
    let numeric: Vec<(&String, &[f64])> = numeric_names
        .iter()
        .filter_map(|n| table.column(n).map(|c| (n, c)))
        .collect();
    let mut t = hxai_data::MixedTable::default();
    for &(name, col) in &numeric {
        t.push(
            name,
            hxai_data::Column::Number(p.rows.iter().map(|&i| col[i]).collect()),
        );
    }
    for (name, cells) in &text {
        t.push(
            name,
            hxai_data::Column::Text(p.rows.iter().map(|&i| cells[i].clone()).collect()),
        );
    }
    t.push("predicted", hxai_data::Column::Number(p.predicted.clone()));
    t.push("spread", hxai_data::Column::Number(p.spread.clone()));
    t.push("reason", hxai_data::Column::Text(p.reason.clone()));
    hxai_data::write_mixed_table(&a.out, &t)
        .with_context(|| format!("cannot write the runs to {}", a.out.display()))?;
    if a.json {
        let doc = serde_json::json!({
            "goal": p.goal.name(),
            "n_candidates": p.n_candidates,
            "left_out": p.left_out,
            "runs": p.rows.iter().enumerate().map(|(k, &i)| {
                let mut settings = serde_json::Map::new();
                for &(name, col) in &numeric {
                    settings.insert(name.clone(), serde_json::json!(col[i]));
                }
                for (name, cells) in &text {
                    settings.insert(name.clone(), serde_json::json!(cells[i]));
                }
                serde_json::json!({
                    "settings": settings,
                    "predicted": p.predicted[k],
                    "spread": p.spread[k],
                    "reason": p.reason[k],
                })
            }).collect::<Vec<_>>(),
            "equations": p.equations.iter().map(|(e, v)| serde_json::json!({
                "equation": e, "predictions": v,
            })).collect::<Vec<_>>(),
        });
        println!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        println!(
            "{} runs chosen from {} candidates for {} ({} candidate equations), written to {}",
            p.rows.len(),
            p.n_candidates,
            p.goal.name(),
            p.equations.len(),
            a.out.display()
        );
        for (k, r) in p.reason.iter().enumerate() {
            println!("  run {}: {r}", k + 1);
        }
    }
    Ok(())
}
