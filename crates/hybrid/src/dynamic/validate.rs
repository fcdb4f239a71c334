//! The check of an `auto` correction on held-out trajectories. The form `auto` chooses on
//! the derivatives, whose cross-validation sees neighbouring samples of one run and whose
//! errors are not the free run's; a correction that wins there may still wander off when
//! integrated beyond the data (a pole, a growth the physics does not have). So the whole
//! fit is repeated without part of the data: a seeded quarter of the runs (at least 4
//! runs) or the last quarter of every run's time (fewer runs). The correction is kept only
//! if its hybrid's free run on that part beats the calibrated physics refitted on the
//! same data; a `free` correction that fails is replaced by `factors` if those pass, and
//! otherwise the model is the calibrated physics, with a warning.

use super::fit::fit_core;
use super::model::DynamicModel;
use super::system::Run;
use super::{DynamicConfig, Initial};
use crate::HybridError;
use crate::tables::Form;
use hxai_sim::ode::OdeError;

/// Runs from which the validation holds out whole runs rather than their ends.
pub(crate) const MIN_RUNS_TO_HOLD_OUT: usize = 4;

/// Share of runs, or of each run's time, held out by the check.
pub(crate) const HOLD_OUT_SHARE: f64 = 0.25;

/// Free-run RMSE of `model` (`hybrid` or its calibrated physics) on `runs`, on the samples
/// after `after` (every sample but the first without it); `None` where one cannot be
/// integrated.
fn free_run(
    model: &DynamicModel,
    hybrid: bool,
    runs: &[Run],
    after: &[Option<f64>],
) -> Option<f64> {
    let values = if hybrid {
        model.parameters.clone()
    } else {
        model.calibrated_values()
    };
    let sys = model.system(&values, hybrid).ok()?;
    let (mut sse, mut n) = (0.0, 0usize);
    for (run, cut) in runs.iter().zip(after) {
        let sim: Result<Vec<Vec<f64>>, OdeError> =
            sys.simulate(run, &run.state_at(0), &super::calibrate::CALIBRATION_ODE);
        for (k, x) in sim.ok()?.iter().enumerate().skip(1) {
            if cut.is_some_and(|t| run.times[k] <= t) {
                continue;
            }
            for (j, v) in x.iter().enumerate() {
                sse += (v - run.states[j][k]).powi(2);
                n += 1;
            }
        }
    }
    let r = (sse / n.max(1) as f64).sqrt();
    r.is_finite().then_some(r)
}

/// The training part and the held-out part of the check.
fn hold_out(runs: &[Run], seed: u64) -> (Vec<Run>, Vec<Run>, Vec<Option<f64>>) {
    if runs.len() >= MIN_RUNS_TO_HOLD_OUT {
        use rand::SeedableRng;
        use rand::seq::SliceRandom;
        let mut idx: Vec<usize> = (0..runs.len()).collect();
        idx.shuffle(&mut rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0x5eed));
        let k = ((runs.len() as f64 * HOLD_OUT_SHARE).round() as usize).max(1);
        let held: Vec<usize> = idx[..k].to_vec();
        let train = (0..runs.len())
            .filter(|i| !held.contains(i))
            .map(|i| runs[i].clone())
            .collect();
        let test: Vec<Run> = held.iter().map(|&i| runs[i].clone()).collect();
        let n = test.len();
        return (train, test, vec![None; n]);
    }
    let cuts: Vec<f64> = runs
        .iter()
        .map(|r| {
            let (a, b) = (r.times[0], r.times[r.times.len() - 1]);
            a + (1.0 - HOLD_OUT_SHARE) * (b - a)
        })
        .collect();
    let train = runs.iter().zip(&cuts).map(|(r, &c)| r.until(c)).collect();
    (train, runs.to_vec(), cuts.into_iter().map(Some).collect())
}

/// [`fit_core`], with an `auto` correction checked on held-out trajectories.
pub(crate) fn fit_runs(
    runs: &[Run],
    cfg: &DynamicConfig,
    test_after: Option<f64>,
    progress: &mut dyn FnMut(&str),
) -> Result<DynamicModel, HybridError> {
    let model = fit_core(runs, cfg, test_after, progress)?;
    if cfg.form != Form::Auto || model.corrections.iter().all(|c| c.model.is_none()) {
        return Ok(model);
    }
    let (train, test, after) = hold_out(runs, cfg.seed);
    if train.iter().any(|r| r.times.len() < 3) {
        return Ok(model);
    }
    let picked = model
        .corrections
        .iter()
        .map(|c| c.form)
        .find(|f| *f != Form::None)
        .unwrap_or(Form::Factors);
    let mut tries = vec![picked];
    if picked == Form::Free {
        tries.push(Form::Factors);
    }
    let mut quiet = |_: &str| {};
    let mut lines = Vec::new();
    for form in tries {
        progress(&format!(
            "checking the {} correction on held-out trajectories",
            form.name()
        ));
        let mut c = cfg.clone();
        c.form = form;
        c.conformal_folds = 0;
        c.initial = Initial::First;
        let Ok(part) = fit_core(&train, &c, None, &mut quiet) else {
            continue;
        };
        let h = free_run(&part, true, &test, &after);
        let p = free_run(&part, false, &test, &after);
        let show = |v: Option<f64>| v.map_or("not finite".into(), |v| format!("{v:.6}"));
        lines.push(format!(
            "{}: hybrid {} against physics {}",
            form.name(),
            show(h),
            show(p)
        ));
        if let (Some(h), Some(p)) = (h, p)
            && h < p
        {
            if form == picked {
                return Ok(model);
            }
            // the factor form passed where the free form did not: refit it on every run
            let mut c = cfg.clone();
            c.form = form;
            let mut m = fit_core(runs, &c, test_after, progress)?;
            m.warnings.push(format!(
                "the free correction did worse than the physics on held-out trajectories; the \
                 factor form did better and is kept ({})",
                lines.join("; ")
            ));
            return Ok(m);
        }
    }
    let mut c = cfg.clone();
    c.form = Form::None;
    let mut m = fit_core(runs, &c, test_after, progress)?;
    m.warnings.push(format!(
        "the correction did not beat the calibrated physics on held-out trajectories (free run \
         RMSE on {}: {}); the model is the calibrated physics alone",
        if after.iter().any(Option::is_some) {
            "the last quarter of each run".to_string()
        } else {
            format!("{} held-out run(s)", test.len())
        },
        if lines.is_empty() {
            "the refit failed".to_string()
        } else {
            lines.join("; ")
        }
    ));
    Ok(m)
}
