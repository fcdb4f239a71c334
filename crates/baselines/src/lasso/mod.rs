//! Lasso by cyclic coordinate descent, and `LassoCv`, a port of scikit-learn's
//! `LassoCV(cv=k)`.
//!
//! Both solvers follow `sklearn/linear_model/_cd_fast.pyx` (version 1.9) step by step:
//! the same objective `1/(2n) ||y - Xw||^2 + alpha ||w||_1` on centred data, the same cyclic
//! coordinate order, the same stopping rule (largest update relative to largest
//! coefficient below `tol`, then a duality gap below `tol * ||y||^2`) and the same gap-safe
//! screening. Matching the iteration, not only the optimum, is what lets the coefficients
//! agree with scikit-learn to 1e-6 even though `tol = 1e-4` stops well before convergence.
//!
//! The solvers themselves are in `descent`; this module holds the two models and the
//! cross-validated alpha path.

mod descent;

use crate::linear::{centre, linear_predict};
use crate::matrix::{check_fit, check_predict};
use crate::{BaselineError, Regressor};
use descent::{cd_gram, cd_plain, dot};
use hxai_table::{Par, Table};
use rayon::prelude::*;

fn check_solver(tol: f64, max_iter: usize) -> Result<(), BaselineError> {
    if !(tol.is_finite() && tol >= 0.0) {
        return Err(BaselineError::InvalidParameter {
            what: "tol",
            detail: format!("must be >= 0, got {tol}"),
        });
    }
    if max_iter == 0 {
        return Err(BaselineError::InvalidParameter {
            what: "max_iter",
            detail: "must be at least 1".into(),
        });
    }
    Ok(())
}

/// Lasso with a fixed `alpha` (scikit-learn's `Lasso(alpha)`), fitted from zero
/// coefficients by plain coordinate descent (scikit-learn's `enet_coordinate_descent`).
#[derive(Debug, Clone)]
pub struct Lasso {
    /// L1 penalty of `1/(2n) ||y - Xw||^2 + alpha ||w||_1`.
    pub alpha: f64,
    /// Duality-gap tolerance relative to `||y - mean(y)||^2` (default 1e-4).
    pub tol: f64,
    /// Maximum coordinate-descent sweeps (default 1000).
    pub max_iter: usize,
    coef: Vec<f64>,
    intercept: f64,
    converged: bool,
    fitted: Option<usize>,
}

impl Lasso {
    /// An unfitted Lasso with scikit-learn's defaults for `tol` and `max_iter`.
    pub fn new(alpha: f64) -> Self {
        Self {
            alpha,
            tol: 1e-4,
            max_iter: 1000,
            coef: Vec::new(),
            intercept: 0.0,
            converged: false,
            fitted: None,
        }
    }

    /// Fitted coefficients.
    pub fn coef(&self) -> &[f64] {
        &self.coef
    }

    /// Fitted intercept.
    pub fn intercept(&self) -> f64 {
        self.intercept
    }

    /// Whether the last fit reached the duality-gap tolerance within `max_iter` sweeps.
    pub fn converged(&self) -> bool {
        self.converged
    }
}

impl Regressor for Lasso {
    fn name(&self) -> &str {
        "lasso"
    }

    fn fit(&mut self, x: &Table, y: &[f64]) -> Result<(), BaselineError> {
        check_fit(x, y)?;
        check_solver(self.tol, self.max_iter)?;
        if !(self.alpha.is_finite() && self.alpha >= 0.0) {
            return Err(BaselineError::InvalidParameter {
                what: "alpha",
                detail: format!("must be >= 0, got {}", self.alpha),
            });
        }
        let n = x.n_rows();
        let (x_mean, cols) = centre(x);
        let (y_mean, yc) = centre_target(y);
        let mut w = vec![0.0; x.n_cols()];
        self.converged = cd_plain(
            &mut w,
            self.alpha * n as f64,
            &cols,
            &yc,
            self.max_iter,
            self.tol,
        );
        self.intercept = y_mean - dot(&x_mean, &w);
        self.coef = w;
        self.fitted = Some(x.n_cols());
        Ok(())
    }

