//! The power primitive of `hxai sr` ([`SearchConfig::power_laws`](super::SearchConfig)):
//! closed-form factor models of the target, offered to selection beside the search's own
//! models.
//!
//! Engineers' laws are mostly products of powers and other one-column factors (the
//! allometric `a m^b`, Taylor's `C v^a f^b`) or sums of such terms (Naismith's rule). A
//! tree search reaches `x^p y^q` only as `exp(a log(x) + b log(y))`, five operators deep,
//! and on a few dozen rows it often stops at a tangle that fits the rows as well. Here the
//! factor form of [`crate::factors`] (cross-validated forward selection of one shape per
//! column, a power with a fitted exponent first, exponents snapped to simple numbers where
//! the criterion allows) fits the product `C prod_j f_j(x_j)` and the sum
//! `c + sum_j a_j s_j(x_j)` on the search's fitting rows; each becomes one more candidate,
//! refitted, snapped and judged by the same criterion as every other model.
//!
//! Only shapes whose operators the user allowed are tried: `exp` for the exponential, `log`
//! for the logarithm, `div` or `inverse` for the pole and the saturation. The power `x^p`
//! itself is the primitive this setting turns on. The harmonic of the hybrid's factor form
//! is not offered here: the search reaches `sin(w x + c)` by itself, and a plain search's
//! defaults were measured without it (docs/benchmarks.md, "Laws in small real tables").
use super::archive::Fitted;
use super::config::ErrorModel;
use super::fitting::{Problem, refitted};
use crate::Table;
use crate::factors::{FactorConfig, Link, Shape, Shapes, fit_factors};
use crate::nesting::NestingRules;
use crate::ops::Op;
use crate::program::{Node, Program};

/// Most folds of the factor form's cross-validation (fewer on small tables: two rows per
/// fold at least).
const MAX_FOLDS: usize = 5;

/// Largest table (rows) the power primitive runs on. Measured on the AI Feynman 100 (1,000
/// rows, 500 fitting rows): offered on every problem, the factor models cost a median 1.14
/// times the CPU time, 1.33 times the wall time on problems of five or more inputs, for one
/// law more; on tables that large the search reaches a power law as `exp(a log(x))` by
/// itself. Real engineering
/// tables of a few dozen to a few hundred rows are where a closed-form product of powers
/// is worth the candidate (docs/benchmarks.md, "Laws in small real tables").
pub(crate) const POWER_LAWS_MAX_ROWS: usize = 300;

/// Most rows the factor models are chosen on: an evenly spaced subset of the fitting rows
/// beyond that (the chosen candidates are refitted on every row by selection). The factor
/// form fits every shape of every column in every fold; a one-column shape is pinned down
/// by far fewer rows.
const MAX_ROWS: usize = 200;

/// The shapes the operators allow: the power and the linear term always, the others where
/// their operator is in `ops` ([`Shapes::allowed_by`]); the interaction `x^p y^q` where
/// multiplication is.
fn shapes(ops: &[Op]) -> Shapes {
    let all = [
        Shape::Power,
        Shape::Linear,
        Shape::Exp,
        Shape::Log,
        Shape::Pole,
        Shape::Saturation,
        Shape::Pair,
    ];
    let s = all.into_iter().fold(Shapes::NONE, Shapes::with);
    let s = s.allowed_by(ops, false);
    if ops.contains(&Op::Mul) {
        s
    } else {
        s.without(Shape::Pair)
    }
}

