"""Which selection criterion picks a structure that comes back across bootstrap resamples:
training BIC or 5-fold cross-validated loss (issue 15 item 5), on the paper's case and on
the two table cases of the results page.

Runs the hxai binary only (no Python packages needed):

    python3 scripts/criterion_stability.py --hxai target/debug/hxai --runs 20 --out DIR

For each case and criterion it runs `hxai fit` (the tool case) or `hxai hybrid fit` (the
tables) with `--stability RUNS --criterion C --json`, then prints one Markdown table row:
the structure selected on all training rows, how many distinct structures the RUNS
resamples selected, the share of the most frequent one, the features used in at least half
of the runs, and the out-of-bag R^2 of the runs. Data and model files go to DIR (made if
missing); nothing outside it is written.
"""
import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

# The table cases as the results page runs them (crates/reproduce/src/beyond/mod.rs):
# 400 rows, seed 42, the physics with its given starting values, the correction form of the
# results page (multiplicative; log for tool life).
TABLES = [
    ("roughness", "Ra_um", "1000*feed_mm^2/(32*nose_radius_mm) + Ra0", "Ra0", "Ra0=0",
     "multiplicative"),
    ("cutting-force", "Fc_N", "kc*width_of_cut_mm*chip_thickness_mm^(1-mc)", "kc,mc",
     "kc=2220,mc=0.14", "multiplicative"),
    ("tool-life", "tool_life_min", "(C/cutting_speed_m_min)^(1/n)", "C,n", "C=500,n=0.25",
     "log"),
]

# `--criteria` values: a criterion of one search, or consensus selection over B resamples
# (`consensus` = B of `--consensus-runs`, selecting by BIC among the stable structures).
def selection_args(crit, b):
    if crit == "consensus":
        return ["--consensus", str(b)]
    return ["--criterion", crit]


def run(cmd):
    t = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stderr}")
    return p.stdout, time.time() - t


def summary(case, criterion, model, stability, seconds, correction=None, test=None):
    runs = stability["runs"]
    structures = stability["structures"]
    top = structures[0]["share"] if structures else float("nan")
    common = [f for f, s in sorted(stability["features"].items(), key=lambda kv: -kv[1])
              if s >= 0.5]
    r2 = stability.get("r2") or {}
    r2_text = (f"{r2['mean']:.3f} ± {r2['sd']:.3f}"
               if r2.get("mean") is not None else "–")
    sel = (correction or {}).get("selection") or {}
    own = sel.get("share")
    own_text = f"{own:.2f}" if own is not None else "–"
    cx = (correction or {}).get("complexity", "–")
    test_text = f"{test:.4g}" if test is not None else "–"
    return (f"| {case} | {criterion} | `{model}` | {cx} | {len(structures)} of {runs} | "
            f"{top:.2f} | {own_text} | {', '.join(common)} | {r2_text} | {test_text} | "
            f"{seconds:.0f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hxai", required=True, help="the hxai binary")
    ap.add_argument("--runs", type=int, default=20, help="bootstrap resamples per fit")
    ap.add_argument("--out", default="target/criterion-stability", help="work folder")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--cases", default="tool,roughness,cutting-force,tool-life")
    ap.add_argument("--criteria", default="bic,cv", help="bic, aic, pareto, cv, consensus")
    ap.add_argument("--consensus-runs", type=int, default=10)
    ap.add_argument("--extra", default="",
                    help="more flags for every fit, space-separated (e.g. '--operators add,mul')")
    ap.add_argument("--forms", default="",
                    help="correction forms other than the results page's, as CASE=FORM,... "
                         "(e.g. 'cutting-force=log')")
    a = ap.parse_args()
    forms = dict(kv.split("=", 1) for kv in a.forms.split(",") if kv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    hx = [a.hxai]
    cases = a.cases.split(",")
    criteria = a.criteria.split(",")
    extra = a.extra.split()
    print("| case | selection | selected structure | complexity | distinct structures | share of "
          "the most frequent | share of the selected | features in >= half the runs | "
          "out-of-bag R^2 | test: R^2 of delta (tool) or hybrid RMSE (tables) | s |")
    print("|---|---|---|---:|---:|---:|---:|---|---|---:|---:|")
    if "tool" in cases:
        sim = out / "sim"
        if not (sim / "manifest.csv").exists():
            run(hx + ["simulate", "--out", str(sim), "--seed", "42"])
        for crit in criteria:
            model = out / f"tool-{crit}.json"
            text, secs = run(hx + ["fit", "--data", str(sim), "--out", str(model), "--seed", "42",
                                   "--stability", str(a.runs), "--json",
                                   "--threads", str(a.threads)]
                             + selection_args(crit, a.consensus_runs) + extra)
            j = json.loads(text)
            m = json.loads(model.read_text())
            dt = (m["training"].get("delta_test") or {}).get("r2")
            print(summary("tool (paper)", crit, m["correction"]["equation"], j["stability"],
                          secs, m["correction"], dt), flush=True)
    for name, target, physics, calibrate, init, form in TABLES:
        if name not in cases:
            continue
        form = forms.get(name, form)
        table = out / f"{name}.csv"
        if not table.exists():
            run(hx + ["simulate", "--case", name.replace("-", "_"), "--out", str(table),
                      "--seed", "42", "--rows", "400"])
        for crit in criteria:
            model = out / f"{name}-{form}-{crit}.json"
            _, secs = run(hx + ["hybrid", "fit", "--data", str(table), "--target", target,
                                "--physics", physics, "--calibrate", calibrate, "--init", init,
                                "--correction", form, "--exclude", "tool",
                                "--max-complexity", "10", "--seed", "42",
                                "--stability", str(a.runs), "--out", str(model),
                                "--threads", str(a.threads)]
                          + selection_args(crit, a.consensus_runs) + extra)
            m = json.loads(model.read_text())
            rmse = (m.get("scores") or {}).get("test", {}).get("hybrid", {}).get("rmse")
            print(summary(name, crit, m["correction"]["equation"], m["stability"], secs,
                          m["correction"], rmse), flush=True)


if __name__ == "__main__":
    main()
