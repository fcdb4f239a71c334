#!/usr/bin/env python3
"""The benchmark suites of `cargo xtask bench-sr --suite NAME` (issues 14 and 24).

`--suite feynman` (the default) is the AI Feynman database (100 equations, `--db`, default
`../shared/data/feynman100.csv` beside the repository), the suite the engine was tuned on.
`--suite nguyen|keijzer|korns|livermore|strogatz` are held-out suites built from their published
formulas (`scripts/suites/NAME.csv`, sources and simplifications in `scripts/suites/README.md`):
an outside measure that nobody tunes on, so `--half odd|even` is refused for them.

Reads every equation of the suite's CSV (AI Feynman database format: file name, number,
formula, variables and their sampling ranges) and, for each equation and noise level:
- draws n training rows (default 1,000) and 1,000 noise-free test rows uniformly from the
  ranges, seeded by (seed, Number), the same inputs at every noise level; a variable is
  positive for sympy when its range starts at 0 or above (a uniform draw is then > 0 almost
  surely), real otherwise, so that sqrt(x**2) is not x on a range such as [-1, 1];
- adds Gaussian noise of sd `noise * sqrt(mean(y**2))` (SRBench's rule: the target's RMS)
  to the training target;
- runs each engine as a subprocess with a per-problem time limit (hxai's binary; pyoperon,
  gplearn and feyn through this script's `--worker` mode);
- scores the returned equation: test R^2, and SRBench's exact rule (constants rounded to 3
  decimals; the difference of model and truth simplifies to a finite constant, or their
  ratio to a non-zero finite constant), under a sympy time limit; a check that runs out of
  time counts as not exact and is flagged `exact_timeout`.

Every row is written as soon as its problem finishes (the results file is rewritten
atomically), and `--resume` skips the (engine, problem, noise) rows already in the file, so
an interrupted run continues where it stopped. Nothing depends on a problem's name or form:
the harness only reads the CSV, and every engine sees inputs named x1..xk and a target y.
Results go to `target/bench-sr/NAME/` unless `--out`/`--results` say otherwise.

`--check-suite` runs no engine: it parses every truth of the suite and draws its data (1,000
rows, noise 0 and 0.01), prints one line per problem, and exits non-zero if any fails.

`--table FILE...` prints the markdown summary of results files: per engine, noise and (for
the AI Feynman suite) half of the database (odd Number = development set, even = held out,
and all).
"""
import argparse, csv, json, math, os, re, signal, subprocess, sys, time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # its sibling, when imported by path
from bench_sr_results import atomic_write, table  # noqa: E402  results files: writing, tables

TEST_ROWS = 1000
FUNCTIONS = {"ln": "log", "arcsin": "asin", "arccos": "acos", "arctan": "atan"}
KNOWN = {"exp", "sqrt", "log", "sin", "cos", "tan", "tanh", "asin", "acos", "atan", "pi",
         "abs", "harmonic"}
SUITES = ["feynman", "nguyen", "keijzer", "korns", "livermore", "strogatz"]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _harmonic(x):
    """The harmonic number H(x) for real x >= 0 (sympy's harmonic continued to the reals,
    digamma(x + 1) + Euler's gamma), element-wise: Keijzer-6's truth, which numpy lacks."""
    import mpmath
    return np.vectorize(lambda v: float(mpmath.harmonic(v)), otypes=[float])(x)


# functions of a truth that numpy does not have, for sympy's lambdify
NUMERIC = {"harmonic": _harmonic}


# ---------------------------------------------------------------- the database

def load_db(path):
    """Rows of the database: dicts with name, number, formula and vars [(name, lo, hi)]."""
    problems = []
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            if not row.get("Formula"):
                continue
            k = int(row["# variables"])
            variables = []
            for i in range(1, k + 1):
                variables.append((row[f"v{i}_name"], float(row[f"v{i}_low"]), float(row[f"v{i}_high"])))
            problems.append({"name": row["Filename"], "number": int(row["Number"]),
                             "formula": row["Formula"], "vars": variables,
                             "output": row.get("Output") or "y"})
    problems.sort(key=lambda p: p["number"])
    return problems


