#!/usr/bin/env python3
"""Reference results of scikit-learn's HistGradientBoostingRegressor for hxai-baselines.

What: three small deterministic synthetic tables, each split into train and test rows, and
scikit-learn's `HistGradientBoostingRegressor()` at its defaults fitted on the train rows:
  - friedman1: 1,000 x 5, Friedman #1 with noise 1 (800 train / 200 test);
  - step: 500 x 3, a three-level step in x0, a slope in x1 and an integer column x2 with ten
    levels (so its bins are midpoints of distinct values) (400 / 100);
  - small: 300 x 4, a smooth target, and a constant column x3 that can never split (240 / 60).
Writes testdata/boosting/<table>_train.csv and <table>_test.csv (columns x0.., y) and
testdata/boosting/reference.json: per table scikit-learn's test predictions, test RMSE,
number of iterations, and the bin thresholds of its binning (`_bin_mapper.bin_thresholds_`).
Every value is rounded to 6 decimals before fitting, and the CSVs hold Python's shortest
round-trip text of each value, so Rust reads back exactly the numbers scikit-learn saw.

Why: `GradientBoosting` in crates/baselines/src/boosting/ ports this estimator; the tests in
crates/baselines/tests/it/boosting.rs compare its binning, test RMSE and predictions with
these (issue 48, item 3).

How to rerun: `cargo xtask refs` (all ref scripts, versions pinned in scripts/requirements.txt),
or `python3 scripts/ref_boosting.py` in an environment with those versions (numpy 2.4.6,
scikit-learn 1.9.1). Not run by CI.

`python3 scripts/ref_boosting.py --time` writes nothing: it times scikit-learn's fit on the
stored friedman1 train rows plus predict on its test rows (median of 5 runs, after one
warm-up run, on scikit-learn's default threads), the work that
`cargo bench -p hxai-baselines --bench boosting` times, so the two can be quoted as a ratio.
"""
import json
import pathlib
import sys
import time

import numpy as np
import sklearn
from sklearn.datasets import make_friedman1
from sklearn.ensemble import HistGradientBoostingRegressor

from _common import write_atomic

OUT = pathlib.Path(__file__).resolve().parent.parent / "testdata" / "boosting"


def friedman1():
    X, y = make_friedman1(n_samples=1000, n_features=5, noise=1.0, random_state=0)
    return X, y, 800


def step():
    rng = np.random.default_rng(48)
    n = 500
    x0 = rng.uniform(0.0, 1.0, n)
    x1 = rng.normal(0.0, 1.0, n)
    x2 = rng.integers(0, 10, n).astype(float)
    level = np.where(x0 < 0.3, 0.0, np.where(x0 < 0.7, 4.0, 1.5))
    y = level + 0.8 * x1 + 0.3 * (x2 % 3) + rng.normal(0.0, 0.5, n)
    return np.column_stack([x0, x1, x2]), y, 400


def small():
    rng = np.random.default_rng(4803)
    n = 300
    X = np.column_stack([
        rng.uniform(-1.0, 1.0, n),
        rng.uniform(0.0, 2.0, n),
        rng.normal(0.0, 1.0, n),
        np.full(n, 3.5),
    ])
    y = np.exp(0.8 * X[:, 0]) + X[:, 1] ** 2 * np.sin(X[:, 2]) + rng.normal(0.0, 0.2, n)
    return X, y, 240


TABLES = {"friedman1": friedman1, "step": step, "small": small}


def rounded(name):
    X, y, n_train = TABLES[name]()
    X, y = np.round(X, 6), np.round(y, 6)
    return X[:n_train], y[:n_train], X[n_train:], y[n_train:]


def csv_text(X, y):
    header = ",".join([f"x{j}" for j in range(X.shape[1])] + ["y"])
    lines = [header] + [",".join(repr(float(v)) for v in (*row, t)) for row, t in zip(X, y)]
    return "\n".join(lines) + "\n"


def write_references():
    out = {"versions": {"numpy": np.__version__, "sklearn": sklearn.__version__},
           "estimator": "HistGradientBoostingRegressor() at its defaults", "tables": {}}
    for name in TABLES:
        xtr, ytr, xte, yte = rounded(name)
        write_atomic(OUT / f"{name}_train.csv", csv_text(xtr, ytr))
        write_atomic(OUT / f"{name}_test.csv", csv_text(xte, yte))
        m = HistGradientBoostingRegressor().fit(xtr, ytr)
        pred = m.predict(xte)
        rmse = float(np.sqrt(np.mean((yte - pred) ** 2)))
        out["tables"][name] = {
            "n_train": len(ytr), "n_test": len(yte), "n_iter": int(m.n_iter_),
            "test_rmse": rmse, "test_pred": pred.tolist(),
            "bin_thresholds": [t.tolist() for t in m._bin_mapper.bin_thresholds_],
        }
        print(f"{name}: {len(ytr)} train / {len(yte)} test, test RMSE {rmse:.6f}, "
              f"{m.n_iter_} iterations")
    write_atomic(OUT / "reference.json", json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT}")


def read_csv(path):
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    return data[:, :-1], data[:, -1]


def time_fit_predict(reps=5):
    xtr, ytr = read_csv(OUT / "friedman1_train.csv")
    xte, _ = read_csv(OUT / "friedman1_test.csv")

    def run():
        t0 = time.perf_counter()
        HistGradientBoostingRegressor().fit(xtr, ytr).predict(xte)
        return time.perf_counter() - t0

    run()  # warm-up: imports, OpenMP thread start
    times = sorted(run() for _ in range(reps))
    median = times[len(times) // 2]
    print(f"sklearn {sklearn.__version__} HistGradientBoostingRegressor fit+predict, "
          f"friedman1 800 train / 200 test: median of {reps} = {median * 1e3:.2f} ms "
          f"(runs: {', '.join(f'{t * 1e3:.2f}' for t in times)} ms)")


if __name__ == "__main__":
    if sys.argv[1:] == ["--time"]:
        time_fit_predict()
    elif sys.argv[1:]:
        sys.exit("usage: ref_boosting.py [--time]")
    else:
        write_references()
