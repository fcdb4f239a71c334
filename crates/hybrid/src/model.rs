//! The tool-position hybrid model: fitting it, its JSON file, and applying it.

use crate::HybridError;
use crate::composer::{Hybrid, RecordInput, RecordPrediction, WindowSample};
use crate::evaluate::{
    DEFAULT_INTERVAL, EvalInput, Evaluation, IntervalReport, evaluate, metrics_um,
};
use crate::explain::{ExplainData, Explanation, ParetoMember};
use crate::tool::{AccelFeatures, DoubleIntegration, SineDecomposition};
use crate::traits::{Correction, FeatureMap, SymbolicCorrection, ZeroCorrection};
use crate::warnings::{Warning, input_warnings, units_warning};
use crate::window::WindowConfig;
use hxai_eval::Metrics;
use hxai_signal::PhysicsConfig;
use hxai_symreg::Strategy;
use hxai_table::Table;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

/// Version of the model file layout this code writes and reads.
pub const SCHEMA_VERSION: u32 = 1;

/// The composer of the tool-position case.
pub type ToolHybrid = Hybrid<DoubleIntegration, SineDecomposition, AccelFeatures>;

/// How samples are split into train and test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SplitKind {
    /// Whole records go to one side (default): windows of one record are never on both
    /// sides, so the test score measures generalisation to unseen recordings.
    #[default]
    Record,
    /// Windows are split individually: neighbouring windows of one recording (strongly
    /// alike) can sit on both sides, which flatters the test score. Offered because it is
    /// how a per-sample 80/20 split behaves.
    Window,
}

/// A window named by record id and index.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct WindowId {
    /// Record id.
    pub record: String,
    /// Window index within the record.
    pub window: usize,
}

/// The split stored in the model file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SplitInfo {
    /// Record or window split.
    pub kind: SplitKind,
    /// Seed of the split.
    pub seed: u64,
    /// Fraction of groups (records or windows) held out.
    pub test_fraction: f64,
    /// Records with at least one training window (sorted).
    pub train: Vec<String>,
    /// Records with at least one test window (sorted).
    pub test: Vec<String>,
    /// With a window split, the test windows (empty for a record split).
    #[serde(default)]
    pub test_windows: Vec<WindowId>,
}

/// Kind of correction stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CorrectionKind {
    /// A symbolic model from `hxai-symreg`.
    Symbolic,
    /// `delta_hat = 0`.
    Zero,
}

/// The correction as stored: the readable forms and the model itself.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CorrectionInfo {
    /// Symbolic or zero.
    pub kind: CorrectionKind,
    /// Plain-text equation.
    pub equation: String,
    /// sympy-parseable equation.
    pub sympy: String,
    /// LaTeX equation.
    pub latex: String,
    /// Complexity (features + operators).
    pub complexity: usize,
    /// Features the equation uses.
    pub features: Vec<String>,
    /// The serialised symbolic model (absent for the zero correction).
    pub model: Option<hxai_symreg::Model>,
    /// The model's constants as a template with named parameters, their standard errors
    /// and 95 % intervals, and the covariance prediction intervals use, on the training
    /// windows (`hxai_symreg::uncertainty`). Absent for the zero correction and in files
    /// written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uncertainty: Option<hxai_symreg::Uncertainty>,
    /// The Pareto front of the search the model was chosen from (complexity, training loss
    /// and equation of each member), for `hxai explain`. Absent for the zero correction and
    /// in files written before it was stored.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pareto: Option<Vec<ParetoMember>>,
}

impl CorrectionInfo {
    /// Stores a symbolic model.
    pub fn symbolic(model: hxai_symreg::Model) -> Self {
        Self {
            kind: CorrectionKind::Symbolic,
            equation: model.equation(),
            sympy: model.sympy(),
            latex: model.latex(),
            complexity: model.complexity(),
            features: model.features(),
            model: Some(model),
            uncertainty: None,
            pareto: None,
        }
    }

    /// The zero correction.
    pub fn zero() -> Self {
        Self {
            kind: CorrectionKind::Zero,
            equation: "0".into(),
            sympy: "0".into(),
            latex: "0".into(),
            complexity: 0,
            features: Vec::new(),
            model: None,
            uncertainty: None,
            pareto: None,
        }
    }
}

