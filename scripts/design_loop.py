"""Runs chosen by `hxai hybrid design` against random runs (issue 49).

For each held-out process of `scripts/heldout_processes.py` (wear, creep, runout: their
truths are Python functions of the settings, so a run can be "measured" at any setting)
and each seed:

1. draw `--start` runs uniformly over the process's space and measure them;
2. fit the hybrid on them (`hxai hybrid fit --test-fraction 0.02`: one or two rows held out, the least the fit accepts);
3. add `--add` runs two ways, each measured with fresh scatter and refitted:
   - `precision`: the settings `hxai hybrid design --goal precision` proposes over the
     space (ranges: 4,000 seeded candidates);
   - `random`: the same number drawn uniformly over the same space;
   - `lhs` (precision goal): the same number from a Latin hypercube of the same space (each
     column's range cut into `--add` equal strata, one run per stratum, the strata of the
     columns paired at random; a stepped column takes the level nearest the draw);
   - `coverage` (precision goal): the runs `hxai hybrid design --goal coverage` proposes
     from the same start;
4. record each physics parameter's 95 % interval width (the model file's
   `physics.params[P].ci95`) and, for the precision goal, the hybrid's RMSE on 2,000 fresh
   runs drawn uniformly over the space and measured (the same runs for every arm).

It prints, per process and parameter, the median over seeds of the width after the designed
runs divided by the width after the random runs (issue 49's goal: at most 0.7) and after the
Latin hypercube's, and the share of seeds where the designed runs gave the narrower interval.

With `--goal discriminate` every fit runs `--stability N` (default 20) and the measure is
the share of resamples whose correction uses exactly the truth's columns (the process's
`effects`; a structure's columns are the column names in its canonical template): after
the start, after `--add` runs chosen by `hxai hybrid design --goal discriminate`, and after
`--add` and 3 x `--add` random runs (issue 49's goal: the designed runs reach the share of
3 x `--add` random ones with at most 1.5 x `--add`).

    python3 scripts/design_loop.py --hxai target/release/hxai --out DIR [--seeds 10]
        [--goal precision|discriminate] [--stability 20]

With `--loop` it runs issue 49's closed loop instead: from the same `--start` runs, three
arms add `--rounds` rounds of `--add` runs each, every arm refitted with `--stability N`
after every round:
- `design`: the runs `hxai hybrid design` proposes at its default goal (`discriminate`
  where the model has alternatives, `precision` where it has none) from the arm's last fit;
- `random`: uniform draws over the space;
- `lhs`: a Latin hypercube of the space, a new one each round.
After every fit it records the share of resamples with the truth's columns, the test RMSE
on 2,000 fresh measured runs (the same for every arm) and each physics parameter's 95 %
interval width, one JSON line per (process, seed, arm, rows) in DIR/loop.jsonl, and prints
the means and medians over seeds per arm and row count. `scripts/design_loop_plot.py`
draws them. The loop's processes are the held-out ones and `tool_life`, the simulated
tool-life case (`hxai_sim::cases::tool_life` at its defaults, written here in Python; the
Python tests check it against `hxai.simulate`).

    python3 scripts/design_loop.py --hxai target/release/hxai --out DIR --loop
        [--seeds 10] [--rounds 3] [--only tool_life,wear]

A fit `hxai hybrid fit` refuses (a correction with no value on a row, say) is left out of
the medians and named at the end; a refused start fit leaves its seed out.

Needs numpy. Writes only under DIR.
"""
import argparse
import csv
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import heldout_processes as hp  # noqa: E402


# The simulated tool-life case at its defaults (crates/sim/src/cases/tool_life.rs): the
# measured life is the extended Taylor law `(C/vc)^(1/n) (f/f_ref)^(-y/n)` with C = 400
# m/min, n = 0.25, f_ref = 0.25 mm/rev, y = 0.6, times a log-normal scatter of 0.3; coolant
# temperature and workpiece diameter have no effect. The hybrid is the results page's:
# Taylor's law with the handbook's C = 500, n = 0.25 as the start, a multiplicative
# correction; the truth's correction is a power law of the feed alone.
TOOL_LIFE = dict(
    target="tool_life_min", physics="(C/cutting_speed_m_min)^(1/n)", calibrate="C,n",
    init="C=500,n=0.25", correction="multiplicative", effects="feed_mm",
    space="cutting_speed_m_min=150:350,feed_mm=0.1:0.4,coolant_temp_C=18:28,"
          "workpiece_diameter_mm=30:120")


