//! `hxai.DynamicRegressor` (python/hxai/dynamic.py): `hxai dynamic fit | predict | compare`
//! on a long table given as named float64 columns, the settings as JSON
//! ([`hxai_hybrid::dynamic::DynamicConfig`]'s fields).

use crate::convert::{err, parse_json, table_of, to_bytes};
use hxai_hybrid::dynamic::{DynamicConfig, DynamicModel, TestSplit};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// `dynamic_fit(names, columns, settings_json)` -> the model file's JSON.
#[pyfunction]
pub(crate) fn dynamic_fit(
    py: Python<'_>,
    names: Vec<String>,
    columns: Vec<Bound<'_, PyBytes>>,
    settings_json: &str,
) -> PyResult<String> {
    let table = table_of(names, &columns)?;
    let cfg: DynamicConfig = parse_json(settings_json, "dynamic settings")?;
    let model = py
        .detach(move || hxai_hybrid::dynamic::fit(&table, &cfg, &mut |_| {}))
        .map_err(err)?;
    Ok(model.to_json())
}

/// `dynamic_predict(model_json, names, columns, interval=None)` -> `(hybrid, physics, lo,
/// hi, warnings)`, each a list with one float64 buffer per state (`lo` and `hi` empty lists
/// without an interval).
#[pyfunction]
#[pyo3(signature = (model_json, names, columns, interval=None))]
#[allow(clippy::type_complexity)]
pub(crate) fn dynamic_predict<'py>(
    py: Python<'py>,
    model_json: &str,
    names: Vec<String>,
    columns: Vec<Bound<'py, PyBytes>>,
    interval: Option<f64>,
) -> PyResult<(
    Vec<Bound<'py, PyBytes>>,
    Vec<Bound<'py, PyBytes>>,
    Vec<Bound<'py, PyBytes>>,
    Vec<Bound<'py, PyBytes>>,
    Vec<String>,
)> {
    let model = DynamicModel::from_json(model_json).map_err(err)?;
    let table = table_of(names, &columns)?;
    let p = py
        .detach(move || model.predict(&table, interval))
        .map_err(err)?;
    let many = |v: &[Vec<f64>]| v.iter().map(|c| to_bytes(py, c)).collect::<Vec<_>>();
    Ok((
        many(&p.hybrid),
        many(&p.physics),
        p.lower.as_deref().map(many).unwrap_or_default(),
        p.upper.as_deref().map(many).unwrap_or_default(),
        p.warnings,
    ))
}

/// `dynamic_compare(names, columns, settings_json, split_json)` -> the comparison's JSON,
/// as `hxai dynamic compare --json` prints it (`split_json`: `test_runs`, `test_after`).
#[pyfunction]
pub(crate) fn dynamic_compare(
    py: Python<'_>,
    names: Vec<String>,
    columns: Vec<Bound<'_, PyBytes>>,
    settings_json: &str,
    split_json: &str,
) -> PyResult<String> {
    let table = table_of(names, &columns)?;
    let cfg: DynamicConfig = parse_json(settings_json, "dynamic settings")?;
    let split: TestSplit = parse_json(split_json, "the held-out split")?;
    let c = py
        .detach(move || hxai_hybrid::dynamic::compare(&table, &cfg, &split, &mut |_| {}))
        .map_err(err)?;
    serde_json::to_string_pretty(&c).map_err(err)
}

/// `dynamic_report(model_json, names=None, columns=None, data_name="TABLE.csv")` -> the
/// page of `hxai report` for a dynamic model, its runs drawn on the table when given.
#[pyfunction]
#[pyo3(signature = (model_json, names=None, columns=None, data_name="TABLE.csv"))]
pub(crate) fn dynamic_report(
    model_json: &str,
    names: Option<Vec<String>>,
    columns: Option<Vec<Bound<'_, PyBytes>>>,
    data_name: &str,
) -> PyResult<String> {
    let model = DynamicModel::from_json(model_json).map_err(err)?;
    let table = match (names, columns) {
        (Some(n), Some(c)) => Some(table_of(n, &c)?),
        _ => None,
    };
    Ok(hxai_plot::report::dynamic_report(
        &model,
        table.as_ref().map(|t| (data_name, t)),
        env!("CARGO_PKG_VERSION"),
    ))
}

/// `dynamic_card(model_json)` -> the Jupyter card of a dynamic model.
#[pyfunction]
pub(crate) fn dynamic_card(model_json: &str) -> PyResult<String> {
    let model = DynamicModel::from_json(model_json).map_err(err)?;
    Ok(hxai_plot::report::dynamic_card(&model))
}
