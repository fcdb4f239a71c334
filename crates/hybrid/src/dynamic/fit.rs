//! The fit of a dynamic hybrid: calibrate, search the correction, refit every constant
//! through the ODE, keep the correction only where it pays, and calibrate conformal bands
//! over runs.

use super::calibrate::{CALIBRATION_ODE, Calibration, Problem, calibrate, residuals};
use super::correction::{Found, search};
use super::model::{DynamicModel, RunConformal, SCHEMA_VERSION, StateCorrection, Training};
use super::spec::OdeSpec;
use super::system::{Run, System, Unknown};
use super::{DynamicConfig, Initial};
use crate::HybridError;
use crate::tables::Form;
use hxai_symreg::ParamEstimate;
use std::collections::BTreeMap;

/// Each state's spread over the runs (1 where it does not vary): the residuals' scales.
pub(crate) fn scales(runs: &[Run], ns: usize) -> Vec<f64> {
    (0..ns)
        .map(|j| {
            let v: Vec<f64> = runs.iter().flat_map(|r| r.states[j].clone()).collect();
            let n = v.len() as f64;
            let m = v.iter().sum::<f64>() / n;
            let sd = (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n).sqrt();
            if sd > 0.0 && sd.is_finite() { sd } else { 1.0 }
        })
        .collect()
}