def tool_life_truth(c):
    """The tool life (min) at settings `c` before scatter."""
    return (400.0 / c["cutting_speed_m_min"]) ** 4.0 * (c["feed_mm"] / 0.25) ** (-0.6 / 0.25)


def tool_life_measure(c, rng):
    return tool_life_truth(c) * np.exp(0.3 * rng.standard_normal(len(c["feed_mm"])))


def loop_processes():
    """The closed loop's processes: the held-out ones and the simulated tool life."""
    procs = {"tool_life": (tool_life_measure, TOOL_LIFE)}
    procs.update({name: (measure, spec) for name, (_, measure, spec) in hp.SPECS.items()})
    return procs


class FitFailed(Exception):
    """`hxai hybrid fit` refused a table (its message is the exception's)."""


def run(cmd, tolerate=False):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        msg = f"failed: {' '.join(cmd)}\n{p.stderr.strip()}"
        if tolerate:
            raise FitFailed(msg)
        raise SystemExit(msg)
    return p.stdout


def ranges(space):
    """`col=lo:hi[:step]` of a space as {col: (lo, hi, step or None)}."""
    out = {}
    for part in space.split(","):
        name, rng = part.split("=")
        v = [float(x) for x in rng.split(":")]
        out[name] = (v[0], v[1], v[2] if len(v) > 2 else None)
    return out


def uniform(space, n, rng):
    cols = {}
    for name, (lo, hi, step) in ranges(space).items():
        if step is None:
            cols[name] = rng.uniform(lo, hi, n)
        else:
            levels = np.arange(lo, hi + step / 2, step)
            cols[name] = rng.choice(levels, n)
    return cols


def latin_hypercube(space, n, rng):
    """n runs of a Latin hypercube over `space`: one run in each of n equal strata of every
    column, the strata paired at random across columns; a stepped column's draw is moved to
    its nearest level."""
    cols = {}
    for name, (lo, hi, step) in ranges(space).items():
        u = (rng.permutation(n) + rng.uniform(0.0, 1.0, n)) / n
        v = lo + u * (hi - lo)
        if step is not None:
            levels = np.arange(lo, hi + step / 2, step)
            v = levels[np.abs(v[:, None] - levels[None, :]).argmin(axis=1)]
        cols[name] = v
    return cols


def hybrid_fit(a, spec, table, model, *extra):
    """`hxai hybrid fit` of the process's hybrid on `table` (one or two rows held out, the
    least the fit accepts); returns the model file."""
    run([a.hxai, "hybrid", "fit", "--data", str(table), "--target", spec["target"],
         "--physics", spec["physics"], "--calibrate", spec["calibrate"], "--init", spec["init"],
         "--correction", spec["correction"], "--test-fraction", "0.02", "--seed", "42",
         *extra, "--threads", str(a.threads), "--out", str(model)], tolerate=True)
    return json.loads(Path(model).read_text())


def fit(a, spec, table, model):
    m = hybrid_fit(a, spec, table, model)
    return {p: (v["ci95"][1] - v["ci95"][0]) if v.get("ci95") else float("nan")
            for p, v in m["physics"]["params"].items()}


def truth_share(m, spec):
    """The share of the model file `m`'s stability resamples whose correction's structure
    uses exactly the truth's columns (the process's `effects`)."""
    columns = list(ranges(spec["space"]))
    truth = set(spec["effects"].split(","))
    share = 0.0
    for st in m["stability"]["structures"]:
        used = {c for c in columns if re.search(rf"\b{re.escape(c)}\b", st["template"])}
        if used == truth:
            share += st["share"]
    return share


def true_set_share(a, spec, table, model):
    """Fits with `--stability` and returns the share of resamples whose correction's
    structure uses exactly the truth's columns."""
    m = hybrid_fit(a, spec, table, model, "--stability", str(a.stability))
    share = truth_share(m, spec)
    return share, bool((m["correction"].get("selection") or {}).get("alternatives"))


def start_and_design(a, out, name, seed, measure, spec, rng, goal, fit_start):
    """The `--start` measured runs (fitted by `fit_start(table, model)`, whose result is
    returned), and the `--add` runs `hxai hybrid design --goal GOAL` proposes from that
    fit, measured: `(base, designed, fit_start's result)`."""
    base = uniform(spec["space"], a.start, rng)
    base[spec["target"]] = measure(base, rng)
    t0 = out / f"{name}-{seed}-start.csv"
    hp.write_csv(t0, base)
    m0 = out / f"{name}-{seed}-start.json"
    started = fit_start(t0, m0)
    designed = design_runs(a, m0, out / f"{name}-{seed}-next.csv", goal, seed, measure, spec,
                           rng)
    return base, designed, started


