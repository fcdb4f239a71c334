"""Peer models for grey-box dynamic models (issue 69, "processes that move"): PySINDy with
control and a NARX gradient boosting, each trained on training runs (or on the samples up to
a time) and scored by FREE-RUN RMSE on held-out samples.

Tested with python 3.11.7, pysindy==2.1.0, derivative==0.6.3, scikit-learn==1.9.1,
scipy==1.17.1, numpy==2.4.6, pandas==3.1.1 (scripts/dynamic_peers_requirements.txt).

    pip install pysindy==2.1.0 scikit-learn==1.9.1 scipy==1.17.1 numpy==2.4.6 pandas==3.1.1
    python scripts/dynamic_peers.py --data spindle.csv --time time_s --run run --state T_C \
        --inputs speed_krpm,ambient_C,humidity_pct [--test-runs 3,7,11 | --test-after 3600] \
        [--seed 42] --json peers.json

Input: a long CSV, one row per sample: a run column, a time column, the state column(s) and
the input column(s) (`--inputs` may be left out for an autonomous process). Split:
- `--test-runs R1,R2`: those runs are held out, the others train;
- `--test-after T`: every run trains on its samples with time <= T and is scored on those
  after T, simulated from its last reading at time <= T (a forecast);
- default: a seeded 25 % of the runs (at least 1) held out (`--seed`).

Free run: each held-out run (segment) is simulated from its first reading with its own
inputs held constant from one sample to the next (zero-order hold, as `hxai`'s integrator
holds them), and compared with the measured state on every later sample; the RMSE pools all
held-out samples but each segment's first (the starting reading). A simulation that blows up
(leaves the data's range by far, or stops) is reported as diverged with rmse null.

Peers:
1. `pysindy`: SINDy with control, PolynomialLibrary(degree 2) over states + inputs, STLSQ
   (normalize_columns=True, so the threshold is on each term's size on the data; the grid is
   fractions of ||x_dot||), derivatives by SmoothedFiniteDifference (Savitzky-Golay, window
   11, order 3) per run. The threshold is chosen by the free-run RMSE of a validation split
   of the training data (25 % of the training runs, seeded; with one run or `--test-after`,
   the last 25 % of each training segment's time), then refitted on all training data. The
   identified ODE is integrated interval by interval by scipy's solve_ivp (RK45, rtol 1e-8,
   atol 1e-10) with the inputs held.
2. `narx_boosting_sklearn`: HistGradientBoostingRegressor (random_state = --seed), one per
   state, predicting the step x[k+1] - x[k] from x[k], u[k] and dt[k]; rolled out from the
   first reading on its own predictions.
"""
import argparse
import json
import math
import sys
import time as _time
import warnings

import numpy as np
import pandas as pd
from scipy.integrate import solve_ivp

SINDY_FRACTIONS = [0.0, 0.001, 0.003, 0.01, 0.03, 0.05, 0.1, 0.2, 0.3]


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--data", required=True, help="long CSV, one row per sample")
    p.add_argument("--time", required=True, help="time column")
    p.add_argument("--run", required=True, help="run column")
    p.add_argument("--state", required=True, help="state column(s), comma-separated")
    p.add_argument("--inputs", default="", help="input columns, comma-separated (may be empty)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--test-runs", help="held-out runs, comma-separated")
    g.add_argument("--test-after", type=float, help="hold out every run's samples after this time")
    p.add_argument("--seed", type=int, default=42)
    p.add_argument("--json", required=True, help="output JSON")
    return p.parse_args(argv)


def cols(s):
    return [c.strip() for c in s.split(",") if c.strip()] if s else []


def run_key(v):
    """A run label as JSON-friendly text: 3.0 -> '3'."""
    if isinstance(v, (float, np.floating)) and float(v).is_integer():
        return str(int(v))
    if isinstance(v, (np.integer,)):
        return str(int(v))
    return str(v)


class Segment:
    """One stretch of one run: times t (n), states x (n, s), inputs u (n, m)."""

    def __init__(self, run, t, x, u):
        self.run, self.t, self.x, self.u = run, t, x, u

    def __len__(self):
        return len(self.t)


