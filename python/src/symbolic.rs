//! Symbolic regression on a table, the glue of the Python `SymbolicRegressor`: `sr_fit`
//! (search, uncertainty and conformal calibration), `sr_predict` and `sr_intervals`.

use crate::convert::{err, floats, method_of, par_of, parse_json, table_of, to_bytes};
use crate::settings::with_overrides;
use hxai_hybrid::IntervalMethod;
use hxai_hybrid::conformal::{ConformalInfo, DEFAULT_CONFORMAL_FOLDS, calibrate_model};
use hxai_symreg::{Model, SearchConfig};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// What `sr_fit` returns: the search's report (as `hxai sr --json`) with the delta
/// method's record of the selected model and its conformal calibration.
#[derive(serde::Serialize)]
struct FitDocument {
    #[serde(flatten)]
    report: hxai_symreg::SearchReport,
    uncertainty: hxai_symreg::Uncertainty,
    conformal: Option<ConformalInfo>,
    conformal_error: Option<String>,
}

/// The table `sr_fit` searches: column names, their columns and the target's bytes.
type FitData<'py> = (Vec<String>, Vec<Bound<'py, PyBytes>>, Bound<'py, PyBytes>);

/// Units of the columns and of the target (`hxai sr --units`), each optional.
type UnitsArg = (Option<Vec<(String, String)>>, Option<String>);

/// `sr_fit((names, columns, y), search_json, n_jobs=None, conformal_folds=5)`: symbolic
/// regression of `y` on the columns with the search settings `search_json` (a JSON object
/// over `SearchConfig`'s defaults), on the threads of `n_jobs` ([`par_of`]). Returns
/// JSON `{best, pareto: [...], selection, evaluations, duplicate_structures, seconds,
/// uncertainty, conformal, conformal_error}`: the search's [`hxai_symreg::SearchReport`]
/// (each model a [`hxai_symreg::ModelSummary`]; `best` also has `template`, `params`,
/// `dof`, `residual_variance` and `reason`); `uncertainty` is the delta method's record and
/// `conformal` the CV+ calibration over `conformal_folds` random folds of the rows
/// (`hxai_hybrid::conformal::calibrate_model`: the constants refitted per fold), `null`
/// with 0 folds or when a fold model is undefined on its held-out rows
/// (`conformal_error` then says why). `stability_runs` > 0 adds `stability` (the search
/// rerun on that many bootstrap resamples, [`hxai_symreg::stability()`]) and the selection's
/// shares over them. `units` (pairs of column and unit) with `target_unit` searches on the
/// dimensionless groups ([`hxai_symreg::units`]) and adds `dimensional_groups`.
///
/// Python passes `data` as `(names, columns, y)` and `units` as `(units, target_unit)`.
#[pyfunction]
#[pyo3(signature = (data, search_json, n_jobs=None, conformal_folds=DEFAULT_CONFORMAL_FOLDS, stability_runs=0, units=(None, None)))]
pub(crate) fn sr_fit(
    py: Python<'_>,
    data: FitData<'_>,
    search_json: &str,
    n_jobs: Option<i64>,
    conformal_folds: usize,
    stability_runs: usize,
    units: UnitsArg,
) -> PyResult<String> {
    let (names, columns, y) = data;
    let (units, target_unit) = units;
    let y = y.as_bytes();
    if conformal_folds == 1 {
        return Err(PyValueError::new_err(
            "conformal_folds 1: CV+ needs at least 2 folds (or 0 to fit without conformal intervals)",
        ));
    }
    let data = table_of(names, &columns)?;
    let y = floats(y, "y")?;
    let mut cfg: SearchConfig = with_overrides("search", search_json)?;
    cfg.par = par_of(n_jobs)?;
    let reduction = match (units, target_unit) {
        (None, None) => None,
        (Some(units), Some(target)) => {
            // the target has no column name: one no column can have
            let key = "\u{0}target".to_string();
            let mut given = units;
            given.push((key.clone(), target));
            let (dims, target) = hxai_symreg::units::dimensions(data.names(), &key, &given)
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            Some(
                hxai_symreg::units::Reduction::of(data.names(), &dims, target)
                    .map_err(|e| PyValueError::new_err(e.to_string()))?,
            )
        }
        _ => {
            return Err(PyValueError::new_err(
                "units and target_units go together: give the unit of every column and of y",
            ));
        }
    };
    let (res, unc, report) = py
        .detach(|| -> Result<_, hxai_symreg::SrError> {
            let res = hxai_symreg::units::search(&data, &y, reduction.as_ref(), &cfg, &mut |_| {})?;
            let unc = res.best.uncertainty(&data, &y)?;
            let stability = match stability_runs {
                0 => None,
                runs => Some(hxai_symreg::units::stability(
                    &data,
                    &y,
                    reduction.as_ref(),
                    &cfg,
                    runs,
                    &mut |_, _| {},
                )?),
            };
            let mut report =
                hxai_symreg::SearchReport::of(&res, &cfg, (&data, &y), &unc, false, stability)?;
            report.dimensional_groups = reduction.as_ref().map(|r| r.describe("y"));
            Ok((res, unc, report))
        })
        .map_err(err)?;
    let (conformal, conformal_error) = if conformal_folds == 0 {
        (None, None)
    } else {
        let calib = hxai_eval::kfold(y.len(), conformal_folds, cfg.seed)
            .map_err(hxai_hybrid::HybridError::from)
            .and_then(|splits| calibrate_model(&res.best, &data, &y, &splits));
        match calib {
            Ok(c) => (Some(c), None),
            Err(e) => (None, Some(e.to_string())),
        }
    };
    let doc = FitDocument {
        report,
        uncertainty: unc,
        conformal,
        conformal_error,
    };
    serde_json::to_string(&doc).map_err(err)
}

