"""Issue 69's simulated case from Python: ``hxai.simulate("spindle_thermal")`` is the
command line's table, value for value, and its settings override as documented."""

import subprocess

import numpy as np
import pandas as pd

import hxai
from conftest import hxai_binary


def test_spindle_thermal_from_python_equals_the_command_line(tmp_path):
    df = hxai.simulate("spindle_thermal")
    assert list(df.columns) == ["run", "time_s", "speed_krpm", "ambient_C", "humidity_pct", "T_C"]
    assert len(df) == 12 * 240 and df.run.nunique() == 12
    out = tmp_path / "s.parquet"
    subprocess.run([hxai_binary(), "simulate", "--case", "spindle_thermal", "--out", str(out)],
                   check=True, capture_output=True)
    cli = pd.read_parquet(out)
    assert list(cli.columns) == list(df.columns)
    np.testing.assert_array_equal(cli.to_numpy(), df.to_numpy())
    small = hxai.simulate("spindle_thermal", n_runs=2, samples_per_run=50, noise_k=0.0)
    assert len(small) == 100
    assert hxai.sim.defaults("spindle_thermal")["forced_convection_per_krpm"] == 0.05
