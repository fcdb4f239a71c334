//! The baseline regressors of the paper's Table 3, behind one [`Regressor`] trait.
//!
//! * [`LinearRegression`]: least squares with intercept (SVD via faer).
//! * [`LassoCv`] (and [`Lasso`]): coordinate descent with alpha chosen by 3-fold CV,
//!   a step-by-step port of scikit-learn's `LassoCV(cv=3)`.
//! * [`DecisionTree`]: best-first tree with `max_leaf_nodes` (the paper's 5, 6, 8 leaves),
//!   scikit-learn's split rule.
//! * [`RandomForest`]: 200 bootstrap trees, seed 42, built in parallel, identical for any
//!   thread count.
//! * [`GradientBoosting`]: scikit-learn's `HistGradientBoostingRegressor` at its defaults
//!   (quantile bins, leaf-wise trees of 31 leaves, 100 iterations), one of the black boxes
//!   `hxai hybrid compare` sets beside the hybrid.
//! * [`SymbolicRegressor`]: `hxai_symreg::search` behind the same trait.
//! * Every model takes its features as an `hxai_table::Table` (re-exported as [`Table`]);
//!   the ones that walk rows make their row-major copy inside. [`cross_validate`] runs any
//!   model over the splits of `hxai-eval`; [`table3_models`] lists the paper's line-up and
//!   [`compare`] fits and scores a line-up on one split (the paper's Table 3).
//!
//! Design decision: every model is written here rather than taken from linfa or smartcore,
//! because the point of Table 3 is comparison with scikit-learn's numbers, so the models
//! must reproduce scikit-learn's algorithms (its alpha grid, fold layout, coordinate order
//! and stopping rule; its best-first growth and threshold rule), not merely solve the same
//! problem.
//!
//! ```
//! use hxai_baselines::{LinearRegression, Regressor, Table};
//!
//! let x = Table::new(
//!     vec!["a".into(), "b".into()],
//!     vec![vec![0.0, 1.0, 2.0, 3.0], vec![1.0, 0.0, 2.0, 1.0]],
//! )?;
//! let y: Vec<f64> = (0..x.n_rows()).map(|i| x.row(i)).map(|r| 1.0 + 2.0 * r[0] - r[1]).collect();
//! let mut m = LinearRegression::new();
//! m.fit(&x, &y)?;
//! assert!((m.coef()[0] - 2.0).abs() < 1e-12 && (m.intercept() - 1.0).abs() < 1e-12);
//! assert_eq!(m.name(), "linear");
//! # Ok::<(), hxai_baselines::BaselineError>(())
//! ```
#![deny(missing_docs)]

mod boosting;
mod compare;
mod cv;
mod error;
mod forest;
mod lasso;
mod linear;
mod matrix;
mod symbolic;
mod tree;

pub use boosting::{AUTO_EARLY_STOPPING_ROWS, EarlyStopping, GradientBoosting};
pub use compare::{Comparison, compare};
pub use cv::cross_validate;
pub use error::BaselineError;
pub use forest::RandomForest;
pub use hxai_table::{Par, Table, TableError};
pub use lasso::{Lasso, LassoCv};
pub use linear::LinearRegression;
pub use symbolic::SymbolicRegressor;
pub use tree::DecisionTree;

/// A regression model: fit on a feature matrix and a target, predict one value per row.
///
/// Implemented by every baseline here and by the symbolic-regression adapter, so the
/// comparison code treats all models alike.
pub trait Regressor {
    /// Short, stable name (e.g. `linear`, `lasso_cv`, `tree_5`, `forest`).
    fn name(&self) -> &str;

    /// Fits the model on the rows of `x` (one column per feature) and targets `y`.
    ///
    /// # Errors
    /// Empty data, mismatched lengths, non-finite targets, invalid hyper-parameters.
    fn fit(&mut self, x: &Table, y: &[f64]) -> Result<(), BaselineError>;

    /// Predicts one value per row of `x` (the columns of the fit, in its order).
    ///
    /// # Errors
    /// Not fitted, wrong number of features.
    fn predict(&self, x: &Table) -> Result<Vec<f64>, BaselineError>;
}

/// What a long computation of this crate ([`compare`], [`cross_validate`]) reports after
/// each step: `done` of `total` models or folds finished.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    /// Steps finished.
    pub done: usize,
    /// Steps in all.
    pub total: usize,
}

/// The paper's Table 3 baselines, unfitted, in table order: `linear`, `lasso_cv`,
/// `tree_5`, `tree_6`, `tree_8`, `forest` (forest seeded with `seed`).
pub fn table3_models(seed: u64) -> Vec<Box<dyn Regressor>> {
    vec![
        Box::new(LinearRegression::new()),
        Box::new(LassoCv::new()),
        Box::new(DecisionTree::with_max_leaf_nodes(5)),
        Box::new(DecisionTree::with_max_leaf_nodes(6)),
        Box::new(DecisionTree::with_max_leaf_nodes(8)),
        Box::new(RandomForest::with_seed(seed)),
    ]
}
