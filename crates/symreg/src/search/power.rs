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
//! itself is the primitive this setting turns on.
use super::archive::Fitted;
use super::fitting::Problem;
use super::separable::refitted;
use crate::Table;
use crate::factors::{FactorConfig, Link, Shape, Shapes, fit_factors};
use crate::nesting::NestingRules;
use crate::ops::Op;

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
/// their operator is in `ops`; the interaction `x^p y^q` where multiplication is.
fn shapes(ops: &[Op]) -> Shapes {
    let mut s = Shapes::NONE.with(Shape::Power).with(Shape::Linear);
    if ops.contains(&Op::Exp) {
        s = s.with(Shape::Exp);
    }
    if ops.contains(&Op::Log) {
        s = s.with(Shape::Log);
    }
    if ops.contains(&Op::Div) || ops.contains(&Op::Inverse) {
        s = s.with(Shape::Pole).with(Shape::Saturation);
    }
    if ops.contains(&Op::Mul) {
        s = s.with(Shape::Pair);
    }
    s
}

/// The product and the sum of factors fitted on the problem's fitting rows, each refitted
/// with every constant free (a product's offset, fixed at -1 in a correction, is free here).
/// Empty where the table is too small for two folds or larger than
/// [`POWER_LAWS_MAX_ROWS`], or no factor model fits. A model that breaks a nesting rule is
/// left out.
pub(super) fn candidates(problem: &Problem, ops: &[Op], nesting: &NestingRules) -> Vec<Fitted> {
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
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SearchConfig;
    use crate::search::fitting::variance;

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
        let problem = Problem::all_rows(&data, &y, variance(&y), &cfg);
        let ops: Vec<Op> = Op::ALL.to_vec();
        let free = crate::Nesting::none().rules().expect("rules");
        let c = candidates(&problem, &ops, &free);
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
        let few = candidates(&problem, &[Op::Add, Op::Sub], &free);
        assert!(
            few.iter()
                .all(|f| !f.program.nodes.contains(&crate::program::Node::Op(Op::Exp)))
        );
    }
}
