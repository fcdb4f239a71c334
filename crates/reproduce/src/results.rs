//! Every number of the tables, as one serialisable document (`docs/results/results.json`).
//!
//! Nothing here depends on timing, so the document is a pure function of the code, the
//! settings and the seed, and `cargo xtask reproduce --check` can compare it exactly.

use crate::{ReproduceError, paper};
use hxai_eval::Metrics;
use hxai_hybrid::records::Evaluation;
use hxai_sim::SimRecord;
use hxai_table::Table;
use serde::Serialize;

/// The whole document.
#[derive(Debug, Clone, Serialize)]
pub struct Results {
    /// How the run was configured.
    pub settings: Settings,
    /// The data set (Table 1) and the split.
    pub data: DataSummary,
    /// Table 2: the features and their ranges on our samples.
    pub feature_ranges: Vec<FeatureRange>,
    /// Per-record amplitudes of command, encoder and probe (Figure 4).
    pub amplitudes: Vec<AmplitudeRow>,
    /// Table 3: every model on delta, 80/20 grouped split.
    pub table3: Vec<ModelRow>,
    /// The selected symbolic model.
    pub symbolic: SymbolicSummary,
    /// Five-fold cross-validation of the symbolic model.
    pub cv: Vec<CvRow>,
    /// Physics vs hybrid displacement on the test records.
    pub hybrid: Evaluation,
    /// The intervals of the corrected amplitude on the test windows by every method
    /// ([`crate::intervals`]).
    pub intervals: Vec<crate::intervals::MethodInterval>,
    /// Stability of the selected structure over bootstrap resamples of the training
    /// windows (`hxai fit --stability N`).
    pub stability: hxai_symreg::Stability,
    /// The model applied in real time (`hxai stream`) against `hxai predict`.
    pub streaming: crate::streaming::StreamingSummary,
}

/// Run settings.
#[derive(Debug, Clone, Serialize)]
pub struct Settings {
    /// The reduced CI configuration.
    pub quick: bool,
    /// Seed of the simulation, split, search and forest.
    pub seed: u64,
    /// Search epochs.
    pub epochs: usize,
    /// Held-out fraction.
    pub test_fraction: f64,
    /// Cross-validation folds.
    pub folds: usize,
    /// How samples are split.
    pub split: String,
}

/// The data set and the split.
#[derive(Debug, Clone, Serialize)]
pub struct DataSummary {
    /// Records simulated.
    pub n_records: usize,
    /// Samples (windows).
    pub n_samples: usize,
    /// Training samples.
    pub n_train: usize,
    /// Test samples.
    pub n_test: usize,
    /// Training records.
    pub train_records: Vec<String>,
    /// Test records.
    pub test_records: Vec<String>,
    /// Commanded amplitudes (um).
    pub amplitudes_um: Vec<f64>,
    /// Commanded frequencies (Hz).
    pub frequencies_hz: Vec<f64>,
    /// Repeats per condition.
    pub repeats: usize,
    /// Record length (s).
    pub duration_s: f64,
    /// Sampling rate (Hz).
    pub fs_hz: f64,
    /// Window length (s).
    pub window_s: f64,
    /// Discarded at each record end (s).
    pub discard_s: f64,
    /// Smallest, mean and largest delta over all samples, and its sample standard deviation (um).
    pub delta_min_mean_max_sd: [f64; 4],
}

/// One feature's range over all samples.
#[derive(Debug, Clone, Serialize)]
pub struct FeatureRange {
    /// `f1`..`f12`.
    pub name: String,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
    /// Mean value.
    pub mean: f64,
}

impl FeatureRange {
    /// Range of the column `name` of `samples`.
    pub fn new(name: &str, samples: &Table) -> Result<Self, ReproduceError> {
        let e = hxai_eval::extent(samples.require(name)?)?;
        Ok(Self {
            name: name.to_string(),
            min: e.min,
            max: e.max,
            mean: e.mean,
        })
    }
}