    fn predict(&self, x: &Table) -> Result<Vec<f64>, BaselineError> {
        check_predict(self.name(), self.fitted, x)?;
        Ok(linear_predict(x, &self.coef, self.intercept))
    }
}

/// Lasso whose `alpha` is chosen by k-fold cross-validation over a geometric path,
/// like scikit-learn's `LassoCV(cv=k)` with its defaults.
///
/// Path: `n_alphas` values from `alpha_max = max|X^T y| / n` (centred data) down to
/// `eps * alpha_max`. Folds: unshuffled contiguous blocks ([`hxai_eval::kfold_contiguous`]).
/// On each fold the path is solved with warm starts by the Gram-matrix solver, as
/// scikit-learn does when `n_samples > n_features`; the alpha with the lowest mean test MSE
/// wins and the final model is refitted on all data from zero coefficients.
#[derive(Debug, Clone)]
pub struct LassoCv {
    /// Number of alphas on the path (default 100).
    pub n_alphas: usize,
    /// `alpha_min / alpha_max` (default 1e-3).
    pub eps: f64,
    /// Number of folds (default 3, as in the paper).
    pub cv: usize,
    /// Duality-gap tolerance (default 1e-4).
    pub tol: f64,
    /// Maximum sweeps per solve (default 1000).
    pub max_iter: usize,
    /// Threads that solve the folds (default [`Par::Current`], the caller's pool); the
    /// result does not depend on it.
    pub par: Par,
    alphas: Vec<f64>,
    mse_path: Vec<Vec<f64>>,
    model: Lasso,
}

impl Default for LassoCv {
    fn default() -> Self {
        Self {
            n_alphas: 100,
            eps: 1e-3,
            cv: 3,
            tol: 1e-4,
            max_iter: 1000,
            par: Par::Current,
            alphas: Vec::new(),
            mse_path: Vec::new(),
            model: Lasso::new(1.0),
        }
    }
}

impl LassoCv {
    /// scikit-learn's defaults with `cv = 3`.
    pub fn new() -> Self {
        Self::default()
    }

    /// The chosen alpha (after `fit`).
    pub fn alpha(&self) -> f64 {
        self.model.alpha
    }

    /// The alpha path, largest first.
    pub fn alphas(&self) -> &[f64] {
        &self.alphas
    }

    /// Test MSE per alpha (rows) and fold (columns), like `mse_path_`.
    pub fn mse_path(&self) -> &[Vec<f64>] {
        &self.mse_path
    }

    /// Coefficients of the refitted model.
    pub fn coef(&self) -> &[f64] {
        self.model.coef()
    }

    /// Intercept of the refitted model.
    pub fn intercept(&self) -> f64 {
        self.model.intercept()
    }
}

/// The mean of `y` and `y` centred on it.
fn centre_target(y: &[f64]) -> (f64, Vec<f64>) {
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    (mean, y.iter().map(|v| v - mean).collect())
}

/// numpy's `geomspace(start, stop, num)`.
fn geomspace(start: f64, stop: f64, num: usize) -> Vec<f64> {
    let (a, b) = (start.log10(), stop.log10());
    let step = if num > 1 {
        (b - a) / (num - 1) as f64
    } else {
        0.0
    };
    let mut v: Vec<f64> = (0..num).map(|i| 10f64.powf(i as f64 * step + a)).collect();
    if let Some(f) = v.first_mut() {
        *f = start;
    }
    if num > 1 {
        v[num - 1] = stop;
    }
    v
}

