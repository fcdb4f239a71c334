#!/usr/bin/env python3
"""Times scikit-learn's Table 3 baselines on the table of crates/baselines/benches/baselines.rs.

Run: RAYON_NUM_THREADS=2 is irrelevant here; the forest uses n_jobs=2 (2 cores), all other
models scikit-learn's single-threaded defaults. Usage:
    python3 scripts/bench_baselines.py   (scikit-learn as pinned in scripts/requirements.txt)
Prints median seconds of fit+predict and of a 5-fold CV per model.
"""
import math
import time

import numpy as np
from sklearn.ensemble import RandomForestRegressor
from sklearn.linear_model import LassoCV, LinearRegression
from sklearn.metrics import mean_absolute_error, mean_squared_error, r2_score
from sklearn.model_selection import KFold
from sklearn.tree import DecisionTreeRegressor

MASK = (1 << 64) - 1


class SplitMix:
    def __init__(self, seed):
        self.s = seed

    def uniform(self):
        self.s = (self.s + 0x9E3779B97F4A7C15) & MASK
        z = self.s
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        z ^= z >> 31
        return (z >> 11) * (1.0 / (1 << 53))


def table(n, p):
    g = SplitMix(2026)
    X = np.empty((n, p))
    y = np.empty(n)
    for i in range(n):
        row = [g.uniform() for _ in range(p)]
        noise = g.uniform() - 0.5
        y[i] = (10.0 * math.sin(math.pi * row[0] * row[1]) + 20.0 * (row[2] - 0.5) ** 2
                + 10.0 * row[3] + 5.0 * row[4] + noise)
        X[i] = row
    return X, y


MODELS = {
    "linear": lambda: LinearRegression(),
    "lasso_cv": lambda: LassoCV(cv=3),
    "tree_5": lambda: DecisionTreeRegressor(max_leaf_nodes=5, random_state=0),
    "tree_8": lambda: DecisionTreeRegressor(max_leaf_nodes=8, random_state=0),
    "forest": lambda: RandomForestRegressor(n_estimators=200, random_state=42, n_jobs=2),
}


def median_time(f, min_total=3.0, min_reps=5):
    times = []
    start = time.perf_counter()
    while len(times) < min_reps or time.perf_counter() - start < min_total:
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
        if len(times) >= 200:
            break
    return float(np.median(times))


def main():
    X, y = table(1000, 12)
    folds = list(KFold(5, shuffle=True, random_state=42).split(X))
    print(f"checksum x[0,0]={X[0, 0]!r} y[0]={y[0]!r} sum(y)={y.sum()!r}")
    for name, make in MODELS.items():
        def fit():
            m = make().fit(X, y)
            m.predict(X)

        def cv():
            for tr, te in folds:
                m = make().fit(X[tr], y[tr])
                p = m.predict(X[te])
                r2_score(y[te], p), mean_squared_error(y[te], p), mean_absolute_error(y[te], p)

        print(f"{name:10s} fit {median_time(fit) * 1e3:10.3f} ms   cv5 {median_time(cv) * 1e3:10.3f} ms")


if __name__ == "__main__":
    main()
