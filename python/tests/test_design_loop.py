"""The design loop's Latin hypercube arm (scripts/design_loop.py, issue 49): one run per
stratum of every column, inside the space, on a stepped column's levels, seeded."""

import importlib.util
import sys

import pytest

from conftest import ROOT

np = pytest.importorskip("numpy")

sys.path.insert(0, str(ROOT / "scripts"))
_spec = importlib.util.spec_from_file_location("design_loop", ROOT / "scripts" / "design_loop.py")
loop = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(loop)


def test_latin_hypercube_puts_one_run_in_each_stratum_of_every_column():
    n = 10
    runs = loop.latin_hypercube("feed=0.05:0.3,speed=80:300", n, np.random.default_rng(3))
    for name, (lo, hi) in {"feed": (0.05, 0.3), "speed": (80.0, 300.0)}.items():
        v = runs[name]
        assert len(v) == n
        assert np.all((v >= lo) & (v <= hi))
        strata = np.floor((v - lo) / (hi - lo) * n).astype(int)
        assert sorted(strata) == list(range(n)), name
    # the strata are paired at random, not in the same order in both columns
    assert not np.array_equal(np.argsort(runs["feed"]), np.argsort(runs["speed"]))
    # the same seed gives the same runs
    again = loop.latin_hypercube("feed=0.05:0.3,speed=80:300", n, np.random.default_rng(3))
    assert all(np.array_equal(runs[k], again[k]) for k in runs)


def test_a_stepped_column_takes_its_levels():
    runs = loop.latin_hypercube("t=100:200:25", 5, np.random.default_rng(1))
    assert set(runs["t"]) <= {100.0, 125.0, 150.0, 175.0, 200.0}
    # the run of the lowest stratum (100-120) is at 100 or 125, of the highest (180-200) at
    # 175 or 200: the levels nearest the stratum
    assert min(runs["t"]) in (100.0, 125.0) and max(runs["t"]) in (175.0, 200.0)


def test_a_refused_fit_is_recorded_where_the_loop_tolerates_it():
    # a command that fails: the loop's fits raise FitFailed (left out of the medians and
    # named at the end); every other command still stops the loop with its message
    cmd = [sys.executable, "-c", "import sys; sys.stderr.write('no value'); sys.exit(2)"]
    with pytest.raises(loop.FitFailed, match="no value"):
        loop.run(cmd, tolerate=True)
    with pytest.raises(SystemExit, match="no value"):
        loop.run(cmd)
    assert loop.run([sys.executable, "-c", "print('ok')"]).strip() == "ok"


def test_the_loops_tool_life_truth_is_the_simulators():
    # the loop measures a proposed run with its own copy of the tool-life case's truth; it
    # must be the simulator's, setting for setting (scatter off; relative 1e-12)
    hxai = pytest.importorskip("hxai")
    df = hxai.simulate("tool_life", n_rows=50, seed=4, noise_rel=0.0)
    settings = {c: df[c].to_numpy() for c in ("cutting_speed_m_min", "feed_mm")}
    np.testing.assert_allclose(loop.tool_life_truth(settings), df["tool_life_min"].to_numpy(),
                               rtol=1e-12)
    # and the loop's space is the simulator's ranges
    space = loop.ranges(loop.TOOL_LIFE["space"])
    for c in ("cutting_speed_m_min", "feed_mm", "coolant_temp_C", "workpiece_diameter_mm"):
        lo, hi, _ = space[c]
        assert lo <= df[c].min() and df[c].max() <= hi, c


def test_the_loop_summary_tabulates_each_arm_by_rows():
    rows = [dict(process="p", seed=s, arm=arm, rows=n, share=share, rmse=1.0 + s,
                 widths={"k": 2.0}, alternatives=1)
            for s in range(2) for arm in loop.ARMS for n, share in ((60, 0.2), (70, 0.4 + s))]
    text = loop.loop_summary(rows)
    line = next(x for x in text.splitlines() if x.startswith("| random | share"))
    # the mean over the two seeds at 70 rows is (0.4 + 1.4) / 2
    assert line.split("|")[4].strip() == "0.90"
    assert "| design | test RMSE (median) | 1.5 | 1.5 |" in text
    # the goals: after one designed round (70 rows) the share is the random runs' at the
    # last count (0.90 both: met); equal widths give the ratio 1 (goal 0.7: missed)
    goal = next(x for x in text.splitlines() if x.startswith("| p | "))
    assert goal.startswith("| p | 0.90 | 0.90 | met | k | 1.00 (2 seeds) | missed | 2 of 2 |")