def symbols_for(variables):
    """Symbols x1..xk for the listed variables [(name, lo, hi)]: positive when the range
    starts at 0 or above (uniform draws are then > 0 almost surely), real otherwise, so that
    sympy does not simplify sqrt(x**2) to x where x can be negative. An int k gives k
    positive symbols (all of the AI Feynman ranges start at 0 or above)."""
    import sympy as sp
    if isinstance(variables, int):
        variables = [(None, 1.0, 1.0)] * variables
    return [sp.Symbol(f"x{i + 1}", positive=True) if lo >= 0
            else sp.Symbol(f"x{i + 1}", real=True) for i, (_, lo, _) in enumerate(variables)]


def parse_truth(problem):
    """The formula as a sympy expression over x1..xk (the i-th listed variable is x{i+1}),
    so that names such as `lambda`, `I`, `E` or `gamma` never meet sympy's own."""
    import sympy as sp
    names = {v[0]: f"x{i + 1}" for i, v in enumerate(problem["vars"])}

    def rename(m):
        word = m.group(0)
        if word in names:
            return names[word]
        word = FUNCTIONS.get(word, word)
        if word not in KNOWN:
            raise ValueError(f"{problem['name']}: unknown name {word!r} in {problem['formula']!r}")
        return word

    text = re.sub(r"[A-Za-z_][A-Za-z_0-9]*", rename, problem["formula"])
    syms = symbols_for(problem["vars"])
    local = {s.name: s for s in syms}
    local.update({"pi": sp.pi, "exp": sp.exp, "sqrt": sp.sqrt, "log": sp.log, "sin": sp.sin,
                  "cos": sp.cos, "tan": sp.tan, "tanh": sp.tanh, "asin": sp.asin, "acos": sp.acos,
                  "atan": sp.atan, "abs": sp.Abs, "harmonic": sp.harmonic})
    return sp.sympify(text, locals=local), syms


# ---------------------------------------------------------------- units (issue 24, item 3)

# [m, kg, s, A, K] of the units `scripts/suites/feynman_units.csv` uses; mol and cd unused
BASE_UNITS = {"1": (0, 0, 0, 0, 0), "m": (1, 0, 0, 0, 0), "kg": (0, 1, 0, 0, 0),
              "s": (0, 0, 1, 0, 0), "A": (0, 0, 0, 1, 0), "K": (0, 0, 0, 0, 1),
              "N": (1, 1, -2, 0, 0), "J": (2, 1, -2, 0, 0), "W": (2, 1, -3, 0, 0),
              "Pa": (-1, 1, -2, 0, 0), "C": (0, 0, 1, 1, 0), "V": (2, 1, -3, -1, 0),
              "T": (0, 1, -2, -1, 0), "F": (-2, -1, 4, 2, 0)}


def unit_dims(text):
    """Exponents [m, kg, s, A, K] of a unit such as `m^3/(kg*s^2)` (the harness's own
    reading, independent of hxai's, so that checking the table also checks hxai)."""
    tokens = re.findall(r"[A-Za-z_]+|\d+|-\d+|[*/^()]", text.replace("**", "^"))
    pos = [0]

    def atom():
        t = tokens[pos[0]]
        pos[0] += 1
        if t == "(":
            d = product()
            pos[0] += 1  # ")"
        else:
            d = np.array(BASE_UNITS[t], dtype=float)
        if pos[0] < len(tokens) and tokens[pos[0]] == "^":
            d = d * int(tokens[pos[0] + 1])
            pos[0] += 2
        return d

    def product():
        d = atom()
        while pos[0] < len(tokens) and tokens[pos[0]] in "*/":
            op = tokens[pos[0]]
            pos[0] += 1
            d = d + atom() if op == "*" else d - atom()
        return d

    return product()


def load_units(path):
    with open(path, newline="") as fh:
        return {r["name"]: r["unit"] for r in csv.DictReader(fh)}


