//! Evaluation statistics for hxai: metrics, splits, cross-validation, confidence intervals, paired t-test.
#![deny(missing_docs)]
