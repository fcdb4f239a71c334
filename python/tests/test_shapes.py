"""Issue 68 from Python: ``HybridRegressor(monotone=..., shapes=...)`` respects a monotone
constraint on a grid, takes the threshold shapes when asked, and refuses bad settings."""

import numpy as np
import pandas as pd
import pytest

from hxai import HybridRegressor


def _dip(n=300, seed=11):
    """``y = 2 x (1 + 0.05 (z - 5)^2)`` with 1 % noise: a correction that falls, then
    rises, in ``z``."""
    rng = np.random.default_rng(seed)
    x, z = rng.uniform(1, 10, n), rng.uniform(0, 10, n)
    y = 2 * x * (1 + 0.05 * (z - 5) ** 2) * (1 + rng.uniform(-0.01, 0.01, n))
    return pd.DataFrame({"x": x, "z": z}), pd.Series(y, name="y")


def _rises_in_z(model, lo, hi):
    z = np.linspace(lo, hi, 201)
    parts = model.predict_parts(pd.DataFrame({"x": np.full(201, 5.0), "z": z}))
    c = np.asarray(parts["correction"])
    return bool(np.all(np.diff(c) >= -1e-9 * (1 + np.abs(c[:-1]))))


def test_a_monotone_constraint_holds_on_a_grid():
    X, y = _dip()
    # a harmonic in z can follow the dip (every other one-column shape is monotone)
    common = dict(calibrate=["k"], correction="multiplicative", conformal_folds=0,
                  periodic=["z"])
    free = HybridRegressor("k*x", form="factors", **common).fit(X, y)
    assert not _rises_in_z(free, X.z.min(), X.z.max()), free.equation_
    m = HybridRegressor("k*x", form="auto", monotone={"z": "+"}, **common).fit(X, y)
    assert _rises_in_z(m, X.z.min(), X.z.max()), m.equation_
    assert m.choice_["picked"] in ("none", "factors")
    m1 = HybridRegressor("k*x", form="factors", monotone={"z": 1}, **common).fit(X, y)
    assert m1.equation_ == HybridRegressor(
        "k*x", form="factors", monotone={"z": "+"}, **common
    ).fit(X, y).equation_


def test_the_threshold_shapes_are_taken_when_asked():
    rng = np.random.default_rng(3)
    x, z = rng.uniform(1, 10, 400), rng.uniform(0, 10, 400)
    y = 3 * x + 0.8 * np.maximum(z - 6, 0) + rng.normal(0, 0.1, 400)
    X = pd.DataFrame({"x": x, "z": z})
    m = HybridRegressor("k*x", calibrate=["k"], form="factors", shapes="all",
                        conformal_folds=0).fit(X, pd.Series(y, name="y"))
    shapes = {f.get("column"): f["shape"] for f in m.factors_}
    assert shapes.get("z") == "hinge", m.factors_


def test_the_factor_form_takes_the_consensus():
    rng = np.random.default_rng(12)
    x, z = rng.uniform(1, 10, 200), rng.uniform(0, 10, 200)
    y = 2 * x * (1 + 0.1 * z) * (1 + rng.uniform(-0.01, 0.01, 200))
    X, y = pd.DataFrame({"x": x, "z": z}), pd.Series(y, name="y")
    common = dict(calibrate=["k"], correction="multiplicative", conformal_folds=0,
                  form="factors")
    plain = HybridRegressor("k*x", **common).fit(X, y)
    assert plain.selection_["runs"] is None
    m = HybridRegressor("k*x", consensus_runs=4, **common).fit(X, y)
    sel = m.selection_
    assert sel["runs"] == 4 and 0.5 < sel["share"] <= 1.0, sel
    assert any(f.get("column") == "z" for f in m.factors_), m.factors_


@pytest.mark.parametrize(
    "kwargs, says",
    [
        (dict(monotone={"z": "up"}), "monotone"),
        (dict(monotone=["z"]), "monotone"),
        (dict(shapes="spline"), "shapes"),
        (dict(interactions=-1), "interactions"),
        (dict(interactions=1.5), "interactions"),
        (dict(monotone={"z": "+"}, form="free"), r"monotone= with form= free"),
        (dict(monotone={"w": "+"}), "not a feature"),
    ],
)
def test_bad_settings_are_refused(kwargs, says):
    X, y = _dip(60)
    with pytest.raises(ValueError, match=says):
        HybridRegressor("k*x", calibrate=["k"], conformal_folds=0, **kwargs).fit(X, y)


def test_compare_shows_ebm_beside_boosting_or_says_why_not(monkeypatch, tmp_path):
    X, y = _dip(200)
    est = HybridRegressor("k*x", calibrate=["k"], correction="multiplicative",
                          form="factors", conformal_folds=0)
    frame = est.compare(X, y, folds=0)
    models = list(frame["model"])
    pytest.importorskip("interpret")
    assert "ebm" in models and "boosting" in models, models
    ebm = frame[frame.model == "ebm"].iloc[0]
    assert np.isfinite(ebm.rmse) and ebm.rmse > 0 and 0 <= ebm.p_value <= 1
    assert "ExplainableBoostingRegressor" in frame.attrs["ebm"]
    # the EBM row reproduces interpret's own fit on the same rows
    from interpret.glassbox import ExplainableBoostingRegressor

    doc = __import__("json").loads(frame.attrs["json"])["hybrid"]["split"]
    tr, te = doc["train"], doc["test"]
    ref = ExplainableBoostingRegressor(random_state=42).fit(X.iloc[tr], y.iloc[tr])
    rmse = float(np.sqrt(np.mean((ref.predict(X.iloc[te]) - y.iloc[te]) ** 2)))
    assert abs(rmse - ebm.rmse) <= 1e-9 * rmse
    # the comparison's JSON holds it too, so the report's comparison table shows it
    names = [m["name"] for m in __import__("json").loads(frame.attrs["json"])["models"]]
    assert names.index("ebm") == names.index("hybrid") - 1
    page = est.fit(X, y).report(tmp_path / "r.html", compare=frame)
    assert ">ebm<" in open(page, encoding="utf-8").read()
    # without interpret the frame says so and has no such row
    import builtins

    real = builtins.__import__

    def no_interpret(name, *a, **k):
        if name.startswith("interpret"):
            raise ImportError(name)
        return real(name, *a, **k)

    monkeypatch.setattr(builtins, "__import__", no_interpret)
    frame = est.compare(X, y, folds=0)
    assert "ebm" not in list(frame["model"])
    assert "not installed" in frame.attrs["ebm"]
