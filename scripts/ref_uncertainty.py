#!/usr/bin/env python3
"""Reference covariances for hxai-symreg's uncertainty (s^2 (J^T J)^-1 at the optimum).

Run: `cargo xtask refs` (all ref scripts, pinned versions from scripts/requirements.txt), or
`python3 scripts/ref_uncertainty.py` in an environment with those versions.
Writes testdata/symreg/uncertainty.json. Not run by CI.

Each case is an equation in hxai's infix syntax over columns and named parameters, data drawn
here with a fixed seed, and scipy.optimize.curve_fit's optimum and covariance (method 'lm',
analytic Jacobian, tolerances at the limit of float64, absolute_sigma False, so
pcov = s^2 (J^T J)^-1 with s^2 = SSE / (n - k)). The Rust test fits the same equation from
the same start and compares at relative 1e-6.
"""
import json
import pathlib

import numpy as np
import scipy
from scipy.optimize import curve_fit

from _common import write_atomic

rng = np.random.default_rng(20261122)
out = {"versions": {"numpy": np.__version__, "scipy": scipy.__version__}, "cases": []}


def case(name, equation, columns, params, p0, X, f, jac, sigma):
    """Adds one case: noise of sd `sigma` on the true values f(X, *truth)."""
    y_true = f(X, *truth[name])
    y = y_true + rng.normal(0.0, sigma, len(y_true))

    def model(_x, *p):
        return f(X, *p)

    def jacobian(_x, *p):
        return jac(X, *p)

    popt, pcov = curve_fit(
        model, np.zeros(len(y)), y, p0=p0, jac=jacobian, method="lm",
        ftol=1e-15, xtol=1e-15, gtol=1e-15, maxfev=100000,
    )
    out["cases"].append({
        "name": name,
        "equation": equation,
        "columns": {c: X[i].tolist() for i, c in enumerate(columns)},
        "column_order": columns,
        "params": params,
        "p0": list(p0),
        "y": y.tolist(),
        "popt": popt.tolist(),
        "pcov": pcov.tolist(),
        "perr": np.sqrt(np.diag(pcov)).tolist(),
    })


truth = {
    "linear": (1.5, -0.8),
    "exp_decay": (3.0, 0.7, 0.5),
    "kienzle": (1700.0, 0.25),
    "sine_trend": (2.0, 1.3, 0.4),
}

# y = a + b x
x = np.sort(rng.uniform(0.0, 10.0, 30))
case("linear", "a + b*x", ["x"], ["a", "b"], (1.0, 1.0), np.array([x]),
     lambda X, a, b: a + b * X[0],
     lambda X, a, b: np.stack([np.ones_like(X[0]), X[0]], axis=1), 0.3)

# y = a exp(-k x) + c
x = np.sort(rng.uniform(0.0, 6.0, 40))
case("exp_decay", "a*exp(-k*x) + c", ["x"], ["a", "k", "c"], (2.5, 0.5, 0.3), np.array([x]),
     lambda X, a, k, c: a * np.exp(-k * X[0]) + c,
     lambda X, a, k, c: np.stack([np.exp(-k * X[0]), -a * X[0] * np.exp(-k * X[0]),
                                  np.ones_like(X[0])], axis=1), 0.05)

# Kienzle's cutting force F = kc b h^(1 - mc)
b = rng.uniform(0.5, 3.0, 50)
h = rng.uniform(0.05, 0.4, 50)
case("kienzle", "kc*b*h^(1-mc)", ["b", "h"], ["kc", "mc"], (1500.0, 0.2), np.array([b, h]),
     lambda X, kc, mc: kc * X[0] * X[1] ** (1 - mc),
     lambda X, kc, mc: np.stack([X[0] * X[1] ** (1 - mc),
                                 -kc * X[0] * X[1] ** (1 - mc) * np.log(X[1])], axis=1), 20.0)

# y = a sin(w x) + c x
x = np.sort(rng.uniform(0.0, 8.0, 60))
case("sine_trend", "a*sin(w*x) + c*x", ["x"], ["a", "w", "c"], (1.8, 1.25, 0.3), np.array([x]),
     lambda X, a, w, c: a * np.sin(w * X[0]) + c * X[0],
     lambda X, a, w, c: np.stack([np.sin(w * X[0]), a * X[0] * np.cos(w * X[0]), X[0]], axis=1),
     0.2)

path = pathlib.Path(__file__).resolve().parent.parent / "testdata" / "symreg" / "uncertainty.json"
write_atomic(path, json.dumps(out, indent=1) + "\n")
print(f"wrote {path}")
