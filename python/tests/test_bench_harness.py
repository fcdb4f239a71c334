"""The AI Feynman suite's scoring (scripts/bench_sr_suite.py): SRBench's exact rule as the
harness applies it, how it reads hxai's sympy text, and the per-pair comparison of engines
that the strategy ablation in docs/benchmarks.md is read with."""

import importlib.util
import json

import pytest

from conftest import ROOT

sp = pytest.importorskip("sympy")

_spec = importlib.util.spec_from_file_location("bench_sr_suite", ROOT / "scripts" / "bench_sr_suite.py")
suite = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(suite)
# the results files' tables live beside it (imported by the suite through its folder)
_rspec = importlib.util.spec_from_file_location(
    "bench_sr_results", ROOT / "scripts" / "bench_sr_results.py"
)
results = importlib.util.module_from_spec(_rspec)
_rspec.loader.exec_module(results)

X = suite.symbols_for(3)
LOCALS = {s.name: s for s in X}


def read(text):
    """A model's text read as the harness reads an engine's output."""
    return sp.sympify(text, locals=LOCALS)


def truth(formula, names=("a", "b", "c")):
    problem = {"name": "t", "formula": formula, "vars": [(n, 1.0, 5.0) for n in names]}
    return suite.parse_truth(problem)[0]


@pytest.mark.parametrize(
    "model, law, want",
    [
        # the law itself, an added constant, a constant factor
        ("x1*x2/3", "a*b/3", True),
        ("x1*x2/3 + 7", "a*b/3", True),
        ("2.5*x1*x2", "a*b/3", True),
        # constants rounded to 3 decimals: 1/3 written as a decimal is no longer 1/3 ...
        ("x3/(-0.3333333333333333 + 1/(x1*x2))", "a*b/(1 - a*b/3)*c", False),
        # ... and written as a fraction it is (hxai's sympy text writes exact fractions so)
        ("x3/(-1/3 + 1/(x1*x2))", "a*b/(1 - a*b/3)*c", True),
        ("x1*sin(1/2*x2*x3)**2/sin(1/2*x2)**2", "a*sin(c*b/2)**2/sin(b/2)**2", True),
        # a phase written with pi survives the rounding
        ("x1*cos(x2 - pi/2)", "a*sin(b)", True),
        # not the law: another function, a ratio that is not constant, a zero model
        ("x1*x2**2", "a*b/3", False),
        ("x1 + x2", "a*b", False),
        ("0", "a*b", False),
        # a constant below the rounding vanishes
        ("x1*x2 + 0.0004*x3", "a*b", True),
    ],
)
def test_exact_rule(model, law, want):
    got, timed_out = suite.exact(read(model), truth(law), 20)
    assert not timed_out
    assert got is want, (model, law)


def test_rounding_keeps_three_decimals_and_zeroes_smaller_constants():
    e = suite.round_floats(read("0.70710678*x1 + 0.0004*x2 + 123.4567"))
    assert e == read("0.707*x1 + 123.457")


def rows(engine, exact, r2):
    return [
        {"engine": engine, "noise": 0.0, "number": n, "exact": e, "r2_test": r}
        for n, (e, r) in enumerate(zip(exact, r2), start=1)
    ]


def test_pairs_name_the_problems_only_one_engine_solves(capsys):
    a = rows("A", [True, True, False, False], [1.0, 1.0, 0.9995, 0.5])
    b = rows("B", [True, False, True, False], [1.0, 0.99, 1.0, 0.99999])
    results.pairs(a + b)
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[-1] == "| 0 | A | B | 4 | 1 (2) | 1 (3) | 1 | 1 (2) | 1 (4) | 1 |"


def test_pairs_compare_only_common_problems_at_the_same_noise(capsys):
    a = rows("A", [True, True], [1.0, 1.0])
    b = rows("B", [False], [0.5])  # problem 1 only
    c = [dict(r, noise=0.01) for r in rows("C", [False, False], [0.5, 0.5])]
    results.pairs(a + b + c)
    lines = capsys.readouterr().out.strip().splitlines()
    # A and B share problem 1; C ran at another noise level, so it is paired with no one
    assert lines[2:] == ["| 0 | A | B | 1 | 1 (1) | 0 | 1 | 1 (1) | 0 | 1 |"]


def test_pairs_mcnemar_p_against_scipy(capsys):
    # A solves 9 problems B does not, B solves 1 A does not, 5 both, 5 neither
    a = rows("A", [True] * 14 + [False] * 6, [1.0] * 20)
    b = rows("B", [False] * 9 + [True] * 5 + [True] + [False] * 5, [1.0] * 20)
    results.pairs(a + b)
    cells = capsys.readouterr().out.strip().splitlines()[-1].strip("| ").split(" | ")
    stats = pytest.importorskip("scipy.stats")
    want = stats.binomtest(1, 10, 0.5).pvalue  # 0.0215
    assert cells[6] == f"{want:.2g}"
    assert cells[9] == "1"  # R^2: no discordant problems


def test_load_rows_keeps_the_first_of_a_repeated_problem(tmp_path):
    first = {"engine": "A", "noise": 0.0, "number": 1, "exact": True}
    again = dict(first, exact=False)
    other = dict(first, number=2)
    p, q = tmp_path / "p.jsonl", tmp_path / "q.jsonl"
    p.write_text(json.dumps(first) + "\n\n" + json.dumps(other) + "\n")
    q.write_text(json.dumps(again) + "\n")
    got, dup = results.load_rows([p, q])
    assert dup == 1
    assert [r["exact"] for r in got] == [True, True]
