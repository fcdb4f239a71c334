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
//! Entry points: `sr_fit`, `sr_predict`, `sr_intervals`, `process_fit`, `process_predict`,
//! `process_intervals`, `tool_predict`,
//! `butter`, `sosfilt`, `sosfiltfilt`, `welch`, `fit_sine`, `displacement`,
//! `features_extract`, `simulate_tool`, `simulate_case`, `defaults`, and the class
//! `StreamEstimator` (the causal estimator of `hxai_hybrid::stream`, which keeps state
//! between calls).
#![deny(missing_docs)]

use hxai_hybrid::IntervalMethod;
use hxai_hybrid::conformal::{ConformalInfo, DEFAULT_CONFORMAL_FOLDS, calibrate_model};
use hxai_hybrid::process::{CorrectionForm, ProcessConfig, ProcessModel, fit_process_split};
use hxai_hybrid::stream::Estimator;
use hxai_hybrid::{HybridModel, RecordInput};
use hxai_signal::{Band, PhysicsConfig, Sos, WelchConfig};
use hxai_symreg::{Model, Par, SearchConfig, Table};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use serde::Deserialize;
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// Any library error as a `ValueError` with the error's own message.
fn err(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Little-endian `float64` bytes to values.
fn floats(b: &[u8], what: &str) -> PyResult<Vec<f64>> {
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
fn to_bytes<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyBytes> {
    let mut out = Vec::with_capacity(v.len() * 8);
    for x in v {
        out.extend_from_slice(&x.to_le_bytes());
    }
    PyBytes::new(py, &out)
}

/// A table from column names and their `float64` bytes.
fn table_of(names: Vec<String>, columns: &[Bound<'_, PyBytes>]) -> PyResult<Table> {
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
fn par_of(n_jobs: Option<i64>) -> PyResult<Par> {
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

fn parse_json<T: serde::de::DeserializeOwned>(text: &str, what: &str) -> PyResult<T> {
    serde_json::from_str(text).map_err(|e| PyValueError::new_err(format!("{what}: {e}")))
}

/// `defaults(what)`: the Rust defaults as JSON, for `search` (symbolic regression),
/// `tool` (the machine simulator), `roughness`, `cutting_force` and `tool_life` (the table
/// cases).
#[pyfunction]
fn defaults(what: &str) -> PyResult<String> {
    let v = default_value(what)?;
    serde_json::to_string(&v).map_err(err)
}

fn default_value(what: &str) -> PyResult<Value> {
    let v = match what {
        "search" => serde_json::to_value(SearchConfig::default()),
        // what a table hybrid's correction searches (HybridRegressor)
        "process_search" => serde_json::to_value(SearchConfig::laws()),
        "tool" => serde_json::to_value(hxai_sim::SimConfig::default()),
        "roughness" => serde_json::to_value(hxai_sim::cases::RoughnessConfig::default()),
        "cutting_force" => serde_json::to_value(hxai_sim::cases::CuttingForceConfig::default()),
        "tool_life" => serde_json::to_value(hxai_sim::cases::ToolLifeConfig::default()),
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
fn with_overrides<T: serde::de::DeserializeOwned>(what: &str, overrides: &str) -> PyResult<T> {
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

/// A model's forms, as the CLI's `hxai sr --json` reports them, plus the model itself.
fn model_summary(m: &Model) -> Value {
    let mut v = serde_json::to_value(hxai_symreg::ModelForms::of(m)).unwrap_or_default();
    v["loss"] = json!(m.train_mse);
    v["model"] = json!(m.to_json());
    v
}

/// An interval method by its name (`None`: the given default).
fn method_of(name: Option<&str>, default: IntervalMethod) -> PyResult<IntervalMethod> {
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

/// `sr_fit(names, columns, y, search_json, n_jobs=None, conformal_folds=5)`: symbolic
/// regression of `y` on the columns with the search settings `search_json` (a JSON object
/// over `SearchConfig`'s defaults), on the threads of `n_jobs` ([`par_of`]). Returns
/// JSON `{best, pareto: [...], evaluations, seconds, uncertainty, conformal}`, each model as
/// [`model_summary`]; `best` also has `template`, `params` and `reason`
/// (`hxai_symreg::uncertainty`); `uncertainty` is the delta method's record and
/// `conformal` the CV+ calibration over `conformal_folds` random folds of the rows
/// (`hxai_hybrid::conformal::calibrate_model`: the constants refitted per fold), `null`
/// with 0 folds or when a fold model is undefined on its held-out rows
/// (`conformal_error` then says why).
#[pyfunction]
#[pyo3(signature = (names, columns, y, search_json, n_jobs=None, conformal_folds=DEFAULT_CONFORMAL_FOLDS))]
fn sr_fit(
    py: Python<'_>,
    names: Vec<String>,
    columns: Vec<Bound<'_, PyBytes>>,
    y: &[u8],
    search_json: &str,
    n_jobs: Option<i64>,
    conformal_folds: usize,
) -> PyResult<String> {
    if conformal_folds == 1 {
        return Err(PyValueError::new_err(
            "conformal_folds 1: CV+ needs at least 2 folds (or 0 to fit without conformal intervals)",
        ));
    }
    let data = table_of(names, &columns)?;
    let y = floats(y, "y")?;
    let mut cfg: SearchConfig = with_overrides("search", search_json)?;
    cfg.par = par_of(n_jobs)?;
    let (res, unc) = py
        .detach(|| -> Result<_, hxai_symreg::SrError> {
            let res = hxai_symreg::search(&data, &y, &cfg, &mut |_| {})?;
            let unc = res.best.uncertainty(&data, &y)?;
            Ok((res, unc))
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
    let mut best = model_summary(&res.best);
    best["template"] = json!(unc.template);
    best["params"] = serde_json::to_value(&unc).map_err(err)?["params"].take();
    best["reason"] = json!(unc.reason);
    let doc = json!({
        "best": best,
        "pareto": res.pareto.iter().map(model_summary).collect::<Vec<_>>(),
        "selection": hxai_symreg::SelectionReport::of(&res, &cfg),
        "evaluations": res.evaluations,
        "seconds": res.seconds,
        "uncertainty": unc,
        "conformal": conformal,
        "conformal_error": conformal_error,
    });
    Ok(doc.to_string())
}

/// `sr_intervals(model_json, uncertainty_json, conformal_json, names, columns, level,
/// method=None)` -> `(lo, hi, method)`: prediction intervals at `level` of a symbolic model
/// on a table, by `method` (`conformal`, `split` or `delta`; default conformal when
/// `conformal_json` is not empty, else delta), from the records `sr_fit` returned.
#[pyfunction]
#[pyo3(signature = (model_json, uncertainty_json, conformal_json, names, columns, level, method=None))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn sr_intervals<'py>(
    py: Python<'py>,
    model_json: &str,
    uncertainty_json: &str,
    conformal_json: &str,
    names: Vec<String>,
    columns: Vec<Bound<'py, PyBytes>>,
    level: f64,
    method: Option<&str>,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>, String)> {
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
fn sr_predict<'py>(
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

/// Settings of [`process_fit`] as the Python estimator sends them.
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
    #[serde(default)]
    correction: CorrectionForm,
    #[serde(default)]
    joint: bool,
    #[serde(default = "default_conformal_folds")]
    conformal_folds: usize,
    #[serde(default)]
    search: Value,
}

fn default_conformal_folds() -> usize {
    DEFAULT_CONFORMAL_FOLDS
}

/// `process_fit(names, columns, settings_json, n_jobs=None)`: the table workflow's `fit`
/// (docs/hybrid-tables.md) on every row of the table (the caller splits, as scikit-learn
/// does), on the threads of `n_jobs` ([`par_of`]). The table holds the target column named
/// in the settings. Returns the model file's JSON.
#[pyfunction]
#[pyo3(signature = (names, columns, settings_json, n_jobs=None))]
fn process_fit(
    py: Python<'_>,
    names: Vec<String>,
    columns: Vec<Bound<'_, PyBytes>>,
    settings_json: &str,
    n_jobs: Option<i64>,
) -> PyResult<String> {
    let table = table_of(names, &columns)?;
    let s: ProcessSettings = parse_json(settings_json, "hybrid settings")?;
    let mut search: SearchConfig = with_overrides("search", &s.search.to_string())?;
    search.par = par_of(n_jobs)?;
    let mut cfg = ProcessConfig::new(&s.target, &s.physics);
    cfg.calibrate = s.calibrate;
    cfg.init = s.init;
    cfg.set = s.set;
    cfg.features = s.features;
    cfg.exclude = s.exclude;
    cfg.correction = s.correction;
    cfg.joint = s.joint;
    cfg.conformal_folds = s.conformal_folds;
    cfg.seed = search.seed;
    cfg.search = search;
    let split = hxai_eval::Split {
        train: (0..table.n_rows()).collect(),
        test: Vec::new(),
    };
    let model = py
        .detach(move || fit_process_split(&table, &cfg, &split, &mut |_| {}))
        .map_err(err)?;
    Ok(model.to_json())
}

/// `process_predict(model_json, names, columns)` -> `(physics, correction, hybrid)`.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn process_predict<'py>(
    py: Python<'py>,
    model_json: &str,
    names: Vec<String>,
    columns: Vec<Bound<'py, PyBytes>>,
) -> PyResult<(
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
)> {
    let model = ProcessModel::from_json(model_json).map_err(err)?;
    let table = table_of(names, &columns)?;
    let p = py.detach(move || model.predict(&table)).map_err(err)?;
    Ok((
        to_bytes(py, &p.physics),
        to_bytes(py, &p.correction),
        to_bytes(py, &p.hybrid),
    ))
}

/// `process_intervals(model_json, names, columns, level, method=None)` -> `(lo, hi,
/// method)`: the table hybrid's prediction intervals at `level` on a table
/// (`ProcessModel::intervals_with`), by `method` (`conformal`, `split` or `delta`; default:
/// the model file's, conformal where it stores the calibration).
#[pyfunction]
#[pyo3(signature = (model_json, names, columns, level, method=None))]
fn process_intervals<'py>(
    py: Python<'py>,
    model_json: &str,
    names: Vec<String>,
    columns: Vec<Bound<'py, PyBytes>>,
    level: f64,
    method: Option<&str>,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>, String)> {
    let model = ProcessModel::from_json(model_json).map_err(err)?;
    let default = model
        .default_interval_method(level)
        .unwrap_or(IntervalMethod::Delta);
    let method = method_of(method, default)?;
    let table = table_of(names, &columns)?;
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

/// `tool_predict(model_json, record_id, accel, fs_hz, frequency_hz)`: the tool case's
/// per-record pipeline with a model written by `hxai fit` (features, physics, hybrid), as
/// `hxai predict` runs it. Returns `(physics, hybrid, windows_json, warnings)`; each
/// window is `{window, start, len, a_phys_um, phase_rad, delta_hat_um, a_corr_um,
/// features: {name: value}}`.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn tool_predict<'py>(
    py: Python<'py>,
    model_json: &str,
    record_id: &str,
    accel: &[u8],
    fs_hz: f64,
    frequency_hz: f64,
) -> PyResult<(
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    String,
    Vec<String>,
)> {
    let model = HybridModel::from_json(model_json).map_err(err)?;
    let accel = floats(accel, "accel")?;
    let id = record_id.to_string();
    let (pred, names) = py
        .detach(move || {
            let input = RecordInput {
                id: &id,
                fs_hz,
                frequency_hz,
                signal: &accel,
                truth: None,
            };
            model
                .predict(&input)
                .map(|p| (p, model.features.names.clone()))
        })
        .map_err(err)?;
    let windows: Vec<Value> = pred
        .windows
        .iter()
        .zip(&pred.samples)
        .map(|(w, s)| {
            let feats: serde_json::Map<String, Value> = names
                .iter()
                .zip(&s.features)
                .map(|(n, v)| (n.clone(), json!(v)))
                .collect();
            json!({
                "window": w.window,
                "start": w.start,
                "len": w.len,
                "a_phys_um": w.physics.amplitude,
                "phase_rad": w.physics.phase,
                "delta_hat_um": w.delta_hat,
                "a_corr_um": w.corrected.amplitude,
                "features": feats,
            })
        })
        .collect();
    let warnings = pred.warnings.iter().map(ToString::to_string).collect();
    Ok((
        to_bytes(py, &pred.physics),
        to_bytes(py, &pred.hybrid),
        Value::Array(windows).to_string(),
        warnings,
    ))
}

/// `StreamEstimator(model_json, frequency_hz, fs_hz, interval=None)`: the tool position in
/// real time (`hxai_hybrid::stream::Estimator`), a model written by `hxai fit` applied
/// sample by sample, causally. `interval` (a level in (0, 1), e.g. 0.95) adds the hybrid's
/// prediction bounds to every row.
///
/// The estimator is owned by the Python object and mutated through `&mut self`: pyo3's
/// runtime borrow check gives one caller at a time, so a second thread calling `push` on the
/// same object while the first runs (the GIL released) gets a `RuntimeError` ("already
/// borrowed") instead of interleaving two streams' samples. No lock is needed: `Estimator`
/// is `Send + Sync` (plain data), as `#[pyclass]` and `Python::detach` require.
#[pyclass(module = "hxai._hxai", name = "StreamEstimator")]
struct StreamEstimator {
    inner: Estimator,
    interval: bool,
}

/// What `push` returns: `(sample, time, physics, hybrid, lo, hi)`, each little-endian
/// bytes (`sample` as `int64`, the others `float64`; `lo`, `hi` empty without an interval).
type PushOut<'py> = (
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
    Bound<'py, PyBytes>,
);

#[pymethods]
impl StreamEstimator {
    #[new]
    #[pyo3(signature = (model_json, frequency_hz, fs_hz, interval=None))]
    fn new(
        model_json: &str,
        frequency_hz: f64,
        fs_hz: f64,
        interval: Option<f64>,
    ) -> PyResult<Self> {
        let model = HybridModel::from_json(model_json).map_err(err)?;
        let mut inner = Estimator::new(&model, frequency_hz, fs_hz).map_err(err)?;
        if let Some(level) = interval {
            inner = inner.with_interval(level).map_err(err)?;
        }
        Ok(Self {
            inner,
            interval: interval.is_some(),
        })
    }

    /// `push(accel)` -> `(sample, time, physics, hybrid, lo, hi)`: the rows completed by these
    /// samples of acceleration (m/s^2, float64 bytes), one per sample (the delay is 0).
    /// Missing values (the warm-up, an undefined correction) are NaN. A NaN or infinite
    /// sample is a `ValueError` naming its index since the start, and the estimator stays
    /// as it was before that sample (the rows before it are not returned).
    fn push<'py>(&mut self, py: Python<'py>, accel: &[u8]) -> PyResult<PushOut<'py>> {
        let accel = floats(accel, "accel")?;
        let inner = &mut self.inner;
        let rows = py.detach(move || inner.push(&accel)).map_err(err)?;
        let nan = f64::NAN;
        let mut sample = Vec::with_capacity(rows.len() * 8);
        let mut time = Vec::with_capacity(rows.len());
        let mut physics = Vec::with_capacity(rows.len());
        let mut hybrid = Vec::with_capacity(rows.len());
        let (mut lo, mut hi) = (Vec::new(), Vec::new());
        for r in &rows {
            let i = i64::try_from(r.sample).unwrap_or(i64::MAX);
            sample.extend_from_slice(&i.to_le_bytes());
            time.push(r.time_s);
            physics.push(r.physics_um.unwrap_or(nan));
            hybrid.push(r.hybrid_um.unwrap_or(nan));
            if self.interval {
                let (l, h) = r.interval_um.unwrap_or((nan, nan));
                lo.push(l);
                hi.push(h);
            }
        }
        Ok((
            PyBytes::new(py, &sample),
            to_bytes(py, &time),
            to_bytes(py, &physics),
            to_bytes(py, &hybrid),
            to_bytes(py, &lo),
            to_bytes(py, &hi),
        ))
    }

    /// Forgets every sample: the next one starts a new warm-up, with sample index 0.
    fn restart(&mut self) {
        self.inner.restart();
    }

    /// The delay `D`: the row of sample `i` depends on samples up to `i + D` (0).
    #[getter]
    fn delay_samples(&self) -> usize {
        self.inner.delay_samples()
    }

    /// Rows without values at the start and after each restart (`W - 1`).
    #[getter]
    fn warmup_samples(&self) -> usize {
        self.inner.warmup_samples()
    }

    /// Samples between two updates of the correction.
    #[getter]
    fn update_step(&self) -> usize {
        self.inner.update_step()
    }

    /// The window `W` the estimates are made over, samples.
    #[getter]
    fn window_samples(&self) -> usize {
        self.inner.window_samples()
    }

    /// Samples pushed since the start or the last restart.
    #[getter]
    fn samples(&self) -> u64 {
        self.inner.samples()
    }

    /// Whether the rows carry prediction bounds.
    #[getter]
    fn has_interval(&self) -> bool {
        self.interval
    }
}

/// `butter(order, btype, cutoff, fs)`: Butterworth design as second-order sections, flat
/// (`n x 6`, scipy's layout, row-major).
#[pyfunction]
fn butter<'py>(
    py: Python<'py>,
    order: usize,
    btype: &str,
    cutoff: Vec<f64>,
    fs: f64,
) -> PyResult<Bound<'py, PyBytes>> {
    let band = match (btype, cutoff.as_slice()) {
        ("lowpass", [c]) => Band::Lowpass(*c),
        ("highpass", [c]) => Band::Highpass(*c),
        ("bandpass", [lo, hi]) => Band::Bandpass(*lo, *hi),
        ("lowpass" | "highpass", _) => {
            return Err(PyValueError::new_err(format!(
                "a {btype} filter takes one cutoff frequency, got {}",
                cutoff.len()
            )));
        }
        ("bandpass", _) => {
            return Err(PyValueError::new_err(format!(
                "a bandpass filter takes two cutoff frequencies (low, high), got {}",
                cutoff.len()
            )));
        }
        (other, _) => {
            return Err(PyValueError::new_err(format!(
                "unknown btype `{other}`: use lowpass, highpass or bandpass"
            )));
        }
    };
    let sos = hxai_signal::butter(order, band, fs).map_err(err)?;
    let flat: Vec<f64> = sos.sections().iter().flatten().copied().collect();
    Ok(to_bytes(py, &flat))
}

fn sos_of(sos: &[u8]) -> PyResult<Sos> {
    let v = floats(sos, "sos")?;
    let sections: Vec<[f64; 6]> = v
        .chunks(6)
        .map(|c| {
            let mut a = [0.0; 6];
            if c.len() == 6 {
                a.copy_from_slice(c);
                Ok(a)
            } else {
                Err(PyValueError::new_err(
                    "sos must have 6 values per section (shape n x 6)",
                ))
            }
        })
        .collect::<PyResult<_>>()?;
    Sos::from_sections(sections).map_err(err)
}

/// `sosfilt(sos, x)`: causal filtering (scipy's `sosfilt` with zero initial state).
#[pyfunction]
fn sosfilt<'py>(py: Python<'py>, sos: &[u8], x: &[u8]) -> PyResult<Bound<'py, PyBytes>> {
    let sos = sos_of(sos)?;
    let x = floats(x, "x")?;
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "x[{i}] = {} is not a finite number",
            x[i]
        )));
    }
    let y = py.detach(move || sos.filter(&x));
    Ok(to_bytes(py, &y))
}