/// The product and the sum of factors fitted on the problem's fitting rows, each refitted
/// with every constant free (a product's offset, fixed at -1 in a correction, is free here).
/// Empty where the table is too small for two folds or larger than
/// [`POWER_LAWS_MAX_ROWS`], or no factor model fits. A model that breaks a nesting rule is
/// left out.
pub(super) fn factor_models(problem: &Problem, ops: &[Op], nesting: &NestingRules) -> Vec<Fitted> {
    let n = problem.fit_y.len();
    let folds = (n.min(MAX_ROWS) / 2).min(MAX_FOLDS);
    if folds < 2 || problem.y.len() > POWER_LAWS_MAX_ROWS || !ops.contains(&Op::Add) {
        return Vec::new();
    }
    let rows: Vec<usize> = if n > MAX_ROWS {
        (0..MAX_ROWS).map(|i| i * n / MAX_ROWS).collect()
    } else {
        (0..n).collect()
    };
    let names: Vec<String> = (0..problem.fit_cols.len())
        .map(|j| format!("x{j}"))
        .collect();
    let cols: Vec<Vec<f64>> = problem
        .fit_cols
        .iter()
        .map(|c| rows.iter().map(|&i| c[i]).collect())
        .collect();
    let Ok(table) = Table::new(names, cols) else {
        return Vec::new();
    };
    let cfg = FactorConfig {
        folds,
        shapes: shapes(ops),
        seed: problem.cfg.seed,
        par: problem.cfg.par,
        // the shapes of the entry: backfitting was measured on the hybrid's factor form
        // (issue 46's tables), not on `hxai sr`'s suites, whose figures these candidates
        // were measured with
        backfit_rounds: 0,
        ..FactorConfig::default()
    };
    let mut out = Vec::new();
    // a product needs multiplication; its program is `C prod f - 1`, so it is fitted to
    // y - 1 and its offset moved back
    let links: &[(Link, f64)] = if ops.contains(&Op::Mul) {
        &[(Link::Multiplicative, 1.0), (Link::Additive, 0.0)]
    } else {
        &[(Link::Additive, 0.0)]
    };
    for &(link, shift) in links {
        let y: Vec<f64> = rows.iter().map(|&i| problem.fit_y[i] - shift).collect();
        let Ok(fit) = fit_factors(&table, &y, link, &cfg) else {
            continue;
        };
        if fit.factors.is_empty() {
            continue;
        }
        if !nesting.allows(&fit.model.program) {
            continue;
        }
        let mut params = fit.model.params.clone();
        if let Some(offset) = params.get_mut(1) {
            *offset += shift;
        }
        out.extend(refitted(problem, fit.model.program.clone(), params));
    }
    // under a multiplicative (or auto) error model, a positive target's product is also
    // chosen on `ln y`, where every row weighs alike whatever its size, and then refitted
    // by least squares like the others
    let positive = rows.iter().all(|&i| problem.fit_y[i] > 0.0);
    if problem.cfg.error_model != ErrorModel::Additive && positive && ops.contains(&Op::Mul) {
        let log_y: Vec<f64> = rows.iter().map(|&i| problem.fit_y[i].ln()).collect();
        if let Ok(fit) = fit_factors(&table, &log_y, Link::Log, &cfg)
            && !fit.factors.is_empty()
            && let Some((program, params)) = unlogged(&fit.model.program, &fit.model.params)
            && nesting.allows(&program)
        {
            out.extend(refitted(problem, program, params));
        }
    }
    out
}

