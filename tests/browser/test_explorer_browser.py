"""The explorer in a real browser: Voilà serves notebooks/00_explore.ipynb, Playwright drives the
system's Chromium (Debian package ``chromium``; Playwright's own browser download is not used).

Screenshots go to ``$IMAGESPACE_ARTIFACTS/browser`` (default ``artifacts/browser`` in the repository);
the folder is printed. The test runs when ``IMAGESPACE_BROWSER=1`` (``.ci/run``'s browser step sets
it); then a missing browser or package is a failure.
"""

import os
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

pytestmark = [pytest.mark.browser, pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOK = ROOT / "notebooks" / "00_explore.ipynb"
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
REQUESTED = os.environ.get("IMAGESPACE_BROWSER") == "1"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-sync",
                 "--disable-background-networking", "--disable-component-update"]


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


@pytest.fixture(scope="module")
def artifacts():
    base = Path(os.environ.get("IMAGESPACE_ARTIFACTS", ROOT / "artifacts")) / "browser"
    base.mkdir(parents=True, exist_ok=True)
    print(f"\nbrowser screenshots: {base}")
    return base


@pytest.fixture(scope="module")
def served():
    if not REQUESTED:
        pytest.skip("the browser test runs when IMAGESPACE_BROWSER=1 (as in .ci/run's browser step)")
    missing = _missing()
    if missing:
        pytest.fail("the browser test needs " + "; ".join(missing))
    port = _free_port()
    log_path = Path(os.environ.get("IMAGESPACE_ARTIFACTS", ROOT / "artifacts")) / "voila.log"
    log_path.parent.mkdir(parents=True, exist_ok=True)
    with open(log_path, "w") as log:
        yield from _serve(port, log)


def _serve(port, log):
    proc = subprocess.Popen([sys.executable, "-m", "voila", "--no-browser", f"--port={port}",
                             "--Voila.ip=127.0.0.1", "--show_tracebacks=True", str(NOTEBOOK)],
                            cwd=ROOT, stdout=log, stderr=subprocess.STDOUT)
    try:
        deadline = time.time() + 60
        while time.time() < deadline:
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    break
            time.sleep(0.3)
        else:
            pytest.fail("voila did not start within 60 s")
        yield f"http://127.0.0.1:{port}/"
    finally:
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()


@pytest.fixture(scope="module")
def page(served):
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            pg = browser.new_page(viewport={"width": 1250, "height": 1500})
            errors = []
            pg.on("pageerror", lambda e: errors.append(str(e)))     # before loading: start-up errors count
            pg.goto(served, timeout=240_000)
            pg.wait_for_selector(".isp-status", timeout=240_000)
            pg.wait_for_function("document.querySelectorAll('.js-plotly-plot .main-svg').length >= 1",
                                 timeout=120_000)
            pg.wait_for_timeout(1500)
            assert not errors, errors        # e.g. "[anywidget] Failed to initialize model."
            yield pg
        finally:
            browser.close()


_READ_STATUS = """() => { const el = document.querySelector('.isp-status');
    const c = el.querySelector('.isp-count'); return [el.dataset.q, c ? c.innerText : '']; }"""


def _status(pg, settle_ms=500, tries=40):
    """(count, q) read in one go from the status line, once it stopped changing (updates may queue)."""
    last = None
    for _ in range(tries):
        now = pg.evaluate(_READ_STATUS)
        if now == last:
            break
        last = now
        pg.wait_for_timeout(settle_ms)
    q, count = last
    return int(count), np.array([float(v) for v in q.split(",")])


PANELS = {"pose": (0.0, 0.0, 0.47, 0.58), "space": (0.5, 0.0, 1.0, 0.58)}   # fractions of the figure