def design_runs(a, model, nxt, goal, seed, measure, spec, rng):
    """The `--add` runs `hxai hybrid design --goal GOAL` proposes from `model` over the
    process's space, measured."""
    run([a.hxai, "hybrid", "design", "--model", str(model), "--space", spec["space"],
         "--n", str(a.add), "--goal", goal, "--seed", str(seed), "--out", str(nxt)])
    names = list(ranges(spec["space"]))
    with open(nxt, newline="") as fh:
        rows = list(csv.DictReader(fh))
    designed = {c: np.array([float(r[c]) for r in rows]) for c in names}
    designed[spec["target"]] = measure(designed, rng)
    return designed


def fresh_runs(out, name, seed, measure, spec):
    """The 2,000 fresh runs of a seed (uniform over the space, measured; the same for every
    arm), written under `out`: `(their CSV, their measured target, the CSV a prediction of
    them is written to)`."""
    rng = np.random.default_rng(9000 + seed)
    fresh = uniform(spec["space"], 2000, rng)
    y = measure(fresh, rng)
    fresh_csv = out / f"{name}-{seed}-fresh.csv"
    hp.write_csv(fresh_csv, fresh)
    return fresh_csv, y, out / f"{name}-{seed}-fresh-pred.csv"


def test_rmse(a, model, fresh_csv, y, out_csv, tolerate=False):
    """RMSE of the model's hybrid (`hxai hybrid predict`) against `y` on the fresh rows."""
    run([a.hxai, "hybrid", "predict", "--model", str(model), "--data", str(fresh_csv),
         "--threads", str(a.threads), "--out", str(out_csv)], tolerate=tolerate)
    with open(out_csv, newline="") as fh:
        pred = np.array([float(r["hybrid"]) for r in csv.DictReader(fh)])
    return float(np.sqrt(np.mean((pred - y) ** 2)))


def discriminate(a, out, name, measure, spec):
    shares = {"start": [], "designed": [], "random": [], "random3": []}
    alternatives = 0
    for seed in range(a.seeds):
        rng = np.random.default_rng(2000 + seed)
        base, designed, (share, alt) = start_and_design(
            a, out, name, seed, measure, spec, rng, "discriminate",
            lambda t, m: true_set_share(a, spec, t, m))
        shares["start"].append(share)
        alternatives += alt
        randoms = uniform(spec["space"], 3 * a.add, rng)
        randoms[spec["target"]] = measure(randoms, rng)
        first = {k: v[:a.add] for k, v in randoms.items()}
        for arm, extra in (("designed", designed), ("random", first), ("random3", randoms)):
            t = out / f"{name}-{seed}-{arm}.csv"
            hp.write_csv(t, joined(base, extra))
            shares[arm].append(true_set_share(a, spec, t, out / f"{name}-{seed}-{arm}.json")[0])
        print(f"  {name} seed {seed}: " + ", ".join(f"{k} {v[-1]:.2f}" for k, v in shares.items()),
              file=sys.stderr, flush=True)
    mean = {k: float(np.mean(v)) for k, v in shares.items()}
    print(f"| {name} | `{spec['effects']}` | {mean['start']:.2f} | {mean['designed']:.2f} | "
          f"{mean['random']:.2f} | {mean['random3']:.2f} | "
          f"{np.mean(np.array(shares['designed']) >= np.array(shares['random3'])):.0%} | "
          f"{alternatives} of {a.seeds} |", flush=True)


def loop_fit(a, spec, table, model, fresh_csv, y_fresh, pred_csv):
    """One fit of the closed loop (with `--stability`): the truth's share, whether the model
    has alternatives, the test RMSE on the fresh runs and each physics parameter's width."""
    m = hybrid_fit(a, spec, table, model, "--stability", str(a.stability))
    share = truth_share(m, spec)
    try:
        rmse = test_rmse(a, model, fresh_csv, y_fresh, pred_csv, tolerate=True)
        refused = None
    except FitFailed as e:
        # a correction with no value somewhere in the space: no test RMSE (None), and why
        rmse, refused = None, str(e).splitlines()[-1]
    widths = {p: (v["ci95"][1] - v["ci95"][0]) if v.get("ci95") else None
              for p, v in m["physics"]["params"].items()}
    return dict(share=share,
                alternatives=len((m["correction"].get("selection") or {}).get("alternatives")
                                 or []),
                rmse=rmse, predict_refused=refused, widths=widths)


