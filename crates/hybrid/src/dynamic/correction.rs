//! The correction's search: the measured states' derivatives, smoothed by a local quadratic
//! (Savitzky-Golay in the sample times), minus the calibrated physics' derivative, searched
//! by the table workflow (its form `auto|none|factors|free`, its safety rules, its
//! cross-validation grouped by run). The constants are refitted through the ODE afterwards
//! (`fit.rs`).

use super::DynamicConfig;
use super::system::{Run, System};
use crate::HybridError;
use crate::correction::FormChoice;
use crate::tables::{Form, TableConfig, TableProgress};
use hxai_symreg::{Model, Table};

/// Local quadratic least squares over `window` samples around each sample (shifted inside
/// the series at its ends), in the times `t`: each sample's smoothed value and slope. For
/// evenly spaced samples this is the Savitzky-Golay filter of order 2 and its derivative.
pub(crate) fn local_quadratic(t: &[f64], x: &[f64], window: usize) -> Vec<(f64, f64)> {
    let n = t.len();
    let w = window.clamp(3, n.max(3)).min(n);
    let half = w / 2;
    (0..n)
        .map(|i| {
            let lo = i.saturating_sub(half).min(n - w);
            let span = (t[lo + w - 1] - t[lo]).max(f64::MIN_POSITIVE);
            // basis 1, s, s^2 with s = (t - t_i) / span: well conditioned at any time scale
            let mut a = [0.0; 9];
            let mut b = [0.0; 3];
            for k in lo..lo + w {
                let s = (t[k] - t[i]) / span;
                let phi = [1.0, s, s * s];
                for r in 0..3 {
                    b[r] += phi[r] * x[k];
                    for c in 0..=r {
                        a[r * 3 + c] += phi[r] * phi[c];
                    }
                }
            }
            if w < 3 || !hxai_symreg::fit::cholesky_solve(&mut a, &mut b, 3) {
                return (x[i], f64::NAN);
            }
            (b[0], b[1] / span)
        })
        .collect()
}

/// What the search of one state's correction found.
pub(crate) struct Found {
    pub(crate) model: Option<Model>,
    /// The training range of each of the model's features.
    pub(crate) ranges: Vec<[f64; 2]>,
    pub(crate) form: Form,
    pub(crate) equation: String,
    pub(crate) choice: Option<FormChoice>,
    /// Samples the derivative was taken at, and how many of all.
    pub(crate) rows: (usize, usize),
}

impl Found {
    /// No correction (the search could not run).
    pub(crate) fn none() -> Self {
        Self {
            model: None,
            ranges: Vec::new(),
            form: Form::None,
            equation: "0".into(),
            choice: None,
            rows: (0, 0),
        }
    }
}

/// Run column of the derivative table.
const RUN: &str = "run";

/// Share of the physics derivative's spread that an input's change inside a window may move
/// it by before the window's derivative counts as smeared (an input step).
pub(crate) const JUMP_SHARE: f64 = 0.1;

/// A sample of the derivative table: run, variables, smoothed rate, physics' rate, and how
/// far the physics' rate moves over the window's inputs.
type Sample = (f64, Vec<f64>, f64, f64, f64);

