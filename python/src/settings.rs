//! The Rust defaults as JSON (`defaults`) and the settings the Python side sends, applied
//! over those defaults with unknown keys refused (`with_overrides`).

use crate::convert::{err, parse_json};
use hxai_symreg::SearchConfig;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use serde_json::Value;
use std::collections::BTreeMap;

/// `defaults(what)`: the Rust defaults as JSON, for `search` (symbolic regression),
/// `tool` (the machine simulator), `roughness`, `cutting_force` and `tool_life` (the table
/// cases).
#[pyfunction]
pub(crate) fn defaults(what: &str) -> PyResult<String> {
    let v = default_value(what)?;
    serde_json::to_string(&v).map_err(err)
}

fn default_value(what: &str) -> PyResult<Value> {
    let v = match what {
        "search" => serde_json::to_value(SearchConfig::default()),
        // what a table hybrid's correction searches (HybridRegressor)
        "table_search" => serde_json::to_value(SearchConfig::laws()),
        "tool" => serde_json::to_value(hxai_sim::SimConfig::default()),
        "roughness" => serde_json::to_value(hxai_sim::cases::RoughnessConfig::default()),
        "cutting_force" => serde_json::to_value(hxai_sim::cases::CuttingForceConfig::default()),
        "tool_life" => serde_json::to_value(hxai_sim::cases::ToolLifeConfig::default()),
        "spindle_thermal" => serde_json::to_value(hxai_sim::cases::SpindleThermalConfig::default()),
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown case `{other}`: the cases are tool, {}",
                hxai_sim::cases::CASE_NAMES.join(", ")
            )));
        }
    };
    v.map_err(err)
}

/// The defaults of `what` with `overrides` (a JSON object) applied; an unknown key is refused
/// with the list of known ones (the case configurations would otherwise ignore it).
pub(crate) fn with_overrides<T: serde::de::DeserializeOwned>(
    what: &str,
    overrides: &str,
) -> PyResult<T> {
    let mut base = default_value(what)?;
    let over: BTreeMap<String, Value> = parse_json(overrides, "settings")?;
    if let Value::Object(map) = &mut base {
        for (k, v) in over {
            if !map.contains_key(&k) {
                let known: Vec<&str> = map.keys().map(String::as_str).collect();
                return Err(PyValueError::new_err(format!(
                    "unknown setting `{k}` for {what}: the settings are {}",
                    known.join(", ")
                )));
            }
            map.insert(k, v);
        }
    }
    serde_json::from_value(base).map_err(|e| PyValueError::new_err(format!("{what}: {e}")))
}
