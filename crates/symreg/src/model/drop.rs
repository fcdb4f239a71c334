//! Dropping a constant's term from a fitted model ([`Model::without_constant`]) and
//! refitting a model's constants on other rows ([`Model::refitted`]): what a hybrid's "every
//! constant earns its place" rule (issue 64) weighs a model against.
use super::{Model, is_exact, prune_snapped};
use crate::eval::Evaluator;
use crate::fit::{LmSettings, Unknowns, levenberg_marquardt};
use crate::program::{Node, Program};
use crate::{SrError, Table};

/// Iterations of the refits here: those of [`Model::uncertainty`]'s refit.
const LM_ITERATIONS: usize = 200;
/// Relative tolerance of the refits here.
const LM_TOLERANCE: f64 = 1e-12;

impl Model {
    /// This model with program parameter `i` set to 0, the terms that kills pruned (`0 * a`
    /// is 0, `a + 0` is `a`, an operator over constants one constant), and the other
    /// constants that are not exact (whole and half numbers stay, as in
    /// [`Model::uncertainty`]) refitted on `data`, `target`. Parameter 0 is the output
    /// scale: without it the model is one constant. The features are those the pruned
    /// program still reads. `None` when the refit has no finite loss.
    ///
    /// # Errors
    /// [`SrError::InvalidConfig`] for an `i` past the parameters; those of
    /// [`Model::predict`] for a missing column, and [`SrError::TargetLength`].
    pub fn without_constant(
        &self,
        i: usize,
        data: &Table,
        target: &[f64],
    ) -> Result<Option<Model>, SrError> {
        self.check()?;
        if i >= self.params.len() {
            return Err(SrError::InvalidConfig(format!(
                "parameter {i} of a model with {} parameters",
                self.params.len()
            )));
        }
        let (program, params, fixed) = if i == 0 {
            (
                Program {
                    nodes: vec![Node::Const],
                    affine: self.program.affine,
                },
                vec![1.0, 0.0, self.params[1]],
                vec![true, true, false],
            )
        } else {
            let mut params = self.params.clone();
            params[i] = 0.0;
            let mut fixed: Vec<bool> = params.iter().map(|&v| is_exact(v)).collect();
            fixed[i] = true;
            prune_snapped(&self.program, &params, &fixed)
        };
        let model = compact(&self.feature_names, program, params)?;
        model.refit_free(data, target, &fixed)
    }

    /// This model with its constants that are not exact refitted on `data`, `target` (rows
    /// other than those it was fitted on: a fold of a cross-validation), from its own values;
    /// `None` when the refit has no finite loss.
    ///
    /// # Errors
    /// As [`Model::without_constant`].
    pub fn refitted(&self, data: &Table, target: &[f64]) -> Result<Option<Model>, SrError> {
        self.check()?;
        let fixed: Vec<bool> = self.params.iter().map(|&v| is_exact(v)).collect();
        self.refit_free(data, target, &fixed)
    }

    /// Refits the parameters not marked `fixed` on `data`, `target`.
    fn refit_free(
        &self,
        data: &Table,
        target: &[f64],
        fixed: &[bool],
    ) -> Result<Option<Model>, SrError> {
        if target.len() != data.n_rows() {
            return Err(SrError::TargetLength {
                target: target.len(),
                data: data.n_rows(),
            });
        }
        let cols = self.columns(data)?;
        let free: Vec<usize> = (0..self.params.len()).filter(|&k| !fixed[k]).collect();
        let mut params = self.params.clone();
        let mut ev = Evaluator::new(&self.program);
        let mut mse = ev.mse(&self.program, &params, &cols, target);
        if !free.is_empty() && free.len() < target.len() {
            let start = params.clone();
            let fitted = levenberg_marquardt(
                &self.program,
                &mut params,
                Unknowns::Free(&free),
                &cols,
                target,
                &LmSettings::new(LM_ITERATIONS, LM_TOLERANCE),
                &mut ev,
            );
            if fitted.is_finite() && (!mse.is_finite() || fitted <= mse) {
                mse = fitted;
            } else {
                params = start;
            }
        }
        if !mse.is_finite() {
            return Ok(None);
        }
        let mut out = Model::new(self.feature_names.clone(), self.program.clone(), params)?;
        out.train_mse = mse;
        Ok(Some(out))
    }
}

/// The model of `program` over the features of `names` it still reads, renumbered.
fn compact(names: &[String], program: Program, params: Vec<f64>) -> Result<Model, SrError> {
    let (feature_names, program) = super::over_used_columns(&program, names);
    Model::new(feature_names, program, params)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::ops::Op;

    /// `a*x + b*z` (as the search writes it: affine inputs) fitted to rows where `z` has no
    /// effect: dropping `z`'s weight leaves a model over `x` alone whose constants refit to
    /// the truth, and dropping the output scale leaves the mean.
    #[test]
    fn a_dropped_weight_removes_its_term_and_the_rest_refits() {
        let x: Vec<f64> = (0..40).map(|i| f64::from(i) / 10.0).collect();
        let z: Vec<f64> = (0..40).map(|i| f64::from((i * 7) % 11)).collect();
        let y: Vec<f64> = x.iter().map(|v| 3.0 * v + 1.0).collect();
        let data = Table::new(vec!["x".into(), "z".into()], vec![x.clone(), z]).unwrap();
        let program = Program {
            nodes: vec![Node::Var(0), Node::Var(1), Node::Op(Op::Add)],
            affine: true,
        };
        // scale, offset, then (weight, bias) of each input
        let m = Model::new(
            vec!["x".into(), "z".into()],
            program,
            vec![1.0, 0.3, 2.9, 0.2, 0.01, 0.4],
        )
        .unwrap();
        // z's weight is parameter 4
        let dropped = m.without_constant(4, &data, &y).unwrap().unwrap();
        assert_eq!(dropped.feature_names, vec!["x".to_string()]);
        let p = dropped.predict(&data).unwrap();
        for (a, b) in p.iter().zip(&y) {
            assert!((a - b).abs() < 1e-8, "{a} vs {b}");
        }
        // dropping x's weight (parameter 2) cannot explain y: a worse fit, still finite
        let worse = m.without_constant(2, &data, &y).unwrap().unwrap();
        assert_eq!(worse.feature_names, vec!["z".to_string()]);
        assert!(worse.train_mse > 0.1);
        // the output scale: one constant, the mean of y
        let flat = m.without_constant(0, &data, &y).unwrap().unwrap();
        assert!(flat.feature_names.is_empty());
        let mean = y.iter().sum::<f64>() / y.len() as f64;
        assert!((flat.predict(&data).unwrap()[0] - mean).abs() < 1e-9);
        assert!(m.without_constant(6, &data, &y).is_err());
    }

    /// A refit on other rows moves the constants to those rows' optimum.
    #[test]
    fn a_refit_follows_the_rows() {
        let x: Vec<f64> = (0..20).map(f64::from).collect();
        let y: Vec<f64> = x.iter().map(|v| 0.7 * v - 0.3).collect();
        let data = Table::new(vec!["x".into()], vec![x]).unwrap();
        let m = Model::new(
            vec!["x".into()],
            Program {
                nodes: vec![Node::Var(0)],
                affine: true,
            },
            vec![1.0, 0.1, 0.6, 0.1],
        )
        .unwrap();
        let r = m.refitted(&data, &y).unwrap().unwrap();
        assert!(r.train_mse < 1e-12);
    }
}
