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


def run_hxai(*args):
    """Runs the `hxai` binary with `args` (strings or paths), failing the test with its
    stderr unless it succeeds; returns its stdout."""
    import subprocess

    out = subprocess.run(
        [hxai_binary(), *map(str, args)], capture_output=True, text=True, check=False
    )
    if out.returncode != 0:
        pytest.fail(f"hxai {' '.join(map(str, args))}: {out.stderr}")
    return out.stdout


@pytest.fixture(scope="session")
def tool_case(tmp_path_factory):
    """A small simulated data folder, a tool model fitted on it (`hxai fit`, two epochs)
    and its page (`hxai report`): a dict with `data`, `model`, `page`."""
    d = tmp_path_factory.mktemp("tool-case")
    data, model, page = d / "data", d / "model.json", d / "tool.html"
    run_hxai("simulate", "--out", data, "--repeats", "1", "--duration-s", "1.5", "--fs-hz",
             "2000", "--amplitudes", "4,8,11", "--frequencies", "10,20,30,40", "--seed", "1")
    run_hxai("fit", "--data", data, "--out", model, "--epochs", "2", "--seed", "5",
             "--threads", "1")
    run_hxai("report", "--model", model, "--data", data, "--out", page)
    return {"data": data, "model": model, "page": page}


@pytest.fixture(scope="session")
def table_case(tmp_path_factory):
    """A simulated roughness table, a table hybrid fitted on it (`hxai hybrid fit`), its
    comparison (`hxai hybrid compare --json`) and its page (`hxai report`): a dict with
    `data`, `model`, `compare`, `page`."""
    d = tmp_path_factory.mktemp("table-case")
    data, model, compare, page = d / "ra.csv", d / "ra.json", d / "compare.json", d / "ra.html"
    run_hxai("simulate", "--case", "roughness", "--rows", "150", "--seed", "3", "--out", data)
    law = ["--data", data, "--target", "Ra_um", "--physics",
           "1000*feed_mm^2/(32*nose_radius_mm) + Ra0", "--calibrate", "Ra0", "--init", "Ra0=0",
           "--correction", "multiplicative", "--exclude", "tool", "--epochs", "2"]
    run_hxai("hybrid", "fit", *law, "--out", model)
    compare.write_text(run_hxai("hybrid", "compare", *law, "--folds", "3", "--json"))
    run_hxai("report", "--model", model, "--data", data, "--compare", compare, "--out", page)
    return {"data": data, "model": model, "compare": compare, "page": page}
