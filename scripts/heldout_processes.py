"""Held-out processes for the defaults of a table hybrid's correction (issue 23).

The defaults of `hxai hybrid` (operators, criterion) were chosen on the three process tables
of `hxai_sim::cases` (roughness, cutting force, tool life). This script measures them on
three processes that are not in hxai and were written down, truths and settings, before the
defaults were compared on them:

- `wear`: Archard's law `V = K F s / H` as the physics, with a handbook K; the truth's wear
  coefficient grows with sliding speed as a power law and falls exponentially with the
  counterface temperature (an oxide layer), 12 % log-normal scatter, two distractors.
- `creep`: Norton-Arrhenius creep `rate = A sigma^n exp(-Q / (R T))` with the handbook's
  `Q` and `n = 4` as the physics; the truth has `n = 4.6`, and a grain-size factor
  `(d / 50)^-0.5`, 20 % log-normal scatter, one distractor.
- `runout`: a roundness error that is the feed's kinematic term in the physics, plus a
  spindle runout that varies as a sine of the spindle's angular position at the start of
  the cut: a periodic effect the law operators cannot write (`--operators` must add `sin`).

Each table has 400 rows (seed 7). For each process and each setting it runs `hxai hybrid
fit --stability 20` and prints one Markdown row: the selected correction, its complexity,
distinct structures over the resamples, the share of the most frequent, the columns used in
at least half of the runs, and the test RMSE of the hybrid on the random 20 % split.

    python3 scripts/heldout_processes.py --hxai target/debug/hxai --out DIR

Needs numpy. Writes only under DIR.
"""
import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROWS = 400
SEED = 7


def wear_settings(rng, n=ROWS):
    return dict(
        load_N=rng.uniform(10, 100, n),           # normal load, N
        distance_m=rng.uniform(100, 2000, n),     # sliding distance, m
        hardness_HV=rng.uniform(150, 600, n),     # hardness, HV
        speed_m_s=rng.uniform(0.1, 2.0, n),       # sliding speed, m/s
        temp_C=rng.uniform(20, 200, n),           # counterface temperature, C
        humidity_pct=rng.uniform(20, 80, n),      # humidity, % (distractor)
        batch_u=rng.uniform(0, 1, n))             # a batch label (distractor)


def wear_measure(c, rng):
    """The measured wear volume at settings `c` (the truth times its scatter)."""
    n = len(c["load_N"])
    K = 5e-4 * c["speed_m_s"] ** 0.4 * np.exp(-c["temp_C"] / 150)
    return K * c["load_N"] * c["distance_m"] / c["hardness_HV"] * np.exp(
        0.12 * rng.standard_normal(n))


def creep_settings(rng, n=ROWS):
    return dict(
        stress_MPa=rng.uniform(50, 200, n),       # stress, MPa
        temp_K=rng.uniform(800, 1000, n),         # temperature, K
        grain_um=rng.uniform(20, 120, n),         # grain size, um
        position_u=rng.uniform(0, 1, n))          # specimen position (distractor)


def creep_measure(c, rng):
    n = len(c["stress_MPa"])
    R = 8.314
    rate = (1e-2 * c["stress_MPa"] ** 4.6 * np.exp(-300e3 / (R * c["temp_K"]))
            * (c["grain_um"] / 50) ** -0.5)
    return rate * np.exp(0.2 * rng.standard_normal(n))


def runout_settings(rng, n=ROWS):
    return dict(
        feed_mm=rng.uniform(0.05, 0.3, n),                 # feed, mm/rev
        nose_radius_mm=rng.choice([0.4, 0.8, 1.2], n),     # nose radius, mm
        angle_deg=rng.uniform(0, 360, n),   # spindle angle at the start of the cut, degrees
        speed_m_min=rng.uniform(80, 250, n))               # cutting speed (distractor)


def runout_measure(c, rng):
    n = len(c["feed_mm"])
    kin = 1000 * c["feed_mm"] ** 2 / (8 * c["nose_radius_mm"])  # kinematic peak-to-valley, um
    err = kin + 1.5 + 1.2 * np.sin(np.radians(c["angle_deg"]) + 0.6)
    return err + 0.15 * rng.standard_normal(n)


