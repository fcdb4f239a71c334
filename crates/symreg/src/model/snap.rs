//! Constant snapping: fitted constants replaced by simple nearby values (whole and half
//! numbers, multiples of pi/2, thirds, quarters, the irrationals a physicist writes, or 1-3
//! significant digits) when the criterion allows.
use crate::eval::Evaluator;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::program::{Node, Program};

/// True for the values snapping fixes as exact: whole and half numbers (0 and +-1 among them).
pub fn is_exact(v: f64) -> bool {
    v.is_finite() && (2.0 * v).fract() == 0.0
}

/// How close (relative) a constant must be to a third, a quarter or a named irrational
/// ([`crate::expr::named_constants`]) for that value to be tried: 1 %. Farther values would
/// rarely pass the criterion and each try costs a refit.
const NAMED_SNAP_WINDOW: f64 = 0.01;

/// How a snap candidate is judged by [`snap_params`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Snap {
    /// An exact value of the plain kinds (0, +-1, an integer, a half, a multiple of pi/2):
    /// kept when the criterion over all snaps so far is no worse.
    Exact,
    /// An exact value of the kinds tried only near the fitted value (a third, a quarter, a
    /// named irrational): kept only when it pays for itself, its loss within one
    /// parameter's charge of the loss just before it, so it cannot use the allowance that
    /// earlier snaps left unused (a quarter that costs 2.7 % of the loss at n = 1,000 is
    /// refused where the three snaps before it each cost nothing).
    ExactAlone,
    /// `v` rounded to 1-3 significant digits: still a fitted value.
    Rounded,
}

/// Candidate simple values near `v`, simplest first, each with how it is judged: exact
/// values (0, +-1, an integer, a half, a multiple of pi/2; a third or a quarter, a named
/// irrational such as `sqrt(2)` or `1/sqrt(2 pi)` when `named`) before `v` rounded to 1-3
/// significant digits.
fn snap_candidates(v: f64, weight: bool, named: bool) -> Vec<(f64, Snap)> {
    let mut c: Vec<(f64, Snap)> = if weight {
        vec![(1.0, Snap::Exact), (-1.0, Snap::Exact), (0.0, Snap::Exact)]
    } else {
        vec![(0.0, Snap::Exact)]
    };
    c.extend([
        (v.round(), Snap::Exact),
        ((v * 2.0).round() / 2.0, Snap::Exact),
    ]);
    // a whole number of quarter turns (a phase: sin(u - pi/2) is -cos(u)), printed as pi
    let k = (v / std::f64::consts::FRAC_PI_2).round();
    if k != 0.0 && k.abs() <= crate::expr::MAX_HALF_PI_MULTIPLE {
        c.push((k * std::f64::consts::FRAC_PI_2, Snap::Exact));
    }
    let a = v.abs();
    let near = |x: f64| (x - v).abs() <= NAMED_SNAP_WINDOW * a;
    if a > 0.0 && a < 1e6 {
        for q in [3.0, 4.0] {
            let x = (v * q).round() / q;
            if near(x) {
                c.push((x, Snap::ExactAlone));
            }
        }
        for (value, _) in crate::expr::named_constants().into_iter().filter(|_| named) {
            let x = value.copysign(v);
            if near(x) {
                c.push((x, Snap::ExactAlone));
            }
        }
    }
    if a > 0.0 && a.is_finite() {
        for digits in [1i32, 2, 3] {
            let mag = a.log10().floor() as i32;
            let f = 10f64.powi(digits - 1 - mag);
            c.push(((v * f).round() / f, Snap::Rounded));
        }
    }
    let mut out: Vec<(f64, Snap)> = Vec::new();
    for (x, kind) in c {
        if x != v && x.is_finite() && !out.iter().any(|o| o.0 == x) {
            out.push((x, kind));
        }
    }
    out
}

/// What [`snap_params`] accepts: a rounding to 1-3 significant digits when the loss grows by
/// at most `rel_tol` (plus `abs_tol`), an exact value when the criterion does not get worse
/// (`penalty`: what it charges for one parameter), the named irrationals among the exact
/// values when `named`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SnapRule {
    pub rel_tol: f64,
    pub abs_tol: f64,
    pub penalty: f64,
    pub named: bool,
}