def load(args):
    df = pd.read_csv(args.data)
    states, inputs = cols(args.state), cols(args.inputs)
    need = [args.run, args.time] + states + inputs
    missing = [c for c in need if c not in df.columns]
    if missing:
        sys.exit(f"columns not in {args.data}: {missing} (it has {list(df.columns)})")
    df = df[need].dropna().sort_values([args.run, args.time], kind="stable")
    runs = {}
    for r, g in df.groupby(args.run, sort=True):
        runs[run_key(r)] = Segment(run_key(r), g[args.time].to_numpy(float),
                                   g[states].to_numpy(float), g[inputs].to_numpy(float))
    return runs, states, inputs


def split(runs, args):
    """(train segments, test segments, description). Each test segment starts at its
    starting reading (not scored)."""
    names = list(runs)
    if args.test_after is not None:
        T = args.test_after
        train, test = [], []
        for r, s in runs.items():
            m = s.t <= T
            if m.sum() >= 2:
                train.append(Segment(r, s.t[m], s.x[m], s.u[m]))
            if (~m).any():
                start = max(int(m.sum()) - 1, 0)
                test.append(Segment(r, s.t[start:], s.x[start:], s.u[start:]))
        how = {"mode": "test_after", "test_after": T,
               "start": "each run's last reading at time <= test_after"}
        return train, test, how
    if args.test_runs:
        wanted = [run_key(float(v)) if _isnum(v) else v for v in cols(args.test_runs)]
        bad = [w for w in wanted if w not in runs]
        if bad:
            sys.exit(f"--test-runs {bad} not among the runs {names}")
        mode = "test_runs"
    else:
        if len(names) < 2:
            sys.exit("only one run: give --test-after T")
        rng = np.random.default_rng(args.seed)
        k = max(1, int(round(0.25 * len(names))))
        wanted = [names[i] for i in sorted(rng.choice(len(names), k, replace=False))]
        mode = "seeded_25pct"
    train = [runs[r] for r in names if r not in wanted]
    if not train:
        sys.exit("no training run left")
    test = [runs[r] for r in names if r in wanted]
    return train, test, {"mode": mode, "seed": args.seed, "start": "each run's first reading"}


def _isnum(v):
    try:
        float(v)
        return True
    except ValueError:
        return False


# ---------------------------------------------------------------- free run and scoring
def zoh_simulate(rhs, seg, bound):
    """Integrates x' = rhs(x, u) from seg.x[0], u held at u[k] on [t_k, t_k+1). Returns
    (trajectory (n, s) with NaN after a blow-up, diverged flag)."""
    n, s = seg.x.shape
    out = np.full((n, s), np.nan)
    out[0] = seg.x[0]
    x = seg.x[0].astype(float)

    def blow(_t, y, *_a):
        return bound - np.max(np.abs(y))
    blow.terminal = True

    for k in range(n - 1):
        u = seg.u[k]
        r = solve_ivp(lambda _t, y: rhs(y, u), (seg.t[k], seg.t[k + 1]), x, method="RK45",
                      rtol=1e-8, atol=1e-10, events=blow)
        if r.status != 0 or not np.all(np.isfinite(r.y[:, -1])):
            return out, True
        x = r.y[:, -1]
        out[k + 1] = x
    return out, False


def score(preds, segs, states):
    """Pooled RMSE (all states), per-state RMSE and per-run RMSE over samples 1.. of each
    segment. preds: list of (trajectory, diverged)."""
    errs, per_run, per_state, diverged = [], {}, [[] for _ in states], []
    for (traj, div), seg in zip(preds, segs):
        e = traj[1:] - seg.x[1:]
        if div or not np.all(np.isfinite(e)):
            per_run[seg.run] = None
            diverged.append(seg.run)
            continue
        per_run[seg.run] = float(np.sqrt(np.mean(e ** 2)))
        errs.append(e)
        for j in range(len(states)):
            per_state[j].append(e[:, j])
    if diverged or not errs:
        return {"rmse": None, "rmse_per_state": None, "per_run": per_run, "diverged": diverged}
    e = np.concatenate(errs)
    return {"rmse": float(np.sqrt(np.mean(e ** 2))),
            "rmse_per_state": {st: float(np.sqrt(np.mean(np.concatenate(v) ** 2)))
                               for st, v in zip(states, per_state)},
            "per_run": per_run, "diverged": diverged}


