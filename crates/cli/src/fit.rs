//! `hxai fit`: fit the tool-position hybrid model on a data folder.
use crate::Global;
use crate::strategy::{CriterionArg, StrategyArg};
use anyhow::{Context, Result};
use hxai_hybrid::records::{FitProgress, RecordConfig, SplitKind, WindowConfig};
use hxai_symreg::SearchConfig;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;

/// How windows are split into train and test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SplitArg {
    /// Whole records on one side (windows of a record never on both sides).
    Record,
    /// Windows split individually (neighbouring windows can land on both sides).
    Window,
}

/// Arguments of `hxai fit`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Data folder (manifest.csv + one CSV/Parquet file per record, with `probe_um`).
    #[arg(long)]
    pub data: PathBuf,
    /// Where to write the model (JSON).
    #[arg(long)]
    pub out: PathBuf,
    /// Seed of the split and of the search.
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// Fraction of records (or windows, with --split window) held out for testing.
    #[arg(long, default_value_t = 0.2)]
    pub test_fraction: f64,
    /// Symbolic-regression search strategy.
    // `--engine` is the old spelling, still read for old scripts; `alias` (not
    // `visible_alias`) keeps it out of `--help` and the docs.
    #[arg(long, alias = "engine", value_enum, default_value_t = StrategyArg::Combined)]
    pub strategy: StrategyArg,
    /// How the correction's equation is chosen among the search's candidates (see
    /// `hxai sr --help`).
    #[arg(long, value_enum, default_value_t = CriterionArg::Bic)]
    pub criterion: CriterionArg,
    /// Folds of `--criterion cv`.
    #[arg(long, default_value_t = 5)]
    pub cv_folds: usize,
    /// Search epochs (default: the search's default, 10).
    #[arg(long)]
    pub epochs: Option<usize>,
    /// Largest equation complexity (default: the search's default).
    #[arg(long)]
    pub max_complexity: Option<usize>,
    /// Comma-separated operators of the correction's search, from: add sub mul div exp log
    /// sqrt square inverse sin cos tanh abs gaussian gaussian2 (default: the paper's set,
    /// arithmetic, sin, cos, the gaussians, log, abs and exp).
    #[arg(long, value_delimiter = ',')]
    pub operators: Option<Vec<String>>,
    /// Which operator may appear inside which: `readable` (the default of corrections: no
    /// exp, log, sin, cos, tanh or gaussian inside another, except a power law
    /// `exp(a*log(x))`), `none`, or rules `OUTER:INNER=MAX` (e.g. `readable,exp:log=0`).
    #[arg(long)]
    pub nesting: Option<String>,
    /// Consensus selection: also search N bootstrap resamples of the rows and select the
    /// structure most of them give back among their near-best models, refitted on all rows
    /// (0, the default, selects by --criterion from one search).
    #[arg(long)]
    pub consensus: Option<usize>,
    /// Complexity of operators, as comma-separated NAME=INTEGER (e.g. `sqrt=2,exp=2`);
    /// operators not named count 1.
    #[arg(long, value_delimiter = ',')]
    pub operator_complexity: Vec<String>,
    /// Complexity the cap grows by with each input beyond the first (default 0: the
    /// paper's fixed cap).
    #[arg(long)]
    pub complexity_per_input: Option<usize>,
    /// Window length in seconds (each window is one sample).
    #[arg(long, default_value_t = 0.5)]
    pub window_s: f64,
    /// Seconds discarded at each record end (filter edge transients).
    #[arg(long, default_value_t = 0.25)]
    pub discard_s: f64,
    /// Train/test split by record (default) or by window.
    #[arg(long, value_enum, default_value_t = SplitArg::Record)]
    pub split: SplitArg,
    /// Also write the samples (record, window, split, f1..f12, A_phys, A_true, delta) to
    /// this CSV or Parquet file.
    #[arg(long)]
    pub samples: Option<PathBuf>,
    /// Also rerun the search on N seeded bootstrap resamples of the training windows and
    /// report how often each feature and each structure is selected (JSON `stability`).
    #[arg(long)]
    pub stability: Option<usize>,
    /// How the correction is searched: free form (the paper's), or one term per signal
    /// feature (`factors`: a sum of one-feature laws, kept where they lower the
    /// cross-validated error; docs/hybrid-tables.md, "The factor form").
    #[arg(long, value_enum, default_value_t = crate::hybrid::args::FormArg::Free)]
    pub form: crate::hybrid::args::FormArg,
    /// Folds of the CV+ calibration of conformal prediction intervals of the corrected
    /// amplitude, grouped by record and stored in the model file (each fold refits the
    /// correction's constants, not its structure); 0 fits without them (the delta method is
    /// then the only interval).
    #[arg(long, default_value_t = hxai_hybrid::conformal::DEFAULT_CONFORMAL_FOLDS)]
    pub conformal_folds: usize,
    /// Print a JSON summary on stdout instead of text.
    #[arg(long)]
    pub json: bool,
}

