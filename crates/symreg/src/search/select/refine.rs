//! One reported model made final: refitted on all rows, written in a shorter form the
//! algebra proves equal, its constants snapped, the terms snapping killed pruned, and
//! subtrees constant over the rows folded, each step kept only when the criterion allows.
use super::export::to_model;
use crate::Table;
use crate::canonical::canonical_program;
use crate::eval::Evaluator;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::model::{Model, SnapRule, fold_data_constants, prune_snapped, snap_params};
use crate::program::{Node, Program};
use crate::search::archive::Fitted;
use crate::search::fitting::Problem;
use crate::uncertainty::is_exact;

/// Levenberg-Marquardt iterations of the final refit on all rows: twice the search's
/// default, since only a dozen or so models are refitted and their constants are reported.
pub(crate) const REFIT_LM_ITERATIONS: usize = 50;

/// Relative improvement per step below which the final refit stops: close to the limit of
/// `f64`, so reported constants are converged and snapping starts from the true optimum.
pub(crate) const REFIT_LM_TOLERANCE: f64 = 1e-12;

/// Absolute slack of the snapping rule, in units of the target's variance: an exact fit has
/// a loss of rounding size, where a purely relative tolerance would refuse every snap
/// (even to the true constant); `1e-14 var` is a relative RMSE of `1e-7`, far below any
/// noise a model could be fitting.
const SNAP_LOSS_SLACK: f64 = 1e-14;

/// Relative change of the loss allowed when terms a snapped weight killed are pruned: the
/// rewrites preserve values, so only rounding (the order of `f64`'s 1e-16, amplified by a
/// few operations) may change it.
const PRUNE_TOLERANCE: f64 = 1e-9;

/// One reported fit refitted on all rows (keeping the search's constants if the refit
/// fails), its constants snapped, scored and exported; and whether it was returned in a
/// shorter form ([`simpler_form`]).
pub(super) fn refine(problem: &Problem, f: &Fitted, data: &Table) -> (Model, bool) {
    let snapped = refine_with(problem, f, data, problem.cfg.snap_constants);
    let chosen = if problem.cfg.snap_constants {
        // snapping comes before the fold and the second shorter form, and a snapped
        // constant can keep a term from folding or a form from shortening that the fitted
        // constants allow: the unsnapped path is kept when its criterion is better (snaps
        // are kept only when the criterion is no worse), or when the snapped one is not
        // defined beside the rows
        let plain = refine_with(problem, f, data, false);
        match (
            defined(problem, &snapped.0, data),
            defined(problem, &plain.0, data),
        ) {
            (true, true) if plain.0.score < snapped.0.score => plain,
            (true, _) => snapped,
            (false, true) => plain,
            (false, false) => return as_searched(problem, f, data),
        }
    } else {
        snapped
    };
    if defined(problem, &chosen.0, data) {
        chosen
    } else {
        as_searched(problem, f, data)
    }
}

/// Whether `m` (a model over some columns of `data`) is defined over the problem's box
/// ([`crate::SearchConfig::defined_margin`]); true when there is none.
fn defined(problem: &Problem, m: &Model, data: &Table) -> bool {
    let Some(b) = &problem.domain else {
        return true;
    };
    crate::search::beside::bounds_of(m, data, b).is_some_and(|bb| {
        crate::enclosure::defined_over(
            &m.program,
            &m.params,
            &bb,
            crate::search::config::DEFINED_BOXES,
        )
        .is_ok()
    })
}

/// The search's own fit of `f`, scored on every row, without the final refit, snapping
/// or rewriting: what is reported when each of those gives a model with a pole beside the
/// rows (the search's constants were proven defined there when it fitted them).
fn as_searched(problem: &Problem, f: &Fitted, data: &Table) -> (Model, bool) {
    let mse = Evaluator::new(&f.program).mse(&f.program, &f.params, &problem.cols, &problem.y);
    let n = problem.y.len();
    let complexity = f
        .program
        .complexity_with(problem.cfg.complexity_measure, &problem.op_costs);
    let model = to_model(
        &f.program,
        f.params.clone(),
        mse,
        problem.score(mse, f.params.len(), n),
        complexity,
        data,
    );
    (model, false)
}