/// Test MSE along the alpha path for one fold.
fn fold_mse(
    x: &Table,
    y: &[f64],
    train: &[usize],
    test: &[usize],
    alphas: &[f64],
    tol: f64,
    max_iter: usize,
) -> Result<Vec<f64>, BaselineError> {
    let xt = x.select_rows(train)?;
    let yt: Vec<f64> = train.iter().map(|&i| y[i]).collect();
    let n = xt.n_rows();
    let p = xt.n_cols();
    let (x_mean, cols) = centre(&xt);
    let (y_mean, yc) = centre_target(&yt);
    let mut gram = vec![0.0; p * p];
    for a in 0..p {
        for b in 0..p {
            gram[a * p + b] = dot(&cols[a], &cols[b]);
        }
    }
    let q: Vec<f64> = cols.iter().map(|c| dot(c, &yc)).collect();
    let y_norm2 = dot(&yc, &yc);
    let xs = x.select_rows(test)?;
    let ys: Vec<f64> = test.iter().map(|&i| y[i]).collect();
    let mut w = vec![0.0; p];
    let mut out = Vec::with_capacity(alphas.len());
    for &alpha in alphas {
        cd_gram(&mut w, alpha * n as f64, &gram, &q, y_norm2, max_iter, tol);
        let intercept = y_mean - dot(&x_mean, &w);
        let pred = linear_predict(&xs, &w, intercept);
        out.push(
            pred.iter()
                .zip(&ys)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                / ys.len() as f64,
        );
    }
    Ok(out)
}

impl Regressor for LassoCv {
    fn name(&self) -> &str {
        "lasso_cv"
    }

    fn fit(&mut self, x: &Table, y: &[f64]) -> Result<(), BaselineError> {
        check_fit(x, y)?;
        check_solver(self.tol, self.max_iter)?;
        if self.n_alphas == 0 {
            return Err(BaselineError::InvalidParameter {
                what: "n_alphas",
                detail: "must be at least 1".into(),
            });
        }
        if !(self.eps.is_finite() && self.eps > 0.0) {
            return Err(BaselineError::InvalidParameter {
                what: "eps",
                detail: format!("must be > 0, got {}", self.eps),
            });
        }
        let folds = hxai_eval::kfold_contiguous(x.n_rows(), self.cv)?;
        if folds.iter().any(|f| f.train.len() < 2) {
            return Err(BaselineError::InvalidParameter {
                what: "cv",
                detail: format!(
                    "{} folds of {} rows leave fewer than 2 training rows",
                    self.cv,
                    x.n_rows()
                ),
            });
        }
        let n = x.n_rows() as f64;
        let (_, cols) = centre(x);
        let (_, yc) = centre_target(y);
        let alpha_max = cols.iter().map(|c| dot(c, &yc).abs()).fold(0.0, f64::max) / n;
        let resolution = 1e-15;
        self.alphas = if alpha_max <= resolution {
            vec![resolution; self.n_alphas]
        } else {
            geomspace(alpha_max, alpha_max * self.eps, self.n_alphas)
        };
        let per_fold: Vec<Vec<f64>> = self.par.run(|| {
            folds
                .par_iter()
                .map(|f| {
                    fold_mse(
                        x,
                        y,
                        &f.train,
                        &f.test,
                        &self.alphas,
                        self.tol,
                        self.max_iter,
                    )
                })
                .collect::<Result<_, _>>()
        })?;
        self.mse_path = (0..self.alphas.len())
            .map(|a| per_fold.iter().map(|f| f[a]).collect())
            .collect();
        let mut best = 0;
        let mut best_mse = f64::INFINITY;
        for (a, row) in self.mse_path.iter().enumerate() {
            let m = row.iter().sum::<f64>() / row.len() as f64;
            if m < best_mse {
                best_mse = m;
                best = a;
            }
        }
        let mut model = Lasso::new(self.alphas[best]);
        model.tol = self.tol;
        model.max_iter = self.max_iter;
        model.fit(x, y)?;
        self.model = model;
        Ok(())
    }

    fn predict(&self, x: &Table) -> Result<Vec<f64>, BaselineError> {
        check_predict(self.name(), self.model.fitted, x)?;
        self.model.predict(x)
    }
}