# Each process: its settings' sampler, its measurement (truth and scatter) at given
# settings, the target's name, the hybrid's physics, its ranges for `hxai hybrid design`
# and the columns whose effects the truth adds to the physics (the correction's true
# column set, as the docstring above describes each truth).
SPECS = {
    "wear": (wear_settings, wear_measure, dict(
        target="wear_mm3", physics="K*load_N*distance_m/hardness_HV", calibrate="K",
        init="K=3e-4", correction="multiplicative", effects="speed_m_s,temp_C",
        space="load_N=10:100,distance_m=100:2000,hardness_HV=150:600,speed_m_s=0.1:2,"
              "temp_C=20:200,humidity_pct=20:80,batch_u=0:1")),
    "creep": (creep_settings, creep_measure, dict(
        target="rate_per_s", physics="A*stress_MPa^4*exp(-Q/(8.314*temp_K))",
        calibrate="A,Q", init="A=0.1,Q=280000", correction="log", effects="stress_MPa,grain_um",
        space="stress_MPa=50:200,temp_K=800:1000,grain_um=20:120,position_u=0:1")),
    "runout": (runout_settings, runout_measure, dict(
        target="roundness_um", physics="k*1000*feed_mm^2/(8*nose_radius_mm)",
        calibrate="k", init="k=1", correction="additive", effects="angle_deg",
        space="feed_mm=0.05:0.3,nose_radius_mm=0.4:1.2:0.4,angle_deg=0:360,"
              "speed_m_min=80:250")),
}


def make(name, rng, n=ROWS):
    """A table of `n` runs of process `name`: its columns and the hybrid's spec."""
    settings, measure, spec = SPECS[name]
    cols = settings(rng, n)
    cols[spec["target"]] = measure(cols, rng)
    return cols, {k: v for k, v in spec.items() if k != "space"}


def wear(rng):
    return make("wear", rng)


def creep(rng):
    return make("creep", rng)


def runout(rng):
    return make("runout", rng)


PROCESSES = [("wear", wear), ("creep", creep), ("runout", runout)]

SETTINGS = [
    ("before: paper operators, bic", ["--operators",
                                      "add,sub,mul,div,sin,cos,gaussian,gaussian2,log,abs,exp",
                                      "--criterion", "bic"]),
    ("defaults: law operators, cv", []),
    ("law operators + sin, cos, cv", ["--operators", "add,sub,mul,div,exp,log,sin,cos"]),
]


def write_csv(path, cols):
    names = list(cols)
    with open(path, "w") as fh:
        fh.write(",".join(names) + "\n")
        for i in range(len(cols[names[0]])):
            fh.write(",".join(repr(float(cols[k][i])) for k in names) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hxai", required=True)
    ap.add_argument("--out", default="target/heldout-processes")
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    print("| process | setting | selected correction | complexity | distinct of runs | most "
          "frequent | columns in >= half the runs | test hybrid RMSE | s |")
    print("|---|---|---|---:|---:|---:|---|---:|---:|")
    for name, make in PROCESSES:
        cols, spec = make(np.random.default_rng(SEED))
        table = out / f"{name}.csv"
        write_csv(table, cols)
        for i, (label, extra) in enumerate(SETTINGS):
            model = out / f"{name}-{i}.json"
            cmd = [a.hxai, "hybrid", "fit", "--data", str(table), "--target", spec["target"],
                   "--physics", spec["physics"], "--calibrate", spec["calibrate"],
                   "--init", spec["init"], "--correction", spec["correction"],
                   "--stability", str(a.runs), "--out", str(model),
                   "--threads", str(a.threads)] + extra
            t = time.time()
            p = subprocess.run(cmd, capture_output=True, text=True)
            secs = time.time() - t
            if p.returncode != 0:
                print(f"| {name} | {label} | failed: {p.stderr.strip()[:200]} | | | | | | |")
                continue
            m = json.loads(model.read_text())
            st = m["stability"]
            top = st["structures"][0]["share"] if st["structures"] else float("nan")
            common = [f for f, s in sorted(st["features"].items(), key=lambda kv: -kv[1])
                      if s >= 0.5]
            rmse = m["scores"]["test"]["hybrid"]["rmse"]
            c = m["correction"]
            print(f"| {name} | {label} | `{c['equation']}` | {c['complexity']} | "
                  f"{len(st['structures'])} of {st['runs']} | {top:.2f} | {', '.join(common)} | "
                  f"{rmse:.4g} | {secs:.0f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
