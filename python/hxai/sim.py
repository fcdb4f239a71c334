"""The simulators as pandas DataFrames."""

import json

import numpy as np
import pandas as pd

from . import _hxai
from ._arrays import from_bytes

CASES = ("tool", "roughness", "cutting_force", "tool_life")


def _jsonable(v):
    if isinstance(v, dict):
        return {k: _jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple, np.ndarray)):
        return [_jsonable(x) for x in v]
    if isinstance(v, np.generic):
        return v.item()
    return v


def defaults(case="tool"):
    """The default settings of a case (a dict), as ``simulate`` accepts them."""
    return json.loads(_hxai.defaults(case))


def simulate(case="tool", n_jobs=None, **settings):
    """Runs a simulator with its defaults overridden by ``settings`` (the Rust
    configuration's field names; see :func:`defaults`) and returns a DataFrame.

    - ``case="tool"``: the slow-tool-servo machine (``hxai simulate``, docs/simulator.md),
      e.g. ``simulate(amplitudes_um=[5.0], frequencies_hz=[20.0], repeats=1, fs_hz=2000.0)``.
      One row per sample: ``record``, ``amplitude_um``, ``frequency_hz``, ``repeat``,
      ``fs_hz``, ``time_s``, ``accel_ms2``, ``probe_um``, ``command_um``, ``encoder_um``.
    - ``case="roughness"``, ``"cutting_force"`` or ``"tool_life"``: the table cases
      (``hxai simulate --case``, docs/cases.md), e.g. ``simulate("roughness", n_rows=200,
      seed=1)``; one row per cut (per tool-life test for ``tool_life``).
    - ``case="spindle_thermal"``: a spindle's thermal drift (issue 69), one row per sample of
      ``n_runs`` runs of ``samples_per_run`` samples: ``run``, ``time_s``, the inputs
      ``speed_krpm`` and ``ambient_C``, a distractor ``humidity_pct`` and the measured
      ``T_C``.

    ``n_jobs``: threads that simulate the tool case's records (``None``, the default: every
    core; ``-1``: every core in a pool of its own; a positive int: that many); the table
    cases run on one thread. The result never depends on it.
    """
    overrides = json.dumps(_jsonable(settings))
    if case == "tool":
        parts = []
        for rid, amp, freq, rep, fs, t, a, p, c, e in _hxai.simulate_tool(overrides, n_jobs):
            t = from_bytes(t)
            n = len(t)
            parts.append(
                pd.DataFrame(
                    {
                        "record": [rid] * n,
                        "amplitude_um": np.full(n, amp),
                        "frequency_hz": np.full(n, freq),
                        "repeat": np.full(n, rep, dtype=np.int64),
                        "fs_hz": np.full(n, fs),
                        "time_s": t,
                        "accel_ms2": from_bytes(a),
                        "probe_um": from_bytes(p),
                        "command_um": from_bytes(c),
                        "encoder_um": from_bytes(e),
                    }
                )
            )
        return pd.concat(parts, ignore_index=True)
    names, cols = _hxai.simulate_case(str(case), overrides)
    return pd.DataFrame({n: from_bytes(c) for n, c in zip(names, cols)})
