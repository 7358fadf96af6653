"""Voila + Playwright + Debian's Chromium for the explorer tests (Playwright's own browser download
is not used). The tests run when ``IMAGESPACE_BROWSER=1`` (``.ci/run``'s browser step sets it); then
a missing browser or package is a failure.

Screenshots and the measured timings (``timings.json``) go to ``$IMAGESPACE_ARTIFACTS/browser``
(default ``artifacts/browser`` in the repository); the folder is printed.
"""

import contextlib
import json
import os
import shutil
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
REQUESTED = os.environ.get("IMAGESPACE_BROWSER") == "1"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-sync",
                 "--disable-background-networking", "--disable-component-update"]
ARTIFACTS = Path(os.environ.get("IMAGESPACE_ARTIFACTS", ROOT / "artifacts"))


def _missing():
    why = []
    if CHROMIUM is None:
        why.append("the chromium executable (apt-get install chromium)")
    for mod in ("playwright", "voila", "PIL"):
        try:
            __import__(mod)
        except ImportError:
            why.append(f"the python package {mod} (pip install -e '.[browser]')")
    return why


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Timings:
    """Measured browser figures, written to ``timings.json`` as they come in."""

    def __init__(self, path):
        self.path = path
        self.data = json.loads(path.read_text()) if path.exists() else {}

    def record(self, key, value):
        self.data[key] = value
        self.path.write_text(json.dumps(self.data, indent=2, sort_keys=True))
        print(f"\n[browser timing] {key}: {value}")


class Served:
    """A Voila server on one notebook; ``kernel_started`` is the wall time at which its log said
    the kernel started (polled every 20 ms)."""

    def __init__(self, notebook, log_path):
        if not REQUESTED:
            pytest.skip("the browser test runs when IMAGESPACE_BROWSER=1 (as in .ci/run's browser step)")
        missing = _missing()
        if missing:
            pytest.fail("the browser test needs " + "; ".join(missing))
        self.port = _free_port()
        self.log_path = log_path
        self.kernel_started = None
        self._log = open(log_path, "w")
        # the kernel imports this checkout's imagespace (not another editable install's)
        env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT)] + [p for p in os.environ.get(
            "PYTHONPATH", "").split(os.pathsep) if p]))
        self.proc = subprocess.Popen([sys.executable, "-m", "voila", "--no-browser", f"--port={self.port}",
                                      "--Voila.ip=127.0.0.1", "--show_tracebacks=True", str(notebook)],
                                     cwd=ROOT, stdout=self._log, stderr=subprocess.STDOUT, env=env)
        self._stop = False
        threading.Thread(target=self._watch, daemon=True).start()
        deadline = time.time() + 60
        while time.time() < deadline:
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", self.port)) == 0:
                    break
            time.sleep(0.2)
        else:
            self.close()
            pytest.fail("voila did not start within 60 s")
        self.url = f"http://127.0.0.1:{self.port}/"

    def _watch(self):
        while not self._stop and self.kernel_started is None:
            try:
                if "Kernel started" in Path(self.log_path).read_text():
                    self.kernel_started = time.time()
            except OSError:
                pass
            time.sleep(0.02)

    def close(self):
        self._stop = True
        self.proc.terminate()
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        self._log.close()


def open_page(served, notebook_label, timings, ready_js):
    """Launch Chromium on the served notebook; wait for ``ready_js``; record page-ready times."""
    from playwright.sync_api import sync_playwright

    pw = sync_playwright().start()
    browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
    pg = browser.new_page(viewport={"width": 1250, "height": 1500})
    errors = []
    pg.on("pageerror", lambda e: errors.append(str(e)))     # before loading: start-up errors count
    t0 = time.time()
    pg.goto(served.url, timeout=240_000)
    pg.wait_for_function(ready_js, timeout=240_000, polling=50)
    t_ready = time.time()
    started = served.kernel_started
    timings.record(f"{notebook_label}.page_ready_after_navigation_s", round(t_ready - t0, 2))
    if started is not None:
        timings.record(f"{notebook_label}.page_ready_after_kernel_start_s", round(t_ready - started, 2))
    pg.wait_for_timeout(500)
    assert not errors, errors        # e.g. "[anywidget] Failed to initialize model."
    return pw, browser, pg, errors


def one_cell_notebook(path, cell, cell_id):
    """Write a notebook of one code cell ``cell`` to ``path`` (for Voila) and return ``path``."""
    path.write_text(json.dumps({"cells": [{"cell_type": "code", "execution_count": None, "id": cell_id,
                                           "metadata": {}, "outputs": [], "source": cell}],
                                "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python",
                                                            "name": "python3"}},
                                "nbformat": 4, "nbformat_minor": 5}))
    return path


@contextlib.contextmanager
def served_page(notebook, log_name, notebook_label, timings, ready_js):
    """Voila on ``notebook`` (its log ``ARTIFACTS / log_name``) and Chromium on its page, ready
    (:func:`open_page`); yields the page; after the block, no page error may have occurred."""
    served = Served(notebook, ARTIFACTS / log_name)
    try:
        pw, browser, pg, errors = open_page(served, notebook_label, timings, ready_js)
        try:
            yield pg
            assert not errors, errors
        finally:
            browser.close()
            pw.stop()
    finally:
        served.close()


# -- measuring what the user sees -------------------------------------------------------------------
INSTALL_PROBE = """(panel) => {
  const probe = window.__isp = {keys: [], paints: [], frames: 0, counting: false, dirty: false};
  document.addEventListener('keydown', () => probe.keys.push(performance.now()), true);
  const target = document.querySelector(panel);
  new MutationObserver(() => {
    const now = performance.now();
    probe.dirty = true;
    requestAnimationFrame(() => probe.paints.push(now));
  }).observe(target, {subtree: true, attributes: true, childList: true, characterData: true});
  function tick() {
    if (probe.dirty && probe.counting) probe.frames += 1;
    probe.dirty = false;
    requestAnimationFrame(tick);
  }
  requestAnimationFrame(tick);
}"""


def key_to_repaint(pg, key, settle_ms):
    """Press ``key`` (on the focused element); the ms from the key event to the first repaint of the
    probed panel after it (None if nothing repainted within ``settle_ms``)."""
    pg.keyboard.press(key)
    pg.wait_for_timeout(settle_ms)
    keys, paints = pg.evaluate("[window.__isp.keys, window.__isp.paints]")
    after = [t for t in paints if t > keys[-1]]
    return after[0] - keys[-1] if after else None


def summary(values):
    v = np.asarray([x for x in values if x is not None], dtype=float)
    return {"n": int(len(v)), "p50_ms": round(float(np.percentile(v, 50)), 1),
            "p90_ms": round(float(np.percentile(v, 90)), 1), "max_ms": round(float(v.max()), 1)}


# -- fixtures shared by the browser test modules (imported there; a conftest.py here would clash
# with tests/conftest.py under --doctest-modules, both being imported as the module "conftest")

import pytest as _pytest


@_pytest.fixture(scope="session")
def artifacts():
    base = ARTIFACTS / "browser"
    base.mkdir(parents=True, exist_ok=True)
    print(f"\nbrowser screenshots and timings: {base}")
    return base


@_pytest.fixture(scope="session")
def timings(artifacts):
    path = artifacts / "timings.json"
    if path.exists():
        path.unlink()
    return Timings(path)