def units_arg(problem, units):
    """hxai's `--units` for a problem: x1..xk and y, in the order the harness names them."""
    names = [v[0] for v in problem["vars"]] + [problem["output"]]
    missing = [n for n in names if n not in units]
    if missing:
        raise ValueError(f"no unit for {missing} in the units table")
    cols = [f"x{i + 1}" for i in range(len(problem["vars"]))] + ["y"]
    return ",".join(f"{c}={units[n]}" for c, n in zip(cols, names))


def check_units(a):
    """Each equation's homogeneity under the units table: scaling every base unit by 1.7 in
    turn (each variable by 1.7 to its exponent) must scale the output by 1.7 to its own, at
    five points of the ranges, to 1e-9. Returns the number of equations that fail."""
    import sympy as sp
    units = load_units(a.units)
    failed = 0
    for p in selected(a, load_db(a.db)):
        try:
            truth, syms = parse_truth(p)
            units_arg(p, units)
            f = sp.lambdify(syms, truth, [NUMERIC, "numpy"])
            dims = [unit_dims(units[v[0]]) for v in p["vars"]]
            out = unit_dims(units[p["output"]])
            rng = np.random.default_rng(p["number"])
            lo = np.array([v[1] for v in p["vars"]])
            hi = np.array([v[2] for v in p["vars"]])
            X = rng.uniform(lo, hi, size=(5, len(lo)))
            y0 = np.asarray(f(*X.T), dtype=float)
            for b in range(5):
                lam = 1.7
                Xs = X * np.array([lam ** d[b] for d in dims])
                ys = np.asarray(f(*Xs.T), dtype=float)
                want = y0 * lam ** out[b]
                if not np.allclose(ys, want, rtol=1e-9, atol=0):
                    raise ValueError(f"not homogeneous in {['m', 'kg', 's', 'A', 'K'][b]}")
            print(f"ok    {p['number']:3d} {p['name']:<10} {units_arg(p, units)}", flush=True)
        except Exception as e:
            failed += 1
            print(f"FAIL  {p['number']:3d} {p['name']:<10} {type(e).__name__}: {e}", flush=True)
    n = len(selected(a, load_db(a.db)))
    print(f"{a.suite}: {n - failed} of {n} equations are homogeneous under {a.units}")
    return failed


def make_data(problem, truth, syms, rows, noise, seed):
    """Training inputs and target (with noise), test inputs and target (noise-free). The
    inputs depend only on (seed, Number); rows whose truth is not finite are redrawn."""
    import sympy as sp
    f = sp.lambdify(syms, truth, [NUMERIC, "numpy"])
    rng = np.random.default_rng([seed, problem["number"]])
    lo = np.array([v[1] for v in problem["vars"]])
    hi = np.array([v[2] for v in problem["vars"]])

    def draw(n):
        parts, got = [], 0
        for _ in range(100):
            X = rng.uniform(lo, hi, size=(n, len(lo)))
            with np.errstate(all="ignore"):
                y = np.broadcast_to(np.asarray(f(*X.T), dtype=float), (n,))
            ok = np.isfinite(y)
            parts.append((X[ok], y[ok]))
            got += int(ok.sum())
            if got >= n:
                break
        X = np.concatenate([p[0] for p in parts])[:n]
        y = np.concatenate([p[1] for p in parts])[:n]
        if len(y) < n:
            raise ValueError(f"{problem['name']}: the truth is not finite on most of its ranges")
        return X, y

    Xtr, ytr = draw(rows)
    Xte, yte = draw(TEST_ROWS)
    if noise > 0:
        nrng = np.random.default_rng([seed, problem["number"], int(round(noise * 1e6))])
        ytr = ytr + nrng.normal(0.0, noise * math.sqrt(float(np.mean(ytr ** 2))), rows)
    return Xtr, ytr, Xte, yte


# ---------------------------------------------------------------- scoring

class Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise Timeout()


def round_floats(expr, digits=3):
    import sympy as sp
    return expr.xreplace({f: sp.Float(round(float(f), digits)) if abs(float(f)) >= 10 ** -digits
                          else sp.Integer(0) for f in expr.atoms(sp.Float)})