ARMS = ("design", "random", "lhs")


def fit_or_note(a, spec, table, model, fresh, failures, what):
    """`loop_fit` on the fresh runs `(csv, y, prediction csv)`, or `None` with the
    refusal noted in `failures` as `what`."""
    try:
        return loop_fit(a, spec, table, model, *fresh)
    except FitFailed as e:
        failures.append(f"{what}: {e}")
        return None


def closed_loop(a, out, name, measure, spec, log, failures):
    """Issue 49's loop on one process: `--rounds` rounds of `--add` runs per arm, each arm
    refitted after each round; one JSON line per fit in `log`."""
    for seed in range(a.first_seed, a.seeds):
        rng = np.random.default_rng(3000 + seed)
        base = uniform(spec["space"], a.start, rng)
        base[spec["target"]] = measure(base, rng)
        fresh_csv, y_fresh, pred_csv = fresh_runs(out, name, seed, measure, spec)
        t0 = out / f"{name}-{seed}-loop-start.csv"
        hp.write_csv(t0, base)
        m0 = out / f"{name}-{seed}-loop-start.json"
        fresh = (fresh_csv, y_fresh, pred_csv)
        start = fit_or_note(a, spec, t0, m0, fresh, failures,
                            f"{name} seed {seed}, start (the seed is left out)")
        if start is None:
            continue
        for arm in ARMS:
            log.write(json.dumps(dict(process=name, seed=seed, arm=arm, rows=a.start,
                                      **start)) + "\n")
        for k, arm in enumerate(ARMS):
            # each arm its own stream of settings and scatter, the same whatever the others do
            arng = np.random.default_rng([3000 + seed, k])
            table, model = base, m0
            for r in range(1, a.rounds + 1):
                if arm == "design":
                    nxt = out / f"{name}-{seed}-loop-{arm}-{r}-next.csv"
                    try:
                        run([a.hxai, "hybrid", "design", "--model", str(model), "--space",
                             spec["space"], "--n", str(a.add), "--seed", str(seed), "--out",
                             str(nxt)], tolerate=True)
                    except FitFailed as e:
                        failures.append(f"{name} seed {seed}, {arm} round {r} (design): {e}")
                        print(f"  {name} seed {seed} {arm} round {r}: design refused",
                              file=sys.stderr, flush=True)
                        break
                    with open(nxt, newline="") as fh:
                        rows = list(csv.DictReader(fh))
                    extra = {c: np.array([float(row[c]) for row in rows])
                             for c in ranges(spec["space"])}
                elif arm == "random":
                    extra = uniform(spec["space"], a.add, arng)
                else:
                    extra = latin_hypercube(spec["space"], a.add, arng)
                extra[spec["target"]] = measure(extra, arng)
                table = joined(table, extra)
                t = out / f"{name}-{seed}-loop-{arm}-{r}.csv"
                hp.write_csv(t, table)
                model = out / f"{name}-{seed}-loop-{arm}-{r}.json"
                got = fit_or_note(a, spec, t, model, fresh, failures,
                                  f"{name} seed {seed}, {arm} round {r}")
                if got is None:
                    break
                log.write(json.dumps(dict(process=name, seed=seed, arm=arm,
                                          rows=a.start + r * a.add, **got)) + "\n")
                log.flush()
                print(f"  {name} seed {seed} {arm} +{r * a.add}: share {got['share']:.2f}, "
                      f"rmse {got['rmse'] if got['rmse'] is None else format(got['rmse'], '.4g')}", file=sys.stderr, flush=True)


