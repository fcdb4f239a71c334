"""A page opened in headless Chromium through the Chrome DevTools protocol over a pipe
(``--remote-debugging-pipe``: no port, no websocket, nothing beyond the standard library):
what the browser complained about, where the elements landed, and a screenshot.

Used by test_browser.py on the pages of ``hxai report`` (issue 50). Chromium is Debian's
``chromium`` package (``.ci/run`` installs it when missing)."""

import base64
import fcntl
import json
import os
import queue
import shutil
import subprocess
import tempfile
import threading
import time

CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome")

# What the page reports about the equation and the figures, in CSS pixels of the page
INSPECT = """(() => {
  const box = e => { const r = e.getBoundingClientRect();
    return {x: r.left + window.scrollX, y: r.top + window.scrollY, w: r.width, h: r.height}; };
  const eq = document.getElementById('hybrid-equation');
  return JSON.stringify({
    math: eq ? {tag: eq.tagName, mathml: eq instanceof MathMLElement,
                display: getComputedStyle(eq).display,
                box: box(eq.firstElementChild || eq)} : null,
    figures: [...document.querySelectorAll('figure')].map(f => {
      const svg = f.querySelector('svg');
      return {label: (f.querySelector('[role=img]') || f).getAttribute('aria-label'),
              box: svg ? box(svg) : null, marks: svg ? svg.querySelectorAll('*').length : 0};
    }),
    width: document.documentElement.scrollWidth,
    height: document.documentElement.scrollHeight,
  });
})()"""


def chromium():
    """The Chromium binary, or None."""
    for name in CHROMIUM_NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


class Browser:
    """One headless Chromium, driven over ``--remote-debugging-pipe`` (the child reads
    commands on fd 3 and writes replies and events on fd 4, each a JSON text ending in NUL)."""

    def __init__(self, binary, timeout=60.0):
        self.timeout = timeout
        self.profile = tempfile.mkdtemp(prefix="hxai-chromium-")
        to_child_r, self._to_child = os.pipe()
        self._from_child, from_child_w = os.pipe()

        def fds():
            # out of the way first: a pipe end may itself be fd 3 or 4
            a = fcntl.fcntl(to_child_r, fcntl.F_DUPFD, 10)
            b = fcntl.fcntl(from_child_w, fcntl.F_DUPFD, 10)
            os.dup2(a, 3)  # inheritable, unlike the pipe's own ends
            os.dup2(b, 4)

        args = [binary, "--headless", "--remote-debugging-pipe", "--disable-gpu",
                "--no-first-run", "--no-default-browser-check", "--disable-extensions",
                "--disable-dev-shm-usage", "--hide-scrollbars",
                f"--user-data-dir={self.profile}", "about:blank"]
        if hasattr(os, "geteuid") and os.geteuid() == 0:
            args.insert(1, "--no-sandbox")  # Chromium refuses to run its sandbox as root
        self.proc = subprocess.Popen(  # noqa: S603 - a fixed argument list
            args, preexec_fn=fds, close_fds=False, stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
        )
        os.close(to_child_r)
        os.close(from_child_w)
        self._next = 0
        self._replies = {}
        self.events = []
        self._inbox = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        buf = b""
        while True:
            chunk = os.read(self._from_child, 1 << 16)
            if not chunk:
                self._inbox.put(None)
                return
            buf += chunk
            while b"\0" in buf:
                msg, buf = buf.split(b"\0", 1)
                self._inbox.put(json.loads(msg))

    def send(self, method, params=None, session=None):
        """Sends a command and waits for its reply; returns its result (RuntimeError on an
        error reply, TimeoutError when none comes)."""
        self._next += 1
        msg = {"id": self._next, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self._to_child, json.dumps(msg).encode() + b"\0")
        return self._wait(lambda: self._replies.pop(self._next, None), method)

    def wait_event(self, method):
        """Waits for the event `method` (already received or to come)."""
        def seen():
            return next((e for e in self.events if e["method"] == method), None)
        return self._wait(seen, method)

    def _wait(self, found, what):
        deadline = time.monotonic() + self.timeout
        while True:
            got = found()
            if got is not None:
                if "error" in got:
                    raise RuntimeError(f"{what}: {got['error']}")
                return got.get("result", got)
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"Chromium did not answer {what} in {self.timeout} s")
            try:
                msg = self._inbox.get(timeout=left)
            except queue.Empty:
                continue
            if msg is None:
                err = self.proc.stderr.read().decode(errors="replace")[-2000:]
                raise RuntimeError(f"Chromium exited while waiting for {what}: {err}")
            if "id" in msg:
                self._replies[msg["id"]] = msg
            else:
                self.events.append(msg)

    def close(self):
        try:
            self.send("Browser.close")
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        for fd in (self._to_child, self._from_child):
            try:
                os.close(fd)
            except OSError:
                pass
        self.proc.stderr.close()
        shutil.rmtree(self.profile, ignore_errors=True)


def problems(events):
    """Every console error, uncaught exception, error log entry and failed or refused
    resource among the events, as text."""
    out = []
    for e in events:
        m, p = e["method"], e.get("params", {})
        if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
            out.append("console: " + " ".join(str(a.get("value", a.get("description")))
                                               for a in p.get("args", [])))
        elif m == "Runtime.exceptionThrown":
            out.append("exception: " + p["exceptionDetails"].get("text", ""))
        elif m == "Log.entryAdded" and p["entry"].get("level") == "error":
            out.append(f"log: {p['entry'].get('text')} ({p['entry'].get('url', '')})")
        elif m == "Network.loadingFailed":
            out.append(f"resource failed: {p.get('errorText')} ({p.get('type')})")
        elif m == "Network.responseReceived" and p["response"].get("status", 200) >= 400:
            out.append(f"resource {p['response']['status']}: {p['response'].get('url')}")
    return out


def open_page(path, width=1000, height=800):
    """Opens the file `path` at a `width` x `height` viewport and returns ``(problems,
    layout, png)``: the browser's complaints, what :data:`INSPECT` measured and a PNG
    screenshot of the whole page. Raises RuntimeError when there is no Chromium."""
    binary = chromium()
    if binary is None:
        raise RuntimeError("no Chromium (install Debian's `chromium` package)")
    b = Browser(binary)
    try:
        target = b.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = b.send("Target.attachToTarget", {"targetId": target, "flatten": True})[
            "sessionId"]
        for domain in ("Page", "Runtime", "Log", "Network"):
            b.send(f"{domain}.enable", session=session)
        b.send("Emulation.setDeviceMetricsOverride",
               {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False},
               session=session)
        b.events.clear()
        b.send("Page.navigate", {"url": "file://" + os.path.abspath(path)}, session=session)
        b.wait_event("Page.loadEventFired")
        got = b.send("Runtime.evaluate", {"expression": INSPECT, "returnByValue": True},
                     session=session)
        layout = json.loads(got["result"]["value"])
        shot = b.send("Page.captureScreenshot", {
            "format": "png", "captureBeyondViewport": True,
            "clip": {"x": 0, "y": 0, "width": max(layout["width"], width),
                     "height": layout["height"], "scale": 1},
        }, session=session)
        return problems(b.events), layout, base64.b64decode(shot["data"])
    finally:
        b.close()
