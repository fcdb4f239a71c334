#!/usr/bin/env python3
"""Reference vectors for hxai-signal and hxai-features, computed with numpy/scipy.

Run: `cargo xtask refs` (all ref scripts, pinned versions from scripts/requirements.txt), or
`python3 scripts/ref_signal.py` in an environment with those versions.
Writes testdata/signal/*.json and testdata/features/*.json (small; committed; not run by CI).
Signals are drawn from a seeded numpy generator and stored, so Rust never has to regenerate them.
"""
import json
import pathlib

import numpy as np
import scipy
from scipy import integrate, signal, stats

from _common import write_atomic

ROOT = pathlib.Path(__file__).resolve().parent.parent
SIG = ROOT / "testdata" / "signal"
FEAT = ROOT / "testdata" / "features"
rng = np.random.default_rng(20260521)


def dump(path, obj):
    obj = {"generator": f"scripts/ref_signal.py (scipy {scipy.__version__}, numpy {np.__version__})", **obj}
    write_atomic(path, json.dumps(obj, separators=(",", ":")) + "\n")


def lst(a):
    return [float(v) for v in np.asarray(a).ravel()]


def test_signal(n, fs):
    t = np.arange(n) / fs
    return np.sin(2 * np.pi * 20 * t) + 0.3 * np.sin(2 * np.pi * 170 * t + 0.4) + 0.5 * rng.standard_normal(n) + 0.2


# 1. Butterworth designs: orders 1..6, low/high/band, two sampling rates.
designs = []
bands = [
    ("lowpass", [50.0], 1000.0),
    ("lowpass", [320.0], 1000.0),
    ("highpass", [10.0], 1000.0),
    ("highpass", [260.0], 1000.0),
    ("bandpass", [5.0, 200.0], 1000.0),
    ("bandpass", [1.0, 450.0], 1000.0),
    ("bandpass", [100.0, 110.0], 1000.0),
    ("bandpass", [5.0, 200.0], 5000.0),
]
for order in range(1, 7):
    for btype, wn, fs in bands:
        sos = signal.butter(order, wn if len(wn) > 1 else wn[0], btype=btype, fs=fs, output="sos")
        designs.append({"order": order, "btype": btype, "wn": wn, "fs": fs, "sos": [lst(r) for r in sos]})
dump(SIG / "butter.json", {"designs": designs})

# 2. Filtering: sosfilt, sosfilt_zi, sosfiltfilt on stored signals, odd lengths and lengths
#    just above the pad length.
cases = []
for order, btype, wn, fs, n in [
    (4, "bandpass", [5.0, 200.0], 1000.0, 401),
    (4, "bandpass", [5.0, 200.0], 1000.0, None),  # padlen + 1
    (1, "lowpass", [50.0], 1000.0, None),
    (3, "highpass", [10.0], 1000.0, 257),
    (5, "lowpass", [320.0], 1000.0, None),
    (6, "bandpass", [1.0, 450.0], 1000.0, 300),
    (2, "highpass", [260.0], 1000.0, None),
]:
    sos = signal.butter(order, wn if len(wn) > 1 else wn[0], btype=btype, fs=fs, output="sos")
    ntaps = 2 * len(sos) + 1 - min((sos[:, 2] == 0).sum(), (sos[:, 5] == 0).sum())
    padlen = 3 * int(ntaps)
    if n is None:
        n = padlen + 1
    x = test_signal(n, fs)
    cases.append({
        "order": order, "btype": btype, "wn": wn, "fs": fs, "padlen": padlen, "x": lst(x),
        "sosfilt": lst(signal.sosfilt(sos, x)),
        "zi": [lst(r) for r in signal.sosfilt_zi(sos)],
        "sosfiltfilt": lst(signal.sosfiltfilt(sos, x)),
    })
dump(SIG / "filter.json", {"cases": cases})

# 3. Welch / periodogram.
wcases = []
for n, kw in [
    (1000, {}),
    (200, {}),  # shorter than 256: nperseg cut to 200
    (777, {}),
    (777, {"nperseg": 128, "noverlap": 100}),
    (513, {"nperseg": 101}),
    (600, {"detrend": "linear", "scaling": "spectrum"}),
    (500, {"window": "boxcar", "detrend": False}),
]:
    fs = 1000.0
    x = test_signal(n, fs)
    f, p = signal.welch(x, fs, **kw)
    wcases.append({"fs": fs, "kwargs": kw, "x": lst(x), "freqs": lst(f), "density": lst(p)})
