//! `hxai dynamic compare`: the physics as written, the calibrated physics, the hybrid and a
//! NARX gradient boosting, each fitted on the training runs and scored by its free-run
//! error on held-out runs (`--test-runs`, a seeded share of the runs) or on every run's
//! samples after a time (`--test-after T`), with paired t-tests over runs.

use super::calibrate::CALIBRATION_ODE;
use super::narx::Narx;
use super::system::{Run, System};
use super::validate::fit_runs;
use super::{DynamicConfig, DynamicModel};
use crate::HybridError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// How `compare` holds data out.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TestSplit {
    /// These runs are held out (`--test-runs`).
    pub test_runs: Vec<f64>,
    /// Every run's samples after this time are held out (`--test-after`).
    pub test_after: Option<f64>,
}

/// One model's held-out free-run error (JSON `models[i]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DynamicScore {
    /// `physics`, `physics_calibrated`, `hybrid` or `narx_boosting`.
    pub name: String,
    /// Root mean square error over every held-out sample (and state), `null` when a run
    /// could not be simulated.
    pub rmse: Option<f64>,
    /// The same per held-out run, in `test_runs` order.
    pub per_run: Vec<Option<f64>>,
    /// Paired t-test of the hybrid's per-run mean squared error against this model's
    /// (`null` for the hybrid itself, or where undefined: see `t_test_note`).
    pub p_value: Option<f64>,
}

/// The hybrid's correction as `compare --json` reports it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CorrectionSummary {
    /// Each state's correction, `STATE: equation` joined by `; ` (just the equation for one
    /// state).
    pub equation: String,
    /// The columns the corrections read.
    pub features: Vec<String>,
}

/// The hybrid's summary in the comparison.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HybridSummary {
    /// The correction.
    pub correction: CorrectionSummary,
    /// The whole hybrid ODE.
    pub equation: String,
    /// Its physics parameters.
    pub parameters: BTreeMap<String, f64>,
}

/// The result of [`compare`] (`hxai dynamic compare --json`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DynamicComparison {
    /// The four models, in the order `physics`, `physics_calibrated`, `hybrid`,
    /// `narx_boosting`.
    pub models: Vec<DynamicScore>,
    /// The hybrid fitted on the training runs.
    pub hybrid: HybridSummary,
    /// Runs trained on.
    pub train_runs: Vec<f64>,
    /// Runs scored.
    pub test_runs: Vec<f64>,
    /// With `--test-after T`.
    pub test_after: Option<f64>,
    /// Why a t-test is undefined, where one is.
    pub t_test_note: Option<String>,
    /// The fit's warnings.
    pub warnings: Vec<String>,
}

/// The share of runs held out by default (at least one run).
pub const TEST_SHARE: f64 = 0.25;

