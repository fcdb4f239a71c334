//! Selection: the archive's front (and its best-scoring model) refitted on all rows, their
//! constants snapped, the Pareto front of the refitted models, and the one model the
//! criterion picks.
use super::cv::{cross_validate, one_standard_error_pick, within_one_standard_error};
use super::pick::{pareto_front, pareto_score_pick, simplest_within_one_charge};
use super::refine::refine;
use crate::canonical::structure_of;
use crate::eval::Evaluator;
use crate::model::Model;
use crate::prior::Codelengths;
use crate::search::archive::{Archive, Fitted};
use crate::search::config::{Criterion, ErrorModel, Prior};
use crate::search::fitting::Problem;
use crate::{SrError, Table};
use hxai_table::Pool;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashSet;
use std::time::Instant;

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

/// What selection chooses from: the archive of the search and the `extra` candidates (a
/// decomposition's joins, polynomials and factor models, `crate::search::decompose` and
/// `power`: reported beside the archive's models, never displacing one).
#[derive(Clone, Copy)]
pub(crate) struct Finalists<'a> {
    /// The best fit per complexity.
    pub archive: &'a Archive,
    /// Candidates from outside the loop.
    pub extra: &'a [Fitted],
}

/// What the search counted, reported in its [`SearchResult`].
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Counts {
    /// Models fitted.
    pub evaluations: u64,
    /// Candidates whose structure had been fitted under another program.
    pub duplicate_structures: u64,
}

/// Refits the archive's front and best model, and the extra candidates, on all rows, snaps
/// their constants, and picks the reported models; the refits run in `pool`.
pub(crate) fn select(
    problem: &Problem,
    data: &Table,
    finalists: Finalists,
    counts: Counts,
    t0: Instant,
    pool: &Pool,
) -> Result<SearchResult, SrError> {
    let Counts {
        evaluations,
        duplicate_structures,
    } = counts;
    let Finalists { archive, extra } = finalists;
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
    // a model that blows up beside the rows is not offered (unless every one does)
    crate::search::beside::drop_blow_ups(
        (problem.domain.as_deref(), problem.allowed),
        &mut models,
        data,
    );
    models.sort_by(|a, b| {
        a.complexity
            .cmp(&b.complexity)
            .then(a.train_mse.total_cmp(&b.train_mse))
    });
    distinct_structures(&mut models, pool);
    if problem.cfg.criterion == Criterion::Mdl {
        match problem.cfg.prior {
            Prior::Uniform => {
                let charge = problem.structure_charge();
                for m in &mut models {
                    m.score += charge * m.complexity as f64;
                }
            }
            Prior::Laws => {
                // the score is twice the negative log-likelihood in nats: twice the
                // structure's codelength joins it on the same scale, and twice the
                // constants' codelength at their precision takes the place of BIC's
                // `ln n` per constant
                let n = problem.y.len();
                let per_constant = problem.param_penalty(n);
                let lambda = problem.cfg.complexity_penalty;
                for m in &mut models {
                    let k = m
                        .params
                        .iter()
                        .filter(|&&v| !crate::uncertainty::is_exact(v))
                        .count();
                    let lengths = Codelengths::laws(m, (data, &problem.y), problem.y_var);
                    m.score += 2.0 * lengths.structure - per_constant * k as f64
                        + 2.0 * lambda * lengths.parameters;
                }
            }
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
        Criterion::CrossValidation => match problem.cfg.prior {
            Prior::Uniform => one_standard_error_pick(&models, &cv, None),
            Prior::Laws => {
                // the data cannot tell the band apart: the prior's likeliest description
                let codelength = |m: &Model| {
                    let l = Codelengths::laws(m, (data, &problem.y), problem.y_var);
                    l.structure + l.parameters
                };
                one_standard_error_pick(&models, &cv, Some(&codelength))
            }
        },
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
/// structure ([`crate::canonical::structure_of`]): programs the algebra proves equal are
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

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::super::cv::cv_folds;
    use super::super::pick::{plainness, simplest};
    use super::super::refine::refine;
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
        let valid = cfg.check().expect("valid");
        let problem = Problem::all_rows(&data, &y, crate::search::fitting::variance(&y), &valid);
        let mut archive = Archive::default();
        for nodes in [
            vec![Node::Var(0), Node::Var(1), Node::Op(Op::Add)],
            vec![Node::Var(0), Node::Op(Op::Abs)],
        ] {
            archive.offer(&fit_of(&problem, nodes));
        }
        let finalists = Finalists {
            archive: &archive,
            extra: &[],
        };
        let counts = Counts {
            evaluations: 2,
            duplicate_structures: 0,
        };
        let res = select(
            &problem,
            &data,
            finalists,
            counts,
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
        let valid = cfg.check().expect("valid");
        let problem = Problem::all_rows(&data, &y, crate::search::fitting::variance(&y), &valid);
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
