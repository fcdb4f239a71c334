//! The table hybrid (`hxai_hybrid::tables`, docs/hybrid-tables.md), the glue of the
//! Python `HybridRegressor`: `table_fit`, `table_predict` and `table_intervals`.

use crate::convert::{err, method_of, par_of, parse_json, table_of, to_bytes};
use crate::settings::with_overrides;
use hxai_hybrid::IntervalMethod;
use hxai_hybrid::conformal::DEFAULT_CONFORMAL_FOLDS;
use hxai_hybrid::tables::{
    CalibratePer, CorrectionForm, Form, Prepared, TableConfig, TableModel, prepare,
};
use hxai_symreg::SearchConfig;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use serde::Deserialize;
use serde_json::Value;
use std::collections::BTreeMap;

/// Settings of [`table_fit`] as the Python estimator sends them.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ProcessSettings {
    target: String,
    physics: String,
    #[serde(default)]
    calibrate: Vec<String>,
    #[serde(default)]
    init: BTreeMap<String, f64>,
    #[serde(default)]
    set: BTreeMap<String, f64>,
    #[serde(default)]
    features: Option<Vec<String>>,
    #[serde(default)]
    exclude: Vec<String>,
    /// `periodic`: the columns that may carry a harmonic (none by default).
    #[serde(default)]
    periodic: Vec<String>,
    /// `monotone`: {column: `+` or `-`} (issue 68, `--monotone COL=+|-`).
    #[serde(default)]
    monotone: BTreeMap<String, String>,
    /// `shapes`: `classic`, `all` or a comma-separated list of the factor form's shapes.
    #[serde(default)]
    shapes: Option<String>,
    /// `interactions`: most pair factors of the factor form (default 3).
    #[serde(default)]
    interactions: Option<usize>,
    #[serde(default)]
    correction: CorrectionForm,
    /// `free` or `factors` (docs/hybrid-tables.md, "The factor form").
    #[serde(default)]
    form: Form,
    #[serde(default)]
    joint: bool,
    #[serde(default = "default_conformal_folds")]
    conformal_folds: usize,
    /// `search_rows`: the sample the structure is searched on (issue 67).
    #[serde(default = "default_search_rows")]
    search_rows: usize,
    /// Bootstrap resamples of the correction's stability (0: not measured).
    #[serde(default)]
    stability_runs: usize,
    #[serde(default)]
    search: Value,
    /// `calibrate_per`: the physics parameters fitted once per level of a text column.
    #[serde(default)]
    calibrate_per: Option<PerClassSettings>,
    /// `correction_per`: the correction's constants refitted per level of a text column.
    #[serde(default)]
    correction_per: Option<CorrectionPerSettings>,
}

/// The estimator's `correction_per` (`--correction-per COL`): the column and its cells.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CorrectionPerSettings {
    column: String,
    cells: Vec<String>,
}

/// The estimator's `calibrate_per` (`--calibrate-per COL=P1,P2`): the column, the
/// parameters, and the column's cells (the estimator takes the column out of `X`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PerClassSettings {
    column: String,
    parameters: Vec<String>,
    cells: Vec<String>,
}

/// Appends the level indicators of a model with per-level constants (of the physics,
/// `per_class`, or of the correction, `correction_per`) to `table`, from the cells of each
/// text column (`levels`: column -> cells); refuses a column the model needs and lacks.
fn with_levels(
    model: &TableModel,
    table: &mut hxai_symreg::Table,
    levels: Option<BTreeMap<String, Vec<String>>>,
) -> PyResult<()> {
    let text: Vec<(String, Vec<String>)> = levels.unwrap_or_default().into_iter().collect();
    model.add_levels(table, &text).map_err(err)
}

fn default_search_rows() -> usize {
    hxai_hybrid::tables::SEARCH_ROWS
}

fn default_conformal_folds() -> usize {
    DEFAULT_CONFORMAL_FOLDS
}

