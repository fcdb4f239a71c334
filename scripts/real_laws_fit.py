#!/usr/bin/env python3
"""Fits the law of each real-law table (issue 47) and writes `testdata/real/laws.json`.

The real-law suite (`scripts/bench_real_laws.py`) scores `hxai sr` against the law the
literature fits to each table, so the law must be fitted the same way for everyone: by
`scipy.optimize.curve_fit` (unweighted least squares, the loss `hxai sr` minimises) on every
row, from starting values computed here from the rows alone (linearisations in the spirit of
R's self-starting models; nothing else is looked at). A fit that does not converge stops the
script. Prints each fit with its R^2; `testdata/real/README.md` compares them with R's.

Each law is a sympy expression string in the table's column names and the parameter names;
`file` is relative to laws.json's folder; `law_complexity` counts the law in `hxai sr`'s terms
(see `complexity`).

Usage: python scripts/real_laws_fit.py [--dir testdata/real]
"""
import argparse
import json
from pathlib import Path

import numpy as np
import pandas as pd
import sympy as sp
from scipy.optimize import curve_fit


def line(x, z):
    """Slope and intercept of the least-squares line of z on x."""
    slope, intercept = np.polyfit(x, z, 1)
    return slope, intercept


def start_asymptotic(x, y):
    """SSasymp: log(Asym - y) is linear in x, with Asym a little above the largest y."""
    asym = y.max() + 0.1 * np.ptp(y)
    slope, intercept = line(x, np.log(asym - y))
    return [asym, asym - np.exp(intercept), np.log(-slope)]


def start_logistic(x, y):
    """SSlogis: log(y / (Asym - y)) = (x - xmid) / scal, with Asym a little above the largest y."""
    asym = 1.05 * y.max()
    slope, intercept = line(x, np.log(y / (asym - y)))
    return [asym, -intercept / slope, 1 / slope]


def start_fpl(x, y):
    """SSfpl in log(x): the logistic start between asymptotes just outside the range of y."""
    a, b = y.min() - 0.05 * np.ptp(y), y.max() + 0.05 * np.ptp(y)
    slope, intercept = line(np.log(x), np.log((y - a) / (b - y)))
    return [a, b, -intercept / slope, 1 / slope]


def start_biexp(x, y):
    """SSbiexp by curve peeling: the slow phase from the later half of the times, the fast
    phase from what it leaves of the earlier half."""
    late = x >= np.median(x)
    slope2, intercept2 = line(x[late], np.log(y[late]))
    rest = y - np.exp(intercept2 + slope2 * x)
    early = ~late & (rest > 0)
    slope1, intercept1 = line(x[early], np.log(rest[early]))
    return [np.exp(intercept1), np.log(-slope1), np.exp(intercept2), np.log(-slope2)]


def start_asymptotic_theta(x, y):
    """alpha + beta*exp(-x/theta): as SSasymp, log(alpha - y) is linear in x."""
    alpha = y.max() + 0.1 * np.ptp(y)
    slope, intercept = line(x, np.log(alpha - y))
    return [alpha, -np.exp(intercept), -1 / slope]


def start_power(x, y):
    """a*x**b: the straight line of log(y) on log(x)."""
    slope, intercept = line(np.log(x), np.log(y))
    return [np.exp(intercept), slope]


def start_linear(X, y):
    """a*dist + b*climb: linear least squares."""
    return list(np.linalg.lstsq(np.column_stack(X), y, rcond=None)[0])


# name, target, inputs, law, parameters in the start function's order, start function, reference
LAWS = [
    ("loblolly", "height", ["age"], "Asym + (R0 - Asym)*exp(-exp(lrc)*age)",
     ["Asym", "R0", "lrc"], start_asymptotic, "asymptotic growth, R's SSasymp"),
    ("orange", "circumference", ["age"], "Asym/(1 + exp((xmid - age)/scal))",
     ["Asym", "xmid", "scal"], start_logistic, "logistic growth, R's SSlogis"),
    ("dnase1", "density", ["conc"], "A + (B - A)/(1 + exp((xmid - log(conc))/scal))",
     ["A", "B", "xmid", "scal"], start_fpl, "four-parameter logistic in log(conc), R's SSfpl"),
    ("indometh", "conc", ["time"], "A1*exp(-exp(lrc1)*time) + A2*exp(-exp(lrc2)*time)",
     ["A1", "lrc1", "A2", "lrc2"], start_biexp, "bi-exponential decay, R's SSbiexp"),
    ("muscle", "length", ["conc"], "alpha + beta*exp(-conc/theta)",
     ["alpha", "beta", "theta"], start_asymptotic_theta,
     "asymptotic exponential, Venables & Ripley, MASS 4th ed., ch. 8 (common curve)"),
    ("mammals", "brain", ["body"], "a*body**b",
     ["a", "b"], start_power, "allometric power law, MASS 4th ed. (fitted there on the log scale)"),
    ("hills", "time", ["dist", "climb"], "a*dist + b*climb",
     ["a", "b"], start_linear, "Naismith's rule, no intercept (MASS 4th ed. fits lm(time ~ dist + climb))"),
]


