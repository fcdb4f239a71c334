//! The computation: simulate, build samples, fit, compare, cross-validate, evaluate.

use crate::results::{
    AmplitudeRow, CvRow, DataSummary, FeatureRange, ModelRow, Results, Settings, SymbolicSummary,
};
use crate::{Progress, ReproduceConfig, ReproduceError};
use hxai_baselines::{Regressor, SymbolicRegressor};
use hxai_hybrid::records::{FitOutput, FitProgress, RecordConfig, RecordInput};
use hxai_sim::SimRecord;
use hxai_symreg::SearchConfig;
use std::time::Instant;

/// Everything the report and the figures are made from.
#[derive(Debug)]
pub struct Computed {
    /// The numbers.
    pub results: Results,
    /// The simulated records.
    pub records: Vec<SimRecord>,
    /// The fit: model, samples, split, search result.
    pub fit: FitOutput,
    /// `delta_hat` of every sample, in sample order.
    pub delta_hat: Vec<f64>,
    /// Wall time of each stage, for the terminal summary only (never written to the
    /// committed results, which must not depend on timing).
    pub timings: Vec<(&'static str, f64)>,
}

/// A simulated record as the record model takes it, with its probe as the truth.
pub(crate) fn input(r: &SimRecord) -> RecordInput<'_> {
    RecordInput {
        id: &r.id,
        fs_hz: r.fs_hz,
        frequency_hz: r.frequency_hz,
        signal: &r.accel_ms2,
        truth: Some(&r.probe_um),
    }
}

/// `values[i]` for every `i` of `idx`.
fn pick(values: &[f64], idx: &[usize]) -> Vec<f64> {
    idx.iter().map(|&i| values[i]).collect()
}

/// The search settings of every symbolic fit in the run (main fit and CV folds).
pub fn search_config(cfg: &ReproduceConfig) -> SearchConfig {
    SearchConfig {
        seed: cfg.seed,
        epochs: cfg.epochs(),
        ..SearchConfig::paper()
    }
}

