"""The real-law suite's scorer (scripts/bench_real_laws.py, issue 47): on every table of
testdata/real/ it gives the law itself and the law refitted on its own noiseless samples a
score of (nearly) zero, and rejects a degree-5 polynomial that fits the rows as well as the
law (the script's --self-test, which runs no hxai)."""

import subprocess
import sys

import pytest

from conftest import ROOT

pytest.importorskip("scipy")
pytest.importorskip("sympy")


def test_the_scorer_recovers_each_law_from_its_samples_and_rejects_a_tangle():
    out = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "bench_real_laws.py"), "--self-test"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    lines = [l for l in out.stdout.splitlines() if "(a) own" in l]
    assert len(lines) == 7, out.stdout
    # every law scores itself and its refit as recovered, and its tangle is rejected
    for line in lines:
        assert "(a) own 0 ok" in line, line
        assert "(b) refit" in line and line.split("(b) refit")[1].split()[1] == "ok", line
        assert line.rstrip().endswith("rejected"), line
    assert "self-test: ok (7 laws)" in out.stdout
