"""Free form against factor form on the six process tables of issue 46 (the goals' table).

The cases: the three seeded tables of `hxai simulate --case` (roughness, cutting force, tool
life; 400 rows, seed 42, the settings of the results page's "Beyond the paper") and the
three held-out processes of `scripts/heldout_processes.py` (wear, creep, runout; 400 rows,
seed 7). For each case and each form (`--form free`, `--form factors`) it runs

- `hxai hybrid fit --stability RUNS` on the random 20 % split: the test RMSE, the shares of
  the most frequent structure, of the most frequent set of factor columns and of each kept
  factor's most frequent shape, distractor shares, the wall time;
- `hxai hybrid fit --extrapolate COL`: the test RMSE outside the training range;

and, on the same splits (the model file's `split`), scikit-learn's
`HistGradientBoostingRegressor` and interpret's `ExplainableBoostingRegressor` on the target
(random_state 0, default settings), and `hxai hybrid compare`'s `physics_forest`.

    python3 scripts/factor_form.py --hxai target/release/hxai --out DIR [--runs 20]

Needs numpy, scikit-learn and interpret-core. Writes only under DIR; prints Markdown tables.
"""
import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import heldout_processes as hp  # noqa: E402

SIMULATED = [
    # name, target, physics, init (calibrated), correction, extrapolate, distractors
    ("roughness", "Ra_um", "1000*feed_mm^2/(32*nose_radius_mm) + Ra0", "Ra0=0",
     "multiplicative", "feed_mm", ["coolant_temp_C", "workpiece_diameter_mm"]),
    ("cutting_force", "Fc_N", "kc*width_of_cut_mm*chip_thickness_mm^(1-mc)",
     "kc=2220,mc=0.14", "multiplicative", "cutting_time_min", ["coolant_temp_C"]),
    ("tool_life", "tool_life_min", None, None, "log", "feed_mm",
     ["coolant_temp_C", "workpiece_diameter_mm"]),
]
HELDOUT_EXTRAPOLATE = {"wear": "speed_m_s", "creep": "grain_um", "runout": "feed_mm"}
HELDOUT_DISTRACTORS = {"wear": ["humidity_pct", "batch_u"], "creep": ["position_u"],
                       "runout": ["speed_m_min"]}


def run(cmd):
    t = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(" ".join(cmd) + "\n" + p.stderr)
    return time.time() - t, p.stdout


def read_csv(path):
    with open(path) as fh:
        names = fh.readline().strip().split(",")
        rows = [line.strip().split(",") for line in fh if line.strip()]
    cols = {}
    for j, n in enumerate(names):
        try:
            cols[n] = np.array([float(r[j]) for r in rows])
        except ValueError:
            cols[n] = None  # a text column (the tool identifier)
    return cols


