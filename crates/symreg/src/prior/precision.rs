//! The constants' part of a model's description length under the laws prior: each
//! constant written to the precision the rows pin it down to (Bartlett, Desmond and
//! Ferreira's MDL), in place of BIC's `ln n / 2` per constant.
use super::{LawPrior, Prior};
use crate::Table;
use crate::eval::Evaluator;
use crate::model::Model;
use serde::{Deserialize, Serialize};

/// A model's description length in its two parts, in nats: what `--criterion mdl` charged
/// it beside its loss (`hxai sr --json`'s `codelength` on the selected model, each model of
/// the Pareto front and each alternative; the Python `sr_fit`'s likewise).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Codelengths {
    /// Its structure: `-ln P` of its tokens under the model of written laws
    /// ([`Prior::Laws`]), or `ln B` per unit of complexity ([`Prior::Uniform`], `B` the
    /// symbols it is written in: the operators and the inputs, at least 2).
    pub structure: f64,
    /// Its constants: each written to the precision the rows pin it down to, an exact one
    /// as a number ([`Prior::Laws`]); `ln(n) / 2` for each fitted one ([`Prior::Uniform`],
    /// BIC's charge).
    pub parameters: f64,
}

impl Codelengths {
    /// The two codelengths of `m` under `prior`, for a search over `symbols` symbols (its
    /// operators and inputs), its constants' precision read on `data` against `y`; `None`
    /// when `m` cannot be evaluated there.
    pub fn of(
        m: &Model,
        prior: Prior,
        symbols: usize,
        (data, y): (&Table, &[f64]),
    ) -> Option<Self> {
        let fitted = m
            .params
            .iter()
            .filter(|&&v| !crate::uncertainty::is_exact(v))
            .count();
        let lengths = match prior {
            Prior::Laws => {
                let n = y.len().max(1) as f64;
                let mean = y.iter().sum::<f64>() / n;
                let var = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n;
                Self::laws(m, (data, y), if var > 0.0 { var } else { 1.0 })
            }
            Prior::Uniform => Self {
                structure: m.complexity as f64 * (symbols.max(2) as f64).ln(),
                parameters: fitted as f64 * (y.len().max(1) as f64).ln() / 2.0,
            },
        };
        (lengths.structure.is_finite() && lengths.parameters.is_finite()).then_some(lengths)
    }

    /// The two codelengths of `m` under [`Prior::Laws`]: what the selection charges (under
    /// `mdl`) and picks by (under `cv`), `y_var` the target's variance that floors the
    /// residual one; a part is infinite where `m` cannot be evaluated on `data`.
    pub(crate) fn laws(m: &Model, (data, y): (&Table, &[f64]), y_var: f64) -> Self {
        Self {
            structure: LawPrior::builtin().codelength_program(&m.program),
            parameters: precision_codelength(m, data, y, y_var),
        }
    }
}

/// The codelength in nats of the constants of `m` (Bartlett, Desmond and Ferreira's
/// description length, issue 65): an exact one `ln(1 + |v|)`; for each constant that is not
/// exact, at its precision, `ln|theta| + ln(I)/2 - ln(3)/2`, `I` the Fisher information of the constant alone
/// (`(J^T J)_ii / s^2`, `s^2` the mean squared error, floored as the loss is), each term at
/// least 0 (a constant the rows cannot tell from 0 costs nothing to write: it is 0 to its
/// precision). Infinite when the model cannot be evaluated on `data`.
fn precision_codelength(m: &Model, data: &Table, y: &[f64], y_var: f64) -> f64 {
    let Ok(cols) = m.columns(data) else {
        return f64::INFINITY;
    };
    // an exact constant (a whole or half number the search snapped to) is written as a
    // number: `ln(1 + |v|)` nats (0 for 0, ln 2 for 1; 8.4 for 4267), as exhaustive SR
    // charges its integers, so a snapped `-4267*a/(a - 1806)` does not come for free
    let exact: f64 = m
        .params
        .iter()
        .filter(|v| crate::uncertainty::is_exact(**v))
        .map(|v| v.abs().ln_1p())
        .sum();
    let free: Vec<usize> = (0..m.params.len())
        .filter(|&i| !crate::uncertainty::is_exact(m.params[i]))
        .collect();
    if free.is_empty() {
        return exact;
    }
    let k = free.len();
    let (mut jtj, mut jtr) = (vec![0.0; k * k], vec![0.0; k]);
    let mut ev = Evaluator::new(&m.program);
    let mse = crate::fit::Unknowns::Free(&free).normal_equations(
        &mut ev,
        crate::eval::Inputs {
            prog: &m.program,
            params: &m.params,
            cols: &cols,
        },
        y,
        &mut jtj,
        &mut jtr,
    );
    if !mse.is_finite() {
        return f64::INFINITY;
    }
    let s2 = mse.max(PRECISION_FLOOR * y_var);
    exact
        + free
            .iter()
            .enumerate()
            .map(|(a, &i)| {
                let info = jtj[a * k + a] / s2;
                let bits = m.params[i].abs().ln() + 0.5 * info.ln() - 0.5 * 3f64.ln();
                if bits.is_finite() { bits.max(0.0) } else { 0.0 }
            })
            .sum::<f64>()
}

/// The floor of the residual variance, over the target's, in [`precision_codelength`]: the
/// loss's own floor, so an exact fit's constants are not charged without bound.
const PRECISION_FLOOR: f64 = 1e-12;

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::program::{Node, Program};

    /// A constant costs more to write the more precisely the rows pin it down: the slope of
    /// `3.7 x` under scatter 0.1 costs about `ln(10)` = 2.3 nats more than under scatter 1,
    /// an exact fit is charged at the loss's floor (finite), and exact constants cost what
    /// writing the number costs.
    #[test]
    fn a_constant_costs_its_precision() {
        let x: Vec<f64> = (0..50).map(f64::from).collect();
        let wiggle: Vec<f64> = (0..50).map(|i| (f64::from(i) * 2.39).sin()).collect();
        let data = Table::new(vec!["x".into()], vec![x.clone()]).unwrap();
        // scale 1 and the biases exact: the slope 3.7 is the one fitted constant
        let m = Model::new(
            vec!["x".into()],
            Program {
                nodes: vec![Node::Var(0)],
                affine: true,
            },
            vec![1.0, 0.5, 3.7, 0.0],
        )
        .unwrap();
        let y_at = |s: f64| -> Vec<f64> {
            x.iter()
                .zip(&wiggle)
                .map(|(v, w)| 0.5 + 3.7 * v + s * w)
                .collect()
        };
        let var = 100.0;
        let (fine, coarse) = (
            precision_codelength(&m, &data, &y_at(0.1), var),
            precision_codelength(&m, &data, &y_at(1.0), var),
        );
        assert!(
            ((fine - coarse) - 10f64.ln()).abs() < 0.05,
            "{fine} {coarse}"
        );
        let exact = precision_codelength(&m, &data, &y_at(0.0), var);
        assert!(exact.is_finite() && exact > fine);
        let flat = Model::new(
            Vec::new(),
            Program {
                nodes: vec![Node::Const],
                affine: true,
            },
            vec![1.0, 0.0, 2.0],
        )
        .unwrap();
        // its exact constants written as numbers: 1, 0 and 2
        let numbers = 2f64.ln() + 3f64.ln();
        assert!((precision_codelength(&flat, &data, &y_at(0.1), var) - numbers).abs() < 1e-12);
    }
}
