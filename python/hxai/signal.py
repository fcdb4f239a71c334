"""The signal functions of hxai on NumPy arrays, in scipy's shapes.

Each function is the Rust function of ``hxai-signal`` (which the Rust tests compare with
scipy's reference vectors); tests/test_signal.py compares these bindings with scipy
directly.
"""

import numpy as np

from . import _hxai
from ._arrays import from_bytes, to_bytes

_BTYPES = {
    "lowpass": "lowpass",
    "low": "lowpass",
    "highpass": "highpass",
    "high": "highpass",
    "bandpass": "bandpass",
    "band": "bandpass",
}


def _sos_bytes(sos):
    a = np.asarray(sos, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 6:
        raise ValueError(f"sos must have shape (n, 6), got {a.shape}")
    return np.ascontiguousarray(a, dtype="<f8").tobytes()


def butter(order, cutoff, btype="lowpass", fs=None):
    """Digital Butterworth filter as second-order sections: an ``(n, 6)`` array laid out
    as ``scipy.signal.butter(order, cutoff, btype, output="sos", fs=fs)``.

    ``btype`` is ``lowpass``/``highpass`` (``cutoff`` a number, Hz) or ``bandpass``
    (``cutoff`` a pair); ``fs`` (Hz) is required.
    """
    if fs is None:
        raise ValueError("fs is required: hxai designs digital filters from cutoffs in Hz")
    kind = _BTYPES.get(str(btype).lower())
    if kind is None:
        raise ValueError(f"unknown btype `{btype}`: use lowpass, highpass or bandpass")
    cut = [float(c) for c in np.atleast_1d(np.asarray(cutoff, dtype=np.float64))]
    if isinstance(order, bool) or int(order) != order or order < 0:
        raise ValueError(f"order must be a positive integer, got {order!r}")
    flat = from_bytes(_hxai.butter(int(order), kind, cut, float(fs)))
    return flat.reshape(-1, 6)


def sosfilt(sos, x):
    """Causal filtering by second-order sections (``scipy.signal.sosfilt``, zero state)."""
    return from_bytes(_hxai.sosfilt(_sos_bytes(sos), to_bytes(x, "x")))


def sosfiltfilt(sos, x):
    """Zero-phase filtering (``scipy.signal.sosfiltfilt`` with its default odd padding)."""
    return from_bytes(_hxai.sosfiltfilt(_sos_bytes(sos), to_bytes(x, "x")))


def welch(x, fs, nperseg=256):
    """Welch's power spectral density, ``(freqs, density)`` as ``scipy.signal.welch(x, fs)``
    (periodic Hann window, half overlap, constant detrend, one-sided density)."""
    if isinstance(nperseg, bool) or int(nperseg) != nperseg or nperseg < 1:
        raise ValueError(f"nperseg must be a positive integer, got {nperseg!r}")
    f, p = _hxai.welch(to_bytes(x, "x"), float(fs), int(nperseg))
    return from_bytes(f), from_bytes(p)


def fit_sine(x, fs, freq_hz):
    """Least-squares sine of known frequency: ``(amplitude, phase, offset)`` with
    ``x[i] ~ offset + amplitude * sin(2 pi freq_hz i / fs + phase)``."""
    return _hxai.fit_sine(to_bytes(x, "x"), float(fs), float(freq_hz))


def displacement(accel, fs):
    """Displacement in micrometres from acceleration in m/s^2 (the physics model: 4th-order
    5-200 Hz Butterworth band-pass applied forwards and backwards, double integration by
    the trapezoidal rule, linear drift removed after each integration)."""
    return from_bytes(_hxai.displacement(to_bytes(accel, "accel"), float(fs)))
