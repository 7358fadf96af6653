"""The Gough-Stewart explorer without a browser (issue [16]): counts against msolve on the exact
system, the drawing against the leg lengths, the section against det J of the leg lines written here."""

import numpy as np
import pytest

pytest.importorskip("ipywidgets")
pytest.importorskip("plotly")

import imagespace as isp  # noqa: E402
from imagespace.core.msolve import msolve_available  # noqa: E402
from imagespace.spatial.study import study_point, transform_points  # noqa: E402


@pytest.fixture(scope="module")
def dietmaier():
    gs, L = isp.examples.dietmaier_1998()
    ex = isp.widgets.explore(gs, L)
    assert ex.wait(120)
    return ex


def _segments(trace):
    P = np.column_stack([np.asarray(trace.x, float), np.asarray(trace.y, float), np.asarray(trace.z, float)])
    out, cur = [], []
    for p in P:
        if np.isnan(p).any():
            if cur:
                out.append(np.array(cur))
            cur = []
        else:
            cur.append(p)
    return out


@pytest.mark.slow
def test_counts_and_the_legs_drawn(dietmaier):
    ex = dietmaier
    st = ex.status
    assert st["certified_count"] == st["fast_count"] == 40 and st["certified"] and st["reliable"]
    assert "40</span> real assembly modes</b> (certified)" in ex.status_line.value
    legs = _segments(ex.trace("legs+1")) + _segments(ex.trace("legs-1"))
    assert len(legs) == 6 * 40
    # every drawn leg is as long as its slider says: the drawing is the geometry
    lengths = np.sort(np.array([np.linalg.norm(seg[1] - seg[0]) for seg in legs]).reshape(-1))
    assert np.allclose(lengths, np.sort(np.tile(ex.lengths, 40)), rtol=1e-9)
    shown = sorted(int(v) for t in ex.trace("numbers").text if t for v in t.split(", "))
    assert shown == list(range(1, 41))


def test_section_regions_follow_det_j_of_the_leg_lines(dietmaier):
    ex = dietmaier
    k = ex.section_mode.value
    R, t = ex.result.rotations[k], ex.result.translations[k]
    xs, ys = np.asarray(ex.trace("regions").x), np.asarray(ex.trace("regions").y)
    Z = np.asarray(ex.trace("regions").z, dtype=float)
    gs = ex.gs
    rng = np.random.default_rng(4)
    checked = 0
    for _ in range(40):
        i, j = rng.integers(0, len(ys)), rng.integers(0, len(xs))
        p = np.array([xs[j], ys[i], t[2]])
        s = p + gs.platform_points @ R.T - gs.base_points           # leg directions
        det = np.linalg.det(np.hstack([s, np.cross(gs.base_points, s)]))
        if abs(det) > 1e-6:
            assert np.sign(Z[i][j]) == np.sign(det)
            checked += 1
    assert checked > 30
    assert np.allclose(ex.trace("position").x, [t[0]]) and ex.view.layout("section")["xaxis"]["range"] == [xs[0], xs[-1]]


@pytest.mark.slow
@pytest.mark.skipif(not msolve_available(), reason="msolve binary not installed")
def test_a_count_change_keeps_the_survivors_numbers(dietmaier):
    ex = dietmaier
    L0 = ex.lengths.copy()
    crossed = False
    for k in range(1, 30):
        before = {n: (s, a) for n, s, a in zip(ex.mode_numbers, ex.result.study_points, ex.result.aspects)}
        ex.set_lengths(L0 * (1 + 2e-5 * k))
        now = {n: (s, a) for n, s, a in zip(ex.mode_numbers, ex.result.study_points, ex.result.aspects)}
        assert set(now) <= set(before) or not crossed
        for n, (s, a) in now.items():     # a survivor is the old mode of its aspect nearest to it
            if n in before:
                d = {m: min(np.linalg.norm(s - b), np.linalg.norm(s + b)) for m, (b, c) in before.items() if c == a}
                assert min(d, key=d.get) == n
        if len(now) < len(before):
            crossed = True
            assert set(now) < set(before) and "left the real modes" in ex.status["events"]
            break
    assert crossed and ex.wait(120)
    L = ex.lengths
    assert ex.status["certified_count"] == ex.gs.direct_kinematics(L, method="exact").count == ex.status["fast_count"]
    ex.set_lengths(L0)
    assert ex.wait(120) and ex.status["certified_count"] == 40


@pytest.mark.slow
def test_default_lengths_and_bad_input():
    base = np.array([[2.0, 0.1, 0.0], [1.1, 1.6, 0.05], [-0.9, 1.8, -0.1], [-2.1, 0.2, 0.0], [-1.0, -1.7, 0.1],
                     [0.8, -1.9, 0.0]])
    plat = np.array([[0.9, 0.45, 0.0], [0.05, 1.05, 0.1], [-0.55, 0.8, 0.0], [-1.0, -0.3, -0.05], [-0.3, -1.0, 0.0],
                     [0.6, -0.8, 0.05]])
    gs = isp.GoughStewart(base, plat)
    ex = isp.widgets.explore(gs)                 # lengths of a pose above the base
    assert ex.wait(120) and ex.status["certified_count"] >= 1
    # the default pose is among the modes: the platform level, above the base's centre
    S = ex.result.study_points
    X = np.array([transform_points(s, plat) for s in S])
    assert any(np.allclose(Xk[:, 2] - plat[:, 2], Xk[0, 2] - plat[0, 2]) and Xk[0, 2] > 1 for Xk in X)
    for s, a in zip(S, ex.result.aspects):       # numbers of legs at each mode: the sliders' lengths
        assert np.allclose(np.linalg.norm(transform_points(s, plat) - base, axis=1), ex.lengths)
    with pytest.raises(isp.InputError):
        isp.widgets.explore(gs, [1.0, 2.0])
    with pytest.raises(isp.InputError):
        ex.set_lengths([1.0, 1.0, 1.0, 1.0, 1.0, -1.0])
    ex.close()
    assert study_point([1.0, 0, 0, 0], [0, 0, 0]).shape == (8,)
