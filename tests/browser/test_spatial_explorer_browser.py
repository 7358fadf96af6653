"""The Gough-Stewart explorer in a real browser (Voila + Playwright + Debian's Chromium, see
browser_harness.py) on Dietmaier's design with 40 real modes. Counts are refereed by msolve on
the exact system (``method="exact"``, a different algorithm from the explorer's homotopy and
Krawczyk boxes)."""

import json

import numpy as np
import pytest

from browser_harness import INSTALL_PROBE, key_to_repaint, one_cell_notebook, served_page, summary
from browser_harness import artifacts, timings  # noqa: F401  (fixtures)

pytestmark = [pytest.mark.browser, pytest.mark.slow]

CELL = ("import imagespace as isp\n"
        "gs, L = isp.examples.dietmaier_1998()      # Dietmaier's design: 40 real modes\n"
        "explorer = isp.widgets.explore(gs, L)\n"
        "explorer")
READY = ("() => document.querySelector('.isp-status .isp-count') && "
         "document.querySelectorAll('.isp-panel .main-svg').length >= 2")


@pytest.fixture(scope="module")
def page(artifacts, timings, tmp_path_factory):
    nb = one_cell_notebook(tmp_path_factory.mktemp("gs") / "explore_gough_stewart.ipynb", CELL, "gs-explorer")
    with served_page(nb, "voila_spatial.log", "gough_stewart", timings, READY) as pg:
        yield pg


_READ = """() => { const el = document.querySelector('.isp-status');
    const c = el.querySelector('.isp-count'), f = el.querySelector('.isp-fast-count');
    return [el.dataset.lengths, c ? c.innerText : '', f ? f.innerText : '', el.dataset.modes, el.innerText]; }"""


def _status(pg, settle_ms=500, tries=60):
    last = None
    for _ in range(tries):
        now = pg.evaluate(_READ)
        if now == last and now[1] != "":
            break
        last = now
        pg.wait_for_timeout(settle_ms)
    L, count, fast, modes, text = last
    return np.array([float(v) for v in L.split(",")]), int(count), int(fast), json.loads(modes), text


def _exact_count(L):
    import imagespace as isp
    from imagespace.core.msolve import msolve_available

    if not msolve_available():
        pytest.skip("msolve binary not installed")
    gs, _ = isp.examples.dietmaier_1998()
    return gs.direct_kinematics(L, method="exact").count


def test_gough_stewart_explorer_counts_and_views(page, artifacts, timings):
    L, count, fast, modes, text = _status(page)
    assert count == fast == 40 == _exact_count(L) and "certified" in text and "reliable" in text
    assert len(modes) == 40 and sorted(m[0] for m in modes) == list(range(1, 41))
    page.screenshot(path=str(artifacts / "20_gough_stewart.png"), full_page=True)
    page.locator(".isp-panel-platform").screenshot(path=str(artifacts / "21_gough_stewart_platform.png"))
    page.locator(".isp-panel-section").screenshot(path=str(artifacts / "22_gough_stewart_section.png"))
    # leg 1 up in slider steps until the count changes: the certified count follows msolve
    page.evaluate(INSTALL_PROBE, ".isp-panel-platform")
    handle = page.locator(".widget-slider .noUi-handle").nth(0)
    handle.focus()
    lat = []
    for _ in range(12):
        lat.append(key_to_repaint(page, "ArrowRight", 700))
        L2, count2, fast2, modes2, text2 = _status(page)
        if count2 != count:
            break
    assert L2[0] > L[0] and np.allclose(L2[1:], L[1:])
    assert count2 == _exact_count(L2) and count2 != 40
    survivors = {m[0] for m in modes2}
    assert survivors < {m[0] for m in modes} and "left the real modes" in text2    # numbers kept
    timings.record("gough_stewart.key_to_platform_repaint", summary(lat))
    page.wait_for_timeout(800)
    page.screenshot(path=str(artifacts / "23_gough_stewart_moved.png"), full_page=True)
