//! The paper's case study end to end, with our numbers beside the published ones.
//!
//! `cargo xtask reproduce` calls [`run`]: it simulates the default data set of the
//! slow-tool-servo machine (`hxai-sim`, seed 42), computes the physics model, the correction
//! factor delta and the twelve features per window (`hxai-hybrid`), fits the symbolic model of
//! delta on an 80/20 split grouped by record (`hxai-symreg`, 10 epochs), fits the Table 3
//! baselines on the same split (`hxai-baselines`), cross-validates the symbolic model over
//! five grouped folds, evaluates the hybrid against the physics model on the test records with
//! a paired t-test (`hxai-eval`), and renders the tables, the figures and the sample table.
//!
//! # Main types
//! - [`ReproduceConfig`]: the full run or the reduced `--quick` one used by CI.
//! - [`Reproduction`]: the [`Results`](results::Results) and the output files as
//!   `(name, text)` pairs; the caller writes them (this crate touches no files).
//! - [`Progress`]: stage events for a progress bar.
//!
//! # Design decision: outputs are strings, and nothing in them depends on time
//! Wall times go to [`Reproduction::timings`] for the terminal only. Every committed file is
//! a pure function of the code and the seed, so `cargo xtask reproduce --check` can compare
//! the committed `docs/results/` with a fresh run byte for byte.
//!
//! # Example
//! ```no_run
//! let cfg = hxai_reproduce::ReproduceConfig::quick();
//! let out = hxai_reproduce::run(&cfg, &mut |_| {})?;
//! assert!(out.files.iter().any(|(name, _)| name == "README.md"));
//! # Ok::<(), hxai_reproduce::ReproduceError>(())
//! ```
#![deny(missing_docs)]

pub mod beyond;
pub mod figures;
pub mod intervals;
mod pages;
pub mod paper;
pub mod pipeline;
mod plots;
pub mod report;
pub mod results;
pub mod streaming;

use hxai_sim::SimConfig;

/// File names and captions of the figures a run produces.
pub fn plots_captions() -> &'static [(&'static str, &'static str)] {
    &plots::CAPTIONS
}

/// Settings of a reproduction run.
#[derive(Debug, Clone, PartialEq)]
pub struct ReproduceConfig {
    /// Reduced data and epochs (CI); the results are then not comparable with the paper.
    pub quick: bool,
    /// Seed of everything (the paper's 42).
    pub seed: u64,
    /// Held-out fraction (the paper's 0.2).
    pub test_fraction: f64,
    /// Cross-validation folds (the paper's 5).
    pub folds: usize,
}

impl Default for ReproduceConfig {
    fn default() -> Self {
        Self {
            quick: false,
            seed: 42,
            test_fraction: 0.2,
            folds: 5,
        }
    }
}

impl ReproduceConfig {
    /// The reduced run: one repeat of each condition, 1.5 s records, 2 epochs.
    pub fn quick() -> Self {
        Self {
            quick: true,
            ..Self::default()
        }
    }

    /// Search epochs: the paper's 10, or 2 when quick.
    pub fn epochs(&self) -> usize {
        if self.quick { 2 } else { 10 }
    }

    /// Bootstrap runs of the stability table: 20, or 3 when quick.
    pub fn stability_runs(&self) -> usize {
        if self.quick { 3 } else { 20 }
    }

    /// The simulator settings: the default data set, or a reduced one when quick.
    pub fn sim_config(&self) -> SimConfig {
        let mut c = SimConfig {
            seed: self.seed,
            ..SimConfig::default()
        };
        if self.quick {
            c.repeats = 1;
            c.duration_s = 1.5;
        }
        c
    }
}

/// A stage event.
#[derive(Debug, Clone, PartialEq)]
pub struct Progress {
    /// Stage name.
    pub stage: &'static str,
    /// Units done.
    pub done: u64,
    /// Units in all.
    pub total: u64,
    /// Free text (e.g. best loss so far).
    pub message: String,
}

