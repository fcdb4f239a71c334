"""Plots of issue 49's closed loop (`scripts/design_loop.py --loop`): for each process, the
share of resamples with the truth's columns (mean over seeds), the test RMSE on 2,000 fresh
runs and each physics parameter's 95 % interval width (medians over seeds) against the
number of runs, one line per arm (runs chosen by `hxai hybrid design`, uniform random runs,
a Latin hypercube).

    python3 scripts/design_loop_plot.py LOOP.jsonl [LOOP2.jsonl ...] --out DIR

Writes DIR/design_loop_PROCESS.svg (one figure per process) and DIR/design_loop_tables.md (the
tables of `design_loop.loop_summary`). Needs numpy and matplotlib. The SVGs carry no date,
so the same lines give the same files.
"""
import argparse
import importlib.util
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
_spec = importlib.util.spec_from_file_location("design_loop", HERE / "design_loop.py")
loop = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(loop)

LABELS = {"design": "hxai hybrid design", "random": "uniform random", "lhs": "Latin hypercube"}
STYLES = {"design": ("#c0392b", "o"), "random": ("#7f8c8d", "s"), "lhs": ("#2471a3", "^")}


def series(rows, arm, value):
    """(row counts, the per-count statistic `value(list of lines)`) of one arm."""
    counts = sorted({r["rows"] for r in rows if r["arm"] == arm})
    return counts, [value([r for r in rows if r["arm"] == arm and r["rows"] == c])
                    for c in counts]


def plot(name, rows, path):
    import matplotlib
    matplotlib.use("svg")
    import matplotlib.pyplot as plt
    plt.rcParams["svg.hashsalt"] = "hxai-design-loop"
    params = sorted({p for r in rows for p in r["widths"]})
    panels = [("share of resamples with the truth's columns (mean)",
               lambda rs: float(np.mean([r["share"] for r in rs]))),
              ("test RMSE, 2,000 fresh runs (median)",
               lambda rs: float(np.nanmedian([np.nan if r["rmse"] is None else r["rmse"]
                                              for r in rs])))]
    for p in params:
        panels.append((f"95 % interval width of {p} (median)",
                       lambda rs, p=p: float(np.nanmedian(
                           [np.nan if r["widths"].get(p) is None else r["widths"][p]
                            for r in rs]))))
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 3.4))
    for ax, (title, value) in zip(np.atleast_1d(axes), panels):
        for arm in loop.ARMS:
            x, y = series(rows, arm, value)
            colour, marker = STYLES[arm]
            ax.plot(x, y, marker=marker, color=colour, label=LABELS[arm])
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("runs")
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].legend(fontsize=8)
    seeds = len({r["seed"] for r in rows})
    fig.suptitle(f"{name}: runs added by design, at random and by a Latin hypercube "
                 f"({seeds} seeds)", fontsize=10)
    fig.tight_layout()
    tmp = path.with_suffix(".svg.tmp")
    fig.savefig(tmp, format="svg", metadata={"Date": None})
    plt.close(fig)
    tmp.replace(path)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("jsonl", nargs="+")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = [json.loads(x) for f in a.jsonl for x in Path(f).read_text().splitlines() if x]
    if not rows:
        raise SystemExit("no lines in " + ", ".join(a.jsonl))
    for name in dict.fromkeys(r["process"] for r in rows):
        plot(name, [r for r in rows if r["process"] == name], out / f"design_loop_{name}.svg")
    tmp = out / "design_loop_tables.md.tmp"
    tmp.write_text(loop.loop_summary(rows).lstrip() + "\n")
    tmp.replace(out / "design_loop_tables.md")


if __name__ == "__main__":
    main()