def loop_summary(rows):
    """Markdown tables of the loop's lines `rows`: per process, arm and row count, the mean
    share of the truth's columns, the median test RMSE and each parameter's median width
    over seeds, and the goal's comparison."""
    out = []
    by = {}
    for r in rows:
        by.setdefault(r["process"], []).append(r)
    for name, rs in by.items():
        counts = sorted({r["rows"] for r in rs})
        params = sorted({p for r in rs for p in r["widths"]})
        out.append(f"\n**{name}** (seeds: {len({r['seed'] for r in rs})})\n")
        out.append("| arm | measure | " + " | ".join(f"{c} rows" for c in counts) + " |")
        out.append("|---|---|" + "---:|" * len(counts))
        for arm in ARMS:
            cell = {c: [r for r in rs if r["arm"] == arm and r["rows"] == c] for c in counts}
            out.append(f"| {arm} | share of the truth's columns (mean) | " + " | ".join(
                f"{np.mean([r['share'] for r in cell[c]]):.2f}" if cell[c] else "-"
                for c in counts) + " |")
            out.append(f"| {arm} | test RMSE (median) | " + " | ".join(
                f"{np.nanmedian([np.nan if r['rmse'] is None else r['rmse'] for r in cell[c]]):.4g}"
                if cell[c] else "-"
                for c in counts) + " |")
            for p in params:
                out.append(f"| {arm} | {p} 95 % width (median) | " + " | ".join(
                    f"{np.nanmedian([np.nan if r['widths'].get(p) is None else r['widths'][p] for r in cell[c]]):.4g}"
                    if cell[c] else "-" for c in counts) + " |")
    out.append("\n" + loop_goals(rows))
    return "\n".join(out)


def loop_goals(rows):
    """Issue 49's two goals on the loop's lines `rows`, per process: the designed runs'
    share of the truth's columns after one round (`--add` runs, at most 1.5 x `--add`)
    against the random runs' after three, means over seeds; and each physics parameter's
    width after one designed round over its width after one random round, the median over
    seeds of the ratio (goal <= 0.7); with the design rounds proposed from a model that had
    alternatives (so at the `discriminate` goal, `precision` otherwise)."""
    out = ["| process | share, +1 round designed | share, +3 rounds random | share goal | "
           "parameter | width ratio, +1 round designed / random (median) | ratio goal | "
           "design rounds from a model with alternatives |",
           "|---|---:|---:|---|---|---:|---|---:|"]
    by = {}
    for r in rows:
        by.setdefault(r["process"], []).append(r)
    for name, rs in by.items():
        counts = sorted({r["rows"] for r in rs})
        if len(counts) < 2:
            continue
        first, last = counts[1], counts[-1]
        pick = {(r["seed"], r["arm"], r["rows"]): r for r in rs}
        designed = [r["share"] for r in rs if r["arm"] == "design" and r["rows"] == first]
        random3 = [r["share"] for r in rs if r["arm"] == "random" and r["rows"] == last]
        bases = [r for r in rs if r["arm"] == "design" and r["rows"] < last]
        with_alt = sum(1 for r in bases if r["alternatives"])
        sd, sr = float(np.mean(designed)), float(np.mean(random3))
        params = sorted({p for r in rs for p in r["widths"]})
        for i, p in enumerate(params):
            ratios = []
            for seed in sorted({r["seed"] for r in rs}):
                d, q = pick.get((seed, "design", first)), pick.get((seed, "random", first))
                if d and q and d["widths"].get(p) and q["widths"].get(p):
                    ratios.append(d["widths"][p] / q["widths"][p])
            ratio = float(np.median(ratios)) if ratios else float("nan")
            lead = (f"| {name} | {sd:.2f} | {sr:.2f} | {'met' if sd >= sr else 'missed'} | "
                    if i == 0 else "| | | | | ")
            out.append(lead + f"{p} | {ratio:.2f} ({len(ratios)} seeds) | "
                       f"{'met' if ratio <= 0.7 else 'missed'} | "
                       + (f"{with_alt} of {len(bases)} |" if i == 0 else " |"))
    return "\n".join(out)


