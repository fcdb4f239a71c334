//! Fitting the tool-position hybrid model: the samples of every record, a seeded split, and
//! symbolic regression of `delta` on the training windows' features.

use super::samples::{SamplesTable, samples_table};
use super::{
    CorrectionKind, FeatureInfo, RecordModel, SCHEMA_VERSION, SplitKind, TrainingInfo, check_band,
};
use crate::HybridError;
use crate::correction::CorrectionInfo;
use crate::records::composer::RecordHybrid;
use crate::records::sample::{RecordInput, WindowSample};
use crate::records::warnings::{Warning, input_warnings, units_warning};
use crate::records::window::WindowConfig;
use crate::split::{SplitInfo, WindowId};
use hxai_signal::PhysicsConfig;
use hxai_table::Table;
use std::collections::BTreeSet;

/// Settings of [`fit`].
#[derive(Debug, Clone)]
pub struct RecordConfig {
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
    /// How the correction of the signal features is searched: free form (the paper's), or
    /// one factor per feature ([`hxai_symreg::factors`], an additive correction: a sum of
    /// one-feature terms; its folds are seeded by `search.seed`).
    pub form: crate::correction::Form,
    /// Folds of the CV+ calibration of conformal intervals of the corrected amplitude,
    /// grouped by record (0: none; the model file then offers only the delta method).
    pub conformal_folds: usize,
}

impl Default for RecordConfig {
    fn default() -> Self {
        Self {
            physics: PhysicsConfig::default(),
            features: hxai_features::FeatureConfig::default(),
            window: WindowConfig::default(),
            split: SplitKind::Record,
            test_fraction: 0.2,
            seed: 42,
            search: hxai_symreg::SearchConfig::paper(),
            form: crate::correction::Form::Free,
            conformal_folds: crate::conformal::DEFAULT_CONFORMAL_FOLDS,
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
    pub model: RecordModel,
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
        if self.model.correction.form == Some(crate::correction::Form::Factors) {
            let fc = hxai_symreg::factors::FactorConfig {
                seed: search.seed,
                par: search.par,
                ..Default::default()
            };
            return Ok(hxai_symreg::factors::factor_stability(
                &table,
                &delta,
                hxai_symreg::factors::Link::Additive,
                &fc,
                runs,
                progress,
            )?);
        }
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
pub fn record_hybrid(physics: &PhysicsConfig, window: WindowConfig) -> RecordHybrid {
    record_hybrid_with(physics, &hxai_features::FeatureConfig::default(), window)
}

/// The tool-position composer with explicit feature settings.
pub fn record_hybrid_with(
    physics: &PhysicsConfig,
    features: &hxai_features::FeatureConfig,
    window: WindowConfig,
) -> RecordHybrid {
    RecordHybrid {
        physics: physics.clone(),
        features: features.clone(),
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
    cfg: &RecordConfig,
    progress: &mut dyn FnMut(FitProgress),
) -> Result<FitOutput, HybridError> {
    if !(cfg.test_fraction > 0.0 && cfg.test_fraction < 1.0) {
        return Err(HybridError::InvalidConfig(format!(
            "test fraction must lie strictly between 0 and 1, got {}",
            cfg.test_fraction
        )));
    }
    cfg.window.check()?;
    if matches!(
        cfg.form,
        crate::correction::Form::None | crate::correction::Form::Auto
    ) {
        return Err(HybridError::InvalidConfig(format!(
            "correction form {}: the tool case's correction is searched free or as factors",
            cfg.form.name()
        )));
    }
    let hybrid = record_hybrid_with(&cfg.physics, &cfg.features, cfg.window);
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
    let (result, selection, factors) = match cfg.form {
        crate::correction::Form::Free => {
            let result = hxai_symreg::search(&train_table, &train_delta, &cfg.search, &mut |p| {
                progress(FitProgress::Search(p.clone()));
            })?;
            let selection = hxai_symreg::SelectionReport::of(&result, &cfg.search);
            (result, selection, None)
        }
        crate::correction::Form::Factors
        | crate::correction::Form::None
        | crate::correction::Form::Auto => factor_search(&train_table, &train_delta, cfg)?,
    };
    let conformal = if cfg.conformal_folds > 0 {
        Some(conformal_of(
            &result.best,
            &train,
            &train_table,
            &train_delta,
            cfg,
        )?)
    } else {
        None
    };
    let correction = CorrectionInfo::learned(
        CorrectionKind::Symbolic,
        result.best.clone(),
        &train_table,
        &train_delta,
        &result.pareto,
        selection,
    )?;
    let correction = CorrectionInfo {
        form: Some(cfg.form),
        factors,
        ..correction
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
    let model = RecordModel {
        schema_version: SCHEMA_VERSION,
        physics: cfg.physics.clone(),
        features: FeatureInfo {
            config: cfg.features.clone(),
            ..FeatureInfo::default()
        },
        window: cfg.window,
        correction,
        split: SplitInfo {
            kind: cfg.split,
            seed: Some(cfg.seed),
            test_fraction: Some(cfg.test_fraction),
            train: side(false),
            test: side(true),
            test_windows: Some(test_windows),
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
        conformal,
    };
    Ok(FitOutput {
        model,
        samples,
        is_test,
        search: result,
        warnings,
    })
}

/// The factor form's search of the training windows' `delta` (an additive correction: one
/// term per signal feature), written as a search result with the factor form's selection
/// report and its factors.
fn factor_search(
    table: &Table,
    delta: &[f64],
    cfg: &RecordConfig,
) -> Result<
    (
        hxai_symreg::SearchResult,
        hxai_symreg::SelectionReport,
        Option<Vec<hxai_symreg::factors::Factor>>,
    ),
    HybridError,
> {
    let start = std::time::Instant::now();
    let fc = hxai_symreg::factors::FactorConfig {
        seed: cfg.search.seed,
        par: cfg.search.par,
        ..Default::default()
    };
    let found = crate::correction::factor_search(
        table,
        delta,
        None,
        hxai_symreg::factors::Link::Additive,
        &fc,
    )?;
    let result = hxai_symreg::SearchResult {
        best: found.model,
        alternatives: found.pareto[1..].to_vec(),
        pareto: found.pareto,
        consensus: None,
        evaluations: 0,
        duplicate_structures: 0,
        simplified: 0,
        seconds: start.elapsed().as_secs_f64(),
        error_model: hxai_symreg::ErrorModel::Additive,
    };
    Ok((result, found.selection, Some(found.factors)))
}

/// CV+ calibration of the correction `best` over `cfg.conformal_folds` folds of the training
/// windows, grouped by record (the windows of one recording are alike, so they stay on one
/// side, as in the split).
fn conformal_of(
    best: &hxai_symreg::Model,
    train: &[&WindowSample],
    table: &Table,
    delta: &[f64],
    cfg: &RecordConfig,
) -> Result<crate::conformal::ConformalInfo, HybridError> {
    let k = cfg.conformal_folds;
    let records: Vec<&str> = train.iter().map(|s| s.record.as_str()).collect();
    let distinct: BTreeSet<&str> = records.iter().copied().collect();
    if k < 2 || distinct.len() < k {
        return Err(HybridError::InvalidConfig(format!(
            "conformal intervals need at least 2 folds and a training record per fold: \
             {k} fold(s) asked for, {} training records: use fewer folds \
             (--conformal-folds, at least 2), or 0 to fit without conformal intervals",
            distinct.len()
        )));
    }
    let splits = hxai_eval::grouped_kfold(&records, k, cfg.seed)?;
    crate::conformal::calibrate_model(best, table, delta, &splits)
}