/// The product `C prod_j f_j` of a [`Link::Log`] factor program `log(C * f_1 * ... * f_k)`
/// (its leading constant `C`, the first product, then the factors, each joined by a
/// product, under the final `log`), as a program of `y` itself: the factors' product with
/// `C` as the output scale. `None` for any other form.
fn unlogged(program: &Program, params: &[f64]) -> Option<(Program, Vec<f64>)> {
    let nodes = &program.nodes;
    let n = nodes.len();
    if n < 4 || nodes[n - 1] != Node::Op(Op::Log) || nodes[0] != Node::Const {
        return None;
    }
    // the product joining `C` to the first factor: the first `Mul` whose left subtree is
    // the leading constant alone
    let children = program.children();
    let join = (1..n - 1).find(|&i| nodes[i] == Node::Op(Op::Mul) && children[i][0] == 0)?;
    let kept: Vec<Node> = nodes[1..n - 1]
        .iter()
        .enumerate()
        .filter(|&(i, _)| i + 1 != join)
        .map(|(_, node)| *node)
        .collect();
    // the constants: `C` becomes the output scale, the offset is 0, the factors' follow
    let c = *params.get(2)?;
    let mut out = vec![c, 0.0];
    out.extend_from_slice(params.get(3..)?);
    let program = Program {
        nodes: kept,
        affine: false,
    };
    (program.n_params() == out.len()).then_some((program, out))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SearchConfig;
    use crate::search::fitting::variance;

    #[test]
    fn a_log_product_is_read_back_as_the_product_itself() {
        // y = 2 a^0.5 exp(0.3 b), fitted as log(C prod f) to ln y: the product of the
        // unlogged program is exp of the log program's output on every row
        let a: Vec<f64> = (0..40).map(|i| 1.0 + (i * 7 % 40) as f64).collect();
        let b: Vec<f64> = (0..40).map(|i| (i * 11 % 40) as f64 / 10.0).collect();
        let ln_y: Vec<f64> = a
            .iter()
            .zip(&b)
            .map(|(a, b)| (2.0 * a.sqrt() * (0.3 * b).exp()).ln())
            .collect();
        let data = Table::new(vec!["a".into(), "b".into()], vec![a, b]).expect("table");
        let fit = fit_factors(&data, &ln_y, Link::Log, &FactorConfig::default()).expect("fit");
        assert_eq!(fit.factors.len(), 2);
        let (program, params) =
            unlogged(&fit.model.program, &fit.model.params).expect("a log product");
        assert_ne!(program.nodes.last(), Some(&Node::Op(Op::Log)));
        let product = crate::Model::new(data.names().to_vec(), program, params)
            .expect("model")
            .predict(&data)
            .expect("predict");
        let logged = fit.model.predict(&data).expect("predict");
        for (p, l) in product.iter().zip(&logged) {
            assert!((p.ln() - l).abs() < 1e-12, "{p} vs exp({l})");
        }
        // another form is not a log product
        assert!(
            unlogged(
                &Program {
                    nodes: vec![Node::Var(0)],
                    affine: false
                },
                &[1.0, 0.0]
            )
            .is_none()
        );
    }

    #[test]
    fn a_product_of_powers_is_offered_with_its_exponents() {
        // y = 3 a^0.75 / b on 30 rows: the product candidate is exact
        let a: Vec<f64> = (0..30).map(|i| 1.0 + (i * 7 % 30) as f64).collect();
        let b: Vec<f64> = (0..30).map(|i| 2.0 + (i * 11 % 30) as f64 / 3.0).collect();
        let y: Vec<f64> = a
            .iter()
            .zip(&b)
            .map(|(a, b)| 3.0 * a.powf(0.75) / b)
            .collect();
        let data = Table::new(vec!["a".into(), "b".into()], vec![a, b]).expect("table");
        let cfg = SearchConfig::default();
        let valid = cfg.check().expect("valid");
        let problem = Problem::all_rows(&data, &y, variance(&y), &valid);
        let ops: Vec<Op> = Op::ALL.to_vec();
        let free = crate::Nesting::none().rules().expect("rules");
        let c = factor_models(&problem, &ops, &free);
        let best = c
            .iter()
            .min_by(|p, q| p.mse.total_cmp(&q.mse))
            .expect("a candidate");
        assert!(best.mse < 1e-12 * variance(&y), "mse {}", best.mse);
        assert!(
            best.program
                .nodes
                .contains(&crate::program::Node::Op(Op::Pow))
        );
        // with only add and sub allowed there is no product, and no sum of anything
        // but powers and lines
        let few = factor_models(&problem, &[Op::Add, Op::Sub], &free);
        assert!(
            few.iter()
                .all(|f| !f.program.nodes.contains(&crate::program::Node::Op(Op::Exp)))
        );
    }
}