/// Feature settings stored with the model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FeatureInfo {
    /// What computes them.
    pub extractor: String,
    /// Input of the feature map.
    pub input: String,
    /// Feature names, in order.
    pub names: Vec<String>,
    /// Sigma convention and PSD estimator.
    pub config: hxai_features::FeatureConfig,
}

impl Default for FeatureInfo {
    fn default() -> Self {
        Self {
            extractor: "hxai_features::extract (paper Table 2)".into(),
            input: "raw acceleration window (m/s^2); f1 = commanded frequency from the manifest"
                .into(),
            names: AccelFeatures::default().names(),
            config: hxai_features::FeatureConfig::default(),
        }
    }
}

/// How the model was trained.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainingInfo {
    /// Search strategy, `None` for a zero correction. Stored under the key `strategy` with
    /// [`Strategy`]'s serde names (`null` for none); files that stored it as `engine` with
    /// the names `qlattice`, `genetic`, `combined` or `none` still load.
    #[serde(alias = "engine", with = "strategy_name")]
    pub strategy: Option<Strategy>,
    /// Seed of the search.
    pub seed: u64,
    /// Epochs of the search.
    pub epochs: usize,
    /// Models fitted by the search.
    pub evaluations: u64,
    /// Wall time of the search, s.
    pub seconds: f64,
    /// Training windows.
    pub n_train_windows: usize,
    /// Test windows.
    pub n_test_windows: usize,
    /// `delta_hat` vs `delta` on the training windows (JSON keys `rmse_um`, `r2`, `mae_um`).
    #[serde(with = "metrics_um::option")]
    pub delta_train: Option<Metrics>,
    /// `delta_hat` vs `delta` on the test windows.
    #[serde(with = "metrics_um::option")]
    pub delta_test: Option<Metrics>,
}

/// The serde form of [`TrainingInfo::strategy`]: [`Strategy`]'s own names, `null` for none;
/// reads `none`, written by files from before, too.
mod strategy_name {
    use hxai_symreg::Strategy;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub(crate) fn serialize<S: Serializer>(v: &Option<Strategy>, s: S) -> Result<S::Ok, S::Error> {
        v.serialize(s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Strategy>, D::Error> {
        let Some(name) = Option::<String>::deserialize(d)? else {
            return Ok(None);
        };
        match name.as_str() {
            "none" => Ok(None),
            other => {
                Strategy::deserialize(serde::de::value::StrDeserializer::<D::Error>::new(other))
                    .map(Some)
            }
        }
    }
}

/// A fitted tool-position hybrid model: everything needed to predict, and the record of
/// how it was made. Serialises to the model file (`hxai fit --out MODEL.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HybridModel {
    /// [`SCHEMA_VERSION`] of the writer.
    pub schema_version: u32,
    /// Physics settings.
    pub physics: PhysicsConfig,
    /// Feature settings.
    pub features: FeatureInfo,
    /// Window settings.
    pub window: WindowConfig,
    /// The correction.
    pub correction: CorrectionInfo,
    /// Train and test records.
    pub split: SplitInfo,
    /// Training details.
    pub training: TrainingInfo,
}

/// Settings of [`fit`].
#[derive(Debug, Clone)]
pub struct FitConfig {
    /// Physics settings.
    pub physics: PhysicsConfig,
    /// Feature settings.
    pub features: hxai_features::FeatureConfig,
    /// Window settings.
    pub window: WindowConfig,
    /// Record (default) or window split.
    pub split: SplitKind,
    /// Held-out fraction (default 0.2).
    pub test_fraction: f64,
    /// Seed of the split (the search has its own in `search.seed`).
    pub seed: u64,
    /// Symbolic-regression settings.
    pub search: hxai_symreg::SearchConfig,
}

impl Default for FitConfig {
    fn default() -> Self {
        Self {
            physics: PhysicsConfig::default(),
            features: hxai_features::FeatureConfig::default(),
            window: WindowConfig::default(),
            split: SplitKind::Record,
            test_fraction: 0.2,
            seed: 42,
            search: hxai_symreg::SearchConfig::paper(),
        }
    }
}

/// What [`fit`] reports while it works.
#[derive(Debug, Clone, PartialEq)]
pub enum FitProgress {
    /// Samples built for `done` of `total` records.
    Samples {
        /// Records done.
        done: usize,
        /// Records in all.
        total: usize,
    },
    /// A search epoch finished.
    Search(hxai_symreg::Progress),
}

/// The result of [`fit`]: the model and the samples it was fitted on.
#[derive(Debug, Clone)]
pub struct FitOutput {
    /// The model.
    pub model: HybridModel,
    /// Every sample, in record then window order.
    pub samples: Vec<WindowSample>,
    /// Whether each sample is on the test side.
    pub is_test: Vec<bool>,
    /// The full search result (Pareto front etc.).
    pub search: hxai_symreg::SearchResult,
    /// Implausible but legal input met while fitting ([`input_warnings`], and records whose
    /// probe and physics amplitudes differ by a units-like factor).
    pub warnings: Vec<Warning>,
}

fn json_type(v: &serde_json::Value) -> &'static str {
    match v {
        serde_json::Value::Null => "null",
        serde_json::Value::Bool(_) => "boolean",
        serde_json::Value::Number(_) => "number",
        serde_json::Value::String(_) => "string",
        serde_json::Value::Array(_) => "array",
        serde_json::Value::Object(_) => "object",
    }
}

