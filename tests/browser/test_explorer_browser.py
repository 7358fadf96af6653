"""The planar explorer in a real browser: Voila serves notebooks/00_explore.ipynb, Playwright drives
the system's Chromium (see conftest.py). Counts are refereed by msolve (tests/msolve_ref.py); what
the user sees is measured in the browser: key press to repainted pose panel, page ready, the frame
rate of a mode change played in the browser (written to timings.json beside the screenshots).
"""

import json
import sys

import numpy as np
import pytest

from browser_harness import INSTALL_PROBE, ROOT, key_to_repaint, served_page, summary
from browser_harness import artifacts, timings  # noqa: F401  (fixtures)

pytestmark = [pytest.mark.browser, pytest.mark.slow]

NOTEBOOK = ROOT / "notebooks" / "00_explore.ipynb"
READY = ("() => document.querySelector('.isp-status .isp-count') && "
         "document.querySelectorAll('.isp-panel .main-svg').length >= 4")


@pytest.fixture(scope="module")
def page(artifacts, timings):
    with served_page(NOTEBOOK, "voila.log", "planar", timings, READY) as pg:
        yield pg


_READ_STATUS = """() => { const el = document.querySelector('.isp-status');
    const c = el.querySelector('.isp-count');
    return [el.dataset.q, c ? c.innerText : '', el.dataset.modes, el.innerText]; }"""


def _status(pg, settle_ms=400, tries=50):
    """(count, q, modes, text) read in one go from the status line, once it stopped changing."""
    last = None
    for _ in range(tries):
        now = pg.evaluate(_READ_STATUS)
        if now == last:
            break
        last = now
        pg.wait_for_timeout(settle_ms)
    q, count, modes, text = last
    return int(count), np.array([float(v) for v in q.split(",")]), json.loads(modes), text


def _shot(pg, panel, path):
    """Screenshot one panel; returns its pixels."""
    pg.locator(f".isp-panel-{panel}").first.screenshot(path=str(path))
    from PIL import Image

    return np.asarray(Image.open(path).convert("RGB"), dtype=np.int16)


def _reference(q):
    sys.path.insert(0, str(ROOT / "tests"))
    from msolve_ref import msolve_available, planar_dk_reference

    import imagespace as isp

    if not msolve_available():
        pytest.skip("msolve binary not installed")
    return planar_dk_reference(isp.examples.stigger_husty(), q).poses


def _angle(a, b):
    return np.abs(np.remainder(a - b + np.pi, 2 * np.pi) - np.pi)


def test_slider_keeps_mode_numbers_across_a_count_change(page, artifacts, timings):
    count0, q0, modes0, _ = _status(page)
    ref0 = _reference(q0)
    assert count0 == len(ref0) == 6
    import imagespace as isp

    # the sliders start at q_example (their grids are aligned with it; the browser snaps to the grid)
    assert np.allclose(q0, isp.examples.stigger_husty().q_example_float, rtol=1e-12, atol=0)
    before = _shot(page, "space", artifacts / "01_image_space_before.png")
    page.screenshot(path=str(artifacts / "00_explorer.png"), full_page=True)
    handle = page.locator(".widget-slider .noUi-handle").nth(2)
    prev_modes, prev_q = modes0, q0
    survived_checked = 0
    crossed = False
    for _ in range(40):                      # q3 upwards in slider steps until the count changes
        handle.focus()
        page.keyboard.press("PageUp")
        count, q, modes, text = _status(page)
        assert q[2] > prev_q[2] and np.allclose(q[:2], q0[:2])
        # every mode shown is a real mode (msolve), and a mode keeps its number: the mode numbered n
        # now is the one nearest (same aspect, in pose space) to the mode numbered n before
        ref = _reference(q)
        assert count == len(ref)
        for n, a, x, y, phi in modes:
            d = np.hypot(ref[:, 0] - x, ref[:, 1] - y) + _angle(ref[:, 2], phi)
            assert d.min() < 1e-6
            old = [m for m in prev_modes if m[0] == n]
            if old:
                cands = [m for m in modes if m[1] == a]
                dist = [np.hypot(m[2] - old[0][2], m[3] - old[0][3]) + _angle(m[4], old[0][4]) for m in cands]
                assert cands[int(np.argmin(dist))][0] == n
                survived_checked += 1
        if count != len(prev_modes):
            crossed = True
            gone = sorted({m[0] for m in prev_modes} - {m[0] for m in modes})
            assert gone and all(f"{g}" in text for g in gone) and "merged" in text
            assert {m[0] for m in modes} <= {m[0] for m in prev_modes}    # survivors keep their numbers
            break
        prev_modes, prev_q = modes, q
    assert crossed and survived_checked >= 6
    after = _shot(page, "space", artifacts / "02_image_space_after.png")
    page.screenshot(path=str(artifacts / "03_explorer_moved.png"), full_page=True)
    assert before.shape != after.shape or np.abs(before - after).sum() > 1000


