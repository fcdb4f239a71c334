#!/usr/bin/env python3
"""Reference for per-class constants (issue 48): MASS::whiteside, R's `lm(Gas ~ Insul/Temp)`.

Fits one line per level of `insul` (gas consumption against outside temperature, before and
after cavity-wall insulation) by least squares on testdata/real/whiteside.csv and writes each
level's intercept and slope with its standard error to testdata/per_class/whiteside_lm.json.

`lm(Gas ~ Insul/Temp)` is one pooled model (a common residual variance) parameterised as an
intercept, an `Insul` offset and one slope per level; its per-level intercepts and slopes are
those of the design [1{Before}, 1{After}, 1{Before} Temp, 1{After} Temp], which numpy's
lstsq solves here. statsmodels' formula `gas ~ insul/temp` (R's parameterisation) is fitted
too, and the two must agree to 1e-10 before anything is written. Tolerance for hxai: 1e-6
relative (issue 48's goal), on values and standard errors.

Usage: python3 scripts/ref_per_class.py [--out testdata/per_class/whiteside_lm.json]
Needs numpy and statsmodels.
"""
import argparse
import csv
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "testdata/per_class/whiteside_lm.json"))
    a = ap.parse_args()
    path = os.path.join(ROOT, "testdata/real/whiteside.csv")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    insul = [r["insul"] for r in rows]
    temp = np.array([float(r["temp"]) for r in rows])
    gas = np.array([float(r["gas"]) for r in rows])
    levels = sorted(set(insul))
    ind = np.array([[1.0 if v == lv else 0.0 for lv in levels] for v in insul])
    X = np.hstack([ind, ind * temp[:, None]])
    beta, *_ = np.linalg.lstsq(X, gas, rcond=None)
    resid = gas - X @ beta
    n, m = X.shape
    s2 = resid @ resid / (n - m)
    se = np.sqrt(np.diag(s2 * np.linalg.inv(X.T @ X)))

    import pandas as pd
    import statsmodels.formula.api as smf

    df = pd.DataFrame({"insul": insul, "temp": temp, "gas": gas})
    fit = smf.ols("gas ~ insul/temp", df).fit()
    p = fit.params
    # R's parameterisation: the first level (alphabetical) is the baseline intercept
    base = levels[0]
    for k, lv in enumerate(levels):
        icpt = p["Intercept"] + (0.0 if lv == base else p[f"insul[T.{lv}]"])
        slope = p[f"insul[{lv}]:temp"]
        if abs(icpt - beta[k]) > 1e-10 * abs(icpt) or abs(slope - beta[len(levels) + k]) > 1e-10 * abs(slope):
            sys.exit(f"numpy and statsmodels disagree at level {lv}")
        if abs(fit.bse[f"insul[{lv}]:temp"] - se[len(levels) + k]) > 1e-10 * se[len(levels) + k]:
            sys.exit(f"numpy and statsmodels disagree on the slope's standard error at {lv}")
    out = {
        "source": "MASS::whiteside (testdata/real/whiteside.csv); R lm(Gas ~ Insul/Temp)",
        "script": "scripts/ref_per_class.py",
        "versions": {"numpy": np.__version__, "statsmodels": __import__("statsmodels").__version__},
        "rows": int(n),
        "residual_df": int(n - m),
        "levels": {
            lv: {
                "intercept": float(beta[k]),
                "intercept_se": float(se[k]),
                "slope": float(beta[len(levels) + k]),
                "slope_se": float(se[len(levels) + k]),
            }
            for k, lv in enumerate(levels)
        },
        "tolerance": "1e-6 relative on values and standard errors",
    }
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    tmp = a.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(out, f, indent=2)
        f.write("\n")
    os.replace(tmp, a.out)
    print(json.dumps(out["levels"], indent=2))


if __name__ == "__main__":
    main()
