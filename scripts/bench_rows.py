"""Issue 67's scale benchmark: the README's roughness hybrid on `hxai simulate --case
roughness --rows N` (Parquet), for each N the wall time and peak RSS of `hybrid fit` and of
`hybrid predict` (GNU time), the fit's test RMSE on fresh rows (another seed), and the
log-log slope of the wall time between consecutive sizes. One JSON line per size.
`--search-rows S1,S2` fits each size once per sample size of the structure's search
(`hybrid fit --search-rows`), the measurement of the size that loses no accuracy.

    python scripts/bench_rows.py --hxai target/release/hxai --rows 10000,100000,1000000
    python scripts/bench_rows.py --hxai target/release/hxai --rows 10000,100000 \
        --search-rows 1000,2000,5000
"""
import argparse
import json
import math
import re
import subprocess
import tempfile
from pathlib import Path

FIT = [
    "--target", "Ra_um",
    "--physics", "1000*feed_mm^2/(32*nose_radius_mm) + Ra0",
    "--calibrate", "Ra0", "--init", "Ra0=0",
    "--correction", "multiplicative", "--exclude", "tool",
]


def timed(cmd):
    """Runs `cmd` under GNU time: (wall seconds, peak RSS in MB, stdout)."""
    p = subprocess.run(["/usr/bin/time", "-v", *cmd], capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed:\n{p.stderr[-2000:]}")
    wall = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", p.stderr)
    h, m, s = wall.groups()
    seconds = int(h or 0) * 3600 + int(m) * 60 + float(s)
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr).group(1))
    return seconds, rss / 1024, p.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--hxai", required=True)
    ap.add_argument("--rows", default="10000,100000")
    ap.add_argument("--fresh", type=int, default=20000, help="rows of the fresh test table")
    ap.add_argument("--search-rows", default="", help="sample sizes of the structure's search")
    ap.add_argument("--no-predict", action="store_true", help="time the fit only")
    a = ap.parse_args()
    sizes = [int(r) for r in a.rows.split(",")]
    samples = [int(s) for s in a.search_rows.split(",") if s] or [None]
    last = None
    with tempfile.TemporaryDirectory() as d:
        fresh = Path(d) / "fresh.csv"
        subprocess.run([a.hxai, "simulate", "--case", "roughness", "--rows", str(a.fresh),
                        "--seed", "7", "--out", str(fresh)], check=True, capture_output=True)
        for n in sizes:
            data, model = Path(d) / f"r{n}.parquet", Path(d) / f"m{n}.json"
            subprocess.run([a.hxai, "simulate", "--case", "roughness", "--rows", str(n),
                            "--seed", "42", "--out", str(data)], check=True, capture_output=True)
            for sample in samples:
                last = one_size(a, d, n, data, model, sample, last)


def one_size(a, d, n, data, model, sample, last):
    """Fits (and predicts) `n` rows with the search sample `sample` (the default when None),
    prints the JSON line; returns `(n, fit seconds)` for the next size's slope."""
    extra = [] if sample is None else ["--search-rows", str(sample)]
    fresh = Path(d) / "fresh.csv"
    fit_s, fit_mb, _ = timed([a.hxai, "hybrid", "fit", "--data", str(data), *FIT, *extra,
                              "--out", str(model)])
    row = {"rows": n, "search_rows": sample, "fit_s": round(fit_s, 2),
           "fit_peak_mb": round(fit_mb, 1)}
    if not a.no_predict:
        pred = Path(d) / f"p{n}.parquet"
        pred_s, pred_mb, _ = timed([a.hxai, "hybrid", "predict", "--model", str(model),
                                    "--data", str(data), "--out", str(pred)])
        row.update(predict_s=round(pred_s, 2), predict_peak_mb=round(pred_mb, 1),
                   predict_rows_per_s=round(n / pred_s))
    ev = subprocess.run([a.hxai, "hybrid", "evaluate", "--model", str(model), "--data",
                         str(fresh), "--json"], check=True, capture_output=True, text=True)
    m = json.loads(Path(model).read_text())
    row["fresh_rmse"] = json.loads(ev.stdout)["hybrid"]["rmse"]
    row["correction"] = m["correction"]["equation"]
    if last and last[0] != n:
        row["fit_slope"] = round(math.log(fit_s / last[1]) / math.log(n / last[0]), 2)
    print(json.dumps(row), flush=True)
    return (n, fit_s)


if __name__ == "__main__":
    main()
