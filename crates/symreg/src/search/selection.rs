//! Selection: the archive's front (and its best-scoring model) refitted on all rows, their
//! constants snapped, the Pareto front of the refitted models, and the one model the
//! criterion picks.
use super::archive::{Archive, Fitted};
use super::config::{Criterion, ErrorModel};
use super::cv::{cross_validate, one_standard_error_pick, within_one_standard_error};
use super::export::to_model;
use super::fitting::Problem;
use crate::canonical::canonical_program;
use crate::eval::Evaluator;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::model::{Model, SnapRule, fold_data_constants, prune_snapped, snap_params};
use crate::ops::{Op, parse_operators};
use crate::program::{Node, Program};
use crate::stability::structure_of;
use crate::uncertainty::is_exact;
use crate::{SrError, Table};
use hxai_table::Pool;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use std::time::Instant;

/// Levenberg-Marquardt iterations of the final refit on all rows: twice the search's
/// default, since only a dozen or so models are refitted and their constants are reported.
pub(super) const REFIT_LM_ITERATIONS: usize = 50;

/// Relative improvement per step below which the final refit stops: close to the limit of
/// `f64`, so reported constants are converged and snapping starts from the true optimum.
pub(super) const REFIT_LM_TOLERANCE: f64 = 1e-12;

/// Absolute slack of the snapping rule, in units of the target's variance: an exact fit has
/// a loss of rounding size, where a purely relative tolerance would refuse every snap
/// (even to the true constant); `1e-14 var` is a relative RMSE of `1e-7`, far below any
/// noise a model could be fitting.
const SNAP_LOSS_SLACK: f64 = 1e-14;

/// Relative change of the loss allowed when terms a snapped weight killed are pruned: the
/// rewrites preserve values, so only rounding (the order of `f64`'s 1e-16, amplified by a
/// few operations) may change it.
const PRUNE_TOLERANCE: f64 = 1e-9;

/// Under [`Criterion::ParetoScore`], candidates are the front's models with a loss within
/// this factor of the lowest (PySR's rule).
const PARETO_SCORE_LOSS_WINDOW: f64 = 1.5;

/// Floor on the loss inside the log-loss slope of [`Criterion::ParetoScore`], so an exact
/// fit (loss 0) gives a large finite slope instead of infinity.
const LOG_LOSS_FLOOR: f64 = 1e-300;

/// What a search returns.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SearchResult {
    /// The model chosen by the criterion.
    pub best: Model,
    /// Best model at each complexity that lowers the loss, by increasing complexity.
    pub pareto: Vec<Model>,
    /// The models the data cannot tell apart from the best: every other reported model
    /// whose cross-validated loss (`cv_folds` seeded folds of all rows, the constants
    /// refitted on each) is within one standard error of the lowest, simplest first, one
    /// per structure. Computed whatever the criterion; empty in files written before it.
    #[serde(default)]
    pub alternatives: Vec<Model>,
    /// With [`SearchConfig::consensus_runs`](crate::SearchConfig::consensus_runs) > 0, how
    /// the structure of `best` was voted for ([`crate::consensus`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub consensus: Option<crate::consensus::Consensus>,
    /// Models fitted.
    pub evaluations: u64,
    /// Candidates whose structure was algebraically equal to one fitted earlier in the
    /// search (the same [`crate::canonical::Effort::Fast`] structure key, though not the
    /// same program): given that fit under
    /// [`SearchConfig::skip_equivalent`](crate::SearchConfig::skip_equivalent) (not in
    /// `evaluations`), fitted again without it (in `evaluations`). 0 in files written
    /// before it was counted.
    #[serde(default)]
    pub duplicate_structures: u64,
    /// Reported models (refitted on all rows: the front and its runners-up, before the
    /// Pareto front is taken) that were returned in a shorter form under
    /// [`SearchConfig::simplify`](crate::SearchConfig::simplify). 0 in files written before
    /// it was counted.
    #[serde(default)]
    pub simplified: u64,
    /// Wall time in seconds.
    pub seconds: f64,
    /// The error model the criterion read the scatter with
    /// ([`SearchConfig::error_model`](crate::SearchConfig::error_model), resolved: never
    /// `auto`). Written only when multiplicative; additive in files without it.
    #[serde(default, skip_serializing_if = "ErrorModel::is_additive")]
    pub error_model: ErrorModel,
}