def exact(model, truth, seconds):
    """SRBench's symbolic-solution rule. Returns (exact, timed_out)."""
    import sympy as sp

    def finite_constant(e):
        return not e.free_symbols and e.is_finite is True

    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(seconds)
    try:
        m = round_floats(model)
        if finite_constant(sp.simplify(truth - m)):
            return True, False
        r = sp.simplify(m / truth)
        return bool(finite_constant(r) and r != 0), False
    except Timeout:
        return False, True
    except Exception:
        return False, False
    finally:
        signal.alarm(0)


def r2(pred, y):
    pred = np.asarray(pred, dtype=float)
    if pred.shape != y.shape or not np.all(np.isfinite(pred)):
        return float("nan")
    return float(1.0 - np.sum((y - pred) ** 2) / np.sum((y - y.mean()) ** 2))


def tree_size(expr):
    import sympy as sp
    return sum(1 for _ in sp.preorder_traversal(expr))


# ---------------------------------------------------------------- engines (worker mode)

def worker(a):
    """Runs one Python engine on one training file; prints one JSON line: the equation as
    sympy text over x1..xk, the fit's wall seconds, and what the engine reports."""
    data = np.loadtxt(a.train, delimiter=",", skiprows=1, ndmin=2)
    X, y = data[:, :-1], data[:, -1]
    k = X.shape[1]
    names = [f"x{i + 1}" for i in range(k)]
    opts = json.loads(a.settings)
    info = {}
    t = time.time()
    if a.worker == "pyoperon":
        from pyoperon.sklearn import SymbolicRegressor
        reg = SymbolicRegressor(random_state=a.seed, **opts)
        reg.fit(X.astype(np.float32), y.astype(np.float32))
        sec = time.time() - t
        text = reg.get_model_string(reg.model_, precision=15, names=names).replace("^", "**")
        try:
            info = {"complexity": int(reg.stats_["model_length"])}
        except Exception:
            info = {}
    elif a.worker == "gplearn":
        from gplearn.genetic import SymbolicRegressor
        opts = dict(opts)
        opts["init_depth"] = tuple(opts.get("init_depth", (2, 6)))
        opts["function_set"] = tuple(opts["function_set"])
        reg = SymbolicRegressor(random_state=a.seed, **opts)
        reg.fit(X, y)
        sec = time.time() - t
        text = str(reg._program)
        for i in range(k):
            text = re.sub(rf"\bX{i}\b", names[i], text)
        info = {"complexity": int(reg._program.length_)}
    elif a.worker == "feyn":
        import feyn, pandas as pd
        df = pd.DataFrame(X, columns=names)
        df["y"] = y
        ql = feyn.QLattice(random_seed=a.seed)
        models = ql.auto_run(df, output_name="y", **opts)
        sec = time.time() - t
        text = str(models[0].sympify(signif=15))
        info = {"complexity": len(models[0])}
    else:
        raise SystemExit(f"unknown engine {a.worker}")
    print(json.dumps({"expr": text, "seconds": sec, **info}))


def gplearn_locals():
    import sympy as sp
    return {"add": lambda a, b: a + b, "sub": lambda a, b: a - b, "mul": lambda a, b: a * b,
            # gplearn's protected operators, as it evaluates them on the data
            "div": lambda a, b: a / b, "sqrt": lambda a: sp.sqrt(sp.Abs(a)),
            "log": lambda a: sp.log(sp.Abs(a)), "neg": lambda a: -a, "inv": lambda a: 1 / a,
            "sin": sp.sin, "cos": sp.cos}


def run_subprocess(cmd, limit):
    """Runs cmd in its own process group; kills the group after `limit` seconds. Returns
    (stdout, stderr, returncode, wall seconds, timed_out); the child's CPU seconds (user +
    system, all threads) go to CPU[0], a fairer measure than wall time on a shared machine."""
    import resource
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.time()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    try:
        out, err = p.communicate(timeout=limit)
        timed_out = False
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
        timed_out = True
    wall = time.time() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    CPU[0] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return out, err, p.returncode, wall, timed_out