fn bar(len: u64, msg: &'static str) -> ProgressBar {
    let pb = crate::progress::bar(len);
    if let Ok(style) = ProgressStyle::with_template("{msg:>12} [{bar:30}] {pos}/{len} {elapsed}") {
        pb.set_style(style.progress_chars("=> "));
    }
    pb.set_message(msg);
    pb
}

/// Runs `hxai fit`.
pub fn run(args: Args, _g: &Global) -> Result<()> {
    let folder = hxai_data::read_folder(&args.data)
        .with_context(|| format!("cannot read the data folder {}", args.data.display()))?;
    // Every output is checked before the (long) fit, so a bad path costs nothing and
    // nothing is written for a command that fails.
    let mut protected = folder.input_files();
    crate::safety::check_output(&args.out, &protected)?;
    if let Some(path) = &args.samples {
        crate::safety::check_table_path(path)?;
        protected.push(crate::safety::input(&args.out, "the model output (--out)"));
        crate::safety::check_output(path, &protected)?;
    }
    if let Some(runs) = args.stability {
        anyhow::ensure!(
            runs >= 1,
            "--stability must be at least 1 (the number of bootstrap reruns), got 0"
        );
    }
    anyhow::ensure!(
        !folder.entries.is_empty(),
        "the manifest of {} lists no records",
        args.data.display()
    );
    let pb = bar(folder.entries.len() as u64, "reading");
    let entries: Vec<&hxai_data::ManifestEntry> = folder.entries.iter().collect();
    let recs = crate::records::read_with_truth(&folder, &entries, "fitting", &pb)?;
    let inputs = crate::records::inputs(&entries, &recs);

    let mut search = SearchConfig {
        seed: args.seed,
        strategy: args.strategy.into(),
        ..SearchConfig::paper()
    };
    crate::strategy::SearchFlags {
        epochs: args.epochs,
        max_complexity: args.max_complexity,
        criterion: Some(args.criterion.into()),
        cv_folds: Some(args.cv_folds),
        operators: args.operators.as_deref(),
        nesting: args.nesting.as_deref(),
        consensus: args.consensus,
        prior: None,
        operator_complexity: &args.operator_complexity,
        complexity_per_input: args.complexity_per_input,
    }
    .apply(&mut search)?;
    search.check()?;
    let cfg = RecordConfig {
        window: WindowConfig {
            length_s: args.window_s,
            discard_s: args.discard_s,
        },
        split: match args.split {
            SplitArg::Record => SplitKind::Record,
            SplitArg::Window => SplitKind::Window,
        },
        test_fraction: args.test_fraction,
        seed: args.seed,
        search,
        form: args.form.into(),
        conformal_folds: args.conformal_folds,
        ..RecordConfig::default()
    };
    let samples_bar = bar(inputs.len() as u64, "samples");
    let search_bar = bar(cfg.search.epochs as u64, "search");
    search_bar.set_position(0);
    let mut out = hxai_hybrid::records::fit(&inputs, &cfg, &mut |p| match p {
        FitProgress::Samples { done, .. } => {
            samples_bar.set_position(done as u64);
            if done == inputs.len() {
                samples_bar.finish_and_clear();
            }
        }
        FitProgress::Search(p) => search_bar.set_position(p.epoch as u64),
    })
    .context("fitting the hybrid model failed")?;
    search_bar.finish_and_clear();
    let mut warnings: Vec<String> = out.warnings.iter().map(ToString::to_string).collect();
    warnings.extend(crate::records::amplitude_warnings(&entries, &inputs));
    crate::safety::warn(&warnings);

    // Everything is computed before anything is written, and every output is staged (written
    // beside its target) before any replaces its target: a failure leaves all as it was.
    let stability = match args.stability {
        Some(runs) => {
            let b = bar(runs as u64, "stability");
            let bb = b.clone();
            let s = out
                .stability(&cfg.search, runs, &mut move |done, _| {
                    bb.set_position(done as u64)
                })
                .context("the stability runs failed")?;
            b.finish_and_clear();
            Some(s)
        }
        None => None,
    };
    // (a tuple of both would take the selection out even without a stability run, and the
    // model file would lose it)
    if let Some(st) = &stability {
        let sel = out.model.correction.selection.take();
        out.model.correction.selection = sel.map(|sel| sel.with_stability(st));
    }
    let json = out.model.to_json().context("cannot serialise the model")?;
    let model_file = hxai_data::stage_text(&args.out, &json)
        .with_context(|| format!("cannot write the model to {}", args.out.display()))?;
    let samples_file = match &args.samples {
        Some(path) => {
            use hxai_data::Column;
            let s = out.samples_table().context("cannot tabulate the samples")?;
            // the names of the library's samples table, its three label columns first
            let mut table = hxai_data::MixedTable {
                names: s.names()[..3].to_vec(),
                columns: vec![
                    Column::Text(s.record),
                    Column::Number(s.window.iter().map(|&w| w as f64).collect()),
                    Column::Text(s.split.iter().map(|s| s.to_string()).collect()),
                ],
                skipped_rows: 0,
            };
            table.push_table(s.values);
            Some(
                hxai_data::stage_mixed_table(path, &table)
                    .with_context(|| format!("cannot write the samples to {}", path.display()))?,
            )
        }
        None => None,
    };

    let out_path = args.out.clone();
    let commit = move || -> Result<()> {
        model_file
            .commit()
            .with_context(|| format!("cannot write the model to {}", out_path.display()))?;
        if let Some(f) = samples_file {
            let shown = f.path().display().to_string();
            f.commit()
                .with_context(|| format!("cannot write the samples to {shown}"))?;
        }
        Ok(())
    };
    let m = &out.model;
    if args.json {
        // the correction's forms (the model file's keys), its constants and its selection
        let doc = serde_json::json!({
            "model": crate::safety::path_text(&args.out),
            "correction": m.correction.report(),
            "stability": stability,
            "split": { "kind": m.split.kind, "train": m.split.train, "test": m.split.test },
            "training": m.training,
            "warnings": warnings,
        });
        let text = serde_json::to_string_pretty(&doc).context("cannot format JSON")?;
        // the document first: a full stdout then leaves the old files as they were
        crate::safety::print_document(&text)?;
        commit()?;
    } else {
        commit()?;
        let t = &m.training;
        let fmt = |s: &Option<hxai_eval::Metrics>| {
            s.map(|s| format!("R^2 {:.4}, RMSE {:.4} um", s.r2, s.rmse))
                .unwrap_or_else(|| "n/a".into())
        };
        #[allow(clippy::print_stdout)]
        {
            println!("wrote {}", args.out.display());
            println!("delta = {}", m.correction.forms.equation);
            println!(
                "complexity {}, features {}",
                m.correction.forms.complexity,
                m.correction.forms.features.join(", ")
            );
            println!(
                "windows: {} train ({} records), {} test ({} records); {} models in {:.1} s",
                t.n_train_windows,
                m.split.train.len(),
                t.n_test_windows,
                m.split.test.len(),
                t.evaluations,
                t.seconds
            );
            println!("delta on train: {}", fmt(&t.delta_train));
            println!("delta on test:  {}", fmt(&t.delta_test));
            if let Some(sel) = &m.correction.selection {
                crate::sr::print_selection(sel);
            }
            if let Some(st) = &stability {
                crate::sr::print_stability(st);
            }
        }
    }
    Ok(())
}