/// `sr_intervals((model_json, uncertainty_json, conformal_json), (names, columns), level,
/// method=None)` -> `(lo, hi, method)`: prediction intervals at `level` of a symbolic model
/// on a table, by `method` (`conformal`, `split` or `delta`; default conformal when
/// `conformal_json` is not empty, else delta), from the records `sr_fit` returned.
#[pyfunction]
#[pyo3(signature = (records, table, level, method=None))]
#[allow(clippy::type_complexity)]
pub(crate) fn sr_intervals<'py>(
    py: Python<'py>,
    records: (String, String, String),
    table: (Vec<String>, Vec<Bound<'py, PyBytes>>),
    level: f64,
    method: Option<&str>,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>, String)> {
    let (model_json, uncertainty_json, conformal_json) = records;
    let (model_json, uncertainty_json, conformal_json) = (
        model_json.as_str(),
        uncertainty_json.as_str(),
        conformal_json.as_str(),
    );
    let (names, columns) = table;
    if !(level > 0.0 && level < 1.0) {
        return Err(PyValueError::new_err(format!(
            "level {level}: give a probability between 0 and 1, such as 0.95"
        )));
    }
    let model = Model::from_json(model_json).map_err(err)?;
    let conformal: Option<ConformalInfo> = if conformal_json.is_empty() {
        None
    } else {
        Some(parse_json(conformal_json, "conformal calibration")?)
    };
    let default = if conformal.is_some() {
        IntervalMethod::Conformal
    } else {
        IntervalMethod::Delta
    };
    let method = method_of(method, default)?;
    let data = table_of(names, &columns)?;
    let iv = py
        .detach(|| -> Result<Vec<(f64, f64)>, String> {
            if method == IntervalMethod::Delta {
                let unc: hxai_symreg::Uncertainty =
                    serde_json::from_str(uncertainty_json).map_err(|e| e.to_string())?;
                return model
                    .prediction_intervals(&unc, &data, level)
                    .map_err(|e| e.to_string());
            }
            let Some(conf) = &conformal else {
                return Err(format!(
                    "no conformal calibration (fitted with conformal_folds=0, or a fold model was \
                     undefined): use method='delta' instead of {}",
                    method.name()
                ));
            };
            conf.check(model.params.len()).map_err(|e| e.to_string())?;
            conf.model_intervals(&model, &data, level, method)
                .map_err(|e| e.to_string())
        })
        .map_err(PyValueError::new_err)?;
    let (lo, hi): (Vec<f64>, Vec<f64>) = iv.into_iter().unzip();
    Ok((
        to_bytes(py, &lo),
        to_bytes(py, &hi),
        method.name().to_string(),
    ))
}

/// `sr_predict(model_json, names, columns)`: a symbolic model's prediction on a table
/// (columns found by name).
#[pyfunction]
pub(crate) fn sr_predict<'py>(
    py: Python<'py>,
    model_json: &str,
    names: Vec<String>,
    columns: Vec<Bound<'py, PyBytes>>,
) -> PyResult<Bound<'py, PyBytes>> {
    let model = Model::from_json(model_json).map_err(err)?;
    let data = table_of(names, &columns)?;
    let pred = py.detach(move || model.predict(&data)).map_err(err)?;
    Ok(to_bytes(py, &pred))
}

/// `sr_mathml(model_json)`: the equation of a symbolic model as presentation MathML (the
/// inner content of a `<math>` element; 4 significant digits), for `_repr_html_`.
#[pyfunction]
pub(crate) fn sr_mathml(model_json: &str) -> PyResult<String> {
    let model = hxai_symreg::Model::from_json(model_json)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    Ok(model.expr().to_mathml(4))
}