CPU = [0.0]


# ---------------------------------------------------------------- the run

def engine_settings(a):
    """Each peer's settings: SRBench's for the method, with the budget stated."""
    return {
        # SRBench's Operon: local search on (5 LM iterations; pyoperon 0.6 names it
        # optimizer_iterations, SRBench's older binding local_iterations), population 1000, tournament 5,
        # length <= 50, its operator set; the evaluation budget scaled (SRBench: 500,000)
        "pyoperon": {"optimizer_iterations": 5, "population_size": 1000, "tournament_size": 5,
                     "max_length": 50, "generations": 100000,
                     "max_evaluations": a.pyoperon_evaluations, "n_threads": 2,
                     "max_time": max(1, a.time_limit - 10),
                     "allowed_symbols": "add,sub,mul,div,exp,log,sin,cos,sqrt,square,constant,variable"},
        # SRBench's gplearn: tournament 20, depth 2-6 half and half, MAE, parsimony 0.001,
        # crossover 0.9, mutations 0.01, its larger function set; generations scaled
        # (SRBench: population 1,000 x 500 generations)
        "gplearn": {"population_size": 1000, "generations": a.gplearn_generations,
                    "tournament_size": 20, "init_depth": [2, 6], "init_method": "half and half",
                    "metric": "mean absolute error", "parsimony_coefficient": 0.001,
                    "p_crossover": 0.9, "p_subtree_mutation": 0.01, "p_hoist_mutation": 0.01,
                    "p_point_mutation": 0.01, "p_point_replace": 0.05, "max_samples": 1.0,
                    "function_set": ["add", "sub", "mul", "div", "log", "sqrt", "sin", "cos"]},
        # feyn's own recommended call: auto_run with its defaults (10 epochs)
        "feyn": {"n_epochs": 10},
    }


def run_engine(a, engine, label, hxai_extra, train_csv, syms):
    import sympy as sp
    local = {s.name: s for s in syms}
    if engine == "hxai":
        cmd = [a.hxai, "sr", "--csv", train_csv, "--target", "y", "--json", "--seed", str(a.seed),
               "--threads", str(a.threads)] + hxai_extra
        out, err, rc, wall, timed_out = run_subprocess(cmd, a.time_limit)
        if timed_out:
            return {"error": "time limit", "timeout": True, "seconds": wall}
        if rc != 0:
            return {"error": err.strip()[-300:], "seconds": wall}
        doc = json.loads(out)
        expr = sp.sympify(doc["best"]["sympy"], locals=local)
        return {"seconds": wall, "fit_seconds": doc.get("seconds"), "complexity": doc["best"].get("complexity"),
                "evaluations": doc.get("evaluations"),
                "duplicate_structures": doc.get("duplicate_structures"),
                "simplified": doc.get("simplified"), "_expr": expr}
    settings = engine_settings(a)[engine]
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", engine,
           "--train", train_csv, "--seed", str(a.seed), "--settings", json.dumps(settings)]
    out, err, rc, wall, timed_out = run_subprocess(cmd, a.time_limit)
    if timed_out:
        return {"error": "time limit", "timeout": True, "seconds": wall}
    lines = [l for l in out.splitlines() if l.startswith("{")]
    if rc != 0 or not lines:
        return {"error": (err.strip() or out.strip())[-300:], "seconds": wall}
    doc = json.loads(lines[-1])
    if engine == "gplearn":
        loc = dict(local)
        loc.update(gplearn_locals())
        expr = sp.sympify(doc["expr"], locals=loc)
    else:
        expr = sp.sympify(doc["expr"], locals=local)
        if engine == "feyn":  # feyn's symbols carry no assumptions: use ours, by name
            expr = expr.subs({s: local[s.name] for s in expr.free_symbols if s.name in local})
    stray = [s.name for s in expr.free_symbols if s.name not in local or s != local[s.name]]
    if stray:
        return {"error": f"equation has symbols that are not inputs: {stray}", "seconds": wall}
    return {"seconds": wall, "fit_seconds": doc["seconds"], "complexity": doc.get("complexity"),
            "_expr": expr}