/// `sosfiltfilt(sos, x)`: zero-phase filtering (scipy's `sosfiltfilt`, odd padding).
#[pyfunction]
fn sosfiltfilt<'py>(py: Python<'py>, sos: &[u8], x: &[u8]) -> PyResult<Bound<'py, PyBytes>> {
    let sos = sos_of(sos)?;
    let x = floats(x, "x")?;
    let y = py.detach(move || sos.filtfilt(&x)).map_err(err)?;
    Ok(to_bytes(py, &y))
}

/// `welch(x, fs, nperseg)` -> `(freqs, density)`: Welch's PSD with scipy's defaults.
#[pyfunction]
#[pyo3(signature = (x, fs, nperseg=256))]
fn welch<'py>(
    py: Python<'py>,
    x: &[u8],
    fs: f64,
    nperseg: usize,
) -> PyResult<(Bound<'py, PyBytes>, Bound<'py, PyBytes>)> {
    let x = floats(x, "x")?;
    let cfg = WelchConfig {
        nperseg,
        ..WelchConfig::default()
    };
    let psd = py
        .detach(move || hxai_signal::welch(&x, fs, &cfg))
        .map_err(err)?;
    Ok((to_bytes(py, &psd.freqs), to_bytes(py, &psd.density)))
}

/// `fit_sine(x, fs, freq_hz)` -> `(amplitude, phase, offset)`.
#[pyfunction]
fn fit_sine(py: Python<'_>, x: &[u8], fs: f64, freq_hz: f64) -> PyResult<(f64, f64, f64)> {
    let x = floats(x, "x")?;
    let f = py
        .detach(move || hxai_signal::fit_sine(&x, fs, freq_hz))
        .map_err(err)?;
    Ok((f.amplitude, f.phase, f.offset))
}