/// [`refine`] with constants snapped (`snap`) or not.
fn refine_with(problem: &Problem, f: &Fitted, data: &Table, snap: bool) -> (Model, bool) {
    let cfg = problem.cfg;
    let full_cols = &problem.cols;
    let y = &problem.y;
    let n = y.len();
    let prog = &f.program;
    let mut ev = Evaluator::new(prog);
    let mut params = f.params.clone();
    let free: Vec<usize> = (0..params.len()).collect();
    let mut mse = levenberg_marquardt(
        prog,
        &mut params,
        Unknowns::Free(&free),
        full_cols,
        y,
        &LmSettings::new(REFIT_LM_ITERATIONS, REFIT_LM_TOLERANCE),
        &mut ev,
    );
    if !mse.is_finite() {
        params = f.params.clone();
        mse = ev.mse(prog, &params, full_cols, y);
    }
    // a model the algebra proves equal to a shorter one is reported as the shorter one:
    // before snapping, so that the constants snapped are the shorter form's, and again after
    // snapping and folding, which can leave a form to shorten
    let mut prog = prog.clone();
    let mut fixed = vec![false; params.len()];
    let mut simplified = false;
    if let Some(simpler) = simpler_form(problem, (&prog, &params, &fixed), mse, data.names()) {
        (prog, params, fixed, mse) = simpler;
        simplified = true;
    }
    let (mut prog, mut params, mut exact, mut mse) =
        snap_and_prune(problem, prog, params, &fixed, mse, snap);
    // a subtree that is constant over the rows (a dead term, a saturated tanh) is a constant
    // in disguise: replaced by one, snapped and pruned, the model says what it computes
    // (kept when its criterion is no worse, or its loss within rounding of the original)
    for _ in 0..MAX_FOLD_ROUNDS {
        let Some((folded, folded_params, carried)) =
            fold_data_constants(&prog, &params, &exact, full_cols, n)
        else {
            break;
        };
        let folded_mse = Evaluator::new(&folded).mse(&folded, &folded_params, full_cols, y);
        let (f_prog, f_params, f_exact, f_mse) =
            snap_and_prune(problem, folded, folded_params, &carried, folded_mse, snap);
        let fitted = |e: &[bool]| e.iter().filter(|&&x| !x).count();
        let same_loss = f_mse <= mse * (1.0 + PRUNE_TOLERANCE) + SNAP_LOSS_SLACK * problem.y_var;
        let no_worse =
            problem.score(f_mse, fitted(&f_exact), n) <= problem.score(mse, fitted(&exact), n);
        if !(f_mse.is_finite() && (same_loss || no_worse)) {
            break;
        }
        (prog, params, exact, mse) = (f_prog, f_params, f_exact, f_mse);
    }
    if let Some((s_prog, s_params, s_exact, s_mse)) =
        simpler_form(problem, (&prog, &params, &exact), mse, data.names())
    {
        // the shorter form's constants are the folded ones: snapped again (a phase `2*(x/2
        // - c)` that becomes `x - 2c` can snap where `c` alone could not)
        (prog, params, exact, mse) =
            snap_and_prune(problem, s_prog, s_params, &s_exact, s_mse, snap);
        simplified = true;
    }
    // parameters fixed at exact values are no longer fitted: the criterion does not charge
    // for them
    let n_fitted = exact.iter().filter(|&&e| !e).count();
    let complexity = prog.complexity_with(cfg.complexity_measure, &problem.op_costs);
    let model = to_model(
        &prog,
        params,
        mse,
        problem.score(mse, n_fitted, n),
        complexity,
        data,
    );
    (model, simplified)
}

