#!/usr/bin/env python3
"""Markdown tables from the results.json files written by scripts/bench_sr_run.py (that is,
`cargo xtask bench-sr`). Later files override earlier ones for the same engine, problem and
noise, so a rerun of one engine can be merged with a full run.

Usage: python3 scripts/bench_sr_table.py target/bench-sr/results.json [more.json ...]
"""
import json, sys
from statistics import median

rows = {}
for path in sys.argv[1:]:
    for r in json.load(open(path)):
        rows[(r["engine"], r["problem"], r["noise"])] = r
engines = []
for (e, _, _) in rows:
    if e not in engines:
        engines.append(e)
problems = []
for (_, p, _) in rows:
    if p not in problems:
        problems.append(p)
noises = sorted({n for (_, _, n) in rows})

print("| engine | noise | problems | exact | median test R^2 | median size | total s | median s |")
print("|---|---|---|---|---|---|---|---|")
for e in engines:
    for n in noises:
        rs = [rows[k] for k in rows if k[0] == e and k[2] == n]
        ok = [r for r in rs if "error" not in r]
        if not rs:
            continue
        ex = sum(1 for r in ok if r.get("exact"))
        m = lambda k: median([r[k] for r in ok]) if ok else float("nan")
        tot = sum(r["seconds"] for r in ok)
        err = f" ({len(rs) - len(ok)} failed)" if len(ok) < len(rs) else ""
        print(f"| {e} | {n:g} | {len(rs)}{err} | {ex} | {m('r2_test'):.6f} | {m('size'):.0f} | {tot:.0f} | {m('seconds'):.1f} |")

print()
head = " | ".join(f"{e}" for e in engines)
print(f"| problem | noise | {head} |")
print("|---|---|" + "---|" * len(engines))
for p in problems:
    for n in noises:
        cells = []
        for e in engines:
            r = rows.get((e, p, n))
            if r is None:
                cells.append("")
            elif "error" in r:
                cells.append("error")
            else:
                mark = "**exact**" if r.get("exact") else f"{r['r2_test']:.5f}"
                cells.append(f"{mark}, {r['seconds']:.0f} s")
        print(f"| {p} | {n:g} | " + " | ".join(cells) + " |")
