//! Calibration of tied parameters, and standard errors at the optimum.
//!
//! A physics parameter used twice in an equation (`C` in `C*v + C`) owns two constant
//! leaves in the compiled program; they must move as one unknown. Both the fit and the
//! normal equations of such unknowns are symreg's ([`Unknowns::Tied`] and
//! [`levenberg_marquardt`]), so the calibration and the symbolic-regression search share
//! one evaluator, one differentiator and one optimiser.
use hxai_symreg::Program;
use hxai_symreg::eval::{Evaluator, Inputs};
use hxai_symreg::fit::{LmSettings, Unknowns, cholesky_solve, levenberg_marquardt};

/// The calibration's Levenberg-Marquardt settings: at most `max_iter` steps, stop below a
/// relative gain of `tol`, 12 damping increases per iteration and a damping floor of
/// `1e-12` (where the search uses 8 and `1e-10`), and a diagonal floor relative to each
/// unknown's own curvature ([`LmSettings::scale_free_floor`]): physics constants come in
/// the units of the law, and an absolute floor left an Arrhenius energy at its starting
/// value. Set [`LmSettings::keep_positive`] where the model must stay above zero.
pub(crate) fn settings(max_iter: usize, tol: f64) -> LmSettings {
    LmSettings {
        retries: 12,
        lambda_floor: 1e-12,
        scale_free_floor: true,
        ..LmSettings::new(max_iter, tol)
    }
}

/// Fits the unknowns (each a group of tied parameter indices) by Levenberg-Marquardt with
/// `settings` (normally [`settings`]), updating `params` in place; returns the final mean
/// squared error (`INFINITY` when the model is not finite on the data at the start).
pub(crate) fn lm_tied(
    prog: &Program,
    params: &mut [f64],
    groups: &[Vec<usize>],
    cols: &[&[f64]],
    y: &[f64],
    settings: &LmSettings,
) -> f64 {
    let mut ev = Evaluator::new(prog);
    levenberg_marquardt(
        prog,
        params,
        Unknowns::Tied(groups),
        cols,
        y,
        settings,
        &mut ev,
    )
}

/// Standard errors of the unknowns at the current parameters: the square roots of the
/// diagonal of `s^2 (J^T J)^-1` with `s^2 = SSE / (n - m)`. `None` for an unknown whose
/// error is not defined (no residual degrees of freedom, a non-finite Jacobian, or one the
/// data do not determine, [`hxai_symreg::determined`]). Where `J^T J` is singular, the
/// determined unknowns keep their errors from the rows and columns of `J^T J` that are
/// theirs, the undetermined ones held fixed (issue 63: one per-class level without
/// training rows dropped every parameter's error).
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
    let mut jtj = vec![0.0; m * m];
    let mut jtr = vec![0.0; m];
    let inp = Inputs { prog, params, cols };
    let mse = Unknowns::Tied(groups).normal_equations(&mut ev, inp, y, &mut jtj, &mut jtr);
    if !mse.is_finite() || n <= m {
        return vec![None; m];
    }
    let s2 = mse * n as f64 / (n - m) as f64;
    let ok = hxai_symreg::determined(&jtj, m);
    let keep: Vec<usize> = (0..m).filter(|&i| ok[i]).collect();
    let k = keep.len();
    let sub: Vec<f64> = (0..k * k)
        .map(|ij| jtj[keep[ij / k] * m + keep[ij % k]])
        .collect();
    let mut out = vec![None; m];
    for (i, &u) in keep.iter().enumerate() {
        let mut a = sub.clone();
        let mut e = vec![0.0; k];
        e[i] = 1.0;
        if !cholesky_solve(&mut a, &mut e, k) {
            continue;
        }
        let v = s2 * e[i];
        out[u] = (v.is_finite() && v >= 0.0).then(|| v.sqrt());
    }
    out
}
