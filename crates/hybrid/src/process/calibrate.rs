//! Levenberg-Marquardt over *tied* parameters, and standard errors at the optimum.
//!
//! A physics parameter used twice in an equation (`C` in `C*v + C`) owns two constant
//! leaves in the compiled program; they must move as one unknown. The Jacobian column of
//! the unknown is the sum of its leaves' columns, so the normal equations of the unknowns
//! are sums of blocks of the leaves' normal equations, which symreg's evaluator computes
//! in one adjoint sweep. The damping and acceptance rule are those of
//! `hxai_symreg::fit::levenberg_marquardt`.
use hxai_symreg::Program;
use hxai_symreg::eval::Evaluator;
use hxai_symreg::fit::cholesky_solve;

/// Normal equations of the unknowns: `(J^T J, J^T r, mse)` with `J^T J` full (m x m).
fn tied_normal_equations(
    ev: &mut Evaluator,
    prog: &Program,
    params: &[f64],
    groups: &[Vec<usize>],
    cols: &[&[f64]],
    y: &[f64],
) -> (Vec<f64>, Vec<f64>, f64) {
    let flat: Vec<usize> = groups.iter().flatten().copied().collect();
    let owner: Vec<usize> = groups
        .iter()
        .enumerate()
        .flat_map(|(g, v)| std::iter::repeat_n(g, v.len()))
        .collect();
    let mf = flat.len();
    let mut jtj = vec![0.0; mf * mf];
    let mut jtr = vec![0.0; mf];
    let mse = ev.normal_equations(prog, params, &flat, cols, y, &mut jtj, &mut jtr);
    let m = groups.len();
    let mut g = vec![0.0; m * m];
    let mut r = vec![0.0; m];
    for a in 0..mf {
        r[owner[a]] += jtr[a];
        for b in 0..mf {
            let v = if b <= a {
                jtj[a * mf + b]
            } else {
                jtj[b * mf + a]
            };
            g[owner[a] * m + owner[b]] += v;
        }
    }
    (g, r, mse)
}

fn apply(params: &mut [f64], groups: &[Vec<usize>], delta: &[f64]) {
    for (g, d) in groups.iter().zip(delta) {
        for &i in g {
            params[i] += d;
        }
    }
}

/// Fits the unknowns (each a group of tied parameter indices) by Levenberg-Marquardt,
/// updating `params` in place; returns the final mean squared error (`INFINITY` when the
/// model is not finite on the data at the start).
pub(crate) fn lm_tied(
    prog: &Program,
    params: &mut [f64],
    groups: &[Vec<usize>],
    cols: &[&[f64]],
    y: &[f64],
    max_iter: usize,
    tol: f64,
) -> f64 {
    let mut ev = Evaluator::new(prog);
    let m = groups.len();
    let start = ev.mse(prog, params, cols, y);
    if m == 0 || !start.is_finite() {
        return start;
    }
    let (mut jtj, mut jtr, mut mse) = tied_normal_equations(&mut ev, prog, params, groups, cols, y);
    if !mse.is_finite() {
        return start;
    }
    let mut a = vec![0.0; m * m];
    let mut delta = vec![0.0; m];
    let mut trial = params.to_vec();
    let mut lambda = 1e-3;
    for _ in 0..max_iter {
        let mut accepted = false;
        for _ in 0..12 {
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
            apply(&mut trial, groups, &delta);
            let new = ev.mse(prog, &trial, cols, y);
            if new < mse {
                params.copy_from_slice(&trial);
                lambda = (lambda * 0.2).max(1e-12);
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
        let (j, r, next) = tied_normal_equations(&mut ev, prog, params, groups, cols, y);
        if !next.is_finite() {
            return mse;
        }
        jtj = j;
        jtr = r;
        mse = next;
    }
    mse
}

/// Standard errors of the unknowns at the current parameters: the square roots of the
/// diagonal of `s^2 (J^T J)^-1` with `s^2 = SSE / (n - m)`. `None` for an unknown whose
/// error is not defined (singular `J^T J`, no residual degrees of freedom, a non-finite
/// Jacobian).
pub(crate) fn standard_errors(
    prog: &Program,
    params: &[f64],
    groups: &[Vec<usize>],
    cols: &[&[f64]],
    y: &[f64],
) -> Vec<Option<f64>> {
    let m = groups.len();
    let n = y.len();
    if m == 0 {
        return Vec::new();
    }
    let mut ev = Evaluator::new(prog);
    let (jtj, _, mse) = tied_normal_equations(&mut ev, prog, params, groups, cols, y);
    if !mse.is_finite() || n <= m {
        return vec![None; m];
    }
    let s2 = mse * n as f64 / (n - m) as f64;
    (0..m)
        .map(|i| {
            let mut a = jtj.clone();
            let mut e = vec![0.0; m];
            e[i] = 1.0;
            if !cholesky_solve(&mut a, &mut e, m) {
                return None;
            }
            let v = s2 * e[i];
            (v.is_finite() && v >= 0.0).then(|| v.sqrt())
        })
        .collect()
}
