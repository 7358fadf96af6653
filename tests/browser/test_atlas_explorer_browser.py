"""The planar explorer's atlas panel in a real browser (Voila + Playwright + Debian's Chromium, see
browser_harness.py): ``explore(m, atlas=True)`` on seed 002, the atlas computed in the background.

What the browser draws is read back from the plotly plot itself (the atlas panel's marker trace)
and refereed by certified counts computed here, in the test's process, at the joint values the
status line reports (``certified_root_counts``; not the atlas's grid). Measured: key press to the
repainted pose panel with the atlas panel present (compare with ``planar.key_to_pose_repaint`` of
test_explorer_browser.py, the same measurement without it) and key press to the atlas panel's
redraw (plotly's ``plotly_afterplot`` on that panel).
"""

import numpy as np
import pytest

from browser_harness import INSTALL_PROBE, key_to_repaint, one_cell_notebook, served_page, summary
from browser_harness import artifacts, timings  # noqa: F401  (fixtures)

pytestmark = [pytest.mark.browser, pytest.mark.slow]

CELL = ("import imagespace as isp\n"
        "m = isp.examples.stigger_husty()\n"
        "explorer = isp.widgets.explore(m, atlas=True)    # the atlas is computed in the background\n"
        "explorer")
READY = ("() => document.querySelector('.isp-status .isp-count') && "
         "document.querySelectorAll('.isp-panel .main-svg').length >= 5")
ATLAS_READY = ("() => { const a = document.querySelector('.isp-status .isp-atlas');"
               " return a && a.innerText.includes('region'); }")

# the atlas panel's marker as plotly holds it (the plot div carries its traces as .data)
_MARKER = """() => { const gd = document.querySelector('.isp-panel-atlas');
    const t = (gd.data || []).find((d) => d.meta === 'atlas q');
    if (!t) return null;
    const sheets = gd.data.filter((d) => d.type === 'mesh3d' && d.x && d.x.length > 0).length;
    return {x: Array.from(t.x || []), y: Array.from(t.y || []), z: Array.from(t.z || []), name: t.name,
            sheets: sheets, title: gd.layout.title.text}; }"""
_STATUS = """() => { const el = document.querySelector('.isp-status');
    const a = el.querySelector('.isp-atlas');
    return [el.dataset.q, el.querySelector('.isp-count').innerText, a ? a.dataset.count : null,
            a ? a.innerText : '']; }"""
_AFTERPLOT = """() => { const gd = document.querySelector('.isp-panel-atlas');
    window.__ispAtlas = [];
    gd.on('plotly_afterplot', () => window.__ispAtlas.push(performance.now())); }"""


@pytest.fixture(scope="module")
def page(artifacts, timings, tmp_path_factory):
    nb = one_cell_notebook(tmp_path_factory.mktemp("atlas") / "explore_atlas.ipynb", CELL, "atlas-explorer")
    with served_page(nb, "voila_atlas.log", "planar_atlas", timings, READY) as pg:
        pg.wait_for_function(ATLAS_READY, timeout=240_000, polling=200)
        yield pg


def _settled(pg, tries=60):
    """Status and the atlas marker once both stopped changing and agree on q."""
    last = None
    for _ in range(tries):
        now = (pg.evaluate(_STATUS), pg.evaluate(_MARKER))
        if now == last:
            q = np.array([float(v) for v in now[0][0].split(",")])
            marker = now[1]
            if marker and marker["x"] and np.allclose([marker["x"][0], marker["y"][0], marker["z"][0]], q,
                                                      rtol=0, atol=0):
                return now
        last = now
        pg.wait_for_timeout(300)
    return last


def _certified(q):
    import imagespace as isp
    from imagespace.solve import front

    c, _ = front.certified_root_counts(isp.examples.stigger_husty(), np.asarray(q, dtype=float)[None])
    return int(c[0])


def test_atlas_panel_marker_follows_the_slider_with_the_certified_count(page, artifacts):
    status, marker = _settled(page)
    q = np.array([float(v) for v in status[0].split(",")])
    count = _certified(q)
    assert count == 6 == int(status[1]) == int(status[2])
    assert marker["name"].startswith("q: 6 modes (certified at q)") and marker["sheets"] >= 2
    assert "certified nodes" in marker["title"]
    page.wait_for_timeout(800)
    page.locator(".isp-panel-atlas").first.screenshot(path=str(artifacts / "11_atlas_panel.png"))
    page.screenshot(path=str(artifacts / "12_explorer_with_atlas.png"), full_page=True)
    handle = page.locator(".widget-slider .noUi-handle").nth(2)
    seen = {count}
    for _ in range(12):                       # q3 upwards in big steps: through a count change
        handle.focus()
        page.keyboard.press("PageUp")
        status, marker = _settled(page)
        q = np.array([float(v) for v in status[0].split(",")])
        # the marker sits at the status line's q, with the count certified here at that q
        assert np.allclose([marker["x"][0], marker["y"][0], marker["z"][0]], q, rtol=0, atol=0)
        ref = _certified(q)
        assert int(status[1]) == int(status[2]) == ref
        assert marker["name"].startswith(f"q: {ref} modes")
        seen.add(ref)
    assert len(seen) >= 2                     # the marker crossed the count-change surface
    page.wait_for_timeout(800)
    page.locator(".isp-panel-atlas").first.screenshot(path=str(artifacts / "13_atlas_panel_moved.png"))


def test_key_press_to_repaint_with_the_atlas_panel(page, timings):
    page.evaluate(INSTALL_PROBE, ".isp-panel-pose")
    page.evaluate(_AFTERPLOT)
    handle = page.locator(".widget-slider .noUi-handle").nth(1)
    handle.focus()
    pose, atlas = [], []
    for k in range(40):                       # q2 up and down one step at a time, 0.6 s apart
        pose.append(key_to_repaint(page, "ArrowRight" if (k // 10) % 2 == 0 else "ArrowLeft", 600))
        key, drawn = page.evaluate("[window.__isp.keys[window.__isp.keys.length - 1], window.__ispAtlas]")
        after = [t for t in drawn if t > key]
        atlas.append(after[0] - key if after else None)
    stats = summary(pose)
    timings.record("planar_atlas.key_to_pose_repaint", stats)
    timings.record("planar_atlas.key_to_atlas_redraw", summary(atlas))
    assert stats["n"] >= 35                   # every press repainted the pose panel
    assert sum(a is not None for a in atlas) >= 20      # and the atlas panel followed
