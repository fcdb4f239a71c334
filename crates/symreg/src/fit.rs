//! Constant fitting by Levenberg-Marquardt.
//!
//! Models have at most a few dozen parameters, so the damped normal equations are solved
//! with a hand-written Cholesky factorisation: for systems this small (≤ ~40 unknowns) a
//! general linear-algebra library costs more in set-up than the solve itself, and the
//! fixed operation order keeps results bit-identical everywhere.
use crate::eval::Evaluator;
use crate::program::{Node, Program};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Solves `A x = b` in place for symmetric positive definite `A` given by its lower
/// triangle (row-major, `m x m`). Returns false if `A` is not positive definite.
pub fn cholesky_solve(a: &mut [f64], b: &mut [f64], m: usize) -> bool {
    for j in 0..m {
        let mut d = a[j * m + j];
        for k in 0..j {
            d -= a[j * m + k] * a[j * m + k];
        }
        if d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j * m + j] = d;
        for i in j + 1..m {
            let mut s = a[i * m + j];
            for k in 0..j {
                s -= a[i * m + k] * a[j * m + k];
            }
            a[i * m + j] = s / d;
        }
    }
    for i in 0..m {
        let mut s = b[i];
        for k in 0..i {
            s -= a[i * m + k] * b[k];
        }
        b[i] = s / a[i * m + i];
    }
    for i in (0..m).rev() {
        let mut s = b[i];
        for k in i + 1..m {
            s -= a[k * m + i] * b[k];
        }
        b[i] = s / a[i * m + i];
    }
    true
}

/// Runs at most `max_iter` Levenberg-Marquardt iterations on the parameters whose index is
/// in `free`, starting from `params` (which is updated in place). Returns the final mean
/// squared error (`INFINITY` when the model is not finite on the data). Stops early when an
/// accepted step lowers the error by less than the fraction `tol`.
#[allow(clippy::too_many_arguments)]
pub fn levenberg_marquardt(
    prog: &Program,
    params: &mut [f64],
    free: &[usize],
    cols: &[&[f64]],
    y: &[f64],
    max_iter: usize,
    tol: f64,
    ev: &mut Evaluator,
) -> f64 {
    let m = free.len();
    let mut jtj = vec![0.0; m * m];
    let mut jtr = vec![0.0; m];
    let mut a = vec![0.0; m * m];
    let mut delta = vec![0.0; m];
    let mut trial = params.to_vec();
    let mut mse = ev.normal_equations(prog, params, free, cols, y, &mut jtj, &mut jtr);
    if !mse.is_finite() || m == 0 {
        // a non-finite Jacobian (sqrt or log at 0, say) ends the fit, but the start's own
        // loss may still be finite
        return ev.mse(prog, params, cols, y);
    }
    let mut lambda = 1e-3;
    for _ in 0..max_iter {
        let mut accepted = false;
        for _ in 0..8 {
            a.copy_from_slice(&jtj);
            for i in 0..m {
                let d = jtj[i * m + i];
                a[i * m + i] = d * (1.0 + lambda) + 1e-12 * (1.0 + d);
            }
            for i in 0..m {
                delta[i] = -jtr[i];
            }
            if !cholesky_solve(&mut a, &mut delta, m) {
                lambda *= 10.0;
                continue;
            }
            trial.copy_from_slice(params);
            for (i, &p) in free.iter().enumerate() {
                trial[p] += delta[i];
            }
            let new = ev.mse(prog, &trial, cols, y);
            if new < mse {
                params.copy_from_slice(&trial);
                lambda = (lambda * 0.2).max(1e-10);
                accepted = true;
                let improvement = (mse - new) / mse.max(1e-300);
                mse = new;
                if improvement < tol {
                    return mse;
                }
                break;
            }
            lambda *= 8.0;
        }
        if !accepted {
            break;
        }
        let next = ev.normal_equations(prog, params, free, cols, y, &mut jtj, &mut jtr);
        if !next.is_finite() {
            // the accepted step's loss stands; only its Jacobian is unusable
            return mse;
        }
        mse = next;
    }
    mse
}

/// Scale statistics of the input columns used to initialise affine inputs.
#[derive(Debug, Clone)]
pub struct InputScales {
    /// Root mean square of each column (1 where the column is all zero).
    pub rms: Vec<f64>,
}

impl InputScales {
    /// Computes the statistics.
    pub fn new(cols: &[&[f64]]) -> Self {
        let rms = cols
            .iter()
            .map(|c| {
                let s = (c.iter().map(|v| v * v).sum::<f64>() / c.len().max(1) as f64).sqrt();
                if s > 0.0 && s.is_finite() { s } else { 1.0 }
            })
            .collect();
        Self { rms }
    }
}

/// Initial parameters for a fresh program: inputs scaled to unit RMS (keeping their sign,
/// so `log` and `sqrt` of positive inputs stay defined), randomly perturbed when `rng` is
/// given; constants 1 (or random); output map by least squares.
pub fn initial_params(
    prog: &Program,
    scales: &InputScales,
    rng: Option<&mut ChaCha8Rng>,
    cols: &[&[f64]],
    y: &[f64],
    ev: &mut Evaluator,
) -> Vec<f64> {
    let mut p = vec![0.0; prog.n_params()];
    p[0] = 1.0;
    let offs = prog.param_offsets();
    let mut rng = rng;
    for (k, n) in prog.nodes.iter().enumerate() {
        match n {
            Node::Var(j) if prog.affine => {
                let w = 1.0 / scales.rms[*j as usize];
                let (f, b) = match rng.as_deref_mut() {
                    Some(r) => {
                        let f: f64 =
                            r.gen_range(0.5..2.0) * if r.gen_bool(0.2) { -1.0 } else { 1.0 };
                        let b = if r.gen_bool(0.5) {
                            r.gen_range(-1.0..1.0)
                        } else {
                            0.0
                        };
                        (f, b)
                    }
                    None => (1.0, 0.0),
                };
                p[offs[k]] = w * f;
                p[offs[k] + 1] = b;
            }
            Node::Const => {
                p[offs[k]] = match rng.as_deref_mut() {
                    Some(r) => r.gen_range(-2.0..2.0),
                    None => 1.0,
                };
            }
            _ => {}
        }
    }
    fit_output_map(prog, &mut p, cols, y, ev);
    p
}

/// Sets the output scale and offset to the least-squares fit of `y` on the root value.
pub fn fit_output_map(
    prog: &Program,
    p: &mut [f64],
    cols: &[&[f64]],
    y: &[f64],
    ev: &mut Evaluator,
) {
    let mut root = Vec::new();
    ev.root_values(prog, p, cols, y.len(), &mut root);
    let n = y.len() as f64;
    let mx = root.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let mut sxx = 0.0;
    let mut sxy = 0.0;
    for (x, yv) in root.iter().zip(y) {
        sxx += (x - mx) * (x - mx);
        sxy += (x - mx) * (yv - my);
    }
    if sxx > 0.0 && sxx.is_finite() && sxy.is_finite() {
        p[0] = sxy / sxx;
        p[1] = my - p[0] * mx;
    } else {
        p[0] = 1.0;
        p[1] = 0.0;
    }
}