fn choose_split(
    runs: &[Run],
    split: &TestSplit,
    seed: u64,
) -> Result<(Vec<Run>, Vec<Run>), HybridError> {
    if let Some(t) = split.test_after {
        if !split.test_runs.is_empty() {
            return Err(HybridError::InvalidConfig(
                "--test-runs and --test-after: choose one way to hold data out".into(),
            ));
        }
        let train: Vec<Run> = runs.iter().map(|r| r.until(t)).collect();
        if runs.iter().all(|r| r.times.iter().all(|&x| x <= t)) {
            return Err(HybridError::InvalidConfig(format!(
                "--test-after {t}: no sample is after it; nothing is held out"
            )));
        }
        if let Some(r) = train.iter().find(|r| r.times.len() < 3) {
            return Err(HybridError::InvalidConfig(format!(
                "--test-after {t}: run {} keeps {} sample(s) before it; a run needs 3",
                r.id,
                r.times.len()
            )));
        }
        return Ok((train, runs.to_vec()));
    }
    let test_ids: Vec<f64> = if split.test_runs.is_empty() {
        if runs.len() < 2 {
            return Err(HybridError::InvalidConfig(
                "one run: hold out its end with --test-after T (or give more runs)".into(),
            ));
        }
        use rand::SeedableRng;
        use rand::seq::SliceRandom;
        let mut ids: Vec<f64> = runs.iter().map(|r| r.id).collect();
        ids.shuffle(&mut rand_chacha::ChaCha8Rng::seed_from_u64(seed));
        let k = ((runs.len() as f64 * TEST_SHARE).round() as usize).clamp(1, runs.len() - 1);
        ids.truncate(k);
        ids
    } else {
        if let Some(r) = split
            .test_runs
            .iter()
            .find(|r| !runs.iter().any(|x| x.id == **r))
        {
            return Err(HybridError::InvalidConfig(format!(
                "--test-runs: there is no run {r} (runs: {})",
                runs.iter()
                    .map(|r| r.id.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        split.test_runs.clone()
    };
    let (test, train): (Vec<Run>, Vec<Run>) =
        runs.iter().cloned().partition(|r| test_ids.contains(&r.id));
    if train.is_empty() {
        return Err(HybridError::InvalidConfig(
            "--test-runs holds out every run; keep at least one to train on".into(),
        ));
    }
    Ok((train, test))
}

/// A run's sum of squares and count of its scored samples (`None`: not integrable).
type RunErrors = Option<(f64, usize)>;

/// Per-run sum of squares and count of the free run of `sim` against `run`, on the samples
/// after `after` (all but the first without it).
fn errors(sim: &[Vec<f64>], run: &Run, after: Option<f64>) -> (f64, usize) {
    let mut sse = 0.0;
    let mut n = 0;
    for (k, x) in sim.iter().enumerate().skip(1) {
        if after.is_some_and(|t| run.times[k] <= t) {
            continue;
        }
        for (j, v) in x.iter().enumerate() {
            let e = v - run.states[j][k];
            sse += e * e;
            n += 1;
        }
    }
    (sse, n)
}

/// Compares the four models on held-out data.
///
/// # Errors
/// Bad settings or split, or the hybrid's fit failing.
pub fn compare(
    table: &hxai_symreg::Table,
    cfg: &DynamicConfig,
    split: &TestSplit,
    progress: &mut dyn FnMut(&str),
) -> Result<DynamicComparison, HybridError> {
    cfg.check()?;
    let runs = cfg.runs(table)?;
    let (train, test) = choose_split(&runs, split, cfg.seed)?;
    let mut fit_cfg = cfg.clone();
    fit_cfg.conformal_folds = 0;
    let model: DynamicModel = fit_runs(&train, &fit_cfg, split.test_after, progress)?;
    progress("the NARX gradient boosting");
    let narx = Narx::fit(&train, cfg.seed)?;
    let systems: [(&str, System); 3] = [
        ("physics", model.system(&model.starting, false)?),
        (
            "physics_calibrated",
            model.system(&model.calibrated_values(), false)?,
        ),
        ("hybrid", model.system(&model.parameters, true)?),
    ];
    let mut per: Vec<(String, Vec<RunErrors>)> = Vec::new();
    for (name, sys) in &systems {
        let v = test
            .iter()
            .map(|r| {
                sys.simulate(r, &r.state_at(0), &CALIBRATION_ODE)
                    .ok()
                    .map(|s| errors(&s, r, split.test_after))
            })
            .collect();
        per.push(((*name).to_string(), v));
    }
    let v = test
        .iter()
        .map(|r| {
            narx.roll_out(r)
                .ok()
                .map(|s| errors(&s, r, split.test_after))
        })
        .collect();
    per.push(("narx_boosting".into(), v));
    let mse = |v: &[RunErrors]| -> Option<Vec<f64>> {
        v.iter()
            .map(|e| e.map(|(s, n)| s / n.max(1) as f64))
            .collect()
    };
    let hybrid_mse = mse(&per[2].1);
    let mut note = None;
    if test.len() < 2 {
        note = Some(format!(
            "{} held-out run(s): a paired t-test over runs needs at least 2",
            test.len()
        ));
    }
    let models = per
        .iter()
        .map(|(name, v)| {
            let total = v
                .iter()
                .try_fold((0.0, 0), |(s, n), e| e.map(|(a, b)| (s + a, n + b)));
            let p_value = match (&hybrid_mse, mse(v)) {
                (Some(h), Some(o)) if name != "hybrid" && test.len() >= 2 => {
                    hxai_eval::paired_t_test(h, &o).ok().map(|t| t.p_value)
                }
                _ => None,
            };
            DynamicScore {
                name: name.clone(),
                rmse: total.map(|(s, n)| (s / n.max(1) as f64).sqrt()),
                per_run: v
                    .iter()
                    .map(|e| e.map(|(s, n)| (s / n.max(1) as f64).sqrt()))
                    .collect(),
                p_value,
            }
        })
        .collect();
    let equation = if model.corrections.len() == 1 {
        model.corrections[0].equation.clone()
    } else {
        model
            .corrections
            .iter()
            .map(|c| format!("{}: {}", c.state, c.equation))
            .collect::<Vec<_>>()
            .join("; ")
    };
    let mut features: Vec<String> = Vec::new();
    for c in &model.corrections {
        for f in &c.features {
            if !features.contains(f) {
                features.push(f.clone());
            }
        }
    }
    Ok(DynamicComparison {
        models,
        hybrid: HybridSummary {
            correction: CorrectionSummary { equation, features },
            equation: model.hybrid_equation.clone(),
            parameters: model.parameters.clone(),
        },
        train_runs: train.iter().map(|r| r.id).collect(),
        test_runs: test.iter().map(|r| r.id).collect(),
        test_after: split.test_after,
        t_test_note: note,
        warnings: model.warnings,
    })
}