def bound_of(segs):
    x = np.concatenate([s.x for s in segs])
    return float(np.max(np.abs(x)) + 10 * (np.max(x) - np.min(x)) + 1.0)


def validation_split(train, seed):
    """(fit segments, validation segments) inside the training data."""
    if len(train) >= 2 and not getattr(train, "time_split", False):
        rng = np.random.default_rng(seed + 1)
        k = max(1, int(round(0.25 * len(train))))
        val_idx = set(rng.choice(len(train), k, replace=False).tolist())
        return ([s for i, s in enumerate(train) if i not in val_idx],
                [s for i, s in enumerate(train) if i in val_idx], "25% of training runs")
    fit, val = [], []
    for s in train:
        cut = s.t[0] + 0.75 * (s.t[-1] - s.t[0])
        m = s.t <= cut
        fit.append(Segment(s.run, s.t[m], s.x[m], s.u[m]))
        start = int(m.sum()) - 1
        val.append(Segment(s.run, s.t[start:], s.x[start:], s.u[start:]))
    return fit, val, "last 25% of each training segment's time"


class TimeSplitList(list):
    time_split = True


# ---------------------------------------------------------------- PySINDy
def sindy_fit(segs, feat_names, n_states, frac):
    import pysindy as ps
    w = min(11, min(len(s) for s in segs))
    w = w if w % 2 == 1 else w - 1
    diff = ps.SmoothedFiniteDifference(smoother_kws={"window_length": w,
                                                     "polyorder": min(3, w - 1), "axis": 0})
    # ||x_dot||, the scale of the threshold: from the same derivative estimate
    xdot = np.concatenate([np.asarray(diff(s.x, s.t)) for s in segs])
    scale = float(np.min(np.linalg.norm(xdot, axis=0)))
    opt = ps.STLSQ(threshold=frac * scale, normalize_columns=True)
    model = ps.SINDy(optimizer=opt, feature_library=ps.PolynomialLibrary(degree=2),
                     differentiation_method=diff)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        kw = {"u": [s.u for s in segs]} if segs[0].u.shape[1] else {}
        model.fit([s.x for s in segs], t=[s.t for s in segs], feature_names=feat_names, **kw)
    coef = np.asarray(model.coefficients())            # (n_states, n_features)
    powers = np.asarray(model.feature_library.powers_)  # (n_features, n_states + n_inputs)
    if powers.shape[0] != coef.shape[1]:
        raise RuntimeError("library powers do not match the coefficients")

    def rhs(x, u):
        z = np.concatenate([x, u])
        return coef @ np.prod(z[None, :] ** powers, axis=1)
    return model, rhs, coef, frac * scale


def sindy_equations(model, coef, states):
    names = model.get_feature_names()
    eqs = []
    for i, st in enumerate(states):
        terms = [f"{c:+.4g}*{n}" if n != "1" else f"{c:+.4g}"
                 for c, n in zip(coef[i], names) if c != 0.0]
        eqs.append(f"{st}' = " + (" ".join(terms) if terms else "0"))
    return eqs


def run_sindy(train, test, states, inputs, seed, bound):
    feat = states + inputs
    fit, val, how = validation_split(train, seed)
    grid = []
    for frac in SINDY_FRACTIONS:
        try:
            _, rhs, coef, thr = sindy_fit(fit, feat, len(states), frac)
            sc = score([zoh_simulate(rhs, s, bound) for s in val], val, states)
            grid.append({"fraction": frac, "threshold": thr, "val_rmse": sc["rmse"],
                         "terms": int(np.count_nonzero(coef))})
        except Exception as e:  # a fit that fails is a candidate lost, not the run
            grid.append({"fraction": frac, "threshold": None, "val_rmse": None,
                         "error": str(e)[:200]})
    ok = [g for g in grid if g["val_rmse"] is not None]
    best = min(ok, key=lambda g: g["val_rmse"])["fraction"] if ok else 0.01
    model, rhs, coef, thr = sindy_fit(train, feat, len(states), best)
    t0 = _time.time()
    sc = score([zoh_simulate(rhs, s, bound) for s in test], test, states)
    return {"name": "pysindy", **sc, "equations": sindy_equations(model, coef, states),
            "settings": {"library": "PolynomialLibrary(degree=2) over states + inputs",
                         "optimizer": "STLSQ(normalize_columns=True, alpha=0.05, unbias)",
                         "derivatives": "SmoothedFiniteDifference (savgol) per run",
                         "threshold_fraction_of_xdot_norm": best, "threshold": thr,
                         "validation": how, "validation_grid": grid,
                         "terms": int(np.count_nonzero(coef)),
                         "integrator": "solve_ivp RK45 rtol 1e-8 atol 1e-10, inputs held",
                         "simulate_seconds": round(_time.time() - t0, 2)}}