/// Refuses a record whose commanded frequency lies outside the physics band: the band-pass
/// removes the motion there and the prediction would be a near-zero amplitude.
fn check_band(physics: &PhysicsConfig, r: &RecordInput<'_>) -> Result<(), HybridError> {
    check_band_hz(physics, r.id, r.frequency_hz)
}

/// [`check_band`] for a frequency of the input named `record`.
pub(crate) fn check_band_hz(
    physics: &PhysicsConfig,
    record: &str,
    frequency_hz: f64,
) -> Result<(), HybridError> {
    if frequency_hz.is_finite() && frequency_hz >= physics.low_hz && frequency_hz <= physics.high_hz
    {
        Ok(())
    } else {
        Err(HybridError::FrequencyOutOfBand {
            record: record.to_owned(),
            freq_hz: frequency_hz,
            low_hz: physics.low_hz,
            high_hz: physics.high_hz,
        })
    }
}

/// The samples of a fit as columns, one row per sample in record then window order: the
/// table `hxai fit --samples` and the reproduction's `samples.csv` write.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplesTable {
    /// Record id of each sample (column `record`).
    pub record: Vec<String>,
    /// Window index within the record (column `window`).
    pub window: Vec<usize>,
    /// `train` or `test` (column `split`).
    pub split: Vec<&'static str>,
    /// The features (named by the feature map, `f1`..`f12`), then `A_phys`, `A_true` and
    /// `delta = A_true - A_phys`, in micrometres.
    pub values: Table,
}

impl SamplesTable {
    /// Every column name in file order: `record`, `window`, `split`, then the values'.
    pub fn names(&self) -> Vec<String> {
        let mut names = vec!["record".to_string(), "window".into(), "split".into()];
        names.extend(self.values.names().iter().cloned());
        names
    }
}

/// The samples table of `samples` (each with its truth) split by `is_test`, feature columns
/// named `feature_names`.
///
/// # Errors
/// [`HybridError::NoTruth`] for a sample without truth, [`HybridError::InvalidConfig`] when
/// `is_test` or a sample's features do not match in length, [`HybridError::Table`] for a
/// non-finite value.
pub fn samples_table(
    samples: &[WindowSample],
    is_test: &[bool],
    feature_names: &[String],
) -> Result<SamplesTable, HybridError> {
    if is_test.len() != samples.len() {
        return Err(HybridError::InvalidConfig(format!(
            "{} split flags for {} samples",
            is_test.len(),
            samples.len()
        )));
    }
    let mut values = crate::composer::feature_table(feature_names.to_vec(), samples)?;
    let truth = |w: &WindowSample| {
        w.a_true()
            .zip(w.delta())
            .ok_or_else(|| HybridError::NoTruth {
                record: w.record.clone(),
            })
    };
    let (a_true, delta): (Vec<f64>, Vec<f64>) = samples
        .iter()
        .map(truth)
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    values.push_column(
        "A_phys".into(),
        samples.iter().map(|w| w.a_phys()).collect(),
    )?;
    values.push_column("A_true".into(), a_true)?;
    values.push_column("delta".into(), delta)?;
    Ok(SamplesTable {
        record: samples.iter().map(|w| w.record.clone()).collect(),
        window: samples.iter().map(|w| w.window).collect(),
        split: is_test
            .iter()
            .map(|&t| if t { "test" } else { "train" })
            .collect(),
        values,
    })
}

