"""Issue 50's pages from Python and as HTML: ``ToolModel._repr_html_`` and
``ToolModel.report`` (the same page as ``hxai report``), and every page (table hybrid and
tool model, from the command line and from Python) valid HTML5 by html5lib's strict parser."""

import html.parser
import json
import re

import html5lib
import numpy as np
import pandas as pd
import pytest

import hxai
from conftest import FAST, ROOT


def test_tool_model_card_and_report_equal_the_command_line(tool_case, tmp_path):
    """The card has the hybrid as MathML with its text and the correction's scores; the
    page written from the data folder is ``hxai report``'s, byte for byte."""
    model = hxai.ToolModel.load(tool_case["model"])
    card = model._repr_html_()
    assert card.startswith("<div class=\"hxai-card\">")
    assert "<math" in card and f"x_hat(t) = (A_phys + ({model.equation}))" in card
    assert "test RMSE" in card
    page = tmp_path / "tool.html"
    assert model.report(page, data=tool_case["data"]) == str(page)
    assert page.read_bytes() == tool_case["page"].read_bytes()
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".hxai-report-")]


def test_tool_model_report_from_a_dataframe(tool_case, tmp_path):
    """A DataFrame of samples (``predict_records``' shape with ``probe_um``) draws the same
    three figures; without data the page has the model's own numbers and no figure."""
    model = hxai.ToolModel.load(tool_case["model"])
    manifest = pd.read_csv(tool_case["data"] / "manifest.csv")
    frames = []
    for _, e in manifest.iterrows():
        f = pd.read_parquet(tool_case["data"] / e["file"])  # `hxai simulate`'s default
        f["record"] = e["record"]
        f["frequency_hz"] = e["frequency_hz"]
        frames.append(f)
    df = pd.concat(frames, ignore_index=True)
    page = tmp_path / "frame.html"
    model.report(page, data=df)
    html = page.read_text(encoding="utf-8")
    assert html.count("<svg") == 3
    assert "the DataFrame given" in html
    bare = tmp_path / "bare.html"
    model.report(bare)
    assert "<svg" not in bare.read_text(encoding="utf-8")
    # bad input: a ValueError, nothing written
    with pytest.raises(ValueError, match="probe_um"):
        model.report(tmp_path / "x.html", data=df.drop(columns="probe_um"))
    with pytest.raises(ValueError, match="no manifest.csv"):
        model.report(tmp_path / "x.html", data=tmp_path)
    with pytest.raises(ValueError, match="not written over"):
        model.report(tool_case["model"], data=df)
    assert not (tmp_path / "x.html").exists()


def _strict_parse(html):
    """html5lib's strict parser over `html`: raises on the first parse error."""
    html5lib.HTMLParser(strict=True, namespaceHTMLElements=False).parse(html)


def test_every_page_is_valid_html5(table_case, tool_case, tmp_path):
    """Both pages of ``hxai report``, the Python ``report`` of a table hybrid and the three
    cards parse with no error in html5lib's strict mode (each card inside a minimal
    document)."""
    for page in (table_case["page"], tool_case["page"]):
        _strict_parse(page.read_text(encoding="utf-8"))
    rng = np.random.default_rng(5)
    X = pd.DataFrame({"a": rng.uniform(1, 3, 80), "b": rng.uniform(0, 1, 80)})
    y = pd.Series(2.0 * X["a"] ** 2 + 0.5 * X["b"], name="y")
    est = hxai.HybridRegressor("k*a^2", calibrate=["k"], **FAST).fit(X, y)
    sr = hxai.SymbolicRegressor(**FAST).fit(X, y)
    page = tmp_path / "py.html"
    est.report(page, X, y)
    _strict_parse(page.read_text(encoding="utf-8"))
    frame = "<!DOCTYPE html><html lang=en><head><title>card</title></head><body>{}</body></html>"
    for card in (est._repr_html_(), sr._repr_html_(), hxai.ToolModel.load(tool_case["model"])._repr_html_()):
        _strict_parse(frame.format(card))


def test_the_strict_parser_catches_an_error():
    """The check above can fail: a stray end tag is a parse error."""
    with pytest.raises(html5lib.html5parser.ParseError):
        _strict_parse("<!DOCTYPE html><html><head><title>t</title></head><body></span></body></html>")


class _DataValues(html.parser.HTMLParser):
    """Every ``<data id=... value=...>`` of a page: ``{id: (value, shown text)}``; fails on
    an id used twice."""

    def __init__(self):
        super().__init__()
        self.values, self._open = {}, None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "data" and "id" in a:
            assert a["id"] not in self.values, f"id {a['id']} twice"
            self._open = a["id"]
            self.values[a["id"]] = [a["value"], ""]

    def handle_data(self, data):
        if self._open:
            self.values[self._open][1] += data

    def handle_endtag(self, tag):
        if tag == "data":
            self._open = None


def _numbers(page):
    p = _DataValues()
    p.feed(page.read_text(encoding="utf-8"))
    return p.values


def _slug(*parts):
    return "-".join(re.sub(r"[^A-Za-z0-9_.-]", "_", p) for p in parts)


