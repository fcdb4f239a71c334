#!/usr/bin/env python3
"""Evaluation throughput of pyoperon's interpreter on the programs of
testdata/symreg/eval_programs.json (the same 100 random programs and 10,000-row data as the
criterion bench `cargo bench -p hxai-symreg --bench eval`). Prints node evaluations per
second per thread (pyoperon evaluates in float32; hxai in float64).

Run: /work/main/.venv-sr/bin/python scripts/bench_sr_eval_pyoperon.py
"""
import json, os, time
import numpy as np
import pyoperon as op

here = os.path.dirname(os.path.abspath(__file__))
spec = json.load(open(os.path.join(here, "..", "testdata", "symreg", "eval_programs.json")))
for rows in (1000, 10000):
    r = np.arange(rows)
    X = np.stack([0.5 + 2 * ((7919 * r + 104729 * j) % 10007) / 10007 for j in range(3)], axis=1)
    ds = op.Dataset(np.asfortranarray(X))
    hashes = {v.Name: v.Hash for v in ds.Variables}
    trees = [op.InfixParser.Parse(p["infix"], hashes) for p in spec["programs"]]
    nodes = sum(t.Length for t in trees)
    rng = op.Range(0, rows)
    for t in trees:
        op.Evaluate(t, ds, rng)
    best = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        for t in trees:
            op.Evaluate(t, ds, rng)
        best = min(best, time.perf_counter() - t0)
    print(json.dumps({"rows": rows, "programs": len(trees), "nodes": nodes,
                      "seconds": best, "node_evals_per_s": nodes * rows / best}))
