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

/// Under the laws prior, the model selection picks among `models` (which the criterion
/// cannot tell apart) the one with the shortest description, structure and constants
/// (`codelength`, nats), ties by [`simplest`]; but a model that reads no input (a constant:
/// "the inputs have no effect") goes first when it is among them, as under [`simplest`]:
/// it is the null every effect must beat, and the prior, learned from laws that all have
/// inputs, would price it above a line.
pub(crate) fn likeliest<'m>(
    models: impl Iterator<Item = &'m Model>,
    codelength: &(dyn Fn(&Model) -> f64 + Sync),
) -> Option<Model> {
    let models: Vec<&Model> = models.collect();
    if models.iter().any(|m| m.program.vars().is_empty()) {
        return simplest(models.into_iter().filter(|m| m.program.vars().is_empty()));
    }
    let lengths: Vec<f64> = models.iter().map(|m| codelength(m)).collect();
    let lowest = lengths.iter().copied().fold(f64::INFINITY, f64::min);
    if !lowest.is_finite() {
        return simplest(models.into_iter());
    }
    simplest(
        models
            .into_iter()
            .zip(&lengths)
            .filter(|(_, l)| **l <= lowest + CODELENGTH_TIE)
            .map(|(m, _)| m),
    )
}

/// Codelengths closer than this (nats) are a tie in [`likeliest`]: rounding only.
const CODELENGTH_TIE: f64 = 1e-9;

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

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::program::Program;

    fn model(nodes: Vec<Node>, complexity: usize) -> Model {
        let program = Program {
            nodes,
            affine: true,
        };
        let params = vec![1.0; program.n_params()];
        let mut m = Model::new(vec!["x".into()], program, params).unwrap();
        m.complexity = complexity;
        m
    }

    /// The laws prior's pick: the shortest description, not the lowest complexity; a model
    /// without inputs first whenever it is among the candidates.
    #[test]
    fn the_likeliest_is_the_shortest_description_and_a_constant_goes_first() {
        let line = model(vec![Node::Var(0)], 1);
        let tanh = model(vec![Node::Var(0), Node::Op(Op::Tanh)], 2);
        let flat = model(vec![Node::Const], 0);
        // a made-up price: the tanh cheaper than the line, whatever the complexity
        let price = |m: &Model| {
            if m.program.nodes.contains(&Node::Op(Op::Tanh)) {
                1.0
            } else {
                5.0
            }
        };
        assert_eq!(
            likeliest([&line, &tanh].into_iter(), &price)
                .unwrap()
                .program,
            tanh.program
        );
        assert_eq!(
            simplest([&line, &tanh].into_iter()).unwrap().program,
            line.program
        );
        assert_eq!(
            likeliest([&line, &tanh, &flat].into_iter(), &price)
                .unwrap()
                .program,
            flat.program
        );
        // ties go to the simplest
        let same = |_: &Model| 3.0;
        assert_eq!(
            likeliest([&tanh, &line].into_iter(), &same)
                .unwrap()
                .program,
            line.program
        );
    }
}
