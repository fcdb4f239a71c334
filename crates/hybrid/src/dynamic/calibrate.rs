//! Calibration through the ODE: Levenberg-Marquardt on the simulated trajectories (single
//! shooting), the Jacobian by forward differences of whole simulations, each run from its
//! first reading or from an estimated initial state.
//!
//! The residual of run `r`, sample `k`, state `j` is `(x_sim - x_measured) / scale_j`
//! (`scale_j` the state's spread over the training runs, so that states of different units
//! weigh alike); the first sample is left out when the run starts from it. Forward
//! differences need a tight integration ([`CALIBRATION_ODE`]: the integrator's error must
//! be far below the difference step's effect).

use super::system::{Run, System, Unknown};
use crate::HybridError;
use hxai_sim::ode::{OdeError, OdeSettings};

/// Integration settings of the calibration: tight, so that the forward differences (a
/// relative step of [`FD_STEP`]) see the parameters and not the step-size controller.
pub(crate) const CALIBRATION_ODE: OdeSettings = OdeSettings {
    rtol: 1e-10,
    atol: 1e-10,
    max_steps: 200_000,
};

/// Relative step of the forward differences (of `max(|p|, 1e-3)`).
pub(crate) const FD_STEP: f64 = 1e-5;

/// What the calibration moves and what it starts from.
pub(crate) struct Problem<'a> {
    pub(crate) runs: &'a [Run],
    /// Each state's scale in the residual.
    pub(crate) scale: &'a [f64],
    pub(crate) unknowns: &'a [Unknown],
    /// Each run's initial state; moved too when `estimate_initial`.
    pub(crate) x0: Vec<Vec<f64>>,
    pub(crate) estimate_initial: bool,
    pub(crate) max_iter: usize,
}

/// The calibration's result.
pub(crate) struct Calibration {
    /// Sum of squared scaled residuals at the end.
    pub(crate) sse: f64,
    /// Residuals counted.
    pub(crate) n: usize,
    /// Standard error of each of `unknowns` (`None` where undefined).
    pub(crate) se: Vec<Option<f64>>,
    /// The initial states at the end.
    pub(crate) x0: Vec<Vec<f64>>,
    pub(crate) iterations: usize,
}

/// The scaled residuals of one run simulated from `x0`.
fn run_residuals(
    sys: &System,
    run: &Run,
    x0: &[f64],
    scale: &[f64],
    with_first: bool,
) -> Result<Vec<f64>, OdeError> {
    let sim = sys.simulate(run, x0, &CALIBRATION_ODE)?;
    let mut r = Vec::with_capacity(sim.len() * scale.len());
    for (k, x) in sim.iter().enumerate().skip(usize::from(!with_first)) {
        for (j, s) in scale.iter().enumerate() {
            r.push((x[j] - run.states[j][k]) / s);
        }
    }
    Ok(r)
}

/// Every run's residuals, concatenated.
pub(crate) fn residuals(
    sys: &System,
    runs: &[Run],
    x0: &[Vec<f64>],
    scale: &[f64],
    with_first: bool,
) -> Result<Vec<Vec<f64>>, OdeError> {
    runs.iter()
        .zip(x0)
        .map(|(run, x)| run_residuals(sys, run, x, scale, with_first))
        .collect()
}

fn sse_of(r: &[Vec<f64>]) -> f64 {
    r.iter().flatten().map(|v| v * v).sum()
}

fn step_of(v: f64) -> f64 {
    FD_STEP * v.abs().max(1e-3)
}

