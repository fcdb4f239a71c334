#!/usr/bin/env python3
"""Reference vectors for hxai-eval's conformal module (split conformal quantile, CV+).

Run: `cargo xtask refs` (all ref scripts, pinned versions from scripts/requirements.txt), or
`python3 scripts/ref_conformal.py` in an environment with numpy.
Writes testdata/eval/conformal.json. Not run by CI.

The conformal quantile of n scores at level P is the k-th smallest score with
k = ceil(P (n + 1)) (Lei et al. 2018); k is computed here in exact rational arithmetic from
the level's decimal text, so a level such as 0.9 with n + 1 = 10 gives k = 9 and not the
rank of its binary rounding. The value is numpy's `np.quantile(scores, q, method="higher")`
at q = (k - 1.25) / (n - 1), which puts numpy's virtual index q (n - 1) = k - 1.25 strictly
between k - 2 and k - 1, so "higher" picks the k-th smallest whatever the rounding of
q (n - 1); the script asserts it equals `np.sort(scores)[k - 1]`. Cases with k > n record
`null` (too few scores for a finite interval).

CV+ (Barber et al. 2021): the upper end is the k-th smallest of centre + radius, the lower
end the floor((1 - P)(n + 1))-th smallest of centre - radius (computed with the same numpy
quantile).
"""
import json
import math
import pathlib
from fractions import Fraction

import numpy as np

from _common import write_atomic

rng = np.random.default_rng(20260428)
out = {"versions": {"numpy": np.__version__}}


def rank(n, level_text):
    return math.ceil(Fraction(level_text) * (n + 1))


def order_stat(values, k):
    n = len(values)
    if n == 1:
        q = 0.0
    else:
        q = max(0.0, (k - 1.25) / (n - 1))
    v = float(np.quantile(values, q, method="higher"))
    assert v == float(np.sort(values)[k - 1]), (n, k)
    return v


quantiles = []
for n in [1, 2, 9, 18, 19, 20, 39, 50, 99, 100, 101, 257]:
    scores = np.abs(rng.standard_t(3, n)) * rng.uniform(0.5, 2.0)
    for level_text in ["0.5", "0.8", "0.9", "0.95", "0.99"]:
        k = rank(n, level_text)
        quantiles.append({
            "scores": scores.tolist(),
            "level": float(level_text),
            "rank": k if k <= n else None,
            "quantile": order_stat(scores, k) if k <= n else None,
        })
out["quantiles"] = quantiles

cv_plus = []
for n in [19, 40, 99, 160]:
    centre = 10.0 + rng.normal(0.0, 0.3, n)
    radius = np.abs(rng.normal(0.0, 1.0, n)) * rng.uniform(0.5, 1.5, n)
    for level_text in ["0.8", "0.9", "0.95"]:
        k = rank(n, level_text)
        if k > n:
            continue
        lo_rank = (n + 1) - k  # floor((1 - P)(n + 1))
        lower = float(np.sort(centre - radius)[lo_rank - 1])
        assert lower == -order_stat(radius - centre, k)
        cv_plus.append({
            "centre": centre.tolist(),
            "radius": radius.tolist(),
            "level": float(level_text),
            "lower": lower,
            "upper": order_stat(centre + radius, k),
        })
out["cv_plus"] = cv_plus

path = pathlib.Path(__file__).resolve().parent.parent / "testdata" / "eval" / "conformal.json"
write_atomic(path, json.dumps(out, indent=1) + "\n")
print(f"wrote {path}")