/// Refits the archive's front and best model, and the `extra` candidates (a
/// decomposition's joins, [`super::separable`]: reported beside the archive's models, never
/// displacing one), on all rows, snaps their constants, and picks the reported models; the
/// refits run in `pool`. `counts` are the search's evaluations and duplicate structures.
pub(crate) fn finish(
    problem: &Problem,
    data: &Table,
    (archive, extra): (&Archive, &[Fitted]),
    counts: (u64, u64),
    t0: Instant,
    pool: &Pool,
) -> Result<SearchResult, SrError> {
    let (evaluations, duplicate_structures) = counts;
    let mut reported = reported_fits(archive);
    for f in extra {
        if f.mse.is_finite() && !reported.iter().any(|r| r.program == f.program) {
            reported.push(f.clone());
        }
    }
    if reported.is_empty() {
        return Err(SrError::NoModel);
    }
    let refined: Vec<(Model, bool)> = pool.install(|| {
        reported
            .par_iter()
            .map(|f| refine(problem, f, data))
            .collect()
    });
    let simplified = refined.iter().filter(|(_, s)| *s).count() as u64;
    let mut models: Vec<Model> = refined
        .into_iter()
        .map(|(m, _)| m)
        .filter(|m| m.train_mse.is_finite())
        .collect();
    if models.is_empty() {
        return Err(SrError::NoModel);
    }
    models.sort_by(|a, b| {
        a.complexity
            .cmp(&b.complexity)
            .then(a.train_mse.total_cmp(&b.train_mse))
    });
    distinct_structures(&mut models, pool);
    if problem.cfg.criterion == Criterion::Mdl {
        let charge = problem.structure_charge();
        for m in &mut models {
            m.score += charge * m.complexity as f64;
        }
    }
    let error_model = if matches!(
        problem.cfg.criterion,
        Criterion::Bic | Criterion::Aic | Criterion::Mdl
    ) {
        score_by_error_model(problem, &mut models, pool)
    } else {
        ErrorModel::Additive
    };
    // the alternatives' held-out losses read the scatter as the criterion did
    let cv = cross_validate(problem, &models, data, error_model, pool)?;
    if problem.cfg.criterion == Criterion::CrossValidation {
        for (m, (mean, _)) in models.iter_mut().zip(&cv) {
            m.score = *mean;
        }
    }
    let pareto = pareto_front(&models);
    let best = match problem.cfg.criterion {
        Criterion::ParetoScore => pareto_score_pick(&pareto),
        Criterion::CrossValidation => one_standard_error_pick(&models, &cv),
        Criterion::Bic | Criterion::Aic | Criterion::Mdl => {
            simplest_within_one_charge(problem, &models)
        }
    }
    .ok_or(SrError::NoModel)?;
    let alternatives = within_one_standard_error(&models, &cv, &best);
    Ok(SearchResult {
        best,
        pareto,
        alternatives,
        consensus: None,
        evaluations,
        duplicate_structures,
        simplified,
        seconds: t0.elapsed().as_secs_f64(),
        error_model,
    })
}

/// Rescores `models` under the multiplicative error model where
/// [`SearchConfig::error_model`](crate::SearchConfig::error_model) asks for it: always under
/// [`ErrorModel::Multiplicative`], and under [`ErrorModel::Auto`] when the target is
/// positive on every row and the best multiplicative score is lower than the best additive
/// one (a tie, such as two exact fits at the loss floor, stays additive). Each model's loss
/// in the criterion becomes `g^2 MSE_log` ([`ErrorModel`]); the charges are kept. Returns
/// the error model used.
fn score_by_error_model(problem: &Problem, models: &mut [Model], pool: &Pool) -> ErrorModel {
    let y = &problem.y;
    let wanted = problem.cfg.error_model;
    if wanted == ErrorModel::Additive || y.iter().any(|&v| v <= 0.0) {
        return ErrorModel::Additive;
    }
    let n = y.len();
    let log_y: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let log_g = log_y.iter().sum::<f64>() / n as f64;
    let rescored: Vec<f64> = pool.install(|| {
        models
            .par_iter()
            .map(|m| {
                let mut pred = Vec::new();
                Evaluator::new(&m.program).predict(
                    &m.program,
                    &m.params,
                    &problem.cols,
                    n,
                    &mut pred,
                );
                let mse_log = if pred.iter().all(|&p| p > 0.0 && p.is_finite()) {
                    pred.iter()
                        .zip(&log_y)
                        .map(|(p, ly)| (p.ln() - ly).powi(2))
                        .sum::<f64>()
                        / n as f64
                } else {
                    f64::INFINITY
                };
                let equivalent = mse_log * (2.0 * log_g).exp();
                // the charges of the model's score, kept: its score less its loss term
                m.score - problem.score(m.train_mse, 0, n) + problem.score(equivalent, 0, n)
            })
            .collect()
    });
    let lowest = |s: &mut dyn Iterator<Item = f64>| s.fold(f64::INFINITY, f64::min);
    let additive = lowest(&mut models.iter().map(|m| m.score));
    let multiplicative = lowest(&mut rescored.iter().copied());
    if wanted == ErrorModel::Multiplicative || multiplicative < additive {
        for (m, s) in models.iter_mut().zip(rescored) {
            m.score = s;
        }
        ErrorModel::Multiplicative
    } else {
        ErrorModel::Additive
    }
}