/// Sine amplitudes of one record's channels over the whole record, and the encoder lag.
#[derive(Debug, Clone, Serialize)]
pub struct AmplitudeRow {
    /// Record id.
    pub record: String,
    /// Commanded amplitude (um).
    pub amplitude_um: f64,
    /// Commanded frequency (Hz).
    pub frequency_hz: f64,
    /// Fitted amplitude of the command channel (um).
    pub command_um: f64,
    /// Fitted amplitude of the encoder (um).
    pub encoder_um: f64,
    /// Fitted amplitude of the probe, the true position (um).
    pub probe_um: f64,
    /// How far the encoder lags the probe (ms; positive = later).
    pub encoder_lag_ms: f64,
}

impl AmplitudeRow {
    /// Fits a sine at the commanded frequency to each channel.
    pub fn of(r: &SimRecord) -> Result<Self, ReproduceError> {
        let fit = |x: &[f64]| hxai_signal::fit_sine(x, r.fs_hz, r.frequency_hz);
        let (c, e, p) = (fit(&r.command_um)?, fit(&r.encoder_um)?, fit(&r.probe_um)?);
        Ok(Self {
            record: r.id.clone(),
            amplitude_um: r.amplitude_um,
            frequency_hz: r.frequency_hz,
            command_um: c.amplitude,
            encoder_um: e.amplitude,
            probe_um: p.amplitude,
            encoder_lag_ms: hxai_signal::phase_lag_s(&p, &e, r.frequency_hz) * 1e3,
        })
    }
}

/// One row of Table 3.
#[derive(Debug, Clone, Serialize)]
pub struct ModelRow {
    /// Model name (`linear`, `lasso_cv`, `tree_5`, `tree_6`, `tree_8`, `forest`, `symbolic`).
    pub name: String,
    /// Test scores on delta (RMSE and MAE in um).
    pub test: Metrics,
    /// Complexity (symbolic model only).
    pub complexity: Option<usize>,
    /// The paper's R^2, where it gives one.
    pub paper_r2: Option<f64>,
}

impl ModelRow {
    /// A row with the paper's R^2 looked up by name.
    pub fn new(name: &str, m: Metrics, complexity: Option<usize>) -> Self {
        Self {
            name: name.to_string(),
            test: m,
            complexity,
            paper_r2: paper::table3_r2(name),
        }
    }
}

/// The selected symbolic model.
#[derive(Debug, Clone, Serialize)]
pub struct SymbolicSummary {
    /// Plain text.
    pub equation: String,
    /// sympy-parseable text.
    pub sympy: String,
    /// LaTeX.
    pub latex: String,
    /// Features + operators.
    pub complexity: usize,
    /// Features the equation uses.
    pub features: Vec<String>,
    /// Models evaluated by the search.
    pub evaluations: u64,
    /// The Pareto front: (complexity, equation).
    pub pareto: Vec<(usize, String)>,
    /// How it was selected, its structure's share over the stability runs and the
    /// alternatives the data cannot tell apart from it.
    pub selection: hxai_symreg::SelectionReport,
    /// Test scores on delta (RMSE and MAE in um).
    pub test: Metrics,
}

/// One metric of the cross-validation table.
#[derive(Debug, Clone, Serialize)]
pub struct CvRow {
    /// `R2`, `RMSE` or `MAE`.
    pub metric: String,
    /// Per-fold values.
    pub folds: Vec<f64>,
    /// Mean over folds.
    pub mean: f64,
    /// Sample standard deviation over folds.
    pub sd: f64,
    /// 95 % Student-t interval (the correct one for five folds).
    pub ci_t: [f64; 2],
    /// 95 % normal-approximation interval, mean +- 1.96 sd / sqrt(k) (what the paper used).
    pub ci_normal: [f64; 2],
    /// The paper's mean, sd and normal interval.
    pub paper: [f64; 4],
}

impl CvRow {
    /// Summarises per-fold `values`; `paper_index` picks the paper's row.
    pub fn new(metric: &str, values: &[f64], paper_index: usize) -> Result<Self, ReproduceError> {
        let s = hxai_eval::summarize(values)?;
        let p = paper::CV[paper_index];
        Ok(Self {
            metric: metric.to_string(),
            folds: values.to_vec(),
            mean: s.mean,
            sd: s.std,
            ci_t: [s.ci_t.lower, s.ci_t.upper],
            ci_normal: [s.ci_normal.lower, s.ci_normal.upper],
            paper: [p.1, p.2, p.3, p.4],
        })
    }
}