/// The parsed physics at its starting values, its calibrated parameters checked.
pub(crate) fn physics_of(cfg: &DynamicConfig) -> Result<OdeSpec, HybridError> {
    let spec = OdeSpec::parse(&cfg.ode, &cfg.states, &cfg.inputs, &cfg.time, &cfg.values())?;
    for p in cfg.calibrate.iter().chain(cfg.set.keys()) {
        if !spec.parameters.contains_key(p) {
            return Err(HybridError::InvalidConfig(format!(
                "{p} is not a parameter of the ODE (its parameters: {})",
                spec.parameters
                    .keys()
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    Ok(spec)
}

/// Free-run root mean square error of `sys` on `runs` (every sample after the first, every
/// state in its own units), from each run's first reading; `NaN` when a run cannot be
/// integrated.
pub(crate) fn free_run_rmse(sys: &System, runs: &[Run]) -> f64 {
    let ones = vec![1.0; sys.n_states()];
    let x0: Vec<Vec<f64>> = runs.iter().map(|r| r.state_at(0)).collect();
    match residuals(sys, runs, &x0, &ones, false) {
        Ok(r) => {
            let n: usize = r.iter().map(Vec::len).sum();
            (r.iter().flatten().map(|v| v * v).sum::<f64>() / n.max(1) as f64).sqrt()
        }
        Err(_) => f64::NAN,
    }
}

fn estimates(
    sys: &System,
    names: &[String],
    cal: Option<&Calibration>,
) -> BTreeMap<String, ParamEstimate> {
    names
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let v = sys.get(&Unknown::Physics(p.clone()));
            let se = cal.and_then(|c| c.se.get(i).copied().flatten());
            let df = cal.map_or(0.0, |c| c.n as f64 - c.se.len() as f64);
            let t = hxai_eval::t_upper_quantile(0.025, df.max(1.0));
            (p.clone(), ParamEstimate::with_interval(v, v, se, t))
        })
        .collect()
}

/// Fits on `runs` (all training data), the correction's form as `cfg` says (`validate.rs`
/// checks an `auto` choice on held-out trajectories). `test_after`: the runs were cut
/// there (the model file says so).
pub(crate) fn fit_core(
    runs: &[Run],
    cfg: &DynamicConfig,
    test_after: Option<f64>,
    progress: &mut dyn FnMut(&str),
) -> Result<DynamicModel, HybridError> {
    let spec = physics_of(cfg)?;
    let ns = cfg.states.len();
    let scale = scales(runs, ns);
    let mut sys = System::physics(spec, cfg.correction);
    let physics_start = sys.clone();
    let x0: Vec<Vec<f64>> = runs.iter().map(|r| r.state_at(0)).collect();
    let estimate_initial = cfg.initial == Initial::Estimate;
    let physics_unknowns = sys.unknowns(&cfg.calibrate, false);
    progress(&format!(
        "calibrating {} through the ODE on {} run(s)",
        if cfg.calibrate.is_empty() {
            "nothing".to_string()
        } else {
            cfg.calibrate.join(", ")
        },
        runs.len()
    ));
    let cal = if physics_unknowns.is_empty() && !estimate_initial {
        None
    } else {
        Some(calibrate(
            &mut sys,
            Problem {
                runs,
                scale: &scale,
                unknowns: &physics_unknowns,
                x0: x0.clone(),
                estimate_initial,
                max_iter: cfg.max_iter,
            },
        )?)
    };
    let physics_calibrated = estimates(&sys, &cfg.calibrate, cal.as_ref());
    let calibrated = sys.clone();
    let mut warnings = Vec::new();
    // a correction that cannot be searched (too few samples, a constant rate) leaves the
    // calibrated physics, which is still saved: every fit saves
    let found = match search(&sys, runs, cfg, progress) {
        Ok(f) => f,
        Err(e) => {
            warnings.push(format!(
                "no correction could be searched ({e}); the model is the calibrated physics alone"
            ));
            (0..ns).map(|_| Found::none()).collect()
        }
    };
    for (j, f) in found.iter().enumerate() {
        sys.set_correction(j, f.model.clone(), f.ranges.clone())?;
    }
    let joint_unknowns = sys.unknowns(&cfg.calibrate, true);
    let mut joint: Option<Calibration> = None;
    if sys.corrections.iter().any(Option::is_some) {
        progress(&format!(
            "refitting {} constant(s) of the physics and the correction through the ODE",
            joint_unknowns.len()
        ));
        let start = cal.as_ref().map_or(x0.clone(), |c| c.x0.clone());
        let before = residuals(&sys, runs, &start, &scale, estimate_initial)
            .map(|r| r.iter().flatten().map(|v| v * v).sum::<f64>())
            .unwrap_or(f64::INFINITY);
        let physics_sse = cal.as_ref().map_or_else(
            || {
                residuals(&calibrated, runs, &x0, &scale, false)
                    .map(|r| r.iter().flatten().map(|v| v * v).sum::<f64>())
                    .unwrap_or(f64::INFINITY)
            },
            |c| c.sse,
        );
        let refit = if before.is_finite() {
            calibrate(
                &mut sys,
                Problem {
                    runs,
                    scale: &scale,
                    unknowns: &joint_unknowns,
                    x0: start,
                    estimate_initial,
                    max_iter: cfg.max_iter,
                },
            )
            .ok()
        } else {
            None
        };
        match refit {
            Some(c) if c.sse < physics_sse => joint = Some(c),
            other => {
                warnings.push(format!(
                    "the correction did not make the training runs' trajectories better than \
                     the calibrated physics (sum of squares {} against {}): the model is the \
                     calibrated physics alone",
                    other.map_or("not finite".into(), |c| format!("{:.6}", c.sse)),
                    format_sse(physics_sse)
                ));
                sys = calibrated.clone();
            }
        }
    }
    let states: Vec<StateCorrection> = found
        .into_iter()
        .enumerate()
        .map(|(j, f)| {
            let model = sys.corrections[j].as_ref().map(|c| c.model.clone());
            StateCorrection {
                state: cfg.states[j].clone(),
                form: if model.is_some() { f.form } else { Form::None },
                equation: model
                    .as_ref()
                    .map_or_else(|| "0".to_string(), hxai_symreg::Model::equation),
                searched_equation: f.equation,
                features: model
                    .as_ref()
                    .map(|m| columns_read(m, &sys.spec).0)
                    .unwrap_or_default(),
                groupings: model
                    .as_ref()
                    .map(|m| columns_read(m, &sys.spec).1)
                    .unwrap_or_default(),
                ranges: if model.is_some() {
                    f.ranges
                } else {
                    Vec::new()
                },
                model,
                choice: f.choice,
                samples: [f.rows.0, f.rows.1],
            }
        })
        .collect();
    let hybrid_unknowns = sys.unknowns(&cfg.calibrate, true);
    let conformal = if cfg.conformal_folds >= 2 && runs.len() >= 3 {
        progress("conformal calibration over runs");
        Some(conformal_scores(&sys, runs, &scale, &hybrid_unknowns, cfg))
    } else {
        if cfg.conformal_folds >= 2 {
            warnings.push(format!(
                "{} training run(s): conformal bands need at least 3; `predict --interval` \
                 will refuse",
                runs.len()
            ));
        }
        None
    };
    let mut scores = BTreeMap::new();
    scores.insert("physics".to_string(), free_run_rmse(&physics_start, runs));
    scores.insert(
        "physics_calibrated".to_string(),
        free_run_rmse(&calibrated, runs),
    );
    scores.insert("hybrid".to_string(), free_run_rmse(&sys, runs));
    Ok(DynamicModel {
        schema_version: SCHEMA_VERSION,
        time: cfg.time.clone(),
        run: cfg.run.clone(),
        states: cfg.states.clone(),
        inputs: cfg.inputs.clone(),
        ode: calibrated.spec.text(),
        calibrated: cfg.calibrate.clone(),
        starting: physics_start.spec.parameters.clone(),
        physics_calibrated,
        parameters: sys.spec.parameters.clone(),
        joint_iterations: joint.as_ref().map(|c| c.iterations),
        correction_kind: cfg.correction,
        corrections: states,
        hybrid_equation: String::new(),
        initial: cfg.initial,
        training: Training {
            runs: runs.iter().map(|r| r.id).collect(),
            samples: runs.iter().map(|r| r.times.len()).sum(),
            test_after,
        },
        train_rmse: scores,
        conformal,
        warnings,
        settings: cfg.clone(),
    }
    .with_equation())
}

/// The columns `m`'s program reads (a model names every column it was offered), a grouping
/// of the physics counted as the columns it reads; and the groupings it reads.
fn columns_read(m: &hxai_symreg::Model, spec: &OdeSpec) -> (Vec<String>, Vec<String>) {
    let (mut cols, mut groups) = (Vec::new(), Vec::new());
    let add = |c: &String, cols: &mut Vec<String>| {
        if !cols.contains(c) {
            cols.push(c.clone());
        }
    };
    for &j in &m.program.vars() {
        let Some(name) = m.feature_names.get(j as usize) else {
            continue;
        };
        match spec.groupings.iter().find(|g| g.name == *name) {
            Some(g) => {
                groups.push(name.clone());
                for &v in &g.compiled.program.vars() {
                    if let Some(c) = g.compiled.inputs.get(v as usize) {
                        add(c, &mut cols);
                    }
                }
            }
            None => add(name, &mut cols),
        }
    }
    (cols, groups)
}

fn format_sse(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.6}")
    } else {
        "not finite".into()
    }
}

/// Conformal scores over runs: the runs dealt into folds (seeded), each fold's runs
/// predicted by the system refitted (its structure kept, its constants warm-started) on
/// the others; a run's score for state `j` is its largest absolute free-run error.
fn conformal_scores(
    sys: &System,
    runs: &[Run],
    scale: &[f64],
    unknowns: &[Unknown],
    cfg: &DynamicConfig,
) -> RunConformal {
    use rand::SeedableRng;
    use rand::seq::SliceRandom;
    let k = cfg.conformal_folds.min(runs.len());
    let mut order: Vec<usize> = (0..runs.len()).collect();
    order.shuffle(&mut rand_chacha::ChaCha8Rng::seed_from_u64(cfg.seed));
    let ns = sys.n_states();
    let mut scores = vec![vec![f64::INFINITY; runs.len()]; ns];
    for f in 0..k {
        let held: Vec<usize> = order.iter().copied().skip(f).step_by(k).collect();
        let train: Vec<Run> = (0..runs.len())
            .filter(|i| !held.contains(i))
            .map(|i| runs[i].clone())
            .collect();
        let mut s = sys.clone();
        if !unknowns.is_empty() {
            let x0 = train.iter().map(|r| r.state_at(0)).collect();
            let ok = calibrate(
                &mut s,
                Problem {
                    runs: &train,
                    scale,
                    unknowns,
                    x0,
                    estimate_initial: false,
                    max_iter: cfg.max_iter.min(15),
                },
            );
            if ok.is_err() {
                continue;
            }
        }
        for &i in &held {
            let run = &runs[i];
            if let Ok(sim) = s.simulate(run, &run.state_at(0), &CALIBRATION_ODE) {
                for (j, row) in scores.iter_mut().enumerate() {
                    row[i] = sim
                        .iter()
                        .enumerate()
                        .skip(1)
                        .map(|(q, x)| (x[j] - run.states[j][q]).abs())
                        .fold(0.0, f64::max);
                }
            }
        }
    }
    RunConformal { folds: k, scores }
}
