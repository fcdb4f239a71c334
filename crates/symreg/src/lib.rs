//! Symbolic regression for hxai: QLattice-style path sampling and genetic programming over
//! compact postfix programs, with constants fitted by Levenberg-Marquardt.
//!
//! The paper models the correction factor of a physics model with Abzu's QLattice. This crate
//! is our own engine for the same job, usable on any table: give it a [`Table`] of named
//! columns and a target, get back a [`SearchResult`] with the selected [`Model`] and the Pareto
//! front of complexity against loss. Models print as plain text, sympy-parseable text and
//! LaTeX, serialise to JSON, and predict on new rows by column name.
//!
//! Main types: [`Table`] (from `hxai-table`), [`SearchConfig`] (with [`Strategy`] and [`Criterion`]),
//! [`search()`], [`SearchResult`], [`Model`], [`Progress`], [`fit_structure`]. The
//! strategies (QLattice-style path sampling from a learned field, island genetic programming
//! with age-regularised evolution, both sharing one archive, and random search as the
//! baseline) sit behind an internal trait: [`Strategy`] chooses between them, and the
//! [`search` module](mod@search) maps the engine file by file. Complexity counts input
//! leaves and operators (each operator 1 unless [`SearchConfig::operator_complexity`] says
//! otherwise), capped by [`SearchConfig::complexity_cap`], which grows with the number of
//! inputs.
//!
//! Trust in the numbers: [`Model::uncertainty`] gives a model's constants as a template with
//! named parameters (`p0`, `p1`, ...), their covariance `s^2 (J^T J)^-1`, standard errors and
//! 95 % intervals, and [`Model::prediction_intervals`] the delta-method intervals of its
//! predictions ([`uncertainty`] says what is assumed and how snapped constants are treated).
//! [`stability()`] reruns the search on bootstrap resamples and reports how often each
//! feature and each structure is selected.
//!
//! Design decision: parameters live at the leaves and at the output only. Every input enters
//! as `w * x + b` and every model as `scale * root + offset` (QLattice's parameterisation), so
//! the paper's `29.4 exp(-(a^2 + b^2)) - 9.71` with `a = w1 (f1 - c1)(f6 - c6)` is
//! `gaussian2(mul(f1, f6), f2)`, complexity 5. Because parameters sit only there, the
//! Jacobian for Levenberg-Marquardt comes from one adjoint sweep over the batch buffers the
//! evaluator already filled, and constants converge in a handful of iterations instead of
//! the many epochs of gradient descent QLattice needs.
//!
//! Determinism: candidates are fitted in parallel with rayon (on the threads
//! [`SearchConfig::par`] chooses, by default the caller's pool), each with its own generator
//! seeded from `(seed, round, index)`, and results are collected in proposal order, so the
//! outcome is bit-identical for any thread count.
//!
//! ```
//! use hxai_symreg::{SearchConfig, Table, search};
//! let x: Vec<f64> = (0..200).map(|i| 0.5 + i as f64 / 100.0).collect();
//! let y: Vec<f64> = x.iter().map(|v| 3.0 * v * v + 1.0).collect();
//! let data = Table::new(vec!["x".into()], vec![x])?;
//! let cfg = SearchConfig { epochs: 2, candidates_per_epoch: 200, ..SearchConfig::default() };
//! let res = search(&data, &y, &cfg, &mut |_| {})?;
//! let pred = res.best.predict(&data)?;
//! assert!((pred[10] - y[10]).abs() < 1e-6 * y[10].abs());
//! # Ok::<(), hxai_symreg::SrError>(())
//! ```
#![deny(missing_docs)]

#[doc(hidden)]
pub mod bench_programs;
mod bootstrap;
pub mod canonical;
pub mod consensus;
mod determined;
pub mod enclosure;
mod error;
pub mod eval;
pub mod expr;
pub mod factors;
pub mod fit;
pub mod infix;
mod model;
pub mod nesting;
pub mod ops;
pub mod prior;
pub mod program;
pub mod report;
pub mod search;
pub mod stability;
mod sympy_names;
pub mod uncertainty;
pub mod units;
pub mod vmath;

pub use determined::determined;
pub use error::SrError;
pub use hxai_table::{Par, Table, TableError, TableView};
pub use model::Model;
pub use nesting::Nesting;
pub use ops::Op;
pub use program::{ComplexityMeasure, Node, Program};
pub use report::{
    Alternative, ConstantsSummary, FittedReport, ModelForms, ModelSummary, SearchReport,
    SelectionReport,
};
pub use search::{
    Criterion, DEFAULT_OPERATORS, ErrorModel, FEW_ROWS, LAW_OPERATORS, PAPER_OPERATORS, Prior,
    Progress, RandomStart, SearchConfig, SearchResult, Strategy, ValidSearch, fit_structure,
    search, search_checked,
};
pub use stability::{Stability, stability};
pub use uncertainty::{ParamEstimate, Uncertainty};