def joined(a, b):
    return {k: np.concatenate([a[k], b[k]]) for k in a}


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hxai", required=True)
    ap.add_argument("--out", default="target/design-loop")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--start", type=int, default=60)
    ap.add_argument("--add", type=int, default=10)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--only", default="")
    ap.add_argument("--goal", choices=["precision", "discriminate"], default="precision")
    ap.add_argument("--stability", type=int, default=20)
    ap.add_argument("--loop", action="store_true",
                    help="issue 49's closed loop: design, random and Latin hypercube arms")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--first-seed", type=int, default=0,
                    help="the loop's first seed (to go on from a stopped run)")
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    if a.loop:
        failures = []
        path = out / "loop.jsonl"
        with open(path, "w") as log:
            for name, (measure, spec) in loop_processes().items():
                if a.only and name not in a.only.split(","):
                    continue
                closed_loop(a, out, name, measure, spec, log, failures)
        print(loop_summary([json.loads(x) for x in path.read_text().splitlines()]))
        if failures:
            print(f"\n{len(failures)} fit(s) refused, left out (an arm stops at its refusal):")
            for f in failures:
                print("- " + f.replace("\n", " / "))
        return
    if a.goal == "discriminate":
        print(f"| process | true columns | share after {a.start} | +{a.add} designed | "
              f"+{a.add} random | +{3 * a.add} random | designed >= +{3 * a.add} random | "
              "start model with alternatives |")
        print("|---|---|---:|---:|---:|---:|---:|---:|")
        for name, (_, measure, spec) in hp.SPECS.items():
            if a.only and name not in a.only.split(","):
                continue
            discriminate(a, out, name, measure, spec)
        return
    print(f"| process | parameter | width after {a.start} | after +{a.add} designed | "
          f"after +{a.add} random | after +{a.add} LHS | after +{a.add} coverage | "
          "designed / random (median) | designed / LHS (median) | "
          "designed narrower than random |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    rmse_rows = []
    failures = []
    for name, (_, measure, spec) in hp.SPECS.items():
        if a.only and name not in a.only.split(","):
            continue
        widths = {"start": [], "precision": [], "random": [], "lhs": [], "coverage": []}
        rmses = {k: [] for k in widths}
        for seed in range(a.seeds):
            rng = np.random.default_rng(1000 + seed)
            try:
                base, designed, started = start_and_design(
                    a, out, name, seed, measure, spec, rng, "precision",
                    lambda t, m: fit(a, spec, t, m))
            except FitFailed as e:
                failures.append(f"{name} seed {seed}, start (the seed is left out): {e}")
                continue
            widths["start"].append(started)
            randoms = uniform(spec["space"], a.add, rng)
            randoms[spec["target"]] = measure(randoms, rng)
            # drawn after the random runs, so those are the same as without this arm
            lhs = latin_hypercube(spec["space"], a.add, rng)
            lhs[spec["target"]] = measure(lhs, rng)
            # drawn after the hypercube, so the arms above are the same as without this one
            cover = design_runs(a, out / f"{name}-{seed}-start.json",
                                out / f"{name}-{seed}-next-coverage.csv", "coverage", seed,
                                measure, spec, rng)
            fresh_csv, y_fresh, pred_csv = fresh_runs(out, name, seed, measure, spec)
            rmses["start"].append(test_rmse(a, out / f"{name}-{seed}-start.json", fresh_csv,
                                            y_fresh, pred_csv))
            for arm, extra in (("precision", designed), ("random", randoms), ("lhs", lhs),
                               ("coverage", cover)):
                t = out / f"{name}-{seed}-{arm}.csv"
                hp.write_csv(t, joined(base, extra))
                m = out / f"{name}-{seed}-{arm}.json"
                try:
                    widths[arm].append(fit(a, spec, t, m))
                    rmses[arm].append(test_rmse(a, m, fresh_csv, y_fresh, pred_csv))
                except FitFailed as e:
                    # a refused fit counts as missing (NaN), named at the end
                    failures.append(f"{name} seed {seed}, {arm}: {e}")
                    widths[arm].append({p: float("nan") for p in started})
                    rmses[arm].append(float("nan"))
        for p in widths["start"][0]:
            w0 = np.array([w[p] for w in widths["start"]])
            wd = np.array([w[p] for w in widths["precision"]])
            wr = np.array([w[p] for w in widths["random"]])
            wl = np.array([w[p] for w in widths["lhs"]])
            wc = np.array([w[p] for w in widths["coverage"]])
            both = np.isfinite(wd) & np.isfinite(wr)
            print(f"| {name} | {p} | {np.nanmedian(w0):.4g} | {np.nanmedian(wd):.4g} | "
                  f"{np.nanmedian(wr):.4g} | {np.nanmedian(wl):.4g} | {np.nanmedian(wc):.4g} | "
                  f"{np.nanmedian(wd / wr):.2f} | {np.nanmedian(wd / wl):.2f} | "
                  f"{np.mean(wd[both] < wr[both]):.0%} |", flush=True)
        rmse_rows.append(f"| {name} | " + " | ".join(
            f"{np.nanmedian(rmses[k]):.4g}" for k in ("start", "precision", "random", "lhs",
                                                        "coverage")) + " |")
    print(f"\n| process | test RMSE after {a.start} (2,000 fresh runs, median) | "
          f"+{a.add} designed | +{a.add} random | +{a.add} LHS | +{a.add} coverage |")
    print("|---|---:|---:|---:|---:|---:|")
    print("\n".join(rmse_rows))
    if failures:
        print(f"\n{len(failures)} fit(s) refused, left out of the medians above:")
        for f in failures:
            print("- " + f.replace("\n", " / "))


if __name__ == "__main__":
    main()