def selected(a, problems):
    out = []
    only = set(a.only.split(",")) if a.only else None
    for p in problems:
        n = p["number"]
        if a.half == "odd" and n % 2 == 0 or a.half == "even" and n % 2 == 1:
            continue
        if a.every > 1 and n % a.every != 1 % a.every:
            continue
        if only and str(n) not in only:
            continue
        out.append(p)
    return out


def run(a):
    problems = selected(a, load_db(a.db))
    noises = [float(x) for x in a.noise.split(",")]
    runs = []  # (engine, label, extra hxai args)
    extra = a.hxai_args.split()
    if a.max_evaluations:
        extra += ["--max-evaluations", str(a.max_evaluations), "--epochs", str(a.epochs_cap)]
    if a.strategies and "hxai" in a.engines.split(","):
        # a strategy this binary does not have fails here, clearly, not as 200 error rows
        helptext = subprocess.run([a.hxai, "sr", "--help"], capture_output=True, text=True).stdout
        section = helptext.split("--strategy <", 1)[-1].split("\n      --", 1)[0]
        known = re.findall(r"^\s*- ([a-z_0-9]+):", section, flags=re.M)
        missing = [s for s in a.strategies.split(",") if s not in known]
        if missing:
            raise SystemExit(f"{a.hxai} has no --strategy {','.join(missing)} "
                             f"(it offers: {', '.join(known)})")
    for eng in a.engines.split(","):
        if eng == "hxai" and a.strategies:
            for s in a.strategies.split(","):
                runs.append(("hxai", f"{a.hxai_label} {s}", extra + ["--strategy", s]))
        elif eng == "hxai":
            runs.append(("hxai", a.hxai_label, extra))
        else:
            runs.append((eng, eng, []))
    rows = []
    if os.path.exists(a.results):
        if not a.resume:
            raise SystemExit(f"{a.results} exists: pass --resume to continue it, or another --results")
        with open(a.results) as fh:
            rows = [json.loads(l) for l in fh if l.strip()]
    done = {(r["engine"], r["number"], r["noise"]) for r in rows}
    data_dir = os.path.join(a.out, "data")
    os.makedirs(data_dir, exist_ok=True)
    for p in problems:
        todo = [(e, l, x, z) for z in noises for (e, l, x) in runs if (l, p["number"], z) not in done]
        if not todo:
            continue
        base = {"suite": a.suite, "problem": p["name"], "number": p["number"],
                "half": "odd" if p["number"] % 2 else "even", "inputs": len(p["vars"]),
                "rows": a.rows, "seed": a.seed}
        try:
            truth, syms = parse_truth(p)
        except Exception as e:  # a formula the harness cannot read is a result, reported
            for e_, l, x, z in todo:
                rows.append({**base, "engine": l, "noise": z, "error": f"harness: {e}"[:300]})
            atomic_write(a.results, rows)
            continue
        for z in noises:
            Xtr, ytr, Xte, yte = make_data(p, truth, syms, a.rows, z, a.seed)
            train_csv = os.path.join(data_dir, f"{p['number']}_{z}_train.csv")
            header = ",".join([s.name for s in syms] + ["y"])
            np.savetxt(train_csv, np.column_stack([Xtr, ytr]), delimiter=",", header=header,
                       comments="", fmt="%.17g")
            for eng, label, x, zz in todo:
                if zz != z:
                    continue
                if eng == "hxai" and a.units:
                    x = x + ["--units", units_arg(p, load_units(a.units))]
                row = {**base, "engine": label, "noise": z, "load1": round(os.getloadavg()[0], 2)}
                res = run_engine(a, eng, label, x, train_csv, syms)
                res["cpu_seconds"] = round(CPU[0], 3)
                expr = res.pop("_expr", None)
                row.update(res)
                if expr is not None:
                    import sympy as sp
                    fn = sp.lambdify(syms, expr, "numpy")
                    with np.errstate(all="ignore"):
                        try:
                            pred = np.broadcast_to(np.asarray(fn(*Xte.T), dtype=float), yte.shape)
                        except Exception:
                            pred = np.full(yte.shape, np.nan)
                    ex, to = exact(expr, truth, a.sympy_timeout)
                    row.update({"r2_test": r2(pred, yte), "size": tree_size(expr), "exact": ex,
                                "exact_timeout": to, "expr": str(expr)[:400]})
                rows.append(row)
                atomic_write(a.results, rows)
                print(json.dumps(row), flush=True)


