//! The signal functions in scipy's shapes (`butter`, `sosfilt`, `sosfiltfilt`, `welch`,
//! `fit_sine`), the physics model's `displacement` and the twelve features
//! (`features_extract`), over `hxai_signal` and `hxai_features`.

use crate::convert::{err, floats, to_bytes};
use hxai_signal::{Band, PhysicsConfig, Sos, WelchConfig};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// `butter(order, btype, cutoff, fs)`: Butterworth design as second-order sections, flat
/// (`n x 6`, scipy's layout, row-major).
#[pyfunction]
pub(crate) fn butter<'py>(
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
pub(crate) fn sosfilt<'py>(py: Python<'py>, sos: &[u8], x: &[u8]) -> PyResult<Bound<'py, PyBytes>> {
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
pub(crate) fn sosfiltfilt<'py>(
    py: Python<'py>,
    sos: &[u8],
    x: &[u8],
) -> PyResult<Bound<'py, PyBytes>> {
    let sos = sos_of(sos)?;
    let x = floats(x, "x")?;
    let y = py.detach(move || sos.filtfilt(&x)).map_err(err)?;
    Ok(to_bytes(py, &y))
}

/// `welch(x, fs, nperseg)` -> `(freqs, density)`: Welch's PSD with scipy's defaults.
#[pyfunction]
#[pyo3(signature = (x, fs, nperseg=256))]
pub(crate) fn welch<'py>(
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
pub(crate) fn fit_sine(
    py: Python<'_>,
    x: &[u8],
    fs: f64,
    freq_hz: f64,
) -> PyResult<(f64, f64, f64)> {
    let x = floats(x, "x")?;
    let f = py
        .detach(move || hxai_signal::fit_sine(&x, fs, freq_hz))
        .map_err(err)?;
    Ok((f.amplitude, f.phase, f.offset))
}

/// `displacement(accel, fs)`: the physics chain (band-pass, double integration, drift
/// removal) with its defaults, in micrometres.
#[pyfunction]
pub(crate) fn displacement<'py>(
    py: Python<'py>,
    accel: &[u8],
    fs: f64,
) -> PyResult<Bound<'py, PyBytes>> {
    let a = floats(accel, "accel")?;
    let d = py
        .detach(move || hxai_signal::displacement(&a, fs, &PhysicsConfig::default()))
        .map_err(err)?;
    Ok(to_bytes(py, &d))
}

/// `features_extract(accel, fs, command_hz)`: the twelve features f1..f12, in order.
#[pyfunction]
pub(crate) fn features_extract(
    py: Python<'_>,
    accel: &[u8],
    fs: f64,
    command_hz: f64,
) -> PyResult<Vec<f64>> {
    let a = floats(accel, "accel")?;
    let f = py
        .detach(move || hxai_features::extract(&a, fs, command_hz))
        .map_err(err)?;
    Ok(f.to_vec())
}
