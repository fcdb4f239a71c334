"""Shared helpers of the Python tests: the repository root, the `hxai` binary, small data."""

import os
import pathlib
import shutil

import numpy as np
import pandas as pd
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]

# Small searches keep the suite fast on CI's two cores; the engine is the same.
FAST = dict(epochs=2, candidates_per_epoch=200)

# Taylor's tool life as the physics of a log-form hybrid (the tool_life case's law)
TAYLOR = dict(physics="(C/cutting_speed_m_min)^(1/n)", calibrate=["C", "n"], correction="log")


def hxai_binary():
    """The `hxai` binary: $HXAI_BIN, else target/debug or target/release of this checkout.
    Missing: the test is skipped, unless HXAI_REQUIRE_CLI=1 (CI), where it fails."""
    cands = [os.environ.get("HXAI_BIN")] + [
        str(ROOT / "target" / p / "hxai") for p in ("debug", "release")
    ]
    for c in cands:
        if c and pathlib.Path(c).is_file():
            return c
    found = shutil.which("hxai")
    if found:
        return found
    if os.environ.get("HXAI_REQUIRE_CLI") == "1":
        pytest.fail("no hxai binary (set HXAI_BIN or build with `cargo build -p hxai-cli`)")
    pytest.skip("no hxai binary (set HXAI_BIN or build with `cargo build -p hxai-cli`)")


@pytest.fixture
def quadratic():
    """y = 3 a^2 + 1 + 0.5 b on 120 rows, as a DataFrame and a Series."""
    rng = np.random.default_rng(0)
    a = rng.uniform(0.5, 2.5, 120)
    b = rng.uniform(-1.0, 1.0, 120)
    X = pd.DataFrame({"a": a, "b": b})
    y = pd.Series(3.0 * a * a + 1.0 + 0.5 * b, name="y")
    return X, y
