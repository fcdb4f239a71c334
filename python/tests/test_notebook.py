"""examples/quickstart.ipynb runs from top to bottom with no cell error (nbclient, the
``python3`` kernel of the environment running the tests), in a scratch folder, and writes
its report page."""

import nbformat
import pytest
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

from conftest import ROOT

NOTEBOOK = ROOT / "examples" / "quickstart.ipynb"


def run(nb, folder):
    """Executes `nb` in `folder`; raises CellExecutionError on the first failing cell."""
    NotebookClient(
        nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(folder)}}
    ).execute()


def test_quickstart_notebook_runs(tmp_path):
    nb = nbformat.read(NOTEBOOK, as_version=4)
    run(nb, tmp_path)
    page = tmp_path / "quickstart_report.html"
    assert page.is_file(), "the notebook writes its report"
    html = page.read_text(encoding="utf-8")
    assert 'id="hybrid-equation"' in html and "times the best black box" in html
    # the fitted estimator shows its card, not its constructor
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])]
    assert any("hxai-card" in o.get("data", {}).get("text/html", "") for o in outputs)


def test_a_failing_cell_fails_the_run(tmp_path):
    """The run above can fail: a cell that raises stops it with CellExecutionError."""
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("raise ValueError('x')")])
    with pytest.raises(CellExecutionError):
        run(nb, tmp_path)
