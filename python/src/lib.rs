//! The compiled half of the `hxai` Python package: thin functions over the workspace's
//! library crates, imported by the pure-Python half (`python/hxai/*.py`) as `hxai._hxai`.
//!
//! Users never call this module directly. The scikit-learn estimators, the DataFrame
//! conversions and the argument checks that belong to Python conventions live in Python;
//! every number is computed here, by the same functions the command line calls, so results
//! equal the CLI's for the same seed and data.
//!
//! Design decisions:
//! - **Arrays cross as bytes** (little-endian `float64`, `numpy.ndarray.tobytes()` and
//!   `numpy.frombuffer`): one copy each way, no dependency on a NumPy C-API binding whose
//!   version would have to track pyo3's, and it works under the stable ABI (abi3), where
//!   the buffer protocol is unavailable before Python 3.11.
//! - **Settings and models cross as JSON**, the serde forms the CLI already writes: a fitted
//!   model is its JSON text, which is also what the Python estimators pickle.
//! - **The GIL is released** (`Python::detach`) around every computation, so a search in
//!   one thread does not stop the others.
//! - **Errors are `ValueError`s** carrying the library error's one-line message (the text
//!   the CLI prints after `Error:`); no function panics on user input.
//!
//! Entry points: `sr_fit`, `sr_predict`, `sr_intervals`, `sr_mathml`, `table_fit`, `table_compare`, `table_predict`,
//! `table_intervals`, `table_report`, `table_card`, `table_design`, `tool_predict`,
//! `tool_report`, `tool_card`, `butter`, `sosfilt`, `sosfiltfilt`, `welch`, `fit_sine`, `displacement`,
//! `features_extract`, `simulate_tool`, `simulate_case`, `defaults`, and the class
//! `StreamEstimator` (the causal estimator of `hxai_hybrid::records::stream`, which keeps state
//! between calls).
//!
//! Modules, one job each; this file only assembles them into `hxai._hxai`: `symbolic`
//! (`sr_*`), `table` (`table_*`), `tool` (`tool_*`, `StreamEstimator`), `signal`
//! (the signal functions and `features_extract`), `sim` (`simulate_*`), `settings`
//! (`defaults` and the overrides applied over them) and `convert` (bytes, tables, `n_jobs`,
//! errors).
#![deny(missing_docs)]

mod convert;
mod dynamic;
mod settings;
mod signal;
mod sim;
mod symbolic;
mod table;
mod tool;

use pyo3::prelude::*;
use settings::defaults;
use signal::{butter, displacement, features_extract, fit_sine, sosfilt, sosfiltfilt, welch};
use sim::{simulate_case, simulate_tool};
use symbolic::{sr_fit, sr_intervals, sr_mathml, sr_predict};
use table::{
    table_card, table_compare, table_design, table_fit, table_intervals, table_predict,
    table_report,
};
use tool::{StreamEstimator, tool_card, tool_predict, tool_report};

/// The module `hxai._hxai`.
#[pymodule]
fn _hxai(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(defaults, m)?)?;
    m.add_function(wrap_pyfunction!(sr_fit, m)?)?;
    m.add_function(wrap_pyfunction!(sr_predict, m)?)?;
    m.add_function(wrap_pyfunction!(sr_intervals, m)?)?;
    m.add_function(wrap_pyfunction!(table_intervals, m)?)?;
    m.add_function(wrap_pyfunction!(table_fit, m)?)?;
    m.add_function(wrap_pyfunction!(table_compare, m)?)?;
    m.add_function(wrap_pyfunction!(table_predict, m)?)?;
    m.add_function(wrap_pyfunction!(sr_mathml, m)?)?;
    m.add_function(wrap_pyfunction!(table_report, m)?)?;
    m.add_function(wrap_pyfunction!(table_card, m)?)?;
    m.add_function(wrap_pyfunction!(table_design, m)?)?;
    m.add_function(wrap_pyfunction!(tool_predict, m)?)?;
    m.add_function(wrap_pyfunction!(tool_report, m)?)?;
    m.add_function(wrap_pyfunction!(tool_card, m)?)?;
    m.add_function(wrap_pyfunction!(butter, m)?)?;
    m.add_function(wrap_pyfunction!(sosfilt, m)?)?;
    m.add_function(wrap_pyfunction!(sosfiltfilt, m)?)?;
    m.add_function(wrap_pyfunction!(welch, m)?)?;
    m.add_function(wrap_pyfunction!(fit_sine, m)?)?;
    m.add_function(wrap_pyfunction!(displacement, m)?)?;
    m.add_function(wrap_pyfunction!(features_extract, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_tool, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_case, m)?)?;
    m.add_function(wrap_pyfunction!(dynamic::dynamic_fit, m)?)?;
    m.add_function(wrap_pyfunction!(dynamic::dynamic_predict, m)?)?;
    m.add_function(wrap_pyfunction!(dynamic::dynamic_compare, m)?)?;
    m.add_function(wrap_pyfunction!(dynamic::dynamic_report, m)?)?;
    m.add_function(wrap_pyfunction!(dynamic::dynamic_card, m)?)?;
    m.add_class::<StreamEstimator>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