def parse(text, names, positive=()):
    """`text` as a sympy expression whose every name in `names` is a plain symbol (so that
    `beta` or `A` never meet sympy's own), positive for the names in `positive`."""
    local = {n: sp.Symbol(n, positive=True) if n in positive else sp.Symbol(n) for n in names}
    return sp.parse_expr(text, local_dict=local)


def complexity(expr, inputs):
    """The size of `expr` in `hxai sr`'s terms: input leaves plus operators, where constants
    and affine maps (adding or multiplying by a constant) are free. Each function (exp, log,
    ...) and each power counts 1, a sum or product of k terms that depend on the inputs
    counts k - 1; every other name is a constant. So a*x**b is 2, A1*exp(k1*t) + A2*exp(k2*t)
    is 5."""
    names = {str(n) for n in inputs}
    if isinstance(expr, sp.Symbol):
        return int(expr.name in names)
    varying = [a for a in expr.args if {s.name for s in a.free_symbols} & names]
    if not varying:
        return 0
    own = len(varying) - 1 + int(isinstance(expr, (sp.Function, sp.Pow)))
    return own + sum(complexity(a, inputs) for a in varying)


def law_function(law, inputs, params):
    """The law as a numpy function f(X, *params) with X a tuple of input columns."""
    expr = parse(law, inputs + params)
    f = sp.lambdify([sp.symbols(inputs), *sp.symbols(params)], expr, "numpy")
    return lambda X, *p: f(X, *p)


def fit(law, inputs, params, start, X, y):
    """The parameters of `law` fitted by curve_fit on the rows (X, y) from `start(X, y)`."""
    p0 = start(*X, y) if len(X) == 1 else start(X, y)
    popt, pcov = curve_fit(law_function(law, inputs, params), X, y, p0=p0, maxfev=20000)
    if not np.all(np.isfinite(pcov)):
        raise RuntimeError(f"{law}: the fit did not converge (covariance not finite)")
    return p0, popt


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dir", default="testdata/real", help="folder of the CSVs and laws.json")
    a = ap.parse_args()
    folder = Path(a.dir)
    laws = {}
    for name, target, inputs, law, params, start, reference in LAWS:
        df = pd.read_csv(folder / f"{name}.csv")
        X = tuple(df[c].to_numpy(float) for c in inputs)
        y = df[target].to_numpy(float)
        p0, popt = fit(law, inputs, params, start, X, y)
        pred = law_function(law, inputs, params)(X, *popt)
        r2 = 1 - np.sum((y - pred) ** 2) / np.sum((y - y.mean()) ** 2)
        laws[name] = {
            "file": f"{name}.csv",
            "rows": len(df),
            "target": target,
            "inputs": inputs,
            "law": law,
            "params": dict(zip(params, map(float, popt))),
            "start": dict(zip(params, map(float, p0))),
            "positive": [c for c in df.columns if (df[c] > 0).all()],
            "law_complexity": complexity(parse(law, inputs + params), inputs),
            "r2": float(r2),
            "rmse": float(np.sqrt(np.mean((y - pred) ** 2))),
            "reference": reference,
        }
        fitted = ", ".join(f"{p} = {v:.6g}" for p, v in zip(params, popt))
        print(f"{name:9s} {target} = {law}: {fitted}; R^2 {r2:.4f}, {len(df)} rows")
    (folder / "laws.json").write_text(json.dumps(laws, indent=1) + "\n")


if __name__ == "__main__":
    main()
