#!/usr/bin/env python3
"""Per-operator evaluation cost in pyoperon, the counterpart of the criterion bench
`cargo bench -p hxai-symreg --bench eval_ops`: for each operator a chain of eight
applications on 10,000 rows (unary: op(op(...op(X1))); binary: ((X1 op X2) op X2) ...),
with the same data columns as the throughput bench. Prints node evaluations per second
per thread (pyoperon evaluates in float32; hxai in float64).

Run: /work/main/.venv-sr/bin/python scripts/bench_sr_eval_ops_pyoperon.py
"""
import json, time
import numpy as np
import pyoperon as op

rows = 10000
r = np.arange(rows)
X = np.stack([0.5 + 2 * ((7919 * r + 104729 * j) % 10007) / 10007 for j in range(3)], axis=1)
ds = op.Dataset(np.asfortranarray(X))
hashes = {v.Name: v.Hash for v in ds.Variables}
rng = op.Range(0, rows)
binary = {"add": "+", "mul": "*", "div": "/"}
for name in ["add", "mul", "div", "exp", "log", "sin", "cos", "sqrt", "square", "tanh"]:
    s = "X1"
    for _ in range(8):
        s = f"({s} {binary[name]} X2)" if name in binary else f"{name}({s})"
    tree = op.InfixParser.Parse(s, hashes)
    for _ in range(20):
        op.Evaluate(tree, ds, rng)
    best = float("inf")
    for _ in range(7):
        t0 = time.perf_counter()
        for _ in range(200):
            op.Evaluate(tree, ds, rng)
        best = min(best, (time.perf_counter() - t0) / 200)
    print(json.dumps({"op": name, "nodes": tree.Length, "seconds": best,
                      "node_evals_per_s": tree.Length * rows / best}))