/// `table_fit(names, columns, settings_json, n_jobs=None)`: the table workflow's `fit`
/// (docs/hybrid-tables.md) on every row of the table (the caller splits, as scikit-learn
/// does), on the threads of `n_jobs` ([`par_of`]). The table holds the target column named
/// in the settings; `stability_runs` > 0 in them also measures the correction's stability
/// over that many bootstrap resamples ([`measure_stability`]). Returns the model file's JSON.
#[pyfunction]
#[pyo3(signature = (names, columns, settings_json, n_jobs=None))]
pub(crate) fn table_fit(
    py: Python<'_>,
    names: Vec<String>,
    columns: Vec<Bound<'_, PyBytes>>,
    settings_json: &str,
    n_jobs: Option<i64>,
) -> PyResult<String> {
    let table = table_of(names, &columns)?;
    let s: ProcessSettings = parse_json(settings_json, "hybrid settings")?;
    let ready = prepared(&s, table, n_jobs)?;
    let split = hxai_eval::Split {
        train: (0..ready.table.n_rows()).collect(),
        test: Vec::new(),
    };
    let runs = s.stability_runs;
    let model = py
        .detach(move || {
            let mut model = ready.fit_split(&split, &mut |_| {})?;
            if runs > 0 {
                ready.measure_stability(&mut model, runs, &mut |_, _| {})?;
            }
            Ok::<_, hxai_hybrid::HybridError>(model)
        })
        .map_err(err)?;
    Ok(model.to_json())
}

/// `table_compare(names, columns, settings_json, test_fraction, folds, n_jobs=None)`: `hxai
/// hybrid compare` on the table (its own random split at `test_fraction`, stratified by any
/// per-level column, and `folds` folds of cross-validation; 0 skips them). Returns the
/// comparison's JSON, as `hxai hybrid compare --json` prints it.
#[pyfunction]
#[pyo3(signature = (names, columns, settings_json, test_fraction, folds, n_jobs=None))]
pub(crate) fn table_compare(
    py: Python<'_>,
    names: Vec<String>,
    columns: Vec<Bound<'_, PyBytes>>,
    settings_json: &str,
    test_fraction: f64,
    folds: usize,
    n_jobs: Option<i64>,
) -> PyResult<String> {
    let table = table_of(names, &columns)?;
    let s: ProcessSettings = parse_json(settings_json, "hybrid settings")?;
    let mut ready = prepared(&s, table, n_jobs)?;
    ready.cfg.test_fraction = test_fraction;
    let c = py
        .detach(move || ready.compare(folds, &mut |_| {}))
        .map_err(err)?;
    serde_json::to_string_pretty(&c).map_err(err)
}

/// The one configuration of `s` with the search on the threads of `n_jobs`, handed with
/// `table` and the cells of its level columns to [`prepare`]: the fits and comparisons of
/// the result return complete models.
fn prepared(
    s: &ProcessSettings,
    table: hxai_symreg::Table,
    n_jobs: Option<i64>,
) -> PyResult<Prepared> {
    let mut search: SearchConfig = with_overrides("search", &s.search.to_string())?;
    search.par = par_of(n_jobs)?;
    let mut cfg = TableConfig::new(&s.target, &s.physics);
    cfg.calibrate = s.calibrate.clone();
    cfg.init = s.init.clone();
    cfg.set = s.set.clone();
    cfg.features = s.features.clone();
    cfg.exclude = s.exclude.clone();
    cfg.periodic = s.periodic.clone();
    for (col, dir) in &s.monotone {
        match dir.as_str() {
            "+" => cfg.increasing.push(col.clone()),
            "-" => cfg.decreasing.push(col.clone()),
            _ => {
                return Err(pyo3::exceptions::PyValueError::new_err(format!(
                    "monotone[{col:?}] = {dir:?}: write \"+\" (the effect never decreases) or \"-\" \
                     (never increases)"
                )));
            }
        }
    }
    if let Some(n) = s.interactions {
        cfg.factors.interactions = n;
    }
    if let Some(text) = &s.shapes {
        cfg.factors.shapes = hxai_symreg::factors::Shapes::parse(text).ok_or_else(|| {
            pyo3::exceptions::PyValueError::new_err(format!(
                "shapes={text:?}: write \"classic\", \"all\", or shape names among power, linear, \
                 exp, log, pole, saturation, hinge, saturating_power, step, periodic, pair"
            ))
        })?;
    }
    cfg.correction = s.correction;
    cfg.form = s.form;
    cfg.joint = s.joint;
    cfg.conformal_folds = s.conformal_folds;
    cfg.search_rows = s.search_rows;
    cfg.seed = search.seed;
    cfg.search = search;
    // the estimator takes the level columns out of X and sends their cells
    let mut text = Vec::new();
    if let Some(pc) = &s.calibrate_per {
        cfg.per_level.calibrate = Some(CalibratePer {
            column: pc.column.clone(),
            parameters: pc.parameters.clone(),
        });
        text.push((pc.column.clone(), pc.cells.clone()));
    }
    if let Some(cp) = &s.correction_per {
        cfg.per_level.correction = Some(cp.column.clone());
        if !text.iter().any(|(n, _)| *n == cp.column) {
            text.push((cp.column.clone(), cp.cells.clone()));
        }
    }
    prepare(&cfg, table, &text, Vec::new()).map_err(err)
}