def test_key_press_to_repainted_pose_panel(page, timings):
    page.evaluate(INSTALL_PROBE, ".isp-panel-pose")
    handle = page.locator(".widget-slider .noUi-handle").nth(1)
    handle.focus()
    lat = []
    for k in range(40):                       # q2 up and down one step at a time, 0.6 s apart
        lat.append(key_to_repaint(page, "ArrowRight" if (k // 10) % 2 == 0 else "ArrowLeft", 600))
    stats = summary(lat)
    timings.record("planar.key_to_pose_repaint", stats)
    assert stats["n"] >= 35                   # every press repainted the pose panel
    _, _, _, text = _status(page)
    assert "kernel time" in text


def test_typed_value_off_the_slider_grid_stays_exact(page, artifacts):
    box = page.locator(".widget-text input").nth(2)
    box.fill("27/2")                          # 13.5 is not on q3's slider grid
    box.press("Enter")
    page.wait_for_function("document.querySelector('.isp-status').innerText.includes('exact joint values')",
                           timeout=60_000)
    page.wait_for_timeout(5500)               # the slider's snap to its grid must not replace it
    count, q, _, text = _status(page)
    assert "certified on the exact joint values" in text
    assert q[2] == 13.5 and box.input_value() == "27/2"
    assert count == len(_reference(q))
    page.screenshot(path=str(artifacts / "04_exact_value.png"), full_page=True)


def test_no_real_mode_keeps_the_last_drawing_greyed(page, artifacts):
    box = page.locator(".widget-text input").nth(2)
    box.fill("40")
    box.press("Enter")
    page.wait_for_function("document.querySelector('.isp-status .isp-none') !== null", timeout=60_000)
    count, q, _, text = _status(page)
    assert count == 0 == len(_reference(q)) and "no real assembly mode for these joint values" in text
    page.wait_for_timeout(500)
    img = _shot(page, "pose", artifacts / "05_no_real_mode.png")
    grey = (np.abs(img[..., 0] - 154) < 12) & (np.abs(img[..., 1] - 154) < 12) & (np.abs(img[..., 2] - 154) < 12)
    assert grey.sum() > 200                   # the last drawing, greyed
    box.fill("53/4")
    box.press("Enter")
    page.wait_for_function("document.querySelector('.isp-status').innerText.includes('6 real')", timeout=60_000)


def test_change_mode_played_in_the_browser(page, artifacts, timings):
    box = page.locator(".widget-text input").nth(2)
    box.fill("53/4")
    box.press("Enter")
    page.wait_for_function("document.querySelector('.isp-count') && "
                           "document.querySelector('.isp-status').innerText.includes('exact')", timeout=60_000)
    count, _, _, _ = _status(page)
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
    page.wait_for_function("!document.querySelector('.isp-play').disabled", timeout=30_000)
    page.wait_for_timeout(800)
    page.screenshot(path=str(artifacts / "06_mode_change_planned.png"), full_page=True)
    _shot(page, "space", artifacts / "07_path_in_image_space.png")
    first = _shot(page, "pose", artifacts / "08_pose_frame_0.png")
    page.evaluate(INSTALL_PROBE, ".isp-panel-pose")
    n = int(page.locator(".isp-frame").get_attribute("max")) + 1
    page.evaluate("window.__isp.counting = true")
    t0 = page.evaluate("performance.now()")
    page.locator(".isp-play").click()          # played in the browser
    page.wait_for_function("document.querySelector('.isp-play').innerText.includes('play')", timeout=60_000,
                           polling=20)
    t1 = page.evaluate("performance.now()")
    frames = page.evaluate("window.__isp.frames")
    fps = frames / ((t1 - t0) / 1000)
    timings.record("planar.animation", {"samples": n, "pose_repaints": frames, "seconds": round((t1 - t0) / 1000, 2),
                                        "frames_per_s": round(fps, 1)})
    # played to the end in the browser (the clock picks the sample; a slow repaint skips samples)
    assert page.locator(".isp-frame").input_value() == str(n - 1) and frames >= 10
    moved = _shot(page, "pose", artifacts / "09_pose_frame_last.png")
    assert np.abs(first - moved).sum() > 1000
    pos = [t for t in labels if t.endswith("(+1)")]
    mode_b.select_option(label=pos[0])
    page.get_by_role("button", name="change mode").click()
    page.wait_for_function("document.querySelector('.isp-plan') && "
                           "document.querySelector('.isp-plan').innerText.includes('opposite aspects')",
                           timeout=60_000)
    page.screenshot(path=str(artifacts / "10_opposite_aspects.png"), full_page=True)
    assert page.locator(".isp-play").is_disabled()      # the old animation is gone