/// A refitted model (`prog` with `params`, `exact` marking the ones snapped, loss `mse`)
/// as its canonical form read back as a program ([`canonical_program`]), when that is
/// simpler: no more complex under the search's measure and with no more fitted constants
/// (the whole and half numbers of the form count as exact, as [`Model::uncertainty`] counts
/// them), one of the two strictly lower; only the search's operators, within its nesting
/// rules; and the same loss up to rounding. `None` otherwise.
fn simpler_form(
    problem: &Problem,
    (prog, params, exact): (&Program, &[f64], &[bool]),
    mse: f64,
    names: &[String],
) -> Option<(Program, Vec<f64>, Vec<bool>, f64)> {
    let cfg = problem.cfg;
    if !cfg.simplify {
        return None;
    }
    let (form, values) = canonical_program(prog, params, names)?;
    let known = form.nodes.iter().all(|n| match n {
        Node::Op(op) => cfg.operators().contains(op),
        _ => true,
    });
    if !known || !cfg.nesting().allows(&form) {
        return None;
    }
    let measure = |p: &Program| p.complexity_with(cfg.complexity_measure, &problem.op_costs);
    let form_exact: Vec<bool> = values.iter().map(|&v| is_exact(v)).collect();
    let fitted = |e: &[bool]| e.iter().filter(|&&x| !x).count();
    let (c, form_c) = (measure(prog), measure(&form));
    let (k, form_k) = (fitted(exact), fitted(&form_exact));
    if form_c > c || form_k > k || (form_c, form_k) == (c, k) {
        return None;
    }
    let form_mse = Evaluator::new(&form).mse(&form, &values, &problem.cols, &problem.y);
    (form_mse.is_finite()
        && form_mse <= mse * (1.0 + PRUNE_TOLERANCE) + SNAP_LOSS_SLACK * problem.y_var)
        .then_some((form, values, form_exact, form_mse))
}

/// Rounds of [`fold_data_constants`] in [`refine`]: a fold can expose another (a snapped
/// constant that makes an enclosing term constant); two rounds have been enough in every
/// case seen, the third is a margin.
const MAX_FOLD_ROUNDS: usize = 3;

/// `params` of `prog` (loss `mse`) with its constants snapped ([`snap_params`], those marked
/// in `already` held at their exact values) when `snap` (the configuration's, or false for
/// the unsnapped path of [`refine`]), and the
/// terms a snapped weight killed pruned ([`prune_snapped`]), so the model's features and
/// complexity (which selection ranks by) are those of the equation it reports. Returns the
/// program, its parameters, which are fixed at exact values, and the loss.
fn snap_and_prune(
    problem: &Problem,
    prog: crate::program::Program,
    mut params: Vec<f64>,
    already: &[bool],
    mut mse: f64,
    snap: bool,
) -> (crate::program::Program, Vec<f64>, Vec<bool>, f64) {
    let (cols, y) = (&problem.cols, &problem.y);
    let mut exact = already.to_vec();
    if snap && mse.is_finite() {
        let rule = SnapRule {
            rel_tol: problem.cfg.snap_tolerance,
            abs_tol: SNAP_LOSS_SLACK * problem.y_var,
            penalty: problem.param_penalty(y.len()),
            named: problem.cfg.named_constants,
        };
        (mse, exact) = snap_params(&prog, &mut params, cols, y, &rule, already);
    }
    if exact.iter().any(|&e| e) {
        let (pruned, pruned_params, pruned_exact) = prune_snapped(&prog, &params, &exact);
        let pruned_mse = Evaluator::new(&pruned).mse(&pruned, &pruned_params, cols, y);
        // the rewrites preserve values wherever the model is finite; a pruned model that
        // fits worse than rounding would allow is not the same model, so it is not used
        if pruned_mse.is_finite()
            && pruned_mse <= mse * (1.0 + PRUNE_TOLERANCE) + SNAP_LOSS_SLACK * problem.y_var
        {
            return (pruned, pruned_params, pruned_exact, pruned_mse);
        }
    }
    (prog, params, exact, mse)
}
