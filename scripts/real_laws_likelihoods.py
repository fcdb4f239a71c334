"""-2 ln L of a real-law table's law, of the law with a fitted offset, and of the equation
`hxai sr` selected (read from a results file of bench_real_laws.py), under Gaussian,
Student-t (1, 2, 4, 8 degrees of freedom) and Laplace errors, each scale fitted by maximum
likelihood: does a heavy-tailed error model prefer the law? Issue 47, docs/benchmarks.md,
"The defaults on a quiet machine". Example:

    python scripts/real_laws_likelihoods.py --rows docs/bench-sr/real-laws-2026-12-02-defaults.jsonl --only hills
"""
import argparse
import json
from pathlib import Path

import numpy as np
import sympy as sp
from scipy.optimize import curve_fit, minimize_scalar
from scipy.special import gammaln

from bench_real_laws import evaluate, law_expr, load

ROOT = Path(__file__).resolve().parent.parent


def gaussian(r):
    n = len(r)
    return n * np.log(2 * np.pi * np.mean(r**2)) + n


def laplace(r):
    n = len(r)
    return 2 * n * np.log(2 * np.mean(np.abs(r))) + 2 * n


def student_t(r, nu):
    def m2ll(log_s):
        s = np.exp(log_s)
        return -2 * np.sum(gammaln((nu + 1) / 2) - gammaln(nu / 2) - 0.5 * np.log(nu * np.pi)
                           - np.log(s) - (nu + 1) / 2 * np.log1p(r**2 / (nu * s * s)))
    centre = np.log(np.std(r))
    return minimize_scalar(m2ll, bounds=(centre - 10, centre + 3), method="bounded").fun


def with_offset(law, rows, y):
    """The law's residuals after refitting its parameters with an added constant (curve_fit,
    from the law's own parameters and 0)."""
    names = list(law["params"])
    expr = law_expr(law, {p: sp.Symbol(p) for p in names}) + sp.Symbol("offset_")
    syms = [sp.Symbol(c, positive=c in law["positive"]) for c in law["inputs"]]
    f = sp.lambdify([syms, *[sp.Symbol(p) for p in names], sp.Symbol("offset_")], expr, "numpy")
    p0 = [law["params"][p] for p in names] + [0.0]
    popt, _ = curve_fit(lambda X, *p: f(X, *p), rows, y, p0=p0, maxfev=20000)
    return y - f(rows, *popt)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", required=True, help="a results file of bench_real_laws.py")
    ap.add_argument("--only", default="", help="comma list of data sets (default: all)")
    ap.add_argument("--laws", default=str(ROOT / "testdata/real/laws.json"))
    a = ap.parse_args()
    only = [s for s in a.only.split(",") if s]
    selected = {r["dataset"]: r for r in map(json.loads, Path(a.rows).read_text().splitlines())}
    for law in load(Path(a.laws), only):
        df, y = law["df"], law["df"][law["target"]].to_numpy(float)
        points = {c: df[c].to_numpy(float) for c in law["inputs"]}
        rows = [points[c] for c in law["inputs"]]
        sym = {str(s): s for s in law_expr(law).free_symbols}
        eq = sp.parse_expr(selected[law["name"]]["sympy"], local_dict=sym)
        for name, r in [("law", y - evaluate(law_expr(law), law, points)),
                        ("law + offset", with_offset(law, rows, y)),
                        ("selected", y - evaluate(eq, law, points))]:
            ts = " ".join(f"t{nu} {student_t(r, nu):.1f}" for nu in (1, 2, 4, 8))
            print(f"{law['name']} {name}: mse {np.mean(r**2):.4g} gauss {gaussian(r):.1f} {ts} "
                  f"laplace {laplace(r):.1f}")


if __name__ == "__main__":
    main()
