//! The tool-position hybrid model: fitting it, its JSON file, and applying it.
//!
//! This file holds the model file's schema (the types serialised to JSON) and loading and
//! checking a model; [`fit()`] is in `fit.rs`, prediction and intervals in `predict.rs`,
//! evaluation on records in `evaluate.rs`.

mod evaluate;
mod fit;
mod predict;
mod samples;

pub use fit::{
    FitOutput, FitProgress, RecordConfig, fit, record_hybrid, record_hybrid_with, split_samples,
};
pub use samples::{SamplesTable, samples_table};

use crate::HybridError;
use crate::correction::CorrectionInfo;
use crate::records::composer::{RecordHybrid, feature_names};
use crate::records::metrics_um;
use crate::records::sample::RecordInput;
use crate::records::window::WindowConfig;
use crate::split::SplitInfo;
use hxai_eval::Metrics;
use hxai_signal::PhysicsConfig;
use hxai_symreg::Strategy;
use serde::{Deserialize, Serialize};

/// Version of the model file layout this code writes and reads.
pub const SCHEMA_VERSION: u32 = 1;

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

/// Kind of correction stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CorrectionKind {
    /// A symbolic model from `hxai-symreg`.
    Symbolic,
    /// `delta_hat = 0`.
    Zero,
}

impl CorrectionInfo<CorrectionKind> {
    /// The zero correction of a record model.
    pub fn zero() -> Self {
        Self {
            kind: CorrectionKind::Zero,
            forms: hxai_symreg::ModelForms::zero(),
            candidates: Vec::new(),
            model: None,
            uncertainty: None,
            pareto: None,
            selection: None,
            form: None,
            factors: None,
            choice: None,
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
            names: feature_names(),
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
pub struct RecordModel {
    /// [`SCHEMA_VERSION`] of the writer.
    pub schema_version: u32,
    /// Physics settings.
    pub physics: PhysicsConfig,
    /// Feature settings.
    pub features: FeatureInfo,
    /// Window settings.
    pub window: WindowConfig,
    /// The correction.
    pub correction: CorrectionInfo<CorrectionKind>,
    /// Train and test records.
    pub split: SplitInfo<SplitKind, String>,
    /// Training details.
    pub training: TrainingInfo,
    /// What conformal prediction intervals of the corrected amplitude need
    /// ([`crate::conformal::ConformalInfo`]: CV+ over folds of the training records, the
    /// correction's constants refitted per fold). Absent in files written before it
    /// existed and with `conformal_folds` 0, where the delta method is the only one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conformal: Option<crate::conformal::ConformalInfo>,
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
            frequency_hz,
            low_hz: physics.low_hz,
            high_hz: physics.high_hz,
        })
    }
}

impl RecordModel {
    /// The model as pretty JSON.
    pub fn to_json(&self) -> Result<String, HybridError> {
        serde_json::to_string_pretty(self).map_err(|e| HybridError::ModelFormat(e.to_string()))
    }

    /// Reads a model from JSON; a file of another [`SCHEMA_VERSION`] is a
    /// [`HybridError::SchemaVersion`] error, checked before anything else.
    pub fn from_json(text: &str) -> Result<Self, HybridError> {
        let value: serde_json::Value = serde_json::from_str(text)
            .map_err(|e| HybridError::ModelFormat(hxai_table::plain_json_error(&e.to_string())))?;
        if value.get("target").is_some() && value.get("hybrid").is_some() {
            return Err(HybridError::ModelFormat(
                "this is a model of `hxai hybrid fit` (a process on a table), not of `hxai fit`: \
                 apply it with `hxai hybrid predict` or `hxai hybrid evaluate`"
                    .into(),
            ));
        }
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
        // From the text, not from `value`: a `serde_json::Value` object sorts its keys, and
        // the correction's `uncertainty.params` is an ordered map (`p10` after `p9`) whose
        // order the `slots` and the covariance follow (issue 63).
        drop(value);
        let mut model: RecordModel = serde_json::from_str(text)
            .map_err(|e| HybridError::ModelFormat(hxai_table::plain_json_error(&e.to_string())))?;
        // a record model always writes its test windows, empty for a record split
        model.split.test_windows.get_or_insert_with(Vec::new);
        model.validate()?;
        Ok(model)
    }

    /// Checks a model in full before it is used (done by [`RecordModel::from_json`]): the
    /// symbolic model's program, parameters and input indices, that its features are the
    /// feature map's, the window settings, and the physics settings (band and orders).
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`], [`HybridError::UnknownFeature`],
    /// [`HybridError::InvalidConfig`] or [`HybridError::Signal`], naming what is wrong.
    pub fn validate(&self) -> Result<(), HybridError> {
        let expected = feature_names();
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
        if let Some(conf) = &self.conformal {
            let Some(m) = &self.correction.model else {
                return Err(HybridError::ModelFormat(
                    "`conformal` is given for a zero correction".into(),
                ));
            };
            conf.check(m.params.len())?;
            if conf.scores.len() != self.training.n_train_windows {
                return Err(HybridError::ModelFormat(format!(
                    "`conformal` has {} scores for {} training windows",
                    conf.scores.len(),
                    self.training.n_train_windows
                )));
            }
        }
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
    pub fn hybrid(&self) -> RecordHybrid {
        record_hybrid_with(&self.physics, &self.features.config, self.window)
    }

    /// The correction, checked: a symbolic correction has its model and reads only the
    /// feature map's features; a zero correction has no model.
    ///
    /// # Errors
    /// [`HybridError::ModelFormat`] or [`HybridError::UnknownFeature`], naming what is wrong.
    pub fn correction(&self) -> Result<&CorrectionInfo<CorrectionKind>, HybridError> {
        match (&self.correction.kind, &self.correction.model) {
            (CorrectionKind::Zero, None) => {}
            (CorrectionKind::Zero, Some(_)) => {
                return Err(HybridError::ModelFormat(
                    "the correction is zero but `correction.model` holds a model".into(),
                ));
            }
            (CorrectionKind::Symbolic, Some(m)) => {
                let available = &self.features.names;
                for f in m.features() {
                    if !available.contains(&f) {
                        return Err(HybridError::UnknownFeature {
                            name: f,
                            available: available.join(", "),
                        });
                    }
                }
            }
            (CorrectionKind::Symbolic, None) => {
                return Err(HybridError::ModelFormat(
                    "the correction is symbolic but `correction.model` is missing".into(),
                ));
            }
        }
        Ok(&self.correction)
    }
}