def _check(values, expected):
    """Every `(parts, number)` of `expected` is on the page under the slug of `parts`, its
    ``value`` the same float exactly and its text that number to four significant digits;
    returns how many were checked."""
    for parts, want in expected:
        key = _slug(*parts)
        assert key in values, f"{key} not on the page"
        value, shown = values[key]
        assert float(value) == want, (key, value, want)
        assert float(shown) == pytest.approx(want, rel=5e-4, abs=1e-300), (key, shown, want)
    return len(expected)


def test_every_number_reads_back_by_element_id(table_case, tool_case):
    """Issue 50's goal: the numbers of the page equal the model file's and the comparison
    JSON's. Each is read back from its ``<data>`` element by id: the full value exactly,
    the text shown to four significant digits. The table page: the physics parameters
    (value, standard error, 95 % interval), the correction's constants, the training and
    test scores, the black boxes, every model of the comparison and of its
    cross-validation; the tool page: the correction's constants and its scores at the
    fit."""
    model = json.loads(table_case["model"].read_text())
    compare = json.loads(table_case["compare"].read_text())
    values = _numbers(table_case["page"])
    expected = []
    ph = model["physics"]
    for name, v in ph["parameters"].items():
        expected.append((("physics", name, "value"), v))
        if ph["standard_errors"].get(name) is not None:
            expected.append((("physics", name, "se"), ph["standard_errors"][name]))
        ci = ph.get("params", {}).get(name, {}).get("ci95")
        if ci:
            expected += [(("physics", name, "ci-lo"), ci[0]), (("physics", name, "ci-hi"), ci[1])]
    for name, p in model["correction"]["uncertainty"]["params"].items():
        expected.append((("correction", name, "value"), p["value"]))
        if p.get("std_error") is not None:
            expected.append((("correction", name, "se"), p["std_error"]))
    for split in ("train", "test"):
        for part in ("physics", "hybrid"):
            for m in ("rmse", "r2"):
                expected.append(((split, part, m), model["scores"][split][part][m]))
    bb = model["scores"]["black_boxes"]
    for k in ("physics_forest", "boosting", "hybrid_over_best_black_box"):
        expected.append((("black_boxes", k), bb[k]))
    for m in compare["models"]:
        for k in ("rmse", "r2", "mae"):
            expected.append((("compare", m["name"], k), m[k]))
    for m in compare["cv"]:
        for k in ("r2_mean", "r2_sd", "rmse_mean"):
            expected.append((("cv", m["name"], k), m[k]))
    expected.append((("compare", "hybrid_over_best_black_box"), compare["hybrid_over_best_black_box"]))
    widening = model["conformal"]["widening"]
    for c, lo, hi in zip(widening["columns"], widening["lo"], widening["hi"]):
        expected += [(("range", c, "lo"), lo), (("range", c, "hi"), hi)]
    assert _check(values, expected) >= 30
    assert len(compare["models"]) == 6 and len(compare["cv"]) >= 2

    tool = json.loads(tool_case["model"].read_text())
    values = _numbers(tool_case["page"])
    expected = []
    for name, p in tool["correction"]["uncertainty"]["params"].items():
        expected.append((("correction", name, "value"), p["value"]))
    for part in ("delta_train", "delta_test"):
        for k, key in (("rmse", "rmse_um"), ("r2", "r2"), ("mae", "mae_um")):
            expected.append(((part, k), tool["training"][part][key]))
    assert _check(values, expected) >= 6
    for part in ("physics", "physics_sine", "hybrid"):
        assert _slug("evaluation", part, "rmse") in values


def test_results_pages_read_back_against_results_json():
    """The pages `cargo xtask reproduce` writes into docs/results hold the numbers of its
    results.json: every model of Table 3 on the tool page, and every model of each table
    case's comparison at the random split, read back by element id."""
    results = ROOT / "docs" / "results"
    doc = json.loads((results / "results.json").read_text())
    values = _numbers(results / "report_tool.html")
    expected = [(("compare", m["name"], k), m["test"][k]) for m in doc["table3"]
                for k in ("rmse", "r2", "mae")]
    assert _check(values, expected) == 3 * len(doc["table3"]) >= 18
    cases = doc["beyond_the_paper"]["cases"]
    assert len(cases) == 3
    for case in cases:
        values = _numbers(results / f"report_{case['name']}.html")
        split = case["random"]
        expected = [(("compare", m["name"], k), m[k]) for m in split["models"]
                    for k in ("rmse", "r2", "mae")]
        expected += [(("physics", p["name"], "value"), p["value"]) for p in split["parameters"]]
        assert _check(values, expected) >= 18


def test_the_read_back_catches_a_wrong_number():
    """The check above can fail: a value that differs in the last digit, or a text that is
    not the value, is caught."""
    values = {"a-b": ["0.1234567", "0.1235"], "c": ["2", "3"]}
    _check(values, [(("a", "b"), 0.1234567)])
    with pytest.raises(AssertionError):
        _check(values, [(("a", "b"), 0.1234568)])
    with pytest.raises(AssertionError):
        _check(values, [(("c",), 2.0)])
    with pytest.raises(AssertionError):
        _check(values, [(("d",), 1.0)])
