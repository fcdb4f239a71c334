//! The tool case's model written by `hxai fit`, applied per record (`tool_predict`, as
//! `hxai predict` runs it), sample by sample (the class `StreamEstimator`, as
//! `hxai stream` runs it), and shown (`tool_report`, `tool_card`, as `hxai report`).

use crate::convert::{err, floats, to_bytes};
use hxai_hybrid::records::stream::Estimator;
use hxai_hybrid::records::{RecordInput, RecordModel};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// `tool_predict(model_json, record_id, accel, fs_hz, frequency_hz)`: the tool case's
/// per-record pipeline with a model written by `hxai fit` (features, physics, hybrid), as
/// `hxai predict` runs it. Returns `(physics, hybrid, windows_json, warnings)`; each
/// window is a [`hxai_hybrid::records::WindowRow`] with its features: `{window, start,
/// len, start_s, a_phys_um, phase_rad, delta_hat_um, a_corr_um, features: {name: value}}`.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub(crate) fn tool_predict<'py>(
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
    let model = RecordModel::from_json(model_json).map_err(err)?;
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
    let windows = pred.window_rows(None, fs_hz, Some(&names));
    let warnings = pred.warnings.iter().map(ToString::to_string).collect();
    Ok((
        to_bytes(py, &pred.physics),
        to_bytes(py, &pred.hybrid),
        serde_json::to_string(&windows).map_err(err)?,
        warnings,
    ))
}

/// One record from Python for `tool_report`: `(id, fs_hz, frequency_hz, accel, probe)`, the
/// signals as `float64` bytes.
type PyRecord<'py> = (String, f64, f64, Bound<'py, PyBytes>, Bound<'py, PyBytes>);

/// `tool_report(model_json, records=None, compare_json=None, data_name=None)` -> the HTML
/// page of `hxai report` for a model of `hxai fit`; with records (each with its probe
/// truth), the scores, figures and ranges drawn on them, as `hxai report --data FOLDER`.
#[pyfunction]
#[pyo3(signature = (model_json, records=None, compare_json=None, data_name=None))]
pub(crate) fn tool_report(
    py: Python<'_>,
    model_json: &str,
    records: Option<Vec<PyRecord<'_>>>,
    compare_json: Option<&str>,
    data_name: Option<String>,
) -> PyResult<String> {
    let model = RecordModel::from_json(model_json).map_err(err)?;
    let compare: Option<serde_json::Value> = compare_json
        .map(|t| crate::convert::parse_json(t, "comparison"))
        .transpose()?;
    let signals = records
        .map(|rs| {
            rs.into_iter()
                .map(|(id, fs, f, a, p)| {
                    let accel = floats(a.as_bytes(), "accel")?;
                    let probe = floats(p.as_bytes(), "probe")?;
                    Ok((id, fs, f, accel, probe))
                })
                .collect::<PyResult<Vec<_>>>()
        })
        .transpose()?;
    let name = data_name.unwrap_or_else(|| "the records given".to_string());
    let version = env!("CARGO_PKG_VERSION");
    py.detach(|| {
        let Some(signals) = &signals else {
            let inputs = hxai_plot::report::tool_inputs(&model, None, compare.as_ref(), version)?;
            return Ok(hxai_plot::report::tool_report(&model, &inputs));
        };
        let records: Vec<RecordInput<'_>> = signals
            .iter()
            .map(|(id, fs, f, a, p)| RecordInput {
                id,
                fs_hz: *fs,
                frequency_hz: *f,
                signal: a,
                truth: Some(p),
            })
            .collect();
        let data = hxai_plot::report::ToolData {
            name: &name,
            records: &records,
            warnings: Vec::new(),
        };
        let inputs =
            hxai_plot::report::tool_inputs(&model, Some(&data), compare.as_ref(), version)?;
        Ok(hxai_plot::report::tool_report(&model, &inputs))
    })
    .map_err(|e: hxai_hybrid::HybridError| err(e))
}

/// `tool_card(model_json)` -> the compact HTML card of a model of `hxai fit` (`ToolModel`'s
/// `_repr_html_`).
#[pyfunction]
pub(crate) fn tool_card(model_json: &str) -> PyResult<String> {
    let model = RecordModel::from_json(model_json).map_err(err)?;
    Ok(hxai_plot::report::tool_card(&model))
}

/// `StreamEstimator(model_json, frequency_hz, fs_hz, interval=None)`: the tool position in
/// real time (`hxai_hybrid::records::stream::Estimator`), a model written by `hxai fit` applied
/// sample by sample, causally. `interval` (a level in (0, 1), e.g. 0.95) adds the hybrid's
/// prediction bounds to every row.
///
/// The estimator is owned by the Python object and mutated through `&mut self`: pyo3's
/// runtime borrow check gives one caller at a time, so a second thread calling `push` on the
/// same object while the first runs (the GIL released) gets a `RuntimeError` ("already
/// borrowed") instead of interleaving two streams' samples. No lock is needed: `Estimator`
/// is `Send + Sync` (plain data), as `#[pyclass]` and `Python::detach` require.
#[pyclass(module = "hxai._hxai", name = "StreamEstimator")]
pub(crate) struct StreamEstimator {
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
        let model = RecordModel::from_json(model_json).map_err(err)?;
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
