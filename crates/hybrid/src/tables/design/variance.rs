//! Each candidate equation's prediction variance for `hxai hybrid design`: the hybrid's
//! sensitivity to its constants on the candidates ([`Gradients`], from a model file's
//! covariance), each equation's own outcome variance, and Box and Hill's (1967) criterion
//! that weighs the equations' disagreement by them.

use super::super::CorrectionForm;
use super::super::model::columns_of;
use crate::HybridError;
use hxai_symreg::Table;

/// The hybrid's sensitivity to its constants at every candidate: what the precision goal
/// and the discriminate goal's weighting read from the model file's uncertainty.
pub(super) struct Gradients {
    /// Each candidate's gradient of the prediction with respect to the constants.
    pub(super) grads: Vec<Vec<f64>>,
    /// The constants' covariance.
    pub(super) cov: Vec<Vec<f64>>,
    /// The residual variance.
    pub(super) s2: f64,
}

impl Gradients {
    /// The variance of the hybrid's prediction at candidate `i` from its constants'
    /// uncertainty, `g^T C g`.
    pub(super) fn variance(&self, i: usize) -> f64 {
        let g = &self.grads[i];
        self.cov
            .iter()
            .zip(g)
            .map(|(row, gi)| gi * row.iter().zip(g).map(|(c, gj)| c * gj).sum::<f64>())
            .sum()
    }
}

/// [`Gradients`] of the hybrid template of `u` (the model file's `hybrid.uncertainty`) on
/// `candidates`: central differences of the hybrid equation in each constant.
///
/// # Errors
/// A template that does not compile, a column the candidates lack, a covariance of the
/// wrong shape.
pub(super) fn gradients(
    u: &hxai_symreg::Uncertainty,
    candidates: &Table,
) -> Result<Gradients, HybridError> {
    let m = candidates.n_rows();
    let constants: std::collections::BTreeMap<String, f64> = u
        .params
        .iter()
        .map(|(name, p)| (name.clone(), p.value))
        .collect();
    let compiled = hxai_symreg::infix::compile_text(&u.template, &constants).map_err(|e| {
        HybridError::InvalidConfig(format!("the hybrid equation does not compile: {e}"))
    })?;
    let cols = columns_of(candidates, &compiled.inputs, "input of the hybrid equation")?;
    // the gradient of the prediction with respect to each constant, on every candidate
    let k = u.params.len();
    let mut grad: Vec<Vec<f64>> = Vec::with_capacity(k);
    for (name, p) in &u.params {
        let slots = compiled.slots.get(name).cloned().unwrap_or_default();
        let h = 1e-6 * p.value.abs().max(1e-3);
        let at = |v: f64| {
            let mut c = compiled.clone();
            for &s in &slots {
                c.params[s] = v;
            }
            c.eval_columns(&cols, m)
        };
        let (hi, lo) = (at(p.value + h), at(p.value - h));
        grad.push(
            hi.iter()
                .zip(&lo)
                .map(|(a, b)| (a - b) / (2.0 * h))
                .collect(),
        );
    }
    let cov = u.covariance.clone();
    if cov.len() != k || cov.iter().any(|r| r.len() != k) {
        return Err(HybridError::InvalidConfig(format!(
            "the model file's covariance is not {k} x {k}, one row per constant"
        )));
    }
    let s2 = u.residual_variance;
    // each candidate's gradient, gathered once
    let grads: Vec<Vec<f64>> = (0..m)
        .map(|i| grad.iter().map(|g| g[i]).collect())
        .collect();
    Ok(Gradients { grads, cov, s2 })
}

/// Box and Hill's (1967) expected information for discriminating at one setting, with equal
/// prior weights (the constant factor dropped): over each pair of equations with predictions
/// `y` and outcome variances `v`, `(v_a - v_b)^2 / (v_a v_b) + (y_a - y_b)^2 (1/v_a + 1/v_b)`.
/// With one variance for all it is the squared disagreements over it, twice.
pub(super) fn box_hill(y: &[f64], v: &[f64]) -> f64 {
    let mut sum = 0.0;
    for a in 0..y.len() {
        for b in a + 1..y.len() {
            sum += (v[a] - v[b]).powi(2) / (v[a] * v[b])
                + (y[a] - y[b]).powi(2) * (1.0 / v[a] + 1.0 / v[b]);
        }
    }
    sum
}

/// Each equation's outcome variance at every candidate, `s2` plus its correction's
/// `g^T C g` times the hybrid's sensitivity to the correction there (1, the physics, or the
/// hybrid itself for an additive, multiplicative or log correction); `None` unless every
/// equation in `own` (its correction values, its constants' covariance) has a covariance
/// that evaluates on the candidates.
pub(super) fn own_variances(
    s2: f64,
    own: &[(Vec<f64>, Option<&hxai_symreg::Uncertainty>)],
    phys: &[f64],
    kind: CorrectionForm,
    candidates: &Table,
) -> Option<Vec<Vec<f64>>> {
    own.iter()
        .map(|(delta, u)| {
            let g = gradients((*u)?, candidates).ok()?;
            Some(
                (0..candidates.n_rows())
                    .map(|i| {
                        let dh = match kind {
                            CorrectionForm::Additive => 1.0,
                            CorrectionForm::Multiplicative => phys[i],
                            CorrectionForm::Log => phys[i] * delta[i].exp(),
                        };
                        s2 + dh * dh * g.variance(i).max(0.0)
                    })
                    .collect(),
            )
        })
        .collect()
}
