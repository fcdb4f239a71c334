"""Issue 64's measurement on the real tables of testdata/real: the default hybrid (``--form
auto``) against the free form and the calibrated physics alone, test RMSE at a random and an
extrapolation split, and whether the correction has a sin or cos. Each table gets a plain
textbook physics that leaves something for the correction (the law an engineer would
start from), fitted with ``hxai hybrid fit``.

    python3 scripts/form_auto_real.py [--hxai target/release/hxai] [--seed 42]
        [--forms auto,free] [--extra="--prior laws"]

``--extra`` is passed to every ``hxai hybrid fit`` (issue 65 compares ``--prior laws``
and ``--prior uniform`` with ``--forms free,auto``).

Prints one line per table, split and form, and the worst ratio hybrid / physics per form.
"""

import argparse
import json
import os
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# table, target, physics, parameters to calibrate, their starting values, column to
# extrapolate in
CASES = [
    ("whiteside.csv", "gas", "a + b*temp", "a,b", "a=6,b=-0.3", "temp", ["--exclude", "insul"]),
    ("hills.csv", "time", "k*dist", "k", "k=5", "dist", []),
    ("mammals.csv", "brain", "k*body^0.75", "k", "k=10", "body", []),
    ("loblolly.csv", "height", "k*age", "k", "k=3", "age", []),
    ("indometh.csv", "conc", "c*exp(-r*time)", "c,r", "c=2,r=1", "time", []),
    ("muscle.csv", "length", "a + b*log(conc)", "a,b", "a=15,b=5", "conc", []),
]


def fit(hxai, table, target, physics, calibrate, init, extra, form, split, seed):
    """One ``hxai hybrid fit``: its model file, or None and the last line of its error."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "m.json")
        args = [hxai, "hybrid", "fit", "--data", os.path.join(ROOT, "testdata/real", table),
                "--target", target, "--physics", physics, "--calibrate", calibrate,
                "--init", init, "--form", form, "--seed", str(seed), "--out", out] + extra
        if split:
            args += ["--extrapolate", split]
        r = subprocess.run(args, capture_output=True, text=True)
        if r.returncode != 0:
            return None, r.stderr.strip().splitlines()[-1]
        m = json.load(open(out))
        return m, None


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--hxai", default=os.path.join(ROOT, "target/release/hxai"))
    p.add_argument("--seed", type=int, default=42)
    p.add_argument("--forms", default="auto,free", help="comma list of --form values")
    p.add_argument("--extra", default="", help="more arguments for every hxai hybrid fit")
    a = p.parse_args()
    worst = {}
    for table, target, physics, cal, init, ext, extra in CASES:
        for split in (None, ext):
            for form in a.forms.split(","):
                m, err = fit(a.hxai, table, target, physics, cal, init, extra + a.extra.split(),
                             form, split, a.seed)
                where = f"extrapolate {ext}" if split else "random"
                if m is None:
                    print(f"{table:16} {where:22} {form:6} refused: {err}")
                    continue
                t = m["scores"]["test"]
                ratio = t["hybrid"]["rmse"] / t["physics"]["rmse"]
                eq = m["correction"]["sympy"]
                trig = "sin" in eq or "cos" in eq
                picked = m["correction"].get("form")
                worst[form] = max(worst.get(form, 0.0), ratio)
                print(f"{table:16} {where:22} {form:6} picked {picked:8} hybrid/physics "
                      f"{ratio:6.3f} trig {trig!s:5} correction {eq[:60]}")
    for form, w in worst.items():
        print(f"worst hybrid/physics test RMSE, --form {form}: {w:.3f}")


if __name__ == "__main__":
    main()
