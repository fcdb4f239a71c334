"""Issue 50's pages from Python and as HTML: ``ToolModel._repr_html_`` and
``ToolModel.report`` (the same page as ``hxai report``), and every page (table hybrid and
tool model, from the command line and from Python) valid HTML5 by html5lib's strict parser."""

import html5lib
import numpy as np
import pandas as pd
import pytest

import hxai
from conftest import FAST


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
