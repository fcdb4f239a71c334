"""Dimensional analysis from Python: ``SymbolicRegressor(units=..., target_units=...)``
searches the dimensionless groups as ``hxai sr --units`` does, and refuses bad units by name."""

import json
import subprocess

import numpy as np
import pandas as pd
import pytest

from hxai import SymbolicRegressor
from conftest import FAST, hxai_binary

UNITS = {"G": "m^3/(kg*s^2)", "m1": "kg", "m2": "kg", "r": "m"}


@pytest.fixture
def gravitation():
    """F = G m1 m2 / r^2 on 200 rows."""
    rng = np.random.default_rng(1)
    X = pd.DataFrame(
        {
            "G": rng.uniform(1, 2, 200),
            "m1": rng.uniform(1, 5, 200),
            "m2": rng.uniform(1, 5, 200),
            "r": rng.uniform(1, 5, 200),
        }
    )
    return X, X.G * X.m1 * X.m2 / X.r**2


def test_units_give_the_law_and_its_groups(gravitation):
    X, y = gravitation
    m = SymbolicRegressor(**FAST, units=UNITS, target_units="N").fit(X, y)
    assert m.dimensional_groups_ == ["pi1 = m2/m1", "y = G*m1^2/r^2 * phi(pi1)"]
    assert m.score(X, y) > 1 - 1e-12
    # without units the same small search does not find it by itself ...
    plain = SymbolicRegressor(**FAST, power_laws=False).fit(X, y)
    assert plain.dimensional_groups_ is None
    assert plain.score(X, y) < m.score(X, y)
    # ... but the power primitive (issue 47, on by default up to 300 rows) offers the
    # product of powers G m1 m2 / r^2 as one candidate
    powered = SymbolicRegressor(**FAST).fit(X, y)
    assert powered.score(X, y) > 1 - 1e-12, powered.equation_


def test_same_result_as_cli(gravitation, tmp_path):
    binary = hxai_binary()
    X, y = gravitation
    csv = tmp_path / "g.csv"
    X.assign(F=y).to_csv(csv, index=False, float_format="%.17g")
    table = pd.read_csv(csv)
    units = ",".join(f"{k}={v}" for k, v in UNITS.items()) + ",F=N"
    out = subprocess.run(
        [binary, "sr", "--csv", str(csv), "--target", "F", "--epochs", "2", "--json",
         "--units", units],
        check=True, capture_output=True, text=True,
    )
    cli = json.loads(out.stdout)
    m = SymbolicRegressor(epochs=2, units=UNITS, target_units="N").fit(
        table[list(UNITS)], table["F"]
    )
    assert m.sympy_ == cli["best"]["sympy"]
    assert cli["dimensional_groups"][0] == m.dimensional_groups_[0]


def test_bad_units_are_refused_by_name(gravitation):
    X, y = gravitation
    with pytest.raises(ValueError, match="go together"):
        SymbolicRegressor(**FAST, units=UNITS).fit(X, y)
    with pytest.raises(ValueError, match="no unit for `r`"):
        SymbolicRegressor(**FAST, units={"G": "m", "m1": "kg", "m2": "kg"},
                          target_units="N").fit(X, y)
    with pytest.raises(ValueError, match="`parsec` is not a unit"):
        SymbolicRegressor(**FAST, units={**UNITS, "r": "parsec"}, target_units="N").fit(X, y)
    with pytest.raises(ValueError, match="dimensional constant"):
        SymbolicRegressor(**FAST, units={**UNITS, "G": "1"}, target_units="N").fit(X, y)


def test_the_composed_law_reads_as_the_law(gravitation):
    """The model of the group ``m2/m1`` composed back into the columns cancels ``m1``
    (simplification after the search); ``simplify=False`` keeps the search's programs and
    counts none shortened."""
    X, y = gravitation
    m = SymbolicRegressor(**FAST, units=UNITS, target_units="N").fit(X, y)
    assert m.sympy_ == "G*m1*m2/r**2"
    plain = SymbolicRegressor(**FAST, simplify=False).fit(X, y)
    assert plain.simplified_ == 0
    assert SymbolicRegressor(**FAST).fit(X, y).simplified_ > 0
