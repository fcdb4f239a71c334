//! Ordinary least squares with an intercept (scikit-learn's `LinearRegression`).

use crate::matrix::RowMajor;
use crate::matrix::{check_fit, check_predict};
use crate::{BaselineError, Regressor};
use faer::Mat;
use hxai_table::Table;

/// Least squares `y ~ intercept + x . coef`.
///
/// The columns and the target are centred, then the centred system is solved through a thin
/// SVD (faer), dropping singular values below `eps * s_max` like LAPACK's `gelsd` that
/// scikit-learn calls: full-rank data give the ordinary solution, rank-deficient data the
/// minimum-norm one, and neither case divides by zero.
#[derive(Debug, Clone, Default)]
pub struct LinearRegression {
    coef: Vec<f64>,
    intercept: f64,
    fitted: Option<usize>,
}

impl LinearRegression {
    /// An unfitted model.
    pub fn new() -> Self {
        Self::default()
    }

    /// Fitted coefficients, one per feature (empty before `fit`).
    pub fn coef(&self) -> &[f64] {
        &self.coef
    }

    /// Fitted intercept (0 before `fit`).
    pub fn intercept(&self) -> f64 {
        self.intercept
    }
}

/// Column means and the centred columns-major copy of `x`.
pub(crate) fn centre(x: &Table) -> (Vec<f64>, Vec<Vec<f64>>) {
    let n = x.n_rows() as f64;
    let mut cols = x.columns().to_vec();
    let means: Vec<f64> = cols.iter().map(|c| c.iter().sum::<f64>() / n).collect();
    for (c, m) in cols.iter_mut().zip(&means) {
        c.iter_mut().for_each(|v| *v -= m);
    }
    (means, cols)
}

impl Regressor for LinearRegression {
    fn name(&self) -> &str {
        "linear"
    }

    fn fit(&mut self, x: &Table, y: &[f64]) -> Result<(), BaselineError> {
        check_fit(x, y)?;
        let (n, p) = (x.n_rows(), x.n_cols());
        let (x_mean, cols) = centre(x);
        let y_mean = y.iter().sum::<f64>() / n as f64;
        let a = Mat::<f64>::from_fn(n, p, |i, j| cols[j][i]);
        let svd = a.thin_svd().map_err(|e| BaselineError::Numerical {
            what: "SVD of the centred design matrix",
            detail: format!("{e:?}"),
        })?;
        let (u, s, v) = (svd.U(), svd.S().column_vector(), svd.V());
        let k = s.nrows();
        let s_max = if k > 0 { s[0] } else { 0.0 };
        let cutoff = f64::EPSILON * s_max;
        let mut coef = vec![0.0; p];
        for r in 0..k {
            if s[r] <= cutoff || s[r] == 0.0 {
                continue;
            }
            let uty: f64 = (0..n).map(|i| u[(i, r)] * (y[i] - y_mean)).sum();
            let scale = uty / s[r];
            for (j, c) in coef.iter_mut().enumerate() {
                *c += v[(j, r)] * scale;
            }
        }
        self.intercept = y_mean - x_mean.iter().zip(&coef).map(|(m, c)| m * c).sum::<f64>();
        self.coef = coef;
        self.fitted = Some(p);
        Ok(())
    }

    fn predict(&self, x: &Table) -> Result<Vec<f64>, BaselineError> {
        check_predict(self.name(), self.fitted, x)?;
        Ok(linear_predict(x, &self.coef, self.intercept))
    }
}

pub(crate) fn linear_predict(x: &Table, coef: &[f64], intercept: f64) -> Vec<f64> {
    RowMajor::of(x)
        .rows()
        .map(|r| intercept + r.iter().zip(coef).map(|(a, b)| a * b).sum::<f64>())
        .collect()
}
