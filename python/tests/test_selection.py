"""Readable equations: nesting constraints, consensus selection and the selection report
(`selection_`), as docs/python.md describes them."""
import json

import pytest

import hxai
from hxai import HybridRegressor, SymbolicRegressor
from hxai._hxai import defaults
from conftest import FAST, TAYLOR

TRANSCENDENTAL = ("exp(", "log(", "sin(", "cos(", "tanh(")


def test_every_nesting_form_is_read_and_a_bad_one_refused(quadratic):
    X, y = quadratic
    for form in ("none", "readable", "strict", "readable,exp:log=0", {"exp": {"exp": 0}}):
        est = SymbolicRegressor(**FAST, nesting=form).fit(X, y)
        assert est.selection_["method"] == "mdl"
        assert est.selection_["share"] is None
    with pytest.raises(ValueError, match="nesting"):
        SymbolicRegressor(**FAST, nesting="exp:exp").fit(X, y)
    with pytest.raises(ValueError, match="nesting"):
        SymbolicRegressor(**FAST, nesting=3).fit(X, y)
    # the engine's own default is no constraint, which `none` names
    assert json.loads(defaults("search"))["nesting"] == {}


def test_a_correction_is_readable_and_consensus_reports_its_share():
    X = hxai.simulate("roughness", n_rows=160, seed=5)
    y = X.pop("Ra_um")
    est = HybridRegressor(
        "1000*feed_mm^2/(32*nose_radius_mm) + Ra0",
        calibrate=["Ra0"],
        init={"Ra0": 0.0},
        correction="multiplicative",
        exclude=["tool"],
        consensus_runs=3,
        # consensus selection is the free form's (form="auto" may pick the factors here)
        form="free",
        **FAST,
    ).fit(X, y)
    sel = est.selection_
    assert sel["method"] == "consensus"
    assert sel["runs"] == 3 and 0.0 < sel["share"] <= 1.0
    assert len(sel["alternatives"]) <= 3
    model = json.loads(est.model_json_)
    assert model["correction"]["selection"] == sel
    # readable by default: no transcendental call inside another one's argument
    text = est.sympy_
    for f in TRANSCENDENTAL:
        start = text.find(f)
        while start >= 0:
            depth, i = 0, start + len(f) - 1
            inner = ""
            while i < len(text):
                depth += {"(": 1, ")": -1}.get(text[i], 0)
                inner += text[i]
                if depth == 0:
                    break
                i += 1
            assert not any(g in inner for g in TRANSCENDENTAL if g != "log(" or f != "exp("), text
            start = text.find(f, start + 1)
    with pytest.raises(ValueError, match="consensus_runs"):
        HybridRegressor("k*feed_mm", calibrate=["k"], consensus_runs=-1).fit(X, y)


def test_log_correction_recovers_a_power_law_on_log_normal_scatter():
    # y = (200 / v)^2 * f^-1.5 * exp(0.1 z): the log form's correction is a function of f
    # alone, and the hybrid follows y on the log scale
    np = pytest.importorskip("numpy")
    pd = pytest.importorskip("pandas")
    rng = np.random.default_rng(3)
    n = 300
    v = rng.uniform(100, 300, n)
    f = rng.uniform(0.1, 0.4, n)
    y = (200 / v) ** 2 * f ** -1.5 * np.exp(0.1 * rng.standard_normal(n))
    X = pd.DataFrame({"v": v, "f": f})
    m = HybridRegressor(
        "(C/v)^2", calibrate=["C"], init={"C": 150.0}, correction="log", features=["f"], **FAST
    ).fit(X, y)
    assert m.features_ == ["f"]
    pred = m.predict(X)
    assert np.all(pred > 0)
    assert np.corrcoef(np.log(pred), np.log(y))[0, 1] > 0.95
    assert json.loads(m.model_json_)["correction"]["kind"] == "log"
    with pytest.raises(ValueError, match="correction"):
        HybridRegressor("(C/v)^2", calibrate=["C"], correction="logarithmic").fit(X, y)


def test_stability_runs_report_the_shares_on_both_estimators(quadratic):
    X, y = quadratic
    est = SymbolicRegressor(**FAST, stability_runs=3).fit(X, y)
    st = est.stability_
    assert st["runs"] == 3
    assert abs(sum(s["share"] for s in st["structures"]) - 1.0) < 1e-9
    # the selection's share is now measured over those resamples
    assert est.selection_["runs"] == 3 and 0.0 <= est.selection_["share"] <= 1.0
    assert SymbolicRegressor(**FAST).fit(X, y).stability_ is None
    with pytest.raises(ValueError, match="stability_runs"):
        SymbolicRegressor(**FAST, stability_runs=-1).fit(X, y)

    T = hxai.simulate("tool_life", n_rows=120, seed=3)
    life = T.pop("tool_life_min")
    hyb = HybridRegressor(
        **TAYLOR, init={"C": 500.0, "n": 0.25}, exclude=["tool"], stability_runs=3, **FAST
    ).fit(T, life)
    assert hyb.stability_["runs"] == 3
    assert set(hyb.stability_["features"]) >= set(hyb.features_)
    assert hyb.selection_["runs"] == 3
    # the model file stores the same (hxai hybrid fit --stability writes this key too)
    assert json.loads(hyb.model_json_)["stability"] == hyb.stability_
