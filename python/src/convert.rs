//! What every function of the module shares: arrays from and to little-endian `float64`
//! bytes, tables from column names and bytes, `n_jobs` as a thread count, JSON arguments,
//! interval methods by name, and library errors as `ValueError`s.

use hxai_hybrid::IntervalMethod;
use hxai_symreg::{Par, Table};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// Any library error as a `ValueError` with the error's own message.
pub(crate) fn err(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Little-endian `float64` bytes to values.
pub(crate) fn floats(b: &[u8], what: &str) -> PyResult<Vec<f64>> {
    if !b.len().is_multiple_of(8) {
        return Err(PyValueError::new_err(format!(
            "{what}: {} bytes is not a whole number of float64 values",
            b.len()
        )));
    }
    Ok(b.chunks_exact(8)
        .map(|c| {
            let mut a = [0u8; 8];
            a.copy_from_slice(c);
            f64::from_le_bytes(a)
        })
        .collect())
}

/// Values to little-endian `float64` bytes.
pub(crate) fn to_bytes<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyBytes> {
    let mut out = Vec::with_capacity(v.len() * 8);
    for x in v {
        out.extend_from_slice(&x.to_le_bytes());
    }
    PyBytes::new(py, &out)
}

/// A table from column names and their `float64` bytes.
pub(crate) fn table_of(names: Vec<String>, columns: &[Bound<'_, PyBytes>]) -> PyResult<Table> {
    let cols = columns
        .iter()
        .zip(&names)
        .map(|(c, n)| floats(c.as_bytes(), n))
        .collect::<PyResult<Vec<_>>>()?;
    if cols.len() != names.len() {
        return Err(PyValueError::new_err(format!(
            "{} column names for {} columns",
            names.len(),
            columns.len()
        )));
    }
    Table::new(names, cols).map_err(err)
}

/// Most threads `n_jobs` may ask for (the CLI's `--threads` bound).
const MAX_THREADS: i64 = 1024;

/// scikit-learn's `n_jobs` as the engine's [`Par`]: `None` is rayon's global pool (all
/// cores, unless `RAYON_NUM_THREADS` says otherwise), `-1` a pool of every core the system
/// reports, `n` from 1 to [`MAX_THREADS`] a pool of `n` threads built for the call; other
/// values are a `ValueError`. Results never depend on it.
pub(crate) fn par_of(n_jobs: Option<i64>) -> PyResult<Par> {
    match n_jobs {
        None => Ok(Par::Current),
        Some(-1) => Ok(Par::threads(
            std::thread::available_parallelism().map_or(1, usize::from),
        )),
        Some(n) if (1..=MAX_THREADS).contains(&n) => Ok(Par::threads(n as usize)),
        Some(n) => Err(PyValueError::new_err(format!(
            "n_jobs must be None, -1 (all cores) or 1 to {MAX_THREADS}, got {n}"
        ))),
    }
}

pub(crate) fn parse_json<T: serde::de::DeserializeOwned>(text: &str, what: &str) -> PyResult<T> {
    serde_json::from_str(text).map_err(|e| PyValueError::new_err(format!("{what}: {e}")))
}

/// An interval method by its name (`None`: the given default).
pub(crate) fn method_of(name: Option<&str>, default: IntervalMethod) -> PyResult<IntervalMethod> {
    match name {
        None => Ok(default),
        Some("conformal") => Ok(IntervalMethod::Conformal),
        Some("split") => Ok(IntervalMethod::Split),
        Some("delta") => Ok(IntervalMethod::Delta),
        Some(other) => Err(PyValueError::new_err(format!(
            "interval method `{other}`: use conformal, split or delta"
        ))),
    }
}
