"""Checks with sympy that a process hybrid's one equation reproduces `hxai hybrid predict`.

The model file of `hxai hybrid fit` holds the whole hybrid as one equation over the columns
(`hybrid.sympy`, every parameter substituted). This script parses that text with sympy
(column names as symbols, so names like `E` or `S` stay columns), evaluates it on every row
of the table, and compares with the `hybrid` column that `hxai hybrid predict` wrote.

Usage (needs sympy: `python3 -m venv .venv && .venv/bin/pip install sympy`):
    python3 scripts/check_hybrid_sympy.py --model MODEL.json --data TABLE.csv \
        --predictions PRED.csv [--rtol 1e-9]
Exit status 0 when every row agrees within the relative tolerance, 1 otherwise.
"""
import argparse
import csv
import json
import math
import re
import sys

import sympy


def sanitize(name):
    """The identifier hxai prints for a column (hxai_symreg::expr::sanitize)."""
    s = re.sub(r"[^A-Za-z0-9_]", "_", name)
    if not s or s[0].isdigit():
        s = "_" + s
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", required=True)
    ap.add_argument("--data", required=True, help="CSV table the predictions were made on")
    ap.add_argument("--predictions", required=True, help="CSV written by hxai hybrid predict")
    ap.add_argument("--rtol", type=float, default=1e-9)
    args = ap.parse_args()

    with open(args.model) as f:
        model = json.load(f)
    with open(args.data, newline="") as f:
        rows = list(csv.DictReader(f))
    with open(args.predictions, newline="") as f:
        preds = [float(r["hybrid"]) for r in csv.DictReader(f)]
    if len(rows) != len(preds):
        print(f"{len(rows)} table rows but {len(preds)} predictions", file=sys.stderr)
        return 1

    columns = {sanitize(c): c for c in rows[0].keys()} if rows else {}
    symbols = {s: sympy.Symbol(s) for s in columns}
    expr = sympy.parse_expr(model["hybrid"]["sympy"], local_dict=symbols)
    used = sorted(expr.free_symbols, key=str)
    unknown = [str(s) for s in used if str(s) not in columns]
    if unknown:
        print(f"the equation uses {unknown}, which are not columns", file=sys.stderr)
        return 1
    f = sympy.lambdify(used, expr, "math")

    worst = 0.0
    bad = 0
    for i, (row, want) in enumerate(zip(rows, preds)):
        got = float(f(*[float(row[columns[str(s)]]) for s in used]))
        rel = abs(got - want) / max(abs(got), abs(want), 1e-300)
        worst = max(worst, rel)
        if not (rel <= args.rtol) or not math.isfinite(got):
            bad += 1
            if bad <= 5:
                print(f"row {i}: equation {got!r} vs predict {want!r} (rel {rel:.3e})", file=sys.stderr)
    print(f"{len(rows)} rows, largest relative difference {worst:.3e} (tolerance {args.rtol:g})")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