/// `table_predict(model_json, names, columns, levels=None)` -> `(physics, correction,
/// hybrid, outside_training, warnings)`; `levels`: {column: cells} of the text columns of a
/// model with per-level constants. `outside_training` is 1.0 for a row beside the data
/// (`TableModel::outside_training`), else 0.0; `warnings` those of `hxai hybrid predict`
/// about the rows (beside the data, a sign the training target never had).
#[pyfunction]
#[pyo3(signature = (model_json, names, columns, levels=None))]
#[allow(clippy::type_complexity)]
pub(crate) fn table_predict<'py>(
    py: Python<'py>,
    model_json: &str,
    names: Vec<String>,
    columns: Vec<Bound<'py, PyBytes>>,
    levels: Option<BTreeMap<String, Vec<String>>>,
) -> PyResult<(
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Vec<String>,
)> {
    let model = TableModel::from_json(model_json).map_err(err)?;
    let mut table = table_of(names, &columns)?;
    with_levels(&model, &mut table, levels)?;
    let (p, outside, warnings) = py
        .detach(move || {
            let p = model.predict(&table)?;
            let outside: Vec<f64> = model
                .outside_training(&table)
                .into_iter()
                .map(|o| if o { 1.0 } else { 0.0 })
                .collect();
            let warnings = model.prediction_warnings(&table, &p.hybrid);
            Ok::<_, hxai_hybrid::HybridError>((p, outside, warnings))
        })
        .map_err(err)?;
    Ok((
        to_bytes(py, &p.physics),
        to_bytes(py, &p.correction),
        to_bytes(py, &p.hybrid),
        to_bytes(py, &outside),
        warnings,
    ))
}

/// `table_intervals(model_json, names, columns, level, method=None, levels=None)` -> `(lo,
/// hi, method)`: the table hybrid's prediction intervals at `level` on a table
/// (`TableModel::intervals_with`), by `method` (`conformal`, `split` or `delta`; default:
/// the model file's, conformal where it stores the calibration); `levels` as for
/// [`table_predict`].
#[pyfunction]
#[pyo3(signature = (model_json, names, columns, level, method=None, levels=None))]
pub(crate) fn table_intervals<'py>(
    py: Python<'py>,
    model_json: &str,
    names: Vec<String>,
    columns: Vec<Bound<'py, PyBytes>>,
    level: f64,
    method: Option<&str>,
    levels: Option<BTreeMap<String, Vec<String>>>,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>, String)> {
    let model = TableModel::from_json(model_json).map_err(err)?;
    let default = model
        .default_interval_method(level)
        .unwrap_or(IntervalMethod::Delta);
    let method = method_of(method, default)?;
    let mut table = table_of(names, &columns)?;
    with_levels(&model, &mut table, levels)?;
    let iv = py
        .detach(move || model.intervals_with(&table, level, method))
        .map_err(err)?;
    let (lo, hi): (Vec<f64>, Vec<f64>) = iv.into_iter().unzip();
    Ok((
        to_bytes(py, &lo),
        to_bytes(py, &hi),
        method.name().to_string(),
    ))
}