/// `displacement(accel, fs)`: the physics chain (band-pass, double integration, drift
/// removal) with its defaults, in micrometres.
#[pyfunction]
fn displacement<'py>(py: Python<'py>, accel: &[u8], fs: f64) -> PyResult<Bound<'py, PyBytes>> {
    let a = floats(accel, "accel")?;
    let d = py
        .detach(move || hxai_signal::displacement(&a, fs, &PhysicsConfig::default()))
        .map_err(err)?;
    Ok(to_bytes(py, &d))
}

/// `features_extract(accel, fs, command_hz)`: the twelve features f1..f12, in order.
#[pyfunction]
fn features_extract(py: Python<'_>, accel: &[u8], fs: f64, command_hz: f64) -> PyResult<Vec<f64>> {
    let a = floats(accel, "accel")?;
    let f = py
        .detach(move || hxai_features::extract(&a, fs, command_hz))
        .map_err(err)?;
    Ok(f.to_vec())
}

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
fn simulate_tool<'py>(
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
/// (`roughness`, `cutting_force`, `tool_life`) with its defaults and the given overrides.
#[pyfunction]
fn simulate_case<'py>(
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

/// The module `hxai._hxai`.
#[pymodule]
fn _hxai(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(defaults, m)?)?;
    m.add_function(wrap_pyfunction!(sr_fit, m)?)?;
    m.add_function(wrap_pyfunction!(sr_predict, m)?)?;
    m.add_function(wrap_pyfunction!(sr_intervals, m)?)?;
    m.add_function(wrap_pyfunction!(process_intervals, m)?)?;
    m.add_function(wrap_pyfunction!(process_fit, m)?)?;
    m.add_function(wrap_pyfunction!(process_predict, m)?)?;
    m.add_function(wrap_pyfunction!(tool_predict, m)?)?;
    m.add_function(wrap_pyfunction!(butter, m)?)?;
    m.add_function(wrap_pyfunction!(sosfilt, m)?)?;
    m.add_function(wrap_pyfunction!(sosfiltfilt, m)?)?;
    m.add_function(wrap_pyfunction!(welch, m)?)?;
    m.add_function(wrap_pyfunction!(fit_sine, m)?)?;
    m.add_function(wrap_pyfunction!(displacement, m)?)?;
    m.add_function(wrap_pyfunction!(features_extract, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_tool, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_case, m)?)?;
    m.add_class::<StreamEstimator>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