def check_suite(a):
    """For every problem of the suite: parse the truth and draw the training and test data
    (noise 0 and 0.01); one line per problem. Returns the number of problems that failed."""
    problems = selected(a, load_db(a.db))
    failed = 0
    for p in problems:
        try:
            truth, syms = parse_truth(p)
            ys = []
            for z in (0.0, 0.01):
                Xtr, ytr, Xte, yte = make_data(p, truth, syms, 1000, z, a.seed)
                if not (np.all(np.isfinite(ytr)) and np.all(np.isfinite(yte))):
                    raise ValueError(f"non-finite target at noise {z:g}")
                ys.append(np.concatenate([ytr, yte]) if z == 0 else ytr)
            print(f"ok    {p['number']:3d} {p['name']:<22} {len(p['vars'])} inputs  "
                  f"y in [{ys[0].min():.6g}, {ys[0].max():.6g}] (train and test)  "
                  f"noisy train y in [{ys[1].min():.6g}, {ys[1].max():.6g}]  {truth}", flush=True)
        except Exception as e:
            failed += 1
            print(f"FAIL  {p['number']:3d} {p['name']:<22} {len(p['vars'])} inputs  "
                  f"{type(e).__name__}: {e}", flush=True)
    print(f"{a.suite}: {len(problems) - failed} of {len(problems)} problems parse and sample"
          f" ({a.db})")
    return failed


