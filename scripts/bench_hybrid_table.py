"""Writes the 1,000 rows x 8 columns table of the `hxai hybrid fit` timing in docs/benchmarks.md.

A turning-like process (stdlib only, seeded): feed f, nose radius r, speed v, depth ap, wear
VB, two distractors, and the target Ra = kinematic law + speed and wear effects + scatter.
Usage: python3 scripts/bench_hybrid_table.py OUT.csv
"""
import random
import sys

rng = random.Random(42)
with open(sys.argv[1], "w") as out:
    out.write("f,r,v,ap,VB,d1,d2,Ra\n")
    for _ in range(1000):
        f = rng.uniform(0.05, 0.3)
        r = rng.uniform(0.4, 1.6)
        v = rng.uniform(60.0, 300.0)
        ap = rng.uniform(0.2, 2.0)
        vb = rng.uniform(0.0, 0.3)
        d1 = rng.uniform(0.0, 1.0)
        d2 = rng.gauss(0.0, 1.0)
        ra = 1.2 * f * f / (32 * r) * (1 + 2.0 * vb) + 0.4 / v + rng.gauss(0.0, 2e-4)
        out.write(f"{f},{r},{v},{ap},{vb},{d1},{d2},{ra}\n")