/// Keeps the first of `models` (sorted by complexity, then loss) of each canonical
/// structure ([`crate::stability::structure_of`]): programs the algebra proves equal are
/// one model, written the shortest way. (A longer spelling can fit a little better where
/// its constants snapped differently; it is still the same structure.)
fn distinct_structures(models: &mut Vec<Model>, pool: &Pool) {
    let keys: Vec<String> = pool.install(|| models.par_iter().map(structure_of).collect());
    let mut seen: HashSet<String> = HashSet::new();
    let mut keep = keys.into_iter().map(|k| seen.insert(k));
    models.retain(|_| keep.next().unwrap_or(true));
}

/// The archive's front plus its best-scoring model when that is not on the front.
fn reported_fits(archive: &Archive) -> Vec<Fitted> {
    let mut reported: Vec<Fitted> = archive.front();
    for f in archive
        .best
        .iter()
        .cloned()
        .chain(archive.front_runners_up())
    {
        if !reported.iter().any(|r| r.program == f.program) {
            reported.push(f);
        }
    }
    reported
}

/// How plain a model reads: the sum of [`crate::Op::plainness`] over its operators, a
/// division by an expression of the inputs (a rational function, with a pole) counted 2,
/// after power laws and exponentials (1), unless the divisor is an exponential
/// (`c/exp(c*x)` is `c*exp(-c*x)`). Selection breaks ties of complexity and degrees of
/// freedom by it, before the criterion's score.
pub fn plainness(m: &Model) -> usize {
    let nodes = &m.program.nodes;
    let children = m.program.children();
    // a divisor that holds an input, other than an exponential (`c/exp(c*x)` is
    // `c*exp(-c*x)`): a pole, read after power laws and exponentials
    let pole = |d: usize| {
        d < nodes.len()
            && !matches!(nodes[d], Node::Op(Op::Exp))
            && nodes[m.program.subtree_start(d)..=d]
                .iter()
                .any(|n| matches!(n, Node::Var(_)))
    };
    nodes
        .iter()
        .zip(&children)
        .map(|(n, ch)| match n {
            Node::Op(Op::Div) if pole(ch[1]) => POLE_PLAINNESS,
            Node::Op(Op::Inverse) if pole(ch[0]) => POLE_PLAINNESS,
            Node::Op(op) => op.plainness(),
            _ => 0,
        })
        .sum()
}

/// The plainness of a division by an expression of the inputs (a rational function: a
/// pole): after power laws and exponentials (1), with the periodic functions.
const POLE_PLAINNESS: usize = 2;

/// The model selection picks among `models`, which the criterion cannot tell apart: the
/// lowest complexity, then the fewest degrees of freedom
/// ([`crate::canonical::degrees_of_freedom`]: of two equations of one size, the one with
/// fewer constants to fit), then the plainer ([`plainness`]), then the better score.
pub(super) fn simplest<'m>(models: impl Iterator<Item = &'m Model>) -> Option<Model> {
    let models: Vec<&Model> = models.collect();
    let lowest = models.iter().map(|m| m.complexity).min()?;
    // the count runs the e-graph: only for the models of the lowest complexity, the others
    // cannot be picked
    models
        .into_iter()
        .filter(|m| m.complexity == lowest)
        .map(|m| {
            let dof = crate::canonical::degrees_of_freedom(&m.program, &m.params, &m.feature_names);
            (m, dof)
        })
        .min_by(|(a, da), (b, db)| {
            da.cmp(db)
                .then(plainness(a).cmp(&plainness(b)))
                .then(a.score.total_cmp(&b.score))
        })
        .map(|(m, _)| m.clone())
}

