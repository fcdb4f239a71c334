//! Evaluation statistics for hxai: the numbers every model in the project is judged by.
//!
//! * [`metrics`]: [`r2`], [`rmse`], [`mae`], [`score`] (all three as [`Metrics`]),
//!   [`squared_errors`] and the paper's [`improvement_pct`]. Definitions are
//!   scikit-learn's, including `r2_score`'s rule for a constant target.
//! * [`split`]: seeded [`train_test_split`] and [`kfold`], their grouped variants
//!   [`grouped_train_test_split`] and [`grouped_kfold`] (a group — e.g. one recording — never
//!   lands on both sides), and the unshuffled [`kfold_contiguous`] that `LassoCV` uses.
//! * [`stats`]: [`summarize`] over folds ([`Summary`]: mean, sample standard deviation, a
//!   Student-t 95 % interval and, labelled as such, the normal approximation the paper used)
//!   and [`paired_t_test`] ([`TTest`]), like `scipy.stats.ttest_rel`.
//! * [`conformal`]: prediction intervals that hold in finite samples: split conformal's
//!   [`conformal_quantile`], [`cv_plus`], and the local [`ScaleModel`] that normalises scores.
//!
//! Design decision: the crate works on plain `&[f64]` slices and index lists, not on
//! models or tables. Splits return indices, so the same split can select rows of any
//! container (a feature matrix, a list of record ids) and be written into a model file.
//! Every function validates its input and returns [`EvalError`] instead of producing NaN.
//!
//! The t distribution comes from statrs. Its p-values are computed from the regularised
//! incomplete beta at the small argument `df/(df+t^2)`, which keeps full relative precision
//! for tiny p-values; its quantile is statrs' inverse polished by Newton steps on that
//! p-value function. Both are checked against scipy to 1e-10 relative.
//!
//! ```
//! use hxai_eval::{kfold, paired_t_test, rmse, summarize};
//!
//! let y = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
//! let p = [1.1, 1.9, 3.2, 3.9, 5.1, 6.0];
//! assert!(rmse(&y, &p)? < 0.2);
//!
//! let folds = kfold(y.len(), 3, 42)?;
//! assert_eq!(folds.iter().map(|f| f.test.len()).sum::<usize>(), y.len());
//!
//! let s = summarize(&[0.91, 0.93, 0.90, 0.94, 0.92])?;
//! assert!(s.ci_t.upper - s.ci_t.lower > s.ci_normal.upper - s.ci_normal.lower);
//!
//! let t = paired_t_test(&[4.0, 5.0, 6.0, 5.5], &[1.0, 1.5, 0.5, 1.2])?;
//! assert!(t.p_value < 0.01);
//! # Ok::<(), hxai_eval::EvalError>(())
//! ```
#![deny(missing_docs)]

mod check;
pub mod conformal;
mod error;
pub mod metrics;
pub mod split;
pub mod stats;

pub use conformal::{IntervalMethod, ScaleModel, conformal_quantile, conformal_rank, cv_plus};
pub use error::EvalError;
pub use metrics::{Metrics, improvement_pct, mae, r2, residuals, rmse, score, squared_errors};
pub use split::{
    Split, grouped_kfold, grouped_train_test_split, kfold, kfold_contiguous, shared_rows,
    stratified_sample, stratified_sample_spanning, train_test_split,
};
pub use stats::{
    Extent, Interval, Summary, TTest, extent, means_by_key, paired_t_test, summarize, summarize_at,
    t_two_tailed_p, t_upper_quantile,
};