# ---------------------------------------------------------------- NARX boosting
def narx_xy(segs):
    X, Y = [], []
    for s in segs:
        dt = np.diff(s.t)[:, None]
        X.append(np.hstack([s.x[:-1], s.u[:-1], dt]))
        Y.append(s.x[1:] - s.x[:-1])
    return np.vstack(X), np.vstack(Y)


def run_narx(train, test, states, inputs, seed, bound):
    from sklearn.ensemble import HistGradientBoostingRegressor
    X, Y = narx_xy(train)
    models = [HistGradientBoostingRegressor(random_state=seed).fit(X, Y[:, j])
              for j in range(len(states))]
    preds = []
    for s in test:
        n = len(s)
        out = np.full(s.x.shape, np.nan)
        out[0] = s.x[0]
        dt = np.diff(s.t)
        div = False
        for k in range(n - 1):
            z = np.concatenate([out[k], s.u[k], [dt[k]]])[None, :]
            out[k + 1] = out[k] + np.array([m.predict(z)[0] for m in models])
            if np.max(np.abs(out[k + 1])) > bound:
                div = True
                break
        preds.append((out, div))
    sc = score(preds, test, states)
    return {"name": "narx_boosting_sklearn", **sc, "equations": [],
            "settings": {"regressor": f"HistGradientBoostingRegressor(random_state={seed})",
                         "features": states + inputs + ["dt"],
                         "target": "x[k+1] - x[k] per state",
                         "training_pairs": int(X.shape[0])}}


# ---------------------------------------------------------------- main
def versions():
    out = {"python": sys.version.split()[0]}
    for mod in ["pysindy", "sklearn", "scipy", "numpy", "pandas"]:
        try:
            out[mod] = __import__(mod).__version__
        except Exception:
            out[mod] = None
    return out


def main(argv=None):
    args = parse_args(argv)
    runs, states, inputs = load(args)
    train, test, how = split(runs, args)
    if args.test_after is not None:
        train = TimeSplitList(train)
    if not test:
        sys.exit("no held-out samples")
    bound = bound_of(list(runs.values()))
    models = [run_sindy(train, test, states, inputs, args.seed, bound),
              run_narx(train, test, states, inputs, args.seed, bound)]
    res = {"models": models, "test_runs": [s.run for s in test],
           "settings": {"data": args.data, "time": args.time, "run": args.run,
                        "states": states, "inputs": inputs, "split": how,
                        "train_runs": [s.run for s in train],
                        "train_samples": int(sum(len(s) for s in train)),
                        "scored_samples": int(sum(len(s) - 1 for s in test)),
                        "scoring": "free-run RMSE, inputs held between samples, "
                                   "first reading of each held-out segment not scored",
                        "versions": versions()}}
    with open(args.json, "w") as f:
        json.dump(res, f, indent=2, allow_nan=False)
    print(f"held out: {res['test_runs']} ({how['mode']}), "
          f"{res['settings']['scored_samples']} scored samples")
    print(f"{'model':<24} {'free-run RMSE':>14}  per run")
    for m in models:
        r = "diverged" if m["rmse"] is None else f"{m['rmse']:.4g}"
        pr = ", ".join(f"{k}: {'div' if v is None else f'{v:.3g}'}"
                       for k, v in m["per_run"].items())
        print(f"{m['name']:<24} {r:>14}  {pr}")
    for eq in models[0]["equations"]:
        print("  " + eq)


if __name__ == "__main__":
    main()