/// Levenberg-Marquardt on the trajectories; moves `sys`'s unknowns in place.
///
/// # Errors
/// [`HybridError::InvalidConfig`] when the system cannot be integrated at the starting
/// values (the message says why and asks for better `--init` values).
pub(crate) fn calibrate(sys: &mut System, p: Problem) -> Result<Calibration, HybridError> {
    let Problem {
        runs,
        scale,
        unknowns,
        mut x0,
        estimate_initial,
        max_iter,
    } = p;
    let ns = scale.len();
    let with_first = estimate_initial;
    let mut r = residuals(sys, runs, &x0, scale, with_first).map_err(|e| {
        HybridError::InvalidConfig(format!(
            "the ODE cannot be integrated from the starting values ({}): {e}; give starting \
             values nearer the process with --init P=V",
            unknowns
                .iter()
                .map(|u| format!(
                    "{} = {}",
                    u.label(
                        &sys.spec
                            .equations
                            .iter()
                            .map(|e| e.state.clone())
                            .collect::<Vec<_>>()
                    ),
                    sys.get(u)
                ))
                .collect::<Vec<_>>()
                .join(", ")
        ))
    })?;
    let mut sse = sse_of(&r);
    let n: usize = r.iter().map(Vec::len).sum();
    let mg = unknowns.len();
    let m = mg + if estimate_initial { runs.len() * ns } else { 0 };
    let mut lambda = 1e-3;
    let mut iterations = 0;
    let mut jac: Vec<Vec<f64>> = Vec::new();
    let mut theta: Vec<f64> = unknowns.iter().map(|u| sys.get(u)).collect();
    for _ in 0..max_iter {
        iterations += 1;
        // Jacobian columns: the global unknowns move every run, an initial state its own
        jac = vec![vec![0.0; n]; m];
        for (i, u) in unknowns.iter().enumerate() {
            let h = step_of(theta[i]);
            sys.set(u, theta[i] + h);
            let rp = residuals(sys, runs, &x0, scale, with_first);
            sys.set(u, theta[i]);
            match rp {
                Ok(rp) => {
                    for (slot, (a, b)) in jac[i]
                        .iter_mut()
                        .zip(rp.iter().flatten().zip(r.iter().flatten()))
                    {
                        *slot = (a - b) / h;
                    }
                }
                Err(_) => jac[i].fill(0.0),
            }
        }
        if estimate_initial {
            let mut offset = 0;
            for (ri, run) in runs.iter().enumerate() {
                let len = r[ri].len();
                for j in 0..ns {
                    let col = mg + ri * ns + j;
                    let h = step_of(x0[ri][j]);
                    let mut x = x0[ri].clone();
                    x[j] += h;
                    if let Ok(rp) = run_residuals(sys, run, &x, scale, with_first) {
                        for (q, (a, b)) in rp.iter().zip(&r[ri]).enumerate() {
                            jac[col][offset + q] = (a - b) / h;
                        }
                    }
                }
                offset += len;
            }
        }
        let flat: Vec<f64> = r.iter().flatten().copied().collect();
        let (jtj, g) = normal(&jac, &flat);
        let mut improved = false;
        for _ in 0..12 {
            let mut a = jtj.clone();
            for d in 0..m {
                let diag = jtj[d * m + d];
                a[d * m + d] = diag + lambda * diag.max(1e-12 * (1.0 + diag));
            }
            let mut delta: Vec<f64> = g.iter().map(|v| -v).collect();
            if !hxai_symreg::fit::cholesky_solve(&mut a, &mut delta, m) {
                lambda *= 10.0;
                continue;
            }
            let trial: Vec<f64> = theta.iter().zip(&delta).map(|(t, d)| t + d).collect();
            for (u, v) in unknowns.iter().zip(&trial) {
                sys.set(u, *v);
            }
            let mut x_trial = x0.clone();
            if estimate_initial {
                for (ri, x) in x_trial.iter_mut().enumerate() {
                    for (j, v) in x.iter_mut().enumerate() {
                        *v += delta[mg + ri * ns + j];
                    }
                }
            }
            match residuals(sys, runs, &x_trial, scale, with_first) {
                Ok(rt) if sse_of(&rt) < sse => {
                    let new = sse_of(&rt);
                    let gain = (sse - new) / sse.max(f64::MIN_POSITIVE);
                    theta = trial;
                    x0 = x_trial;
                    r = rt;
                    sse = new;
                    lambda = (lambda / 3.0).max(1e-12);
                    improved = gain > 1e-10;
                    break;
                }
                _ => {
                    for (u, v) in unknowns.iter().zip(&theta) {
                        sys.set(u, *v);
                    }
                    lambda *= 4.0;
                }
            }
        }
        if !improved {
            break;
        }
    }
    let se = standard_errors(&jac, sse, n, mg);
    Ok(Calibration {
        sse,
        n,
        se,
        x0,
        iterations,
    })
}

/// `J^T J` (row-major `m x m`) and `J^T r` of column-stored `jac`.
fn normal(jac: &[Vec<f64>], r: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let m = jac.len();
    let mut a = vec![0.0; m * m];
    let mut g = vec![0.0; m];
    for i in 0..m {
        g[i] = jac[i].iter().zip(r).map(|(x, y)| x * y).sum();
        for k in 0..=i {
            let v: f64 = jac[i].iter().zip(&jac[k]).map(|(x, y)| x * y).sum();
            a[i * m + k] = v;
            a[k * m + i] = v;
        }
    }
    (a, g)
}

/// Standard errors of the first `mg` unknowns: `sqrt(diag(s^2 (J^T J)^-1))` with
/// `s^2 = SSE / (n - m)` (the residuals are scaled, so the errors are in the unknowns' own
/// units); `None` without residual degrees of freedom or where `J^T J` is singular.
fn standard_errors(jac: &[Vec<f64>], sse: f64, n: usize, mg: usize) -> Vec<Option<f64>> {
    let m = jac.len();
    if jac.is_empty() || n <= m {
        return vec![None; mg];
    }
    let s2 = sse / (n - m) as f64;
    let (jtj, _) = normal(jac, &vec![0.0; n]);
    (0..mg)
        .map(|i| {
            let mut a = jtj.clone();
            let mut e = vec![0.0; m];
            e[i] = 1.0;
            if !hxai_symreg::fit::cholesky_solve(&mut a, &mut e, m) {
                return None;
            }
            let v = s2 * e[i];
            (v.is_finite() && v >= 0.0).then(|| v.sqrt())
        })
        .collect()
}