def black_boxes(cols, target, exclude, split):
    from sklearn.ensemble import HistGradientBoostingRegressor
    from interpret.glassbox import ExplainableBoostingRegressor
    feats = [n for n, v in cols.items() if v is not None and n != target and n not in exclude]
    X = np.column_stack([cols[n] for n in feats])
    y = cols[target]
    tr, te = np.array(split["train"]), np.array(split["test"])
    out = {}
    for name, m in [("boosting", HistGradientBoostingRegressor(random_state=0)),
                    ("ebm", ExplainableBoostingRegressor(random_state=0))]:
        m.fit(X[tr], y[tr])
        out[name] = float(np.sqrt(np.mean((m.predict(X[te]) - y[te]) ** 2)))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hxai", required=True)
    ap.add_argument("--out", default="target/factor-form")
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--only", default="")
    ap.add_argument("--reuse-free", default="",
                    help="a folder of an earlier run: read the free form's models from it "
                         "instead of refitting them (the free form's code did not change); "
                         "its seconds are then not measured; a case missing there is refitted")
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    cases = []
    for name, target, physics, init, corr, extra, distract in SIMULATED:
        table = out / f"{name}.csv"
        run([a.hxai, "simulate", "--case", name, "--rows", "400", "--seed", "42",
             "--out", str(table)])
        if physics is None:  # tool life: the law the results page uses
            physics, init = "(C/cutting_speed_m_min)^(1/n)", "C=500,n=0.25"
        calib = ",".join(kv.split("=")[0] for kv in init.split(","))
        cases.append((name, table, target, physics, calib, init, corr, extra, distract,
                      ["tool"]))
    for name, make in hp.PROCESSES:
        cols, spec = make(np.random.default_rng(hp.SEED))
        table = out / f"{name}.csv"
        hp.write_csv(table, cols)
        cases.append((name, table, spec["target"], spec["physics"], spec["calibrate"],
                      spec["init"], spec["correction"], HELDOUT_EXTRAPOLATE[name],
                      HELDOUT_DISTRACTORS[name], []))
    rows_acc, rows_stab = [], []
    for (name, table, target, physics, calib, init, corr, extra, distract, excl) in cases:
        if a.only and name not in a.only.split(","):
            continue
        base = [a.hxai, "hybrid", "fit", "--data", str(table), "--target", target,
                "--physics", physics, "--calibrate", calib, "--init", init,
                "--correction", corr, "--threads", str(a.threads)]
        if excl:
            base += ["--exclude", ",".join(excl)]
        res = {}
        for form in ["free", "factors"]:
            if (form == "free" and a.reuse_free
                    and (Path(a.reuse_free) / f"{name}-free-x.json").exists()):
                old = Path(a.reuse_free)
                m = json.loads((old / f"{name}-free.json").read_text())
                x = json.loads((old / f"{name}-free-x.json").read_text())
                res[form] = (m, x, float("nan"), float("nan"))
                continue
            m_path = out / f"{name}-{form}.json"
            secs, _ = run(base + ["--form", form, "--stability", str(a.runs),
                                  "--out", str(m_path)])
            m = json.loads(m_path.read_text())
            x_path = out / f"{name}-{form}-x.json"
            xsecs, _ = run(base + ["--form", form, "--extrapolate", extra, "--out", str(x_path)])
            x = json.loads(x_path.read_text())
            res[form] = (m, x, secs, xsecs)
        cols = read_csv(table)
        bb = black_boxes(cols, target, excl, res["free"][0]["split"])
        bbx = black_boxes(cols, target, excl, res["free"][1]["split"])
        cmpx = out / f"{name}-compare-x.json"
        cbase = [a.hxai, "hybrid", "compare"] + base[3:] + ["--form", "factors", "--json"]
        _, txt = run(cbase + ["--extrapolate", extra])
        forest_x = {mm["name"]: mm["rmse"] for mm in json.loads(txt)["models"]}["physics_forest"]
        _, txt = run(cbase)
        forest = {mm["name"]: mm["rmse"] for mm in json.loads(txt)["models"]}["physics_forest"]
        cmpx.write_text(txt)
        rf = res["free"][0]["scores"]["test"]["hybrid"]["rmse"]
        for form in ["free", "factors"]:
            m, x, secs, xsecs = res[form]
            r = m["scores"]["test"]["hybrid"]["rmse"]
            rx = x["scores"]["test"]["hybrid"]["rmse"]
            rows_acc.append(
                f"| {name} | {form} | {r:.4g} | {r / rf:.2f} | {r / bb['ebm']:.2f} | "
                f"{r / bb['boosting']:.2f} | {forest:.4g} | {rx:.4g} | {forest_x:.4g} | "
                f"{bbx['ebm']:.4g} | {bbx['boosting']:.4g} | {secs:.0f} |")
            st = m["stability"]
            top = st["structures"][0]["share"] if st["structures"] else float("nan")
            sets = st.get("factor_sets") or []
            set_top = f"{sets[0]['share']:.2f} `{sets[0]['template']}`" if sets else "–"
            shapes = st.get("factors") or {}
            kept = {c for c, s in st["features"].items() if s >= 0.5}
            shape_tops = ", ".join(
                f"{c} {max(v.values()):.2f}" for c, v in sorted(shapes.items())
                if any(c == k or c.split(':') == sorted(c.split(':')) and set(c.split(':')) <= kept
                       for k in kept) and max(v.values()) > 0)
            dis = ", ".join(f"{d} {st['features'].get(d, 0):.2f}" for d in distract)
            rows_stab.append(
                f"| {name} | {form} | `{m['correction']['equation']}` | "
                f"{m['correction']['complexity']} | {top:.2f} | {set_top} | {shape_tops or '–'} | "
                f"{dis} |")
        print(rows_acc[-2] + "\n" + rows_acc[-1] + "\n" + rows_stab[-2] + "\n" + rows_stab[-1],
              flush=True)
    print("\n| case | form | test RMSE | / free | / EBM | / boosting | physics+forest | "
          "extrapolation RMSE | physics+forest (extr.) | EBM (extr.) | boosting (extr.) | "
          "fit + stability s |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    print("\n".join(rows_acc))
    print("\n| case | form | correction | complexity | top structure | top factor-column set | "
          "top shape per factor | distractor shares |")
    print("|---|---|---|---:|---:|---|---|---|")
    print("\n".join(rows_stab))


if __name__ == "__main__":
    sys.exit(main())