/// One reported fit refitted on all rows (keeping the search's constants if the refit
/// fails), its constants snapped, scored and exported; and whether it was returned in a
/// shorter form ([`simpler_form`]).
fn refine(problem: &Problem, f: &Fitted, data: &Table) -> (Model, bool) {
    let snapped = refine_with(problem, f, data, problem.cfg.snap_constants);
    if !problem.cfg.snap_constants {
        return snapped;
    }
    // snapping comes before the fold and the second shorter form, and a snapped constant
    // can keep a term from folding or a form from shortening that the fitted constants
    // allow: the unsnapped path is kept when its criterion is better (snaps are kept only
    // when the criterion is no worse)
    let plain = refine_with(problem, f, data, false);
    if plain.0.score < snapped.0.score {
        plain
    } else {
        snapped
    }
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
    let ops = parse_operators(&cfg.operators).ok()?;
    let known = form.nodes.iter().all(|n| match n {
        Node::Op(op) => ops.contains(op),
        _ => true,
    });
    if !known || !cfg.nesting.rules().ok()?.allows(&form) {
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

/// Each model strictly more complex and strictly better than the previous one, from
/// `models` sorted by complexity then loss.
fn pareto_front(models: &[Model]) -> Vec<Model> {
    let mut pareto: Vec<Model> = Vec::new();
    for m in models {
        if pareto
            .last()
            .is_none_or(|l: &Model| m.train_mse < l.train_mse && m.complexity > l.complexity)
        {
            pareto.push(m.clone());
        }
    }
    pareto
}

/// BIC and AIC: the simplest model whose criterion is within one parameter's charge of the
/// best. A structure picked out of thousands must earn at least that much to justify extra
/// operators (otherwise a near-dead term that happens to fit the noise, its constants
/// snapped, would win).
fn simplest_within_one_charge(problem: &Problem, models: &[Model]) -> Option<Model> {
    let best_score = models
        .iter()
        .map(|m| m.score)
        .min_by(|a, b| a.total_cmp(b))
        .unwrap_or(f64::INFINITY);
    let margin = problem.param_penalty(problem.y.len());
    simplest(models.iter().filter(|m| m.score <= best_score + margin))
}

/// PySR's rule: among front models with a loss within [`PARETO_SCORE_LOSS_WINDOW`] of the
/// lowest, the largest drop of log-loss per unit of complexity from the previous one.
fn pareto_score_pick(pareto: &[Model]) -> Option<Model> {
    let min_loss = pareto
        .iter()
        .map(|m| m.train_mse)
        .fold(f64::INFINITY, f64::min);
    let mut best: Option<(f64, &Model)> = None;
    let mut prev: Option<&Model> = None;
    for m in pareto {
        let s = match prev {
            None => 0.0,
            Some(p) => {
                -((m.train_mse.max(LOG_LOSS_FLOOR)).ln() - (p.train_mse.max(LOG_LOSS_FLOOR)).ln())
                    / (m.complexity as f64 - p.complexity as f64).max(1.0)
            }
        };
        if m.train_mse <= PARETO_SCORE_LOSS_WINDOW * min_loss && best.is_none_or(|(b, _)| s > b) {
            best = Some((s, m));
        }
        prev = Some(m);
    }
    best.map(|(_, m)| m.clone())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::super::cv::cv_folds;
    use super::*;
    use crate::program::{Node, Program};
    use crate::search::archive::Candidate;
    use crate::search::config::SearchConfig;
    use crate::{Op, Par};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The fit of the program `nodes` (affine inputs) on `problem`'s rows.
    fn fit_of(problem: &Problem, nodes: Vec<Node>) -> Fitted {
        let program = Program {
            nodes,
            affine: true,
        };
        problem.fit(&Candidate::new(program, None, 0), 1)
    }

    // Copies of a row (a bootstrap resample repeats rows) share a fold, so no fold is tested
    // on a row it was fitted on; without copies the folds are the plain seeded shuffle of
    // the rows, dealt in nearly equal parts.
    #[test]
    fn cross_validation_keeps_copies_of_a_row_in_one_fold() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let base: Vec<f64> = (0..60).map(|_| rng.gen_range(0.0..1.0)).collect();
        let rows: Vec<usize> = (0..120).map(|_| rng.gen_range(0..60)).collect();
        let x: Vec<f64> = rows.iter().map(|&r| base[r]).collect();
        let y: Vec<f64> = rows.iter().map(|&r| 2.0 * base[r]).collect();
        let (fold_of, k) = cv_folds(&[&x], &y, 5, 42);
        assert_eq!(k, 5);
        for i in 0..rows.len() {
            for j in 0..rows.len() {
                if rows[i] == rows[j] {
                    assert_eq!(fold_of[i], fold_of[j], "copies {i} and {j} split");
                }
            }
        }
        let plain: Vec<f64> = (0..100).map(|i| i as f64).collect();
        let (fold_of, k) = cv_folds(&[&plain], &plain, 5, 42);
        let mut sizes = vec![0usize; k];
        for &f in &fold_of {
            sizes[f] += 1;
        }
        assert_eq!(sizes, vec![20; 5]);
    }

    // The pick ranks models by their complexity after snapping: `add(x0, x1)`, whose x1
    // weight snaps to 0, is the law `x0` (complexity 1) and beats `abs(x0)` (complexity 2),
    // which fits as well. With the count taken before snapping (3) `abs(x0)` won.
    #[test]
    fn the_pick_ranks_by_the_complexity_after_snapping() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let x0: Vec<f64> = (0..200).map(|_| rng.gen_range(1.0..3.0)).collect();
        let x1: Vec<f64> = (0..200).map(|_| rng.gen_range(-2.0..2.0)).collect();
        let y: Vec<f64> = x0.iter().map(|v| 3.0 * v + 2.0).collect();
        let data = Table::new(vec!["x0".into(), "x1".into()], vec![x0, x1]).unwrap();
        let cfg = SearchConfig::default();
        let problem = Problem::all_rows(&data, &y, super::super::fitting::variance(&y), &cfg);
        let mut archive = Archive::default();
        for nodes in [
            vec![Node::Var(0), Node::Var(1), Node::Op(Op::Add)],
            vec![Node::Var(0), Node::Op(Op::Abs)],
        ] {
            archive.offer(&fit_of(&problem, nodes));
        }
        let res = finish(
            &problem,
            &data,
            (&archive, &[]),
            (2, 0),
            Instant::now(),
            &Par::Current.pool(),
        )
        .unwrap();
        assert_eq!(res.best.complexity, 1, "{}", res.best.equation());
        assert_eq!(res.best.features(), vec!["x0".to_string()]);
    }

    // `x0 + x1` and `x1 + x0` are one structure: the simpler is kept, even where the other
    // fits better; a structure of its own is always kept.
    #[test]
    fn programs_equal_by_algebra_are_reported_once() {
        let mut rng = ChaCha8Rng::seed_from_u64(6);
        let x0: Vec<f64> = (0..200).map(|_| rng.gen_range(1.0..3.0)).collect();
        let x1: Vec<f64> = (0..200).map(|_| rng.gen_range(-2.0..2.0)).collect();
        let y: Vec<f64> = x0
            .iter()
            .zip(&x1)
            .map(|(a, b)| 2.3 * a + 0.7 * b + a.sin())
            .collect();
        let data = Table::new(vec!["x0".into(), "x1".into()], vec![x0, x1]).unwrap();
        let cfg = SearchConfig::default();
        let problem = Problem::all_rows(&data, &y, super::super::fitting::variance(&y), &cfg);
        let model = |nodes: Vec<Node>| refine(&problem, &fit_of(&problem, nodes), &data).0;
        let a = model(vec![Node::Var(0), Node::Var(1), Node::Op(Op::Add)]);
        let b = model(vec![Node::Var(1), Node::Var(0), Node::Op(Op::Add)]);
        let other = model(vec![Node::Var(0), Node::Var(1), Node::Op(Op::Mul)]);
        assert_eq!(structure_of(&a), structure_of(&b));
        let pool = Par::Current.pool();
        let kept = |b_mse: f64| {
            let mut b = b.clone();
            b.complexity = a.complexity + 1;
            b.train_mse = b_mse;
            let mut models = vec![a.clone(), b, other.clone()];
            distinct_structures(&mut models, &pool);
            models
                .iter()
                .map(|m| (m.complexity, structure_of(m)))
                .collect::<Vec<_>>()
        };
        let (ca, sa, so) = (a.complexity, structure_of(&a), structure_of(&other));
        assert_eq!(
            kept(a.train_mse),
            vec![(ca, sa.clone()), (other.complexity, so.clone())]
        );
        assert_eq!(
            kept(a.train_mse * 0.5),
            vec![(ca, sa), (other.complexity, so)]
        );
    }

    // Of two models of one complexity and plainness the criterion cannot tell apart, the
    // one with fewer constants to fit is picked, even with the worse score: the log of a
    // shift snapped to 0 (two degrees of freedom) over the exponential (three); the score
    // decides only between equals.
    #[test]
    fn the_pick_prefers_fewer_degrees_of_freedom_at_one_complexity() {
        let log = one_input_model(Op::Log, vec![-2.46, -4.0, 1.3, 0.0], 1.01);
        let exp = one_input_model(Op::Exp, vec![7.3, -4.0, -3.0, 0.2], 1.0);
        assert_eq!(log.complexity, exp.complexity);
        assert_eq!(plainness(&log), plainness(&exp));
        let pick = simplest([&exp, &log].into_iter()).unwrap();
        assert_eq!((pick.program, pick.params), (log.program, log.params));
        let shifted = one_input_model(Op::Log, vec![-2.46, -4.0, 1.3, 0.2], 1.01);
        let pick = simplest([&shifted, &exp].into_iter()).unwrap();
        assert_eq!((pick.program, pick.params), (exp.program, exp.params));
    }

    // A division by an expression of the inputs (a pole) reads after power laws and
    // exponentials: of a rational and a log of one complexity and degrees of freedom, the
    // log is picked even with the worse score; dividing by an exponential is no pole.
    #[test]
    fn a_pole_reads_after_power_laws_and_exponentials() {
        let shifted = one_input_model(Op::Log, vec![-2.9, -4.0, 1.0, 0.05], 1.01);
        let rational = one_input_model(Op::Inverse, vec![4.8, -6.0, 1.5, 0.5], 1.0);
        assert_eq!(plainness(&shifted), 1);
        assert_eq!(plainness(&rational), 2);
        let pick = simplest([&rational, &shifted].into_iter()).unwrap();
        assert_eq!(
            (pick.program, pick.params),
            (shifted.program, shifted.params)
        );
        let names = vec!["f".to_string(), "t".to_string()];
        let of = |nodes: Vec<Node>| {
            let program = Program {
                nodes,
                affine: true,
            };
            let n = program.n_params();
            Model::new(names.clone(), program, vec![1.3; n]).unwrap()
        };
        // c/exp(c*f + c): an exponential
        let over_exp = of(vec![
            Node::Const,
            Node::Var(0),
            Node::Op(Op::Exp),
            Node::Op(Op::Div),
        ]);
        assert_eq!(plainness(&over_exp), 1);
        // (c*t + c)/(c*f + c) and (c*t + c)/log(c*f + c): poles; (c*f + c)/c: none
        let over_input = of(vec![Node::Var(1), Node::Var(0), Node::Op(Op::Div)]);
        assert_eq!(plainness(&over_input), 2);
        let over_log = of(vec![
            Node::Var(1),
            Node::Var(0),
            Node::Op(Op::Log),
            Node::Op(Op::Div),
        ]);
        assert_eq!(plainness(&over_log), 3);
        let over_const = of(vec![Node::Var(0), Node::Const, Node::Op(Op::Div)]);
        assert_eq!(plainness(&over_const), 0);
    }

    /// `scale * op(w*f + b) + offset` over one input `f`, with its score.
    fn one_input_model(op: Op, params: Vec<f64>, score: f64) -> Model {
        let program = Program {
            nodes: vec![Node::Var(0), Node::Op(op)],
            affine: true,
        };
        let mut m = Model::new(vec!["f".to_string()], program, params).unwrap();
        m.score = score;
        m
    }
}
