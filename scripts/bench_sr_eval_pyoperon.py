#!/usr/bin/env python3
"""Evaluation throughput of pyoperon's interpreter, in node evaluations per second per thread
(pyoperon evaluates in float32; hxai in float64), on the same data as the criterion benches.

Default: the programs of testdata/symreg/eval_programs.json (the same 100 random programs as
`cargo bench -p hxai-symreg --bench eval`) on 1,000 and 10,000 rows, best of 5.

`--per-op`: the counterpart of `cargo bench -p hxai-symreg --bench eval_ops`, a chain of eight
applications of each operator on 10,000 rows (unary: op(op(...op(X1))); binary:
((X1 op X2) op X2) ...), best of 7 rounds of 200 evaluations.

Run: .venv-sr/bin/python scripts/bench_sr_eval_pyoperon.py [--per-op]
(.venv-sr is the environment `cargo xtask bench-sr` makes).
"""
import json, os, sys, time
import numpy as np
import pyoperon as op


def dataset(rows):
    """The bench columns: x[r] = 0.5 + 2 ((7919 r + 104729 j) mod 10007) / 10007."""
    r = np.arange(rows)
    X = np.stack([0.5 + 2 * ((7919 * r + 104729 * j) % 10007) / 10007 for j in range(3)], axis=1)
    ds = op.Dataset(np.asfortranarray(X))
    return ds, {v.Name: v.Hash for v in ds.Variables}, op.Range(0, rows)


def programs():
    here = os.path.dirname(os.path.abspath(__file__))
    spec = json.load(open(os.path.join(here, "..", "testdata", "symreg", "eval_programs.json")))
    for rows in (1000, 10000):
        ds, hashes, rng = dataset(rows)
        trees = [op.InfixParser.Parse(p["infix"], hashes) for p in spec["programs"]]
        nodes = sum(t.Length for t in trees)
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


def per_op():
    rows = 10000
    ds, hashes, rng = dataset(rows)
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


if __name__ == "__main__":
    per_op() if "--per-op" in sys.argv[1:] else programs()
