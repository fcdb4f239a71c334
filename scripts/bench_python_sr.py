#!/usr/bin/env python3
"""`hxai.SymbolicRegressor.fit` against feyn's `auto_run` and pyoperon's `SymbolicRegressor`
from Python, on the same DataFrame in the same run: the paper's case, delta on the twelve
features f1..f12 of docs/results/samples.csv (training windows; R^2 on the test windows).

Needs a venv with the hxai package (`pip install ./python`) and, for the other engines,
feyn 3.5.0 and pyoperon 0.6.2 (an engine that does not import is reported as skipped).
Settings as in docs/benchmarks.md's search benchmark: each engine's defaults with 10
epochs where there are epochs, 2 threads for pyoperon. Absolute times on a shared machine
are noise: quote the ratios.

    python scripts/bench_python_sr.py [--repeats 3] [--engines hxai,feyn,pyoperon]
"""
import argparse
import json
import pathlib
import time

import numpy as np
import pandas as pd

ROOT = pathlib.Path(__file__).resolve().parents[1]
FEATURES = [f"f{i}" for i in range(1, 13)]


def r2(y, p):
    p = np.asarray(p, dtype=float)
    return float(1 - np.sum((y - p) ** 2) / np.sum((y - np.mean(y)) ** 2))


def run_hxai(train, test):
    import hxai

    t = time.perf_counter()
    m = hxai.SymbolicRegressor(seed=42).fit(train[FEATURES], train["delta"])
    sec = time.perf_counter() - t
    return sec, r2(test["delta"].to_numpy(), m.predict(test[FEATURES])), m.equation_


def run_feyn(train, test):
    import feyn

    t = time.perf_counter()
    ql = feyn.QLattice(random_seed=42)
    models = ql.auto_run(train[FEATURES + ["delta"]], output_name="delta", n_epochs=10)
    sec = time.perf_counter() - t
    best = models[0]
    return sec, r2(test["delta"].to_numpy(), best.predict(test[FEATURES])), str(best.sympify(signif=3))


def run_pyoperon(train, test):
    from pyoperon.sklearn import SymbolicRegressor

    t = time.perf_counter()
    reg = SymbolicRegressor(random_state=42, n_threads=2)
    reg.fit(train[FEATURES].to_numpy(np.float32), train["delta"].to_numpy(np.float32))
    sec = time.perf_counter() - t
    pred = reg.predict(test[FEATURES].to_numpy(np.float32))
    return sec, r2(test["delta"].to_numpy(), pred), reg.get_model_string(reg.model_, precision=3)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--engines", default="hxai,feyn,pyoperon")
    a = ap.parse_args()
    samples = pd.read_csv(ROOT / "docs" / "results" / "samples.csv")
    train = samples[samples["split"] == "train"].reset_index(drop=True)
    test = samples[samples["split"] == "test"].reset_index(drop=True)
    runners = {"hxai": run_hxai, "feyn": run_feyn, "pyoperon": run_pyoperon}
    rows = []
    for eng in a.engines.split(","):
        times, res = [], None
        try:
            for _ in range(a.repeats):
                sec, score, eq = runners[eng](train, test)
                times.append(sec)
                res = (score, eq)
        except ImportError as e:
            rows.append({"engine": eng, "skipped": f"does not import: {e}"})
            continue
        rows.append({"engine": eng, "seconds_median": float(np.median(times)),
                     "seconds": times, "test_r2": res[0], "equation": res[1]})
    ref = next((r for r in rows if r["engine"] == "hxai" and "seconds_median" in r), None)
    print(f"train {len(train)} rows, test {len(test)} rows, {a.repeats} repeats")
    print("| engine | fit median (s) | time / hxai | test R^2 | equation |")
    print("|---|---|---|---|---|")
    for r in rows:
        if "skipped" in r:
            print(f"| {r['engine']} | skipped: {r['skipped']} | | | |")
            continue
        ratio = r["seconds_median"] / ref["seconds_median"] if ref else float("nan")
        print(f"| {r['engine']} | {r['seconds_median']:.2f} | {ratio:.1f} | {r['test_r2']:.3f} | `{r['equation']}` |")
    print(json.dumps(rows))


if __name__ == "__main__":
    main()
