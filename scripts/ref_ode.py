"""Reference vectors of issue 69's integrator (`crates/sim/src/ode.rs`): three ODEs solved by
scipy's `solve_ivp` with `DOP853` at rtol 1e-13, atol 1e-14, written to
`testdata/ode/solve_ivp.json`; the Rust test integrates them with its Dormand-Prince 5(4) and
compares to 1e-8.

    python3 scripts/ref_ode.py

- `van_der_pol`: x'' = mu (1 - x^2) x' - x, mu = 1, from (2, 0), at t = 0, 0.5, ..., 10;
- `lotka_volterra`: x' = 1.5 x - x y, y' = -3 y + x y, from (10, 5), at t = 0, 0.5, ..., 15;
- `thermal_held`: T' = (q u^1.5 - h (T - Ta)) / C with q 2, h 0.5, Ta 20, C 10, from T 25,
  the input u held between samples (u_k = 1 + ((7 k) mod 5) / 2 on [k, k + 1)), integrated
  interval by interval, at t = 1, ..., 30.
"""
import json
import os

import numpy as np
import scipy
from scipy.integrate import solve_ivp

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOL = dict(method="DOP853", rtol=1e-13, atol=1e-14)


def van_der_pol():
    t = np.arange(0, 10.0001, 0.5)
    r = solve_ivp(lambda t, y: [y[1], (1 - y[0] ** 2) * y[1] - y[0]], (0, 10), [2.0, 0.0],
                  t_eval=t, **TOL)
    return {"t0": 0.0, "y0": [2.0, 0.0], "times": t.tolist(), "states": r.y.T.tolist()}


def lotka_volterra():
    t = np.arange(0, 15.0001, 0.5)
    r = solve_ivp(lambda t, y: [1.5 * y[0] - y[0] * y[1], -3 * y[1] + y[0] * y[1]], (0, 15),
                  [10.0, 5.0], t_eval=t, **TOL)
    return {"t0": 0.0, "y0": [10.0, 5.0], "times": t.tolist(), "states": r.y.T.tolist()}


def thermal_held():
    q, h, ta, c = 2.0, 0.5, 20.0, 10.0
    u = [1 + ((7 * k) % 5) / 2 for k in range(30)]
    y, states = [25.0], []
    for k in range(30):
        r = solve_ivp(lambda t, s, uk=u[k]: [(q * uk ** 1.5 - h * (s[0] - ta)) / c],
                      (k, k + 1), y, **TOL)
        y = [float(r.y[0, -1])]
        states.append(y)
    return {"t0": 0.0, "y0": [25.0], "inputs": u, "times": list(range(1, 31)),
            "states": states}


def main():
    doc = {
        "generator": f"scripts/ref_ode.py, scipy {scipy.__version__}, solve_ivp DOP853 "
                     "rtol 1e-13 atol 1e-14",
        "van_der_pol": van_der_pol(),
        "lotka_volterra": lotka_volterra(),
        "thermal_held": thermal_held(),
    }
    out = os.path.join(ROOT, "testdata", "ode", "solve_ivp.json")
    tmp = out + ".tmp"
    with open(tmp, "w") as fh:
        json.dump(doc, fh, indent=1)
    os.replace(tmp, out)
    print(out)


if __name__ == "__main__":
    main()