impl Progress {
    fn start(stage: &'static str, total: u64) -> Self {
        Self::done_of(stage, 0, total)
    }
    fn done(stage: &'static str, total: u64) -> Self {
        Self::done_of(stage, total, total)
    }
    fn done_of(stage: &'static str, done: u64, total: u64) -> Self {
        Self {
            stage,
            done,
            total,
            message: String::new(),
        }
    }
}

/// Errors of a reproduction run: whichever stage failed, with its reason.
#[derive(Debug, thiserror::Error)]
pub enum ReproduceError {
    /// The simulator refused its settings.
    #[error("simulation: {0}")]
    Sim(#[from] hxai_sim::SimError),
    /// Signal processing failed.
    #[error("signal processing: {0}")]
    Signal(#[from] hxai_signal::SignalError),
    /// Building samples, fitting or evaluating the hybrid failed.
    #[error("hybrid model: {0}")]
    Hybrid(#[from] hxai_hybrid::HybridError),
    /// Symbolic regression failed.
    #[error("symbolic regression: {0}")]
    Symreg(#[from] hxai_symreg::SrError),
    /// A baseline failed.
    #[error("baseline: {0}")]
    Baseline(#[from] hxai_baselines::BaselineError),
    /// A statistic could not be computed.
    #[error("statistics: {0}")]
    Eval(#[from] hxai_eval::EvalError),
    /// A table of samples could not be sliced.
    #[error("table: {0}")]
    Table(#[from] hxai_table::TableError),
    /// A figure could not be drawn.
    #[error(transparent)]
    Figure(#[from] figures::FigureError),
    /// Serialising the results failed.
    #[error("results.json: {0}")]
    Json(#[from] serde_json::Error),
    /// Anything else in the pipeline.
    #[error("{0}")]
    Pipeline(String),
}

/// The outcome of [`run`].
#[derive(Debug)]
pub struct Reproduction {
    /// Every number of the tables.
    pub results: results::Results,
    /// The section "Beyond the paper" (the hybrid of any process on three more processes).
    pub beyond: beyond::BeyondResults,
    /// Output files, `(file name inside docs/results, content)`.
    pub files: Vec<(String, String)>,
    /// Wall time of each stage (s), for the terminal only.
    pub timings: Vec<(&'static str, f64)>,
}

/// Runs the reproduction and renders its outputs.
///
/// # Errors
/// The first stage that fails, as a [`ReproduceError`].
pub fn run(
    cfg: &ReproduceConfig,
    progress: &mut dyn FnMut(Progress),
) -> Result<Reproduction, ReproduceError> {
    let mut computed = pipeline::compute(cfg, progress)?;
    let started = std::time::Instant::now();
    let (beyond, beyond_figures) = beyond::compute(cfg, progress)?;
    computed
        .timings
        .push((beyond::STAGE, started.elapsed().as_secs_f64()));
    progress(Progress::start("report", 1));
    /// results.json: the paper's document with the section "Beyond the paper" appended.
    #[derive(serde::Serialize)]
    struct Document<'a> {
        #[serde(flatten)]
        paper: &'a results::Results,
        beyond_the_paper: &'a beyond::BeyondResults,
    }
    let doc = Document {
        paper: &computed.results,
        beyond_the_paper: &beyond,
    };
    let mut files = vec![
        (
            "README.md".to_string(),
            report::markdown(&computed.results)
                + &beyond::markdown(&beyond)
                + &intervals::markdown(
                    &computed.results.intervals,
                    &beyond
                        .cases
                        .iter()
                        .map(beyond::CaseResult::intervals)
                        .collect::<Vec<_>>(),
                )
                + &pages::markdown(
                    &beyond
                        .cases
                        .iter()
                        .map(|c| c.name.as_str())
                        .collect::<Vec<_>>(),
                ),
        ),
        (
            "results.json".to_string(),
            serde_json::to_string_pretty(&doc)? + "\n",
        ),
        ("samples.csv".to_string(), report::samples_csv(&computed)?),
    ];
    files.extend(plots::all(&computed)?);
    files.push(pages::tool(&computed)?);
    files.extend(beyond_figures);
    progress(Progress::done("report", 1));
    Ok(Reproduction {
        beyond,
        results: computed.results,
        files,
        timings: computed.timings,
    })
}
