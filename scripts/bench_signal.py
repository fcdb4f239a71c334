#!/usr/bin/env python3
"""Times in scipy/numpy the computations of the criterion benches of hxai-signal and
hxai-features (crates/signal/benches/physics.rs, crates/features/benches/features.rs).

Run:  python3 scripts/bench_signal.py [--repeat 7] [--number 20]
with numpy and scipy as pinned in scripts/requirements.txt (`cargo xtask refs` leaves such an
environment in target/refs-venv).
Prints one line per case: name, samples, best seconds per call, samples per second.
Best of `repeat` timeit runs of `number` calls each (the minimum is the least noisy estimate
on a shared machine).
"""
import argparse
import timeit

import numpy as np
from scipy import integrate, signal, stats

FS = 10_000.0


def record(n):
    rng = np.random.default_rng(7)
    w = 2 * np.pi * 20.0
    t = np.arange(n) / FS
    return -w * w * 5e-6 * np.sin(w * t) + 0.01 * (rng.random(n) - 0.5)


def accel_features(n):
    rng = np.random.default_rng(7)
    t = np.arange(n) / FS
    return np.sin(2 * np.pi * 20.0 * t) + 0.1 * (rng.random(n) - 0.5)


def displacement(a, fs=FS):
    """The physics chain with hxai's PhysicsConfig::default(): 4th-order Butterworth
    band-pass 5..200 Hz (designed per call, like hxai_signal::displacement), sosfiltfilt,
    cumulative trapezoid, linear detrend, cumulative trapezoid, linear detrend, to um."""
    sos = signal.butter(4, [5.0, 200.0], btype="bandpass", fs=fs, output="sos")
    af = signal.sosfiltfilt(sos, a)
    v = signal.detrend(integrate.cumulative_trapezoid(af, dx=1 / fs, initial=0), type="linear")
    d = signal.detrend(integrate.cumulative_trapezoid(v, dx=1 / fs, initial=0), type="linear")
    return d * 1e6


SOS = signal.butter(4, [5.0, 200.0], btype="bandpass", fs=FS, output="sos")


def filtfilt_only(a):
    return signal.sosfiltfilt(SOS, a)


def features(a, fs=FS, cmd=20.0):
    """All twelve features with hxai-features defaults (biased sigma, Welch PSD)."""
    mav = np.mean(np.abs(a))
    var = np.var(a, ddof=1)
    peak = np.max(np.abs(a))
    rms = np.sqrt(np.mean(a * a))
    kurt = stats.kurtosis(a, fisher=False, bias=True)
    skew = stats.skew(a, bias=True)
    f, p = signal.welch(a, fs)
    tot = np.sum(p)
    return [cmd, mav, var, peak, rms, kurt, skew, peak / rms, peak / mav, rms / mav, np.sum(f * p) / tot, tot]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--number", type=int, default=20)
    args = ap.parse_args()
    cases = [
        ("physics/displacement", displacement, record),
        ("physics/filtfilt_bp4", filtfilt_only, record),
        ("features/extract", features, accel_features),
    ]
    print("case\tsamples\tbest_s_per_call\tsamples_per_s")
    for name, fn, gen in cases:
        for n in (2_000, 20_000):
            x = gen(n)
            best = min(timeit.repeat(lambda: fn(x), repeat=args.repeat, number=args.number)) / args.number
            print(f"{name}\t{n}\t{best:.3e}\t{n / best:.3e}")


if __name__ == "__main__":
    main()