impl FitOutput {
    /// The stability of the correction's structure: the search of this fit (settings
    /// `search`) rerun on `runs` bootstrap resamples of the training windows
    /// ([`hxai_symreg::stability()`]; out-of-bag R^2 of `delta`). `progress` gets `(runs
    /// done, runs)`.
    ///
    /// # Errors
    /// A sample without truth, and the search's errors.
    pub fn stability(
        &self,
        search: &hxai_symreg::SearchConfig,
        runs: usize,
        progress: &mut (dyn FnMut(usize, usize) + Send),
    ) -> Result<hxai_symreg::Stability, HybridError> {
        let train: Vec<&WindowSample> = self
            .samples
            .iter()
            .zip(&self.is_test)
            .filter(|(_, t)| !**t)
            .map(|(s, _)| s)
            .collect();
        let table = self.model.hybrid().feature_table(train.iter().copied())?;
        let delta = train
            .iter()
            .map(|s| {
                s.delta().ok_or_else(|| HybridError::NoTruth {
                    record: s.record.clone(),
                })
            })
            .collect::<Result<Vec<f64>, HybridError>>()?;
        Ok(hxai_symreg::stability(
            &table, &delta, search, runs, progress,
        )?)
    }

    /// The samples of this fit as a [`SamplesTable`].
    ///
    /// # Errors
    /// As [`samples_table`].
    pub fn samples_table(&self) -> Result<SamplesTable, HybridError> {
        samples_table(&self.samples, &self.is_test, &self.model.features.names)
    }

    /// `delta_hat` of every sample (record then window order) by the fitted correction.
    ///
    /// # Errors
    /// Those of the correction.
    pub fn delta_hat(&self) -> Result<Vec<f64>, HybridError> {
        let hybrid = self.model.hybrid();
        let table = hybrid.feature_table(&self.samples)?;
        self.model.correction()?.predict(&table)
    }
}

/// The tool-position composer for the given settings.
pub fn tool_hybrid(physics: &PhysicsConfig, window: WindowConfig) -> ToolHybrid {
    tool_hybrid_with(physics, &hxai_features::FeatureConfig::default(), window)
}

/// The tool-position composer with explicit feature settings.
pub fn tool_hybrid_with(
    physics: &PhysicsConfig,
    features: &hxai_features::FeatureConfig,
    window: WindowConfig,
) -> ToolHybrid {
    Hybrid {
        physics: DoubleIntegration {
            config: physics.clone(),
        },
        decomposition: SineDecomposition,
        features: AccelFeatures {
            config: features.clone(),
        },
        window,
    }
}

/// Splits samples into train and test (`true` = test).
pub fn split_samples(
    samples: &[WindowSample],
    kind: SplitKind,
    test_fraction: f64,
    seed: u64,
) -> Result<Vec<bool>, HybridError> {
    let split = match kind {
        SplitKind::Record => {
            let groups: Vec<&str> = samples.iter().map(|s| s.record.as_str()).collect();
            hxai_eval::grouped_train_test_split(&groups, test_fraction, seed)?
        }
        SplitKind::Window => hxai_eval::train_test_split(samples.len(), test_fraction, seed)?,
    };
    let mut is_test = vec![false; samples.len()];
    for &i in &split.test {
        is_test[i] = true;
    }
    Ok(is_test)
}

