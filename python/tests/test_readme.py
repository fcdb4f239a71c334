"""The README's Python blocks run as written, from a copy of the repository root's layout
(docs/ and testdata/ linked into a temporary directory, so files they write stay there)."""

import os
import re

from conftest import ROOT


def python_blocks():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def test_readme_has_python_blocks():
    assert len(python_blocks()) >= 2


def test_readme_python_blocks_run(tmp_path, monkeypatch):
    for d in ("docs", "testdata"):
        os.symlink(ROOT / d, tmp_path / d)
    monkeypatch.chdir(tmp_path)
    for i, block in enumerate(python_blocks()):
        exec(compile(block, f"README.md python block {i + 1}", "exec"), {"__name__": "__readme__"})
    assert (tmp_path / "archive").is_dir()
