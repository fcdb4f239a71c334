//! Baseline regressors of the paper's Table 3: linear, LassoCV, best-first tree, random forest.
#![deny(missing_docs)]
