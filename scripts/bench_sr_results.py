"""The results files of `bench_sr_suite.py` (one JSON row per problem, engine and noise
level): written atomically, and summarised (`--table FILE...`: one row per suite, engine,
noise level and half; with `--pairs` the engines' discordant problems and McNemar's test).
Split from bench_sr_suite.py, which runs the suites."""
import json
import math
import os
import tempfile

import numpy as np


def atomic_write(path, rows):
    d = os.path.dirname(os.path.abspath(path))
    os.makedirs(d, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=d, prefix=".tmp-", suffix=".json")
    with os.fdopen(fd, "w") as fh:
        for r in rows:
            fh.write(json.dumps(r) + "\n")
    os.replace(tmp, path)


def load_rows(paths):
    """The rows of results files; a problem run again (same suite, engine and noise) in a
    later row or file is ignored, the first row counts. Returns (rows, number ignored)."""
    rows, seen, dup = [], set(), 0
    for path in paths:
        with open(path) as fh:
            for r in (json.loads(l) for l in fh if l.strip()):
                key = (r.get("suite", "feynman"), r["engine"], r["number"], r["noise"])
                if key in seen:
                    dup += 1
                    continue
                seen.add(key)
                rows.append(r)
    return rows, dup


def accurate(r, above=0.999):
    """Whether a row's test R^2 is above `above` (a failed row has none: not accurate)."""
    return (r.get("r2_test") or -1) > above


def solved(r, kind):
    """Whether a row solves its problem: exactly (`kind` "exact") or to R^2 > 0.999."""
    return bool(r.get("exact")) if kind == "exact" else accurate(r)


def pairs(rows):
    """For each two engines at the same noise level, on the problems both ran: the problems
    only one of them solves (exact, and R^2 > 0.999 on the test rows), by Number, and the
    exact McNemar test's p on those discordant problems. This is what says whether a
    strategy earns its place beside another: the counts of the summary table can be equal
    while the problems differ, and a difference of a few problems on one seed can be
    chance."""
    def mcnemar(b, c):
        """Two-sided exact McNemar p: how likely a split of the b + c discordant problems
        at least this uneven is when neither engine is better (each side p = 1/2)."""
        n = b + c
        if n == 0:
            return 1.0
        tail = sum(math.comb(n, k) for k in range(min(b, c) + 1)) / 2 ** n
        return min(1.0, 2 * tail)

    by = {}
    for r in rows:
        by.setdefault((r["engine"], r["noise"]), {})[r["number"]] = r
    engines = list(dict.fromkeys(r["engine"] for r in rows))
    print("| noise | A | B | common | exact: A only | exact: B only | McNemar p | "
          "R^2 > 0.999: A only | R^2 > 0.999: B only | McNemar p |")
    print("|---|---|---|---:|---|---|---:|---|---|---:|")
    for z in sorted({r["noise"] for r in rows}):
        for i, a in enumerate(engines):
            for b in engines[i + 1:]:
                ra, rb = by.get((a, z), {}), by.get((b, z), {})
                common = sorted(set(ra) & set(rb))
                if not common:
                    continue
                cells = []
                for kind in ("exact", "r2"):
                    counts = []
                    for x, y in ((ra, rb), (rb, ra)):
                        only = [n for n in common if solved(x[n], kind) and not solved(y[n], kind)]
                        counts.append(len(only))
                        cells.append(f"{len(only)}" + (f" ({', '.join(map(str, only))})" if only else ""))
                    cells.append(f"{mcnemar(*counts):.2g}")
                print(f"| {z:g} | {a} | {b} | {len(common)} | " + " | ".join(cells) + " |")


def table(paths, with_pairs=False):
    rows, dup = load_rows(paths)
    if dup:
        print(f"({dup} repeated rows ignored: the first of each counts)")
    print("| suite | engine | noise | half | problems | failed | exact | exact % | sympy timeouts | "
          "R^2 > 0.999 | R^2 > 0.99 | median s | total s | median CPU s | total CPU s | load |")
    print("|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    suite_of = lambda r: r.get("suite", "feynman")
    groups = list(dict.fromkeys((suite_of(r), r["engine"]) for r in rows))
    for sname, eng in groups:
        mine = [r for r in rows if suite_of(r) == sname and r["engine"] == eng]
        for z in sorted({r["noise"] for r in mine}):
            # odd/even halves only mean something for the AI Feynman suite (tuned on odd)
            for half in ("odd", "even", "all") if sname == "feynman" else ("all",):
                rs = [r for r in mine if r["noise"] == z
                      and (half == "all" or r["half"] == half)]
                if not rs:
                    continue
                n = len(rs)
                fail = sum(1 for r in rs if "error" in r)
                ex = sum(1 for r in rs if solved(r, "exact"))
                to = sum(1 for r in rs if r.get("exact_timeout"))
                r3 = sum(1 for r in rs if solved(r, "r2"))
                r2_ = sum(1 for r in rs if accurate(r, 0.99))
                secs = [r["seconds"] for r in rs if "seconds" in r]
                cpus = [r["cpu_seconds"] for r in rs if "cpu_seconds" in r]
                cpu = f"{np.median(cpus):.1f} | {sum(cpus):.0f}" if cpus else "- | -"
                loads = [r["load1"] for r in rs if "load1" in r]
                load = f"{min(loads):.1f}-{max(loads):.1f}" if loads else ""
                print(f"| {sname} | {eng} | {z:g} | {half} | {n} | {fail} | {ex} | {100 * ex / n:.0f} | {to} | "
                      f"{r3} | {r2_} | {np.median(secs):.1f} | {sum(secs):.0f} | {cpu} | {load} |")
    if with_pairs:
        print()
        pairs(rows)
