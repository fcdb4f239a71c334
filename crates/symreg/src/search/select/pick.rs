//! The rules that pick among models the criterion cannot tell apart: the simplest (lowest
//! complexity, fewest degrees of freedom, plainest), the Pareto front, BIC's and AIC's
//! margin of one parameter's charge, and PySR's score.
use crate::model::Model;
use crate::ops::Op;
use crate::program::Node;
use crate::search::fitting::Problem;

/// Under [`Criterion::ParetoScore`], candidates are the front's models with a loss within
/// this factor of the lowest (PySR's rule).
const PARETO_SCORE_LOSS_WINDOW: f64 = 1.5;

/// Floor on the loss inside the log-loss slope of [`Criterion::ParetoScore`], so an exact
/// fit (loss 0) gives a large finite slope instead of infinity.
const LOG_LOSS_FLOOR: f64 = 1e-300;

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
pub(crate) fn simplest<'m>(models: impl Iterator<Item = &'m Model>) -> Option<Model> {
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

/// Each model strictly more complex and strictly better than the previous one, from
/// `models` sorted by complexity then loss.
pub(super) fn pareto_front(models: &[Model]) -> Vec<Model> {
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
pub(super) fn simplest_within_one_charge(problem: &Problem, models: &[Model]) -> Option<Model> {
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
pub(super) fn pareto_score_pick(pareto: &[Model]) -> Option<Model> {
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
