//! The simulators: the machine's records (`simulate_tool`, as `hxai simulate` makes them)
//! and the table cases (`simulate_case`), each from its defaults and the given overrides.

use crate::convert::{err, par_of, to_bytes};
use crate::settings::with_overrides;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// One simulated record: `(id, amplitude_um, frequency_hz, repeat, fs_hz, time_s,
/// accel_ms2, probe_um, command_um, encoder_um)`.
type PyRecord<'py> = (
    String,
    f64,
    f64,
    usize,
    f64,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
);

/// `simulate_tool(overrides_json, n_jobs=None)`: the machine simulator (`hxai simulate`) with
/// `SimConfig`'s defaults and the given overrides, records simulated on the threads of
/// `n_jobs` ([`par_of`]); one tuple per record.
#[pyfunction]
#[pyo3(signature = (overrides_json, n_jobs=None))]
pub(crate) fn simulate_tool<'py>(
    py: Python<'py>,
    overrides_json: &str,
    n_jobs: Option<i64>,
) -> PyResult<Vec<PyRecord<'py>>> {
    let mut cfg: hxai_sim::SimConfig = with_overrides("tool", overrides_json)?;
    cfg.par = par_of(n_jobs)?;
    let recs = py.detach(move || hxai_sim::simulate(&cfg)).map_err(err)?;
    Ok(recs
        .iter()
        .map(|r| {
            (
                r.id.clone(),
                r.amplitude_um,
                r.frequency_hz,
                r.repeat,
                r.fs_hz,
                to_bytes(py, &r.time_s),
                to_bytes(py, &r.accel_ms2),
                to_bytes(py, &r.probe_um),
                to_bytes(py, &r.command_um),
                to_bytes(py, &r.encoder_um),
            )
        })
        .collect())
}

/// `simulate_case(name, overrides_json)` -> `(names, columns)`: a table case
/// (`roughness`, `cutting_force`, `tool_life`, `spindle_thermal`) with its defaults and the
/// given overrides.
#[pyfunction]
pub(crate) fn simulate_case<'py>(
    py: Python<'py>,
    name: &str,
    overrides_json: &str,
) -> PyResult<(Vec<String>, Vec<Bound<'py, PyBytes>>)> {
    let table = match name {
        "roughness" => {
            let c: hxai_sim::cases::RoughnessConfig = with_overrides(name, overrides_json)?;
            py.detach(move || hxai_sim::cases::roughness(&c))
        }
        "cutting_force" => {
            let c: hxai_sim::cases::CuttingForceConfig = with_overrides(name, overrides_json)?;
            py.detach(move || hxai_sim::cases::cutting_force(&c))
        }
        "tool_life" => {
            let c: hxai_sim::cases::ToolLifeConfig = with_overrides(name, overrides_json)?;
            py.detach(move || hxai_sim::cases::tool_life(&c))
        }
        "spindle_thermal" => {
            let c: hxai_sim::cases::SpindleThermalConfig = with_overrides(name, overrides_json)?;
            py.detach(move || hxai_sim::cases::spindle_thermal(&c, None))
        }
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown case `{other}`: the cases are tool, {}",
                hxai_sim::cases::CASE_NAMES.join(", ")
            )));
        }
    }
    .map_err(err)?;
    let (names, columns) = table.into_parts();
    Ok((names, columns.iter().map(|c| to_bytes(py, c)).collect()))
}