/// Runs the whole computation.
pub fn compute(
    cfg: &ReproduceConfig,
    progress: &mut dyn FnMut(Progress),
) -> Result<Computed, ReproduceError> {
    let mut timings = Vec::new();
    let sim_cfg = cfg.sim_config();

    // 1. Simulate.
    let t = Instant::now();
    progress(Progress::start("simulate", sim_cfg.n_records() as u64));
    let records = hxai_sim::simulate(&sim_cfg)?;
    progress(Progress::done("simulate", records.len() as u64));
    timings.push(("simulate", t.elapsed().as_secs_f64()));

    // 2-3. Physics model, delta, features, split, symbolic regression of delta.
    let t = Instant::now();
    let inputs: Vec<RecordInput<'_>> = records.iter().map(input).collect();
    let fit_cfg = RecordConfig {
        seed: cfg.seed,
        test_fraction: cfg.test_fraction,
        search: search_config(cfg),
        ..RecordConfig::default()
    };
    let epochs = fit_cfg.search.epochs as u64;
    progress(Progress::start("fit", epochs));
    let fit = hxai_hybrid::records::fit(&inputs, &fit_cfg, &mut |p| {
        if let FitProgress::Search(s) = p {
            progress(Progress {
                stage: "fit",
                done: s.epoch as u64,
                total: epochs,
                message: format!("{} models, best loss {:.4}", s.evaluations, s.best_loss),
            });
        }
    })?;
    progress(Progress::done("fit", epochs));
    timings.push((
        "physics + features + symbolic fit",
        t.elapsed().as_secs_f64(),
    ));

    let samples = &fit.samples;
    let names = fit.model.features.names.clone();
    let train: Vec<usize> = (0..samples.len()).filter(|&i| !fit.is_test[i]).collect();
    let test: Vec<usize> = (0..samples.len()).filter(|&i| fit.is_test[i]).collect();
    let delta_hat = fit.delta_hat()?;
    let table = fit.samples_table()?;
    let x_all = table.values.select_columns(&names)?;
    let deltas = table.values.require("delta")?.to_vec();

    // 4. Table 3: every baseline on the same split, then the fitted symbolic model.
    let t = Instant::now();
    let (x_train, y_train) = (x_all.select_rows(&train)?, pick(&deltas, &train));
    let (x_test, y_test) = (x_all.select_rows(&test)?, pick(&deltas, &test));
    let models = hxai_baselines::table3_models(cfg.seed);
    let n_models = models.len() as u64 + 1;
    progress(Progress::start("baselines", n_models));
    let compared =
        hxai_baselines::compare(models, &x_train, &y_train, &x_test, &y_test, &mut |p| {
            progress(Progress::done_of("baselines", p.done as u64, n_models))
        })?;
    let mut table3: Vec<ModelRow> = compared
        .into_iter()
        .map(|c| ModelRow::new(&c.name, c.metrics, None))
        .collect();
    let sym_score = hxai_eval::score(&y_test, &pick(&delta_hat, &test))?;
    let best = &fit.search.best;
    table3.push(ModelRow::new(
        "symbolic",
        sym_score,
        Some(best.complexity()),
    ));
    timings.push(("baselines", t.elapsed().as_secs_f64()));

    // 5. Five-fold cross-validation of the symbolic model, grouped by record.
    let t = Instant::now();
    let groups: Vec<&str> = samples.iter().map(|s| s.record.as_str()).collect();
    let folds = hxai_eval::grouped_kfold(&groups, cfg.folds, cfg.seed)?;
    let n_folds = folds.len() as u64;
    progress(Progress::start("cross-validation", n_folds));
    let search = search_config(cfg);
    let make = || -> Box<dyn Regressor> { Box::new(SymbolicRegressor::new(search.clone())) };
    let scores = hxai_baselines::cross_validate(&make, &x_all, &deltas, &folds, &mut |p| {
        progress(Progress::done_of(
            "cross-validation",
            p.done as u64,
            n_folds,
        ))
    })?;
    let metric = |f: fn(&hxai_eval::Metrics) -> f64| scores.iter().map(f).collect::<Vec<_>>();
    let cv = vec![
        CvRow::new("R2", &metric(|m| m.r2), 0)?,
        CvRow::new("RMSE", &metric(|m| m.rmse), 1)?,
        CvRow::new("MAE", &metric(|m| m.mae), 2)?,
    ];
    timings.push(("cross-validation", t.elapsed().as_secs_f64()));

    // 5b. Structure stability of the selected equation: the search rerun on seeded
    // bootstrap resamples of the training windows (issue 15).
    let t = Instant::now();
    let runs = cfg.stability_runs();
    progress(Progress::start("stability", runs as u64));
    // (the library's callback runs on worker threads; this one is not Send, so the stage
    // reports its start and end only)
    let stability = fit.stability(&search, runs, &mut |_, _| {})?;
    progress(Progress::done("stability", runs as u64));
    timings.push(("stability", t.elapsed().as_secs_f64()));

    // 6. Hybrid vs physics on the test records.
    let t = Instant::now();
    progress(Progress::start("evaluate", 1));
    let hybrid = fit.model.evaluate(&inputs, false)?;
    let intervals: Vec<crate::intervals::MethodInterval> = crate::intervals::METHODS
        .iter()
        .filter_map(|&m| {
            let ev = fit
                .model
                .evaluate_with(&inputs, false, hxai_hybrid::DEFAULT_INTERVAL, m)
                .ok()?;
            Some(crate::intervals::MethodInterval {
                report: ev.interval?,
                median_relative_width: None,
            })
        })
        .collect();
    progress(Progress::done("evaluate", 1));
    timings.push(("hybrid evaluation", t.elapsed().as_secs_f64()));

    // 7. The same model in real time: every test record streamed sample by sample.
    let t = Instant::now();
    progress(Progress::start("streaming", 1));
    let streaming = crate::streaming::compute(&records, &fit.model)?;
    progress(Progress::done("streaming", 1));
    timings.push(("streaming", t.elapsed().as_secs_f64()));

    // Descriptive tables.
    let feature_ranges = names
        .iter()
        .map(|name| FeatureRange::new(name, &table.values))
        .collect::<Result<Vec<_>, _>>()?;
    let amplitudes = records
        .iter()
        .map(AmplitudeRow::of)
        .collect::<Result<Vec<_>, _>>()?;
    let delta_summary = hxai_eval::summarize(&deltas)?;
    let delta_extent = hxai_eval::extent(&deltas)?;
    let data = DataSummary {
        n_records: records.len(),
        n_samples: samples.len(),
        n_train: train.len(),
        n_test: test.len(),
        train_records: fit.model.split.train.clone(),
        test_records: fit.model.split.test.clone(),
        amplitudes_um: sim_cfg.amplitudes_um.clone(),
        frequencies_hz: sim_cfg.frequencies_hz.clone(),
        repeats: sim_cfg.repeats,
        duration_s: sim_cfg.duration_s,
        fs_hz: sim_cfg.fs_hz,
        window_s: fit.model.window.length_s,
        discard_s: fit.model.window.discard_s,
        delta_min_mean_max_sd: [
            delta_extent.min,
            delta_summary.mean,
            delta_extent.max,
            delta_summary.std,
        ],
    };
    let symbolic = SymbolicSummary {
        equation: best.equation(),
        sympy: best.sympy(),
        latex: best.latex(),
        complexity: best.complexity(),
        features: best.features(),
        evaluations: fit.search.evaluations,
        pareto: fit
            .search
            .pareto
            .iter()
            .map(|m| (m.complexity(), m.equation()))
            .collect(),
        selection: hxai_symreg::SelectionReport::of(&fit.search, &search)
            .with_stability(&stability),
        test: sym_score,
    };
    let results = Results {
        stability,
        settings: Settings {
            quick: cfg.quick,
            seed: cfg.seed,
            epochs: cfg.epochs(),
            test_fraction: cfg.test_fraction,
            folds: cfg.folds,
            split: "grouped by record".into(),
        },
        data,
        feature_ranges,
        amplitudes,
        table3,
        symbolic,
        cv,
        hybrid,
        intervals,
        streaming,
    };
    Ok(Computed {
        results,
        records,
        fit,
        delta_hat,
        timings,
    })
}
