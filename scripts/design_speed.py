"""The speed goal of `hxai hybrid design` (issue 49): 200 training rows, 5 columns, a model
with 2 alternatives, a CSV of 10,000 candidate settings; the goal is under 10 s on 2 cores.

    python3 scripts/design_speed.py --hxai target/release/hxai --out DIR

Writes the seeded training table (`y = 2 a sqrt(b) + 0.3 c + 0.1 d^2` plus noise of sd
0.05, every column uniform on 1..5, `e` a distractor) and the candidates under DIR, fits
`k*a*sqrt(b)` with `k` calibrated (`hxai --threads 2 hybrid fit`), and times `hxai --threads
2 hybrid design --n 10` for each goal three times, printing the median. Needs numpy.
"""
import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from heldout_processes import write_csv  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hxai", required=True)
    ap.add_argument("--out", default="target/design-speed")
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(7)
    x = rng.uniform(1, 5, (200, 5))
    y = 2 * x[:, 0] * np.sqrt(x[:, 1]) + 0.3 * x[:, 2] + 0.1 * x[:, 3] ** 2 + rng.normal(0, 0.05, 200)
    names = ["a", "b", "c", "d", "e"]
    write_csv(out / "train.csv", {**dict(zip(names, x.T)), "y": y})
    write_csv(out / "candidates.csv", dict(zip(names, rng.uniform(1, 5, (10000, 5)).T)))
    model = out / "model.json"
    subprocess.run([a.hxai, "--threads", "2", "hybrid", "fit", "--data", str(out / "train.csv"),
                    "--target", "y", "--physics", "k*a*sqrt(b)", "--calibrate", "k",
                    "--out", str(model)], check=True, capture_output=True)
    alternatives = json.loads(model.read_text())["correction"]["selection"]["alternatives"]
    print(f"model: {len(alternatives)} alternative(s)")
    for goal in ("discriminate", "precision", "coverage"):
        times = []
        for _ in range(3):
            t0 = time.perf_counter()
            subprocess.run([a.hxai, "--threads", "2", "hybrid", "design", "--model", str(model),
                            "--space", str(out / "candidates.csv"), "--n", "10", "--goal", goal,
                            "--out", str(out / f"next-{goal}.csv")], check=True,
                           capture_output=True)
            times.append(time.perf_counter() - t0)
        print(f"{goal}: median {statistics.median(times):.3f} s over 3 runs")


if __name__ == "__main__":
    main()