/// Replaces parameters by simple nearby values one at a time, refitting the others, and
/// returns the final mean squared error and which parameters were fixed at exact values
/// (`true` at their index: no longer fitted). Parameters marked in `already` are fixed at
/// exact values before it starts (an earlier snap): they are neither snapped nor refitted.
///
/// Two kinds of snap, tried in that order for each parameter (biases first, then weights and
/// constants, then the output map):
/// - to an exact value (0, +-1, an integer, a half, a multiple of pi/2): the parameter is then no longer fitted,
///   so the snap is accepted when the information criterion does not get worse, that is when
///   `n ln(mse' / mse)` stays within `penalty` (what the criterion charges for one
///   parameter: `ln n` for BIC, 2 for AIC);
/// - to 1-3 significant digits: still a fitted value, accepted only when the mean squared
///   error stays within `rel_tol` (plus `abs_tol`).
///
/// Either way the snapped model's criterion is never worse than the unsnapped model's, up
/// to the `rel_tol` slack. On noisy data the first kind removes offsets and factors that
/// only fit the noise (`(3.006 V - 0.02) (0.5 pr - 0.003) + 0.03` becomes `1.503 V pr`).
pub(crate) fn snap_params(
    prog: &Program,
    params: &mut Vec<f64>,
    cols: &[&[f64]],
    y: &[f64],
    rule: &SnapRule,
    already: &[bool],
) -> (f64, Vec<bool>) {
    let SnapRule {
        rel_tol,
        abs_tol,
        penalty,
        named,
    } = *rule;
    let mut ev = Evaluator::new(prog);
    let base = ev.mse(prog, params, cols, y);
    let mut exact_fixed = already.to_vec();
    if !base.is_finite() {
        return (base, exact_fixed);
    }
    let per_param = (penalty / y.len() as f64).exp();
    let mut limit = base * (1.0 + rel_tol) + abs_tol;
    let offs = prog.param_offsets();
    let mut order: Vec<usize> = Vec::new();
    for (k, n) in prog.nodes.iter().enumerate() {
        if matches!(n, Node::Var(_)) && prog.affine {
            order.push(offs[k] + 1);
        }
    }
    order.push(1);
    let n_bias = order.len();
    for (k, n) in prog.nodes.iter().enumerate() {
        match n {
            Node::Var(_) if prog.affine => order.push(offs[k]),
            Node::Const => order.push(offs[k]),
            _ => {}
        }
    }
    order.push(0);
    let mut fixed = already.to_vec();
    let mut current = base;
    for (&i, weight) in order.iter().zip((0..).map(|k| k >= n_bias)) {
        if already[i] {
            continue;
        }
        for (cand, kind) in snap_candidates(params[i], weight, named) {
            let exact = kind != Snap::Rounded;
            let allowed = match kind {
                Snap::Exact => limit * per_param,
                Snap::ExactAlone => (limit * per_param).min(current * per_param + abs_tol),
                Snap::Rounded => limit,
            };
            let mut trial = params.clone();
            trial[i] = cand;
            let mut fx = fixed.clone();
            fx[i] = true;
            let free: Vec<usize> = (0..trial.len()).filter(|&p| !fx[p]).collect();
            let mse = if free.is_empty() {
                ev.mse(prog, &trial, cols, y)
            } else {
                let direct = ev.mse(prog, &trial, cols, y);
                if direct <= allowed {
                    direct
                } else {
                    levenberg_marquardt(
                        prog,
                        &mut trial,
                        Unknowns::Free(&free),
                        cols,
                        y,
                        &LmSettings::new(20, 1e-10),
                        &mut ev,
                    )
                }
            };
            if mse.is_finite() && mse <= allowed {
                *params = trial;
                fixed = fx;
                current = mse;
                if exact {
                    limit = allowed;
                    exact_fixed[i] = true;
                }
                break;
            }
        }
    }
    (current, exact_fixed)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact candidates near a constant include the third, the quarter and the named
    /// irrational within 1 % (with its sign), and none farther away.
    #[test]
    fn thirds_quarters_and_named_irrationals_are_exact_candidates() {
        let exact = |v: f64| -> Vec<f64> {
            snap_candidates(v, true, true)
                .into_iter()
                .filter(|c| c.1 != Snap::Rounded)
                .map(|c| c.0)
                .collect()
        };
        assert!(exact(0.3336).contains(&(1.0 / 3.0)));
        assert!(exact(-0.7496).contains(&(-3.0 / 4.0)));
        assert!(exact(0.70712).contains(&(1.0 / 2f64.sqrt())));
        assert!(exact(-0.39890).contains(&(-1.0 / (2.0 * std::f64::consts::PI).sqrt())));
        assert!(exact(1.7321).contains(&3f64.sqrt()));
        // 2 % away from 1/sqrt(2) and from 2/3, 3/4: not tried as those
        let far = exact(0.69);
        assert!(!far.contains(&(1.0 / 2f64.sqrt())), "{far:?}");
        assert!(
            !far.contains(&(2.0 / 3.0)) && !far.contains(&0.75),
            "{far:?}"
        );
    }
}
