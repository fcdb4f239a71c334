"""Writing an HTML page (``report(path)`` of the estimators and of :class:`ToolModel`): through
a temporary file in the target folder and a rename, so a reader never sees half a page, and
never over an existing file that is not HTML (a model or a table given by mistake)."""

import os
import tempfile


def _umask():
    """The process's umask (read by setting it and setting it back)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def write_page(path, html):
    """Writes ``html`` to ``path`` atomically and returns the path as a string."""
    path = os.fspath(path)
    if os.path.exists(path) and not path.lower().endswith((".html", ".htm")):
        raise ValueError(f"{path}: exists and is not an .html file; not written over")
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".hxai-report-", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(html)
        # mkstemp makes the file private (0600); the page is meant to be shared, so it gets
        # the mode a new file of the user's gets: 0666 less the umask (issue 63)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path