def rescore(a):
    """Checks again, with --sympy-timeout seconds, the rows whose exact check ran out of time
    (on a loaded machine the 20 s of a run can be too few); an equation stored cut at 400
    characters cannot be checked again and keeps its verdict. Rewrites each file atomically:
    run it only on files no run is writing."""
    import sympy as sp
    truths = {}
    for p in load_db(a.db):
        try:
            truths[p["number"]] = parse_truth(p)
        except Exception:
            pass
    for path in a.rescore:
        with open(path) as fh:
            rows = [json.loads(l) for l in fh if l.strip()]
        changed = still = cut = 0
        for r in rows:
            if not r.get("exact_timeout") or r["number"] not in truths:
                continue
            if len(r.get("expr", "")) >= 400:
                cut += 1
                continue
            truth, syms = truths[r["number"]]
            expr = sp.sympify(r["expr"], locals={s.name: s for s in syms})
            ex, to = exact(expr, truth, a.sympy_timeout)
            r["exact"], r["exact_timeout"] = ex, to
            r["exact_check_seconds"] = a.sympy_timeout
            changed += ex
            still += to
        atomic_write(path, rows)
        print(f"{path}: {changed} now exact, {still} still out of time, {cut} cut at 400 characters")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--suite", default="feynman", choices=SUITES,
                    help="feynman (default, the tuning suite) or a held-out suite of "
                         "scripts/suites/")
    ap.add_argument("--hxai", help="the hxai binary")
    ap.add_argument("--db", help="the suite's CSV (default: feynman "
                    "../shared/data/feynman100.csv beside the repository, another suite "
                    "scripts/suites/NAME.csv)")
    ap.add_argument("--engines", default="hxai", help="comma list of hxai,pyoperon,gplearn,feyn")
    ap.add_argument("--noise", default="0,0.01")
    ap.add_argument("--rows", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=42)
    ap.add_argument("--half", choices=["odd", "even", "all"], default="all",
                    help="feynman only: odd Numbers are the development set, even ones held out")
    ap.add_argument("--every", type=int, default=1,
                    help="a fixed subset: Numbers 1, 1+K, 1+2K, ... (K=5: 20 problems, 10 odd)")
    ap.add_argument("--only", help="comma list of Numbers")
    ap.add_argument("--out", help="directory of the data files (default target/bench-sr/SUITE)")
    ap.add_argument("--results", help="results file, one JSON row per (engine, problem, noise) "
                    "(default target/bench-sr/SUITE/results.jsonl)")
    ap.add_argument("--resume", action="store_true", help="continue an existing results file")
    ap.add_argument("--jobs", type=int, default=1, help="problems at once (only 1 is supported)")
    ap.add_argument("--threads", type=int, default=2, help="hxai's --threads")
    ap.add_argument("--time-limit", type=int, default=300, help="seconds per engine and problem")
    ap.add_argument("--sympy-timeout", type=int, default=20, help="seconds for the exact check")
    ap.add_argument("--hxai-args", default="")
    ap.add_argument("--hxai-label", help="hxai's engine name in the rows (default: 'hxai COMMIT', "
                    "the last commit that changed crates/, '+' if they have changes)")
    ap.add_argument("--strategies", help="comma list: one hxai run per --strategy value")
    ap.add_argument("--max-evaluations", type=int,
                    help="hxai's evaluation budget (adds --max-evaluations N --epochs EPOCHS_CAP)")
    ap.add_argument("--epochs-cap", type=int, default=100000)
    ap.add_argument("--pyoperon-evaluations", type=int, default=100000)
    ap.add_argument("--gplearn-generations", type=int, default=20)
    ap.add_argument("--table", nargs="+", metavar="RESULTS", help="print the summary of results files")
    ap.add_argument("--pairs", action="store_true",
                    help="with --table: also, for each two engines, the problems only one solves")
    ap.add_argument("--rescore", nargs="+", metavar="RESULTS",
                    help="check again, with --sympy-timeout seconds, the rows whose check ran out of time")
    ap.add_argument("--units", help="a units table (name,unit; e.g. scripts/suites/feynman_units.csv): "
                    "hxai gets `--units` for every problem")
    ap.add_argument("--check-units", action="store_true",
                    help="check that every equation is homogeneous under --units, and stop")
    ap.add_argument("--check-suite", action="store_true",
                    help="run no engine: parse every truth of the suite and draw its data, one "
                         "line per problem; exit status 1 if any fails")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--train", help=argparse.SUPPRESS)
    ap.add_argument("--settings", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        return worker(a)
    if a.table:
        return table(a.table, a.pairs)
    if a.db is None:
        a.db = ("../shared/data/feynman100.csv" if a.suite == "feynman"
                else os.path.join(ROOT, "scripts", "suites", f"{a.suite}.csv"))
    if a.out is None:
        a.out = f"target/bench-sr/{a.suite}"
    if a.results is None:
        a.results = f"target/bench-sr/{a.suite}/results.jsonl"
    if a.suite != "feynman" and a.half != "all":
        raise SystemExit(f"--half {a.half}: the {a.suite} suite is held out, never tuned on, "
                         "so it has no development half (--half is for --suite feynman)")
    if a.rescore:
        return rescore(a)
    if a.check_suite:
        sys.exit(1 if check_suite(a) else 0)
    if a.check_units:
        if not a.units:
            raise SystemExit("--check-units needs --units FILE")
        sys.exit(1 if check_units(a) else 0)
    if a.jobs != 1:
        raise SystemExit("--jobs: only 1 is supported (hxai itself uses 2 threads)")
    if "hxai" in a.engines.split(",") and not a.hxai:
        raise SystemExit("--hxai BINARY is needed to run hxai")
    if not a.hxai_label:
        a.hxai_label = "hxai " + git_commit()
    run(a)


def git_commit():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    try:
        # the engine's commit: the last one that changed the crates (not this harness)
        paths = ["--", "crates", "Cargo.toml", "Cargo.lock"]
        c = subprocess.run(["git", "log", "-1", "--format=%h"] + paths, cwd=here,
                           capture_output=True, text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"] + paths,
                               cwd=here, capture_output=True, text=True).stdout.strip()
        return c + ("+" if dirty else "")
    except Exception:
        return "unknown"


if __name__ == "__main__":
    main()
