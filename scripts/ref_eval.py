#!/usr/bin/env python3
"""Reference vectors for hxai-eval (metrics, t-test, confidence intervals).

Run: `cargo xtask refs` (all ref scripts, pinned versions from scripts/requirements.txt), or
`python3 scripts/ref_eval.py` in an environment with those versions.
Writes testdata/eval/reference.json. Not run by CI. Values come from scikit-learn and scipy.
"""
import json
import pathlib

import numpy as np
import scipy
import sklearn
from scipy import stats
from sklearn.metrics import mean_absolute_error, mean_squared_error, r2_score

from _common import write_atomic

rng = np.random.default_rng(20261121)
out = {"versions": {"numpy": np.__version__, "scipy": scipy.__version__, "sklearn": sklearn.__version__}}


metrics = []
for n in [2, 5, 17, 100, 333]:
    y = rng.normal(3.0, 2.0, n)
    p = y + rng.normal(0.0, 0.7, n)
    metrics.append({
        "y_true": y.tolist(), "y_pred": p.tolist(),
        "r2": float(r2_score(y, p)),
        "rmse": float(np.sqrt(mean_squared_error(y, p))),
        "mae": float(mean_absolute_error(y, p)),
    })
out["metrics"] = metrics

# Paired t-tests on squared errors; shifts chosen so p-values span 0.5 .. below 1e-12.
ttests = []
for n, shift in [(5, 0.1), (12, 0.3), (30, 0.5), (40, 1.0), (60, 1.5), (80, 2.5), (120, 3.0), (200, 4.0)]:
    a = rng.normal(0.0, 1.0, n) ** 2 + shift
    b = rng.normal(0.0, 1.0, n) ** 2
    r = stats.ttest_rel(a, b)
    ttests.append({"a": a.tolist(), "b": b.tolist(), "statistic": float(r.statistic),
                   "df": float(r.df), "p_value": float(r.pvalue)})
out["ttests"] = ttests

# Two-tailed p-values of given statistics, down to ~1e-30.
pvals = []
for df in [1, 2, 4, 9, 29, 99, 500]:
    for t in [0.01, 0.5, 1.0, 2.0, 3.5, 6.0, 10.0, 20.0, 50.0, 1e3, 1e6]:
        p = float(2.0 * stats.t.sf(t, df))
        if p > 1e-300:
            pvals.append({"t": t, "df": float(df), "p_value": p})
out["t_pvalues"] = pvals

intervals = []
for n in [2, 3, 5, 10, 30]:
    v = rng.normal(0.9, 0.05, n)
    mean, sd = float(np.mean(v)), float(np.std(v, ddof=1))
    se = sd / np.sqrt(n)
    for level in [0.9, 0.95, 0.99]:
        lo_t, hi_t = stats.t.interval(level, n - 1, loc=mean, scale=se)
        lo_z, hi_z = stats.norm.interval(level, loc=mean, scale=se)
        intervals.append({"values": v.tolist(), "level": level, "mean": mean, "std": sd,
                          "t": [float(lo_t), float(hi_t)], "normal": [float(lo_z), float(hi_z)]})
out["intervals"] = intervals

path = pathlib.Path(__file__).resolve().parent.parent / "testdata" / "eval" / "reference.json"
write_atomic(path, json.dumps(out, indent=1))
print(f"wrote {path}")