/// Fits the tool-position hybrid model: samples from every record (each must carry the
/// truth), a seeded split, symbolic regression of `delta` on the training windows' features.
///
/// # Errors
/// Those of the composer, the split ([`HybridError::Eval`]) and the search
/// ([`HybridError::Symreg`]).
pub fn fit(
    records: &[RecordInput<'_>],
    cfg: &FitConfig,
    progress: &mut dyn FnMut(FitProgress),
) -> Result<FitOutput, HybridError> {
    if !(cfg.test_fraction > 0.0 && cfg.test_fraction < 1.0) {
        return Err(HybridError::InvalidConfig(format!(
            "test fraction must lie strictly between 0 and 1, got {}",
            cfg.test_fraction
        )));
    }
    cfg.window.check()?;
    let hybrid = tool_hybrid_with(&cfg.physics, &cfg.features, cfg.window);
    let mut samples = Vec::new();
    let mut warnings = Vec::new();
    for r in records {
        if r.truth.is_none() {
            return Err(HybridError::NoTruth {
                record: r.id.to_owned(),
            });
        }
        check_band(&cfg.physics, r)?;
    }
    for (i, r) in records.iter().enumerate() {
        warnings.extend(input_warnings(r, &cfg.window));
        let rs = hybrid.samples(r)?;
        warnings.extend(units_warning(r.id, &rs.windows));
        samples.extend(rs.windows);
        progress(FitProgress::Samples {
            done: i + 1,
            total: records.len(),
        });
    }
    if samples.is_empty() {
        return Err(HybridError::NoData("no records to fit on".into()));
    }
    let is_test = split_samples(&samples, cfg.split, cfg.test_fraction, cfg.seed)?;
    let train: Vec<&WindowSample> = samples
        .iter()
        .zip(&is_test)
        .filter(|(_, t)| !**t)
        .map(|(s, _)| s)
        .collect();
    let test: Vec<&WindowSample> = samples
        .iter()
        .zip(&is_test)
        .filter(|(_, t)| **t)
        .map(|(s, _)| s)
        .collect();
    let delta_of = |v: &[&WindowSample]| -> Vec<f64> {
        v.iter().map(|s| s.delta().unwrap_or(f64::NAN)).collect()
    };
    let train_table = hybrid.feature_table(train.iter().copied())?;
    let test_table = hybrid.feature_table(test.iter().copied())?;
    let (train_delta, test_delta) = (delta_of(&train), delta_of(&test));
    let result = hxai_symreg::search(&train_table, &train_delta, &cfg.search, &mut |p| {
        progress(FitProgress::Search(p.clone()));
    })?;
    let correction = SymbolicCorrection {
        model: result.best.clone(),
    };
    let hat_train = correction.predict(&train_table)?;
    let hat_test = correction.predict(&test_table)?;

    let side = |want: bool| -> Vec<String> {
        let set: BTreeSet<&str> = samples
            .iter()
            .zip(&is_test)
            .filter(|(_, t)| **t == want)
            .map(|(s, _)| s.record.as_str())
            .collect();
        set.into_iter().map(str::to_owned).collect()
    };
    let test_windows = match cfg.split {
        SplitKind::Record => Vec::new(),
        SplitKind::Window => test
            .iter()
            .map(|s| WindowId {
                record: s.record.clone(),
                window: s.window,
            })
            .collect(),
    };
    let model = HybridModel {
        schema_version: SCHEMA_VERSION,
        physics: cfg.physics.clone(),
        features: FeatureInfo {
            config: cfg.features.clone(),
            ..FeatureInfo::default()
        },
        window: cfg.window,
        correction: CorrectionInfo {
            uncertainty: Some(result.best.uncertainty(&train_table, &train_delta)?),
            pareto: Some(ParetoMember::front(&result.pareto)),
            ..CorrectionInfo::symbolic(result.best.clone())
        },
        split: SplitInfo {
            kind: cfg.split,
            seed: cfg.seed,
            test_fraction: cfg.test_fraction,
            train: side(false),
            test: side(true),
            test_windows,
        },
        training: TrainingInfo {
            strategy: Some(cfg.search.strategy),
            seed: cfg.search.seed,
            epochs: cfg.search.epochs,
            evaluations: result.evaluations,
            seconds: result.seconds,
            n_train_windows: train.len(),
            n_test_windows: test.len(),
            delta_train: hxai_eval::score(&train_delta, &hat_train).ok(),
            delta_test: hxai_eval::score(&test_delta, &hat_test).ok(),
        },
    };
    Ok(FitOutput {
        model,
        samples,
        is_test,
        search: result,
        warnings,
    })
}

/// A correction loaded from a model file.
#[derive(Debug, Clone, PartialEq)]
pub enum LoadedCorrection {
    /// Symbolic model.
    Symbolic(SymbolicCorrection),
    /// Zero.
    Zero(ZeroCorrection),
}

impl Correction for LoadedCorrection {
    fn equation(&self) -> String {
        match self {
            LoadedCorrection::Symbolic(s) => s.equation(),
            LoadedCorrection::Zero(z) => z.equation(),
        }
    }

    fn predict(&self, features: &Table) -> Result<Vec<f64>, HybridError> {
        match self {
            LoadedCorrection::Symbolic(s) => s.predict(features),
            LoadedCorrection::Zero(z) => z.predict(features),
        }
    }
}

impl HybridModel {
    /// The model as pretty JSON.
    pub fn to_json(&self) -> Result<String, HybridError> {
        serde_json::to_string_pretty(self).map_err(|e| HybridError::ModelFormat(e.to_string()))
    }

    /// Reads a model from JSON; a file of another [`SCHEMA_VERSION`] is a
    /// [`HybridError::SchemaVersion`] error, checked before anything else.
    pub fn from_json(text: &str) -> Result<Self, HybridError> {
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| HybridError::ModelFormat(e.to_string()))?;
        match value.get("schema_version") {
            Some(v) if v.as_u64() == Some(u64::from(SCHEMA_VERSION)) => {}
            Some(v) => {
                let found = match v {
                    serde_json::Value::String(s) => {
                        format!(
                            "\"{}\" (text, not a number)",
                            s.chars().take(20).collect::<String>()
                        )
                    }
                    serde_json::Value::Number(n) => n.to_string().chars().take(24).collect(),
                    other => format!("of JSON type {}", json_type(other)),
                };
                return Err(HybridError::SchemaVersion {
                    found,
                    expected: SCHEMA_VERSION,
                });
            }
            None => {
                return Err(HybridError::ModelFormat(
                    "no `schema_version` field; is this a model written by `hxai fit`?".into(),
                ));
            }
        }
        let model: HybridModel =
            serde_json::from_value(value).map_err(|e| HybridError::ModelFormat(e.to_string()))?;
        model.validate()?;
        Ok(model)
    }

    /// Checks a model in full before it is used (done by [`HybridModel::from_json`]): the
    /// symbolic model's program, parameters and input indices, that its features are the
    /// feature map's, the window settings, and the physics settings (band and orders).
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`], [`HybridError::UnknownFeature`],
    /// [`HybridError::InvalidConfig`] or [`HybridError::Signal`], naming what is wrong.
    pub fn validate(&self) -> Result<(), HybridError> {
        let expected = AccelFeatures::default().names();
        if self.features.names != expected {
            return Err(HybridError::ModelFormat(format!(
                "`features.names` must be {} (the features this hxai computes), found {}",
                expected.join(", "),
                self.features.names.join(", ")
            )));
        }
        if let Some(m) = &self.correction.model {
            m.validate().map_err(|e| {
                HybridError::ModelFormat(format!("`correction.model` is corrupt: {e}"))
            })?;
        }
        self.correction()?;
        self.window.check()?;
        // The band and orders are checked against a generous sampling rate: the record's
        // own rate is checked again when the model is applied.
        self.physics
            .check(1e9)
            .map_err(|e| HybridError::ModelFormat(format!("`physics` settings: {e}")))?;
        Ok(())
    }

    /// Refuses a record whose commanded frequency lies outside this model's pass band.
    fn check_band(&self, r: &RecordInput<'_>) -> Result<(), HybridError> {
        check_band(&self.physics, r)
    }

    /// The composer with this model's physics and window settings.
    pub fn hybrid(&self) -> ToolHybrid {
        tool_hybrid_with(&self.physics, &self.features.config, self.window)
    }

    /// The correction as a [`Correction`].
    pub fn correction(&self) -> Result<LoadedCorrection, HybridError> {
        match (&self.correction.kind, &self.correction.model) {
            (CorrectionKind::Zero, _) => Ok(LoadedCorrection::Zero(ZeroCorrection)),
            (CorrectionKind::Symbolic, Some(m)) => {
                let available = self.features.names.clone();
                for f in m.features() {
                    if !available.contains(&f) {
                        return Err(HybridError::UnknownFeature {
                            name: f,
                            available: available.join(", "),
                        });
                    }
                }
                Ok(LoadedCorrection::Symbolic(SymbolicCorrection {
                    model: m.clone(),
                }))
            }
            (CorrectionKind::Symbolic, None) => Err(HybridError::ModelFormat(
                "the correction is symbolic but `correction.model` is missing".into(),
            )),
        }
    }

    /// Physics and hybrid prediction of one record, with warnings about implausible input
    /// ([`input_warnings`]) in [`RecordPrediction::warnings`].
    ///
    /// # Errors
    /// [`HybridError::FrequencyOutOfBand`] when the record's frequency lies outside the
    /// physics model's band, and the composer's errors.
    pub fn predict(&self, record: &RecordInput<'_>) -> Result<RecordPrediction, HybridError> {
        self.check_band(record)?;
        let mut p = self.hybrid().predict(record, &self.correction()?)?;
        p.warnings = input_warnings(record, &self.window);
        Ok(p)
    }

    /// Prediction intervals at `level` of the corrected amplitude `A_corr = A_phys +
    /// delta_hat` of each sample: `A_phys` plus the interval of `delta_hat` (delta method
    /// through the correction with the covariance of its constants, plus the residual
    /// variance of `delta` on the training windows; see `hxai_symreg::uncertainty` for the
    /// assumptions). The zero correction has none.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] when the model stores no uncertainty (the zero
    /// correction, or a file from before it existed: refit), and the correction's errors.
    pub fn amplitude_intervals(
        &self,
        samples: &[WindowSample],
        level: f64,
    ) -> Result<Vec<(f64, f64)>, HybridError> {
        let (Some(model), Some(unc)) = (&self.correction.model, &self.correction.uncertainty)
        else {
            return Err(HybridError::InvalidConfig(
                "this model stores no uncertainty of its correction (a zero correction, or a \
                 file written before prediction intervals existed): refit it with `hxai fit`"
                    .into(),
            ));
        };
        let table = self.hybrid().feature_table(samples)?;
        let iv = model.prediction_intervals(unc, &table, level)?;
        Ok(samples
            .iter()
            .zip(iv)
            .map(|(s, (lo, hi))| (s.a_phys() + lo, s.a_phys() + hi))
            .collect())
    }

    /// [`HybridModel::predict`] with pointwise bounds of the displacement: each window's
    /// sine reconstructed with the lower and the upper corrected amplitude of
    /// [`HybridModel::amplitude_intervals`] (the smaller and larger value at each sample).
    /// The band carries the amplitude's uncertainty only, not the phase's or the noise of
    /// the probe.
    ///
    /// # Errors
    /// As [`HybridModel::predict`] and [`HybridModel::amplitude_intervals`].
    pub fn predict_with_intervals(
        &self,
        record: &RecordInput<'_>,
        level: f64,
    ) -> Result<(RecordPrediction, Vec<f64>, Vec<f64>), HybridError> {
        let p = self.predict(record)?;
        let iv = self.amplitude_intervals(&p.samples, level)?;
        let hybrid = self.hybrid();
        let with = |pick: fn(&(f64, f64)) -> f64| -> Vec<f64> {
            let windows: Vec<_> = p
                .windows
                .iter()
                .zip(&iv)
                .map(|(w, b)| crate::composer::WindowPrediction {
                    corrected: crate::composer::corrected_latent(
                        &w.physics,
                        pick(b) - w.physics.amplitude,
                    ),
                    ..*w
                })
                .collect();
            hybrid.reconstruct_record(
                &windows,
                record.signal.len(),
                record.fs_hz,
                record.frequency_hz,
            )
        };
        let a = with(|b| b.0);
        let b = with(|b| b.1);
        let lo = a.iter().zip(&b).map(|(x, y)| x.min(*y)).collect();
        let hi = a.iter().zip(&b).map(|(x, y)| x.max(*y)).collect();
        Ok((p, lo, hi))
    }

    /// The explanation of the correction ([`crate::explain::explain`]): with `data` (the
    /// samples of a fit: features, `delta`, split) its response to each feature it uses and
    /// predicted vs true `delta`, with prediction intervals at `level`; the Pareto front when
    /// the file stores it.
    ///
    /// # Errors
    /// [`HybridError::InvalidConfig`] for the zero correction (nothing to explain), and those
    /// of [`crate::explain::explain`].
    pub fn explain(
        &self,
        data: Option<&ExplainData<'_>>,
        level: f64,
    ) -> Result<Explanation, HybridError> {
        let Some(model) = &self.correction.model else {
            return Err(HybridError::InvalidConfig(
                "the model's correction is zero: there is no equation to explain".into(),
            ));
        };
        crate::explain::explain(
            model,
            self.correction.uncertainty.as_ref(),
            self.correction.pareto.as_deref(),
            data,
            "delta",
            level,
        )
    }

    /// Evaluates the model on records. With `all` false, only this model's test data is
    /// used: the test records (record split) or the test windows (window split) among
    /// `records`; records not in the test set are skipped. With `all` true, every window
    /// of every record.
    ///
    /// # Errors
    /// [`HybridError::NoData`] when none of the records is a test record.
    pub fn evaluate(
        &self,
        records: &[RecordInput<'_>],
        all: bool,
    ) -> Result<Evaluation, HybridError> {
        self.evaluate_at(records, all, DEFAULT_INTERVAL)
    }

    /// [`HybridModel::evaluate`] with the coverage of prediction intervals at `level`
    /// ([`Evaluation::interval`]: the share of evaluated windows whose true amplitude lies
    /// inside the interval of the corrected amplitude), when the model stores the
    /// uncertainty of its correction.
    ///
    /// # Errors
    /// As [`HybridModel::evaluate`], and a `level` outside (0, 1).
    pub fn evaluate_at(
        &self,
        records: &[RecordInput<'_>],
        all: bool,
        level: f64,
    ) -> Result<Evaluation, HybridError> {
        let mut by_record: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
        for w in &self.split.test_windows {
            by_record
                .entry(w.record.as_str())
                .or_default()
                .push(w.window);
        }
        let mut inputs = Vec::new();
        for r in records {
            if all {
                inputs.push(EvalInput {
                    record: *r,
                    windows: None,
                });
                continue;
            }
            match self.split.kind {
                SplitKind::Record => {
                    if self.split.test.iter().any(|t| t == r.id) {
                        inputs.push(EvalInput {
                            record: *r,
                            windows: None,
                        });
                    }
                }
                SplitKind::Window => {
                    if let Some(ws) = by_record.get(r.id) {
                        inputs.push(EvalInput {
                            record: *r,
                            windows: Some(ws.as_slice()),
                        });
                    }
                }
            }
        }
        if inputs.is_empty() {
            return Err(HybridError::NoData(format!(
                "none of the {} records given is a test record of this model (test records: {}); \
                 evaluate on the data folder the model was fitted on, or evaluate every record",
                records.len(),
                self.split.test.join(", ")
            )));
        }
        for i in &inputs {
            self.check_band(&i.record)?;
        }
        let mut ev = evaluate(&self.hybrid(), &self.correction()?, &inputs)?;
        if self.correction.uncertainty.is_some() {
            let hybrid = self.hybrid();
            let mut samples = Vec::new();
            for i in &inputs {
                let rs = hybrid.samples(&i.record)?;
                samples.extend(
                    rs.windows
                        .into_iter()
                        .filter(|s| i.windows.is_none_or(|w| w.contains(&s.window))),
                );
            }
            let iv = self.amplitude_intervals(&samples, level)?;
            let truth: Vec<f64> = samples
                .iter()
                .map(|s| s.a_true().unwrap_or(f64::NAN))
                .collect();
            ev.interval = Some(IntervalReport::of(level, &truth, &iv));
        }
        ev.warnings = inputs
            .iter()
            .flat_map(|i| input_warnings(&i.record, &self.window))
            .map(|w| w.to_string())
            .collect();
        Ok(ev)
    }
}