/// Searches each state's correction on the training `runs`, the physics of `sys` (already
/// calibrated) giving the derivative the data are compared with.
///
/// # Errors
/// The table workflow's, or too few samples.
pub(crate) fn search(
    sys: &System,
    runs: &[Run],
    cfg: &DynamicConfig,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<Found>, HybridError> {
    let ns = sys.n_states();
    let nv = sys.spec.variables.len();
    let ti = sys.spec.time_index();
    let all: Vec<usize> = (0..nv).collect();
    let mut out = Vec::with_capacity(ns);
    for j in 0..ns {
        let state = &cfg.states[j];
        let target = format!("{state}_rate");
        let physics = format!("{state}_rate_physics");
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); nv + 3];
        let mut stack = Vec::new();
        let mut phys = vec![0.0; ns];
        let mut samples: Vec<Sample> = Vec::new();
        for run in runs {
            let n = run.times.len();
            let w = cfg.smooth.min(n);
            let smooth: Vec<Vec<(f64, f64)>> = run
                .states
                .iter()
                .map(|s| local_quadratic(&run.times, s, w))
                .collect();
            for k in 0..n {
                let lo = k.saturating_sub(w / 2).min(n - w);
                let mut vars = vec![0.0; nv];
                for (q, s) in smooth.iter().enumerate() {
                    vars[q] = s[k].0;
                }
                vars[ti] = run.times[k];
                // the physics' rate at this state under each input the window holds: an
                // input step that matters to the physics moves it
                let (mut lo_rate, mut hi_rate) = (f64::INFINITY, f64::NEG_INFINITY);
                for q in (lo..lo + w - 1).rev() {
                    for (i, u) in run.inputs.iter().enumerate() {
                        vars[ns + i] = u[q];
                    }
                    sys.fill_groupings(&mut vars, &all, &mut stack);
                    sys.physics_at(&vars, &mut phys, &mut stack);
                    lo_rate = lo_rate.min(phys[j]);
                    hi_rate = hi_rate.max(phys[j]);
                }
                // the input in force over the sample's own interval (the last sample's over
                // the one before it)
                for (i, u) in run.inputs.iter().enumerate() {
                    vars[ns + i] = u[k.min(n - 2)];
                }
                sys.fill_groupings(&mut vars, &all, &mut stack);
                sys.physics_at(&vars, &mut phys, &mut stack);
                let rate = smooth[j][k].1;
                if !rate.is_finite() || !phys[j].is_finite() {
                    continue;
                }
                samples.push((run.id, vars, rate, phys[j], hi_rate - lo_rate));
            }
        }
        // samples whose window spans an input step that moves the physics' rate by more than
        // JUMP_SHARE of its spread have a smeared derivative; they are left out unless that
        // leaves fewer than 30 %
        let total = samples.len();
        let rates: Vec<f64> = samples.iter().map(|s| s.3).collect();
        let mean = rates.iter().sum::<f64>() / total.max(1) as f64;
        let spread =
            (rates.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / total.max(1) as f64).sqrt();
        let clean = |s: &Sample| s.4.is_finite() && s.4 <= JUMP_SHARE * spread;
        let mut kept = samples.iter().filter(|s| clean(s)).count();
        let rows: Vec<Sample> = if kept * 10 < total * 3 {
            kept = total;
            samples
        } else {
            samples.into_iter().filter(|s| clean(s)).collect()
        };
        if rows.len() < 10 {
            return Err(HybridError::NoData(format!(
                "{} sample(s) to learn the correction of {state} from; it needs at least 10",
                rows.len()
            )));
        }
        for (id, vars, rate, p, _) in &rows {
            for (q, v) in vars.iter().enumerate() {
                cols[q].push(*v);
            }
            cols[nv].push(*id);
            cols[nv + 1].push(*rate);
            cols[nv + 2].push(*p);
        }
        let mut names: Vec<String> = sys.spec.variables.clone();
        names[ti] = format!("{}_time", cfg.time);
        names.extend([RUN.to_string(), target.clone(), physics.clone()]);
        let table = Table::new(names, cols)?;
        let mut features: Vec<String> = cfg.states.clone();
        features.extend(cfg.inputs.iter().cloned());
        features.extend(sys.spec.groupings.iter().map(|g| g.name.clone()));
        let mut tc = TableConfig::new(&target, &format!("`{physics}`"));
        tc.features = Some(features);
        tc.group = Some(RUN.into());
        tc.form = cfg.form;
        tc.correction = cfg.correction;
        tc.seed = cfg.seed;
        tc.search.seed = cfg.seed;
        tc.conformal_folds = 0;
        tc.periodic = cfg.periodic.clone();
        let split = hxai_eval::Split {
            train: (0..table.n_rows()).collect(),
            test: Vec::new(),
        };
        progress(&format!(
            "searching the correction of {state}' on {kept} of {total} samples' smoothed derivatives"
        ));
        let mut report = |p: &TableProgress| {
            if p.step {
                progress(&format!("  {}", p.label));
            }
        };
        let m = crate::tables::fit_split(&table, &tc, &split, &mut report)?;
        let form = m.correction.form.unwrap_or(cfg.form);
        let model = if form == Form::None {
            None
        } else {
            m.correction.model.clone()
        };
        let ranges = model.as_ref().map_or_else(Vec::new, |m| {
            m.feature_names
                .iter()
                .map(|f| {
                    let c = table.column(f).unwrap_or(&[]);
                    let lo = c.iter().copied().fold(f64::INFINITY, f64::min);
                    let hi = c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    [lo, hi]
                })
                .collect()
        });
        out.push(Found {
            equation: m.correction.forms.equation.clone(),
            model,
            ranges,
            form,
            choice: m.correction.choice.clone(),
            rows: (kept, total),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::local_quadratic;

    /// A quadratic's value and slope are exact at every sample, ends and uneven times too.
    #[test]
    fn the_local_quadratic_is_exact_on_a_quadratic() {
        let t = [0.0, 1.0, 2.5, 3.0, 4.5, 6.0, 7.0, 9.0, 10.0];
        let x: Vec<f64> = t.iter().map(|v| 3.0 - 2.0 * v + 0.5 * v * v).collect();
        for (i, (v, d)) in local_quadratic(&t, &x, 5).into_iter().enumerate() {
            assert!((v - x[i]).abs() < 1e-9, "value at {i}");
            assert!((d - (-2.0 + t[i])).abs() < 1e-9, "slope at {i}: {d}");
        }
    }
}