/// `table_report(model_json, names=None, columns=None, levels=None, compare_json=None,
/// data_name=None)` -> the HTML page of `hxai report` for the model; with a table (the
/// model's columns and its target), the correction's figures drawn on it.
#[pyfunction]
#[pyo3(signature = (model_json, names=None, columns=None, levels=None, compare_json=None, data_name=None))]
pub(crate) fn table_report(
    model_json: &str,
    names: Option<Vec<String>>,
    columns: Option<Vec<Bound<'_, PyBytes>>>,
    levels: Option<BTreeMap<String, Vec<String>>>,
    compare_json: Option<&str>,
    data_name: Option<String>,
) -> PyResult<String> {
    let model = TableModel::from_json(model_json).map_err(err)?;
    let compare: Option<Value> = compare_json
        .map(|t| parse_json(t, "comparison"))
        .transpose()?;
    let (pictures, rows) = match (names, columns) {
        (Some(n), Some(c)) => {
            let mut table = table_of(n, &c)?;
            with_levels(&model, &mut table, levels)?;
            let rows = table.n_rows();
            let p = hxai_plot::report::correction_pictures(&model, &table)
                .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
            (Some(p), Some(rows))
        }
        _ => (None, None),
    };
    let name = data_name.unwrap_or_else(|| "the DataFrame given".to_string());
    Ok(hxai_plot::report::table_report(
        &model,
        &hxai_plot::report::ReportInputs {
            pictures: pictures.as_ref(),
            data: rows.map(|r| (name.as_str(), r)),
            compare: compare.as_ref(),
            version: env!("CARGO_PKG_VERSION"),
        },
    ))
}

/// `table_card(model_json)` -> the compact HTML card of a fitted table hybrid (the
/// estimator's `_repr_html_`).
#[pyfunction]
pub(crate) fn table_card(model_json: &str) -> PyResult<String> {
    let model = TableModel::from_json(model_json).map_err(err)?;
    Ok(hxai_plot::report::table_card(&model))
}

/// Feasible settings from Python: column names and their columns.
type Settings<'py> = (Vec<String>, Vec<Bound<'py, PyBytes>>);

/// `table_design(model_json, space, settings, n, goal, seed, levels=None)` -> JSON text of
/// the proposed runs: `space` is the ranges text, or `None` with the feasible settings given
/// as `settings` = `(names, columns)` and their text columns as `levels` {column: cells}.
/// The JSON's `columns` and `settings` are the numeric settings; `text` {column: cells}
/// the text ones at the picks.
#[pyfunction]
#[pyo3(signature = (model_json, space, settings, n, goal, seed, levels=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn table_design(
    py: Python<'_>,
    model_json: &str,
    space: Option<&str>,
    settings: Option<Settings<'_>>,
    n: usize,
    goal: &str,
    seed: u64,
    levels: Option<BTreeMap<String, Vec<String>>>,
) -> PyResult<String> {
    use hxai_hybrid::tables::design::{Candidates, DesignGoal, candidates, design, parse_space};
    let model = TableModel::from_json(model_json).map_err(err)?;
    let goal = match goal {
        "discriminate" => DesignGoal::Discriminate,
        "coverage" => DesignGoal::Coverage,
        "precision" => DesignGoal::Precision,
        other => {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "goal `{other}`: use discriminate, coverage or precision"
            )));
        }
    };
    let Candidates { mut table, text } = match (space, settings) {
        (Some(s), _) => candidates(&parse_space(s).map_err(err)?, seed).map_err(err)?,
        (None, Some((n, c))) => Candidates {
            table: table_of(n, &c)?,
            text: levels.unwrap_or_default().into_iter().collect(),
        },
        (None, None) => {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "space: give ranges as text ('col=lo:hi,...') or a DataFrame of feasible settings",
            ));
        }
    };
    let names: Vec<String> = table.names().to_vec();
    model.add_levels(&mut table, &text).map_err(err)?;
    let p = py.detach(|| design(&model, &table, n, goal)).map_err(err)?;
    let numeric: Vec<&[f64]> = names.iter().filter_map(|c| table.column(c)).collect();
    let picked_text: BTreeMap<&str, Vec<&str>> = text
        .iter()
        .map(|(c, cells)| {
            (
                c.as_str(),
                p.rows.iter().map(|&i| cells[i].as_str()).collect(),
            )
        })
        .collect();
    let doc = serde_json::json!({
        "goal": p.goal.name(),
        "columns": names,
        "settings": p.rows.iter().map(|&i| numeric.iter().map(|c| c[i]).collect::<Vec<f64>>()).collect::<Vec<_>>(),
        "text": picked_text,
        "predicted": p.predicted,
        "spread": p.spread,
        "reason": p.reason,
        "n_candidates": p.n_candidates,
        "left_out": p.left_out,
    });
    Ok(doc.to_string())
}
