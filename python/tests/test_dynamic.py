"""``hxai.DynamicRegressor`` (issue 69): the command line's ``hxai dynamic`` from Python, on
the simulated spindle: the same model file, predictions from each run's first reading,
a band, the comparison's frame, and settings refused by name."""

import json
import subprocess

import numpy as np
import pandas as pd
import pytest

import hxai
from conftest import hxai_binary

ODE = "T_C' = (q*speed_krpm^1.5 - h*(T_C - ambient_C))/C"
SETTINGS = dict(ode=ODE, states="T_C", time="time_s", run="run",
                inputs=["speed_krpm", "ambient_C", "humidity_pct"], calibrate=["q", "h"],
                init={"q": 30, "h": 8}, set={"C": 20000}, form="factors")


@pytest.fixture(scope="module")
def spindle():
    return hxai.simulate("spindle_thermal", n_runs=4, samples_per_run=160)


def test_fit_equals_the_command_line_and_predicts(spindle, tmp_path):
    m = hxai.DynamicRegressor(**SETTINGS, conformal_folds=4).fit(spindle)
    data = tmp_path / "s.csv"
    spindle.to_csv(data, index=False)
    out = tmp_path / "m.json"
    subprocess.run([hxai_binary(), "dynamic", "fit", "--data", str(data), "--time", "time_s",
                    "--run", "run", "--state", "T_C", "--inputs",
                    "speed_krpm,ambient_C,humidity_pct", "--ode", ODE, "--calibrate", "q,h",
                    "--init", "q=30,h=8", "--set", "C=20000", "--form", "factors",
                    "--conformal-folds", "4", "--out", str(out)],
                   check=True, capture_output=True)
    cli = json.loads(out.read_text())
    assert cli["hybrid_equation"] == m.equation_
    assert "speed_krpm" in m.corrections_["T_C"]
    p = m.predict(spindle, interval=0.75)
    assert list(p.columns) == ["T_C_physics", "T_C_hybrid", "T_C_lo", "T_C_hi"]
    first = spindle.groupby("run").head(1).index
    np.testing.assert_array_equal(p.loc[first, "T_C_hybrid"], spindle.loc[first, "T_C"])
    assert (p.T_C_lo < p.T_C_hybrid).all() and (p.T_C_hybrid < p.T_C_hi).all()
    rmse = lambda c: float(np.sqrt(((p[c] - spindle.T_C) ** 2).mean()))
    assert rmse("T_C_hybrid") < 0.5 * rmse("T_C_physics")


def test_compare_returns_the_four_models(spindle):
    frame = hxai.DynamicRegressor(**SETTINGS).compare(spindle, test_runs=[2])
    assert list(frame.model) == ["physics", "physics_calibrated", "hybrid", "narx_boosting"]
    assert frame.rmse.notna().all()
    assert frame.attrs["json"]["test_runs"] == [2.0]
    assert set(frame.attrs["json"]["hybrid"]["correction"]) == {"equation", "features"}


@pytest.mark.parametrize("change, says", [
    (dict(form="wavy"), "form="),
    (dict(ode="T_C' = k*T_C"), "k in"),
    (dict(time="t"), "no column t"),
    (dict(initial="guess"), "initial="),
])
def test_bad_settings_are_refused(spindle, change, says):
    with pytest.raises(ValueError, match=says):
        hxai.DynamicRegressor(**{**SETTINGS, **change}).fit(spindle)


def test_predict_before_fit_is_refused(spindle):
    with pytest.raises(ValueError, match="fit before predict"):
        hxai.DynamicRegressor(**SETTINGS).predict(spindle)


def test_text_run_names_hold_runs_out(spindle):
    named = spindle.assign(run=spindle.run.map(lambda r: f"batch-{int(r)}"))
    frame = hxai.DynamicRegressor(**{**SETTINGS, "form": "none"}).compare(
        named, test_runs=["batch-3"])
    # batch-3 is the third run to appear: its number is 2
    assert frame.attrs["json"]["test_runs"] == [2.0]
    with pytest.raises(ValueError, match="no run batch-9"):
        hxai.DynamicRegressor(**SETTINGS).compare(named, test_runs=["batch-9"])


def test_report_and_card(spindle, tmp_path):
    m = hxai.DynamicRegressor(**SETTINGS, conformal_folds=0).fit(spindle)
    card = m._repr_html_()
    assert "<math" in card and "Calibrated physics" in card
    page = tmp_path / "dyn.html"
    assert m.report(page, spindle) == str(page)
    html = page.read_text()
    assert 'id="hybrid-equation"' in html and "<svg" in html
    assert "http:" not in html and "https:" not in html
    assert "hxai dynamic fit --data" in html
    assert hxai.DynamicRegressor(**SETTINGS)._repr_html_() is None
