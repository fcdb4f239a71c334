"""Helpers shared by the reference scripts (scripts/ref_*.py), which import it from their
own folder (Python puts a script's folder first on sys.path)."""
import os
import tempfile


def write_atomic(path, text):
    """Writes `text` to `path` through a temporary file in the same folder, then a rename,
    so an interrupted run never leaves a half-written reference file."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(tmp, path)
