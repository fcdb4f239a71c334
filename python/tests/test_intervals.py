"""Prediction intervals of the estimators (issue 28): conformal by default, the same
bounds as the command line for the same model file, and coverage near the level on rows
drawn like the training rows."""

import subprocess

import numpy as np
import pandas as pd
import pytest

import hxai
from conftest import FAST, TAYLOR, hxai_binary
from hxai import HybridRegressor, SymbolicRegressor


def _line(n, seed):
    """y = 2 a + 1 + N(0, 0.3 (1 + a)): scatter that grows with a."""
    rng = np.random.default_rng(seed)
    a = rng.uniform(0.0, 3.0, n)
    y = 2.0 * a + 1.0 + rng.normal(0.0, 0.3 * (1.0 + a))
    return pd.DataFrame({"a": a}), pd.Series(y, name="y")


def test_symbolic_regressor_interval_covers_fresh_rows():
    X, y = _line(400, 1)
    m = SymbolicRegressor(max_complexity=4, **FAST).fit(X, y)
    Xt, yt = _line(4000, 2)
    for method, level in [("conformal", 0.95), ("split", 0.9), ("delta", 0.95)]:
        iv = m.predict_interval(Xt, level=level, method=method)
        assert iv.shape == (4000, 2)
        assert m.interval_method_ == method
        assert np.all(iv[:, 0] < iv[:, 1])
        cover = np.mean((iv[:, 0] <= yt) & (yt <= iv[:, 1]))
        if method != "delta":
            # conformal: within 3 standard errors of the level, the calibration's 400 rows
            # (training-set conditional coverage) and the 4000 test rows together
            se = np.sqrt(level * (1 - level) * (1 / 400 + 1 / 4000))
            assert abs(cover - level) <= 3 * se, (method, cover)
    # the default is conformal, and its width follows the scatter: wider where a is large
    iv = m.predict_interval(Xt)
    assert m.interval_method_ == "conformal"
    width = iv[:, 1] - iv[:, 0]
    a = Xt["a"].to_numpy()
    assert np.median(width[a > 2.5]) > 1.5 * np.median(width[a < 0.5])


def test_symbolic_regressor_without_folds_falls_back_to_delta():
    X, y = _line(200, 3)
    m = SymbolicRegressor(max_complexity=4, conformal_folds=0, **FAST).fit(X, y)
    iv = m.predict_interval(X)
    assert m.interval_method_ == "delta"
    assert iv.shape == (200, 2)
    with pytest.raises(ValueError, match="delta"):
        m.predict_interval(X, method="conformal")
    with pytest.raises(ValueError, match="conformal_folds"):
        SymbolicRegressor(conformal_folds=1, **FAST).fit(X, y)
    with pytest.raises(ValueError, match="level"):
        m.predict_interval(X, level=1.5)
    with pytest.raises(ValueError, match="interval method"):
        m.predict_interval(X, method="bootstrap")


def test_hybrid_interval_equals_the_cli(tmp_path):
    binary = hxai_binary()
    df = hxai.simulate("tool_life", n_rows=200, seed=3)
    y = df.pop("tool_life_min")
    X = df.drop(columns=["tool"])
    m = HybridRegressor(
        **TAYLOR, init={"C": 400.0, "n": 0.25}, features=["feed_mm"], **FAST
    ).fit(X, y)
    iv = m.predict_interval(X)
    assert m.interval_method_ == "conformal"
    pred = m.predict(X)
    assert np.all((iv[:, 0] < pred) & (pred < iv[:, 1]))
    # log-scale scores: the band is wider in absolute terms where the life is long
    width = iv[:, 1] - iv[:, 0]
    assert np.corrcoef(width, pred)[0, 1] > 0.9
    model = tmp_path / "m.json"
    model.write_text(m.model_json_)
    table = tmp_path / "x.csv"
    X.to_csv(table, index=False)
    for method in ("conformal", "split", "delta"):
        out = tmp_path / f"p_{method}.csv"
        subprocess.run(
            [binary, "hybrid", "predict", "--model", str(model), "--data", str(table),
             "--out", str(out), "--interval", "0.9", "--interval-method", method],
            check=True, capture_output=True,
        )
        cli = pd.read_csv(out)
        ours = m.predict_interval(X, level=0.9, method=method)
        np.testing.assert_allclose(ours[:, 0], cli["hybrid_lo"], rtol=1e-9)
        np.testing.assert_allclose(ours[:, 1], cli["hybrid_hi"], rtol=1e-9)