for n in [300, 301]:
    fs = 500.0
    x = test_signal(n, fs)
    f, p = signal.periodogram(x, fs)
    wcases.append({"fs": fs, "kwargs": {"periodogram": True}, "x": lst(x), "freqs": lst(f), "density": lst(p)})
dump(SIG / "welch.json", {"cases": wcases})

# 4. Integration and detrending.
y = test_signal(257, 1000.0)
dump(SIG / "integrate.json", {
    "y": lst(y), "dx": 0.001,
    "cumulative_trapezoid": lst(integrate.cumulative_trapezoid(y, dx=0.001, initial=0)),
    "detrend_linear": lst(signal.detrend(y, type="linear")),
    "detrend_constant": lst(signal.detrend(y, type="constant")),
})

# 5. Physics chain (hxai_signal::displacement), default config and the frequency integrator.
pcases = []
for n, fs in [(1500, 1000.0), (2001, 2000.0)]:
    t = np.arange(n) / fs
    w = 2 * np.pi * 20.0
    a = -w * w * 5e-6 * np.sin(w * t + 0.3) + 0.02 * rng.standard_normal(n) + 0.01
    sos = signal.butter(4, [5.0, 200.0], btype="bandpass", fs=fs, output="sos")
    af = signal.sosfiltfilt(sos, a)
    v = signal.detrend(integrate.cumulative_trapezoid(af, dx=1 / fs, initial=0), type="linear")
    d = signal.detrend(integrate.cumulative_trapezoid(v, dx=1 / fs, initial=0), type="linear") * 1e6
    spec = np.fft.rfft(a)
    f = np.fft.rfftfreq(n, 1 / fs)
    inband = (f >= 5.0) & (f <= 200.0)
    spec2 = np.zeros_like(spec)
    spec2[inband] = spec[inband] / -((2 * np.pi * f[inband]) ** 2)
    dfreq = np.fft.irfft(spec2, n) * 1e6
    pcases.append({"fs": fs, "accel": lst(a), "time": lst(d), "frequency": lst(dfreq)})
dump(SIG / "physics.json", {"cases": pcases})

# 6. Features (paper Table 2) on a few unit-scale signals.
fcases = []
for n, fs, cmd in [(500, 1000.0, 20.0), (333, 2000.0, 40.0), (1024, 5000.0, 10.0)]:
    a = test_signal(n, fs) * 1.7 - 0.1
    mean = a.mean()
    sd_b = a.std(ddof=0)
    sd_u = a.std(ddof=1)
    mav = np.mean(np.abs(a))
    rms = np.sqrt(np.mean(a ** 2))
    peak = np.max(np.abs(a))
    out = {"n": n, "fs": fs, "command_hz": cmd, "accel": lst(a)}
    for name, (f, p) in {"welch": signal.welch(a, fs), "periodogram": signal.periodogram(a, fs)}.items():
        out[name] = {"f11": float(np.sum(f * p) / np.sum(p)), "f12": float(np.sum(p))}
    out.update({
        "f1": cmd, "f2": float(mav), "f3": float(a.var(ddof=1)), "f4": float(peak), "f5": float(rms),
        "f6_biased": float(stats.kurtosis(a, fisher=False, bias=True)),
        "f7_biased": float(stats.skew(a, bias=True)),
        "f6_unbiased_sigma": float(np.mean(((a - mean) / sd_u) ** 4)),
        "f7_unbiased_sigma": float(np.mean(((a - mean) / sd_u) ** 3)),
        "f8": float(peak / rms), "f9": float(peak / mav), "f10": float(rms / mav),
    })
    assert abs(out["f6_biased"] - np.mean(((a - mean) / sd_b) ** 4)) < 1e-12
    fcases.append(out)
dump(FEAT / "features.json", {"cases": fcases})
for p in sorted(list(SIG.glob("*.json")) + list(FEAT.glob("*.json"))):
    print(p.relative_to(ROOT), p.stat().st_size)