def _shot(pg, panel, path):
    """Screenshot one panel of the explorer's figure (the figure is cropped to it)."""
    pg.locator(".js-plotly-plot").first.screenshot(path=str(path))
    from PIL import Image

    img = Image.open(path).convert("RGB")
    x0, y0, x1, y1 = PANELS[panel]
    w, h = img.size
    img = img.crop((int(x0 * w), int(y0 * h), int(x1 * w), int(y1 * h)))
    img.save(path)
    return np.asarray(img, dtype=np.int16)


def _reference_count(q):
    sys.path.insert(0, str(ROOT / "tests"))
    from msolve_ref import msolve_available, planar_dk_reference

    import imagespace as isp

    if not msolve_available():
        pytest.skip("msolve binary not installed")
    return len(planar_dk_reference(isp.examples.stigger_husty(), q).poses)


def test_slider_moves_the_modes_and_the_3d_view(page, artifacts):
    count0, q0 = _status(page)
    assert count0 == _reference_count(q0) == 6
    import imagespace as isp

    # the sliders start at q_example (their grids are aligned with it; the browser snaps to the grid)
    assert np.allclose(q0, isp.examples.stigger_husty().q_example_float, rtol=1e-12, atol=0)
    before = _shot(page, "space", artifacts / "01_image_space_before.png")
    page.screenshot(path=str(artifacts / "00_explorer.png"), full_page=True)
    handle = page.locator(".widget-slider .noUi-handle").nth(2)
    count = count0
    for _ in range(12):                      # q3 upwards in slider steps until the count changes
        handle.focus()
        page.keyboard.press("PageUp")
        page.wait_for_timeout(400)
        count, q = _status(page)
        if count != count0:
            break
    assert q[2] > q0[2] and np.allclose(q[:2], q0[:2])
    assert count != count0
    assert count == _reference_count(q)
    after = _shot(page, "space", artifacts / "02_image_space_after.png")
    page.screenshot(path=str(artifacts / "03_explorer_moved.png"), full_page=True)
    assert before.shape != after.shape or np.abs(before - after).sum() > 1000


def test_change_mode_between_equal_aspects(page, artifacts):
    box = page.locator(".widget-text input").nth(2)
    box.fill("53/4")
    box.press("Enter")
    page.wait_for_function("document.querySelector('.isp-count') && "
                           "document.querySelector('.isp-status').innerText.includes('exact')", timeout=60_000)
    count, _ = _status(page)
    assert count == 6
    mode_a = page.locator(".widget-dropdown", has_text="mode A").locator("select")
    mode_b = page.locator(".widget-dropdown", has_text="mode B").locator("select")
    labels = mode_a.locator("option").all_inner_texts()
    neg = [t for t in labels if t.endswith("(-1)")]
    assert len(neg) >= 2
    mode_a.select_option(label=neg[0])
    mode_b.select_option(label=neg[1])
    page.get_by_role("button", name="change mode").click()
    page.wait_for_function("document.querySelector('.isp-plan') && "
                           "document.querySelector('.isp-plan').innerText.includes('path found')", timeout=120_000)
    page.wait_for_timeout(800)
    page.screenshot(path=str(artifacts / "04_mode_change_planned.png"), full_page=True)
    first = _shot(page, "pose", artifacts / "05_pose_frame_0.png")
    page.locator(".widget-play button").first.click()          # play the animation
    page.wait_for_timeout(2500)
    moved = _shot(page, "pose", artifacts / "06_pose_frame_later.png")
    assert np.abs(first - moved).sum() > 1000
    pos = [t for t in labels if t.endswith("(+1)")]
    mode_b.select_option(label=pos[0])
    page.get_by_role("button", name="change mode").click()
    page.wait_for_function("document.querySelector('.isp-plan') && "
                           "document.querySelector('.isp-plan').innerText.includes('opposite aspects')",
                           timeout=60_000)
    page.screenshot(path=str(artifacts / "07_opposite_aspects.png"), full_page=True)
    assert page.locator(".widget-play button").first.is_disabled()      # the old animation is gone
