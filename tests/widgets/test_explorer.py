"""The Jupyter explorer without a browser: its state against independent references.

Counts are refereed by msolve on the Euclidean formulation (tests/msolve_ref.py), drawings by
the leg lengths they must show, the section by the conic's definition (det J at poses).
"""

import numpy as np
import pytest
import sympy as sp

pytest.importorskip("ipywidgets")
pytest.importorskip("plotly")

import imagespace as isp  # noqa: E402
from imagespace.drawing import chart_coordinates, mechanism_lines  # noqa: E402
from imagespace.exceptions import InputError  # noqa: E402
from imagespace.widgets import explore, joint_ranges, parse_joint_value  # noqa: E402
from msolve_ref import msolve_available, planar_dk_reference  # noqa: E402


@pytest.fixture(scope="module")
def seed002_explorer():
    ex = explore(isp.examples.stigger_husty())
    assert ex.wait(120)                 # the surface is meshed in the background
    return ex


def test_parse_joint_value_is_exact_and_never_evaluates():
    assert parse_joint_value("27/2") == sp.Rational(27, 2)
    assert parse_joint_value("13.25") == sp.Rational(53, 4)
    assert parse_joint_value("pi/3") == sp.pi / 3
    assert parse_joint_value("-3*pi/4") == -3 * sp.pi / 4
    assert parse_joint_value("0.5pi") == sp.pi / 2
    for bad in ("__import__('os')", "1/0", "two", "pi*pi", ""):
        with pytest.raises(InputError, match="q must be a number"):
            parse_joint_value(bad)
    for huge in ("1e400", "1e100000000", "9" * 400):
        with pytest.raises(InputError, match="q3 must be"):
            parse_joint_value(huge, "q3")
    with pytest.raises(TypeError):
        parse_joint_value(3.0)


@pytest.mark.slow
def test_sliders_start_exactly_at_q(seed002_explorer):
    ex = seed002_explorer
    q = isp.examples.stigger_husty().q_example_float
    for s, v in zip(ex.sliders, q):
        k = (v - s.min) / s.step          # the browser snaps to min + k * step: q must be on that grid
        assert abs(k - round(k)) < 1e-6 and s.min <= v <= s.max


def test_joint_ranges_contain_q_and_respect_leg_domains():
    m = isp.examples.stigger_husty()
    q = m.q_example_float
    r = joint_ranges(m, q)
    assert np.all(r[:, 0] <= q) and np.all(q <= r[:, 1])
    assert r[0, 0] == 0 and r[1, 0] == 0          # RPR leg lengths are not negative
    rrr = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                              isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])
    assert np.allclose(joint_ranges(rrr, [0.3, 4.0, 4.0])[0], [-np.pi, np.pi])


@pytest.mark.skipif(not msolve_available(), reason="msolve binary not installed")
def test_status_count_equals_msolve_while_dragging(seed002_explorer):
    ex = seed002_explorer
    m = ex.manipulator
    for q3 in (13.25, 16.0, 19.5):
        q = np.array([10.0, 15.23154621, q3])
        ex.set_q(q)
        ref = planar_dk_reference(m, q)
        assert ex.status["count"] == len(ref.poses)
        assert ex.status["certified"] and not ex.status["exact"]
        assert f'<span class="isp-count">{len(ref.poses)}</span>' in ex.status_line.value
        # the 3D points are the modes in the chart (x2/x0, x3/x0, x1/x0), one per mode
        pts = sum(len(ex.trace(n).x) for n in ("points+1", "points-1"))
        assert pts == len(ref.poses)
        got = np.sort(np.concatenate([ex.trace(n).z for n in ("points+1", "points-1")]))
        assert np.allclose(got, np.sort(np.tan(ref.poses[:, 2] / 2)), atol=1e-8)


def test_exact_text_box_certifies_the_exact_value(seed002_explorer):
    ex = seed002_explorer
    ex.exact_boxes[2].value = "53/4"
    assert ex.status["exact"] and ex.status["certified"]
    assert ex.status["count"] == 6                  # seed 002: six real modes at q3 = 13.25 (Table 1)
    ex.exact_boxes[2].value = "not a number"
    assert "must be a number" in ex.status_line.value
    ex.exact_boxes[2].value = ""
    # the emptied box's error is gone: the status line shows the count again (it used to keep
    # the error, and a later save_html of the same explorer had no count in it)
    assert "must be a number" not in ex.status_line.value and "isp-count" in ex.status_line.value


def test_pose_view_draws_every_mode_with_the_given_leg_lengths(seed002_explorer):
    ex = seed002_explorer
    ex.set_q(isp.examples.stigger_husty().q_example_float)
    m = ex.manipulator
    shown = [int(v) for t in ex.trace("numbers").text if t for v in t.split(", ")]
    assert sorted(shown) == sorted(ex.mode_numbers) and len(set(ex.mode_numbers)) == len(ex.modes)
    for mm in ex.modes:
        lines = mechanism_lines(m, mm.pose, ex.q)
        # RPR legs: the drawn leg is as long as the joint value (the drawing is the geometry)
        for i in (0, 1):
            assert np.isclose(np.linalg.norm(lines.legs[i][-1] - lines.legs[i][0]), ex.q[i], rtol=1e-9)
        assert len(lines.guides) == 4                 # two RPR cylinders + the PPR leg's two guides
        assert np.allclose(lines.platform[0], lines.platform[-1])
    # colours by aspect: every leg polyline sits in the trace of its mode's aspect
    pos = sum(mm.aspect > 0 for mm in ex.modes)
    drawn_pos = np.isnan(np.asarray(ex.trace("legs+1").x, dtype=float)).sum()
    assert drawn_pos == 3 * pos


def test_section_regions_follow_det_j(seed002_explorer):
    ex = seed002_explorer
    m = ex.manipulator
    ex.section_mode.value = 0
    phi = ex.modes[0].pose[2]
    xs, ys = np.asarray(ex.trace("regions").x), np.asarray(ex.trace("regions").y)
    Z = np.asarray(ex.trace("regions").z, dtype=float)
    # aspect = c * sign(det Jx) with one constant c for the design's Jacobian convention
    c = ex.modes[0].aspect * np.sign(m.jacobians(ex.modes[0].pose).det_Jx)
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(60):
        i, j = rng.integers(0, len(ys)), rng.integers(0, len(xs))
        det = m.jacobians([xs[j], ys[i], phi]).det_Jx
        if abs(det) > 1e-6 and Z[i][j] != 0:
            assert np.sign(Z[i][j]) == c * np.sign(det), (xs[j], ys[i])
            checked += 1
    assert checked > 40


@pytest.mark.slow
def test_change_mode_equal_and_opposite_aspects(seed002_explorer):
    ex = seed002_explorer
    ex.set_q(isp.examples.stigger_husty().q_example_float)
    neg = [k for k, mm in enumerate(ex.modes) if mm.aspect < 0]
    pos = [k for k, mm in enumerate(ex.modes) if mm.aspect > 0]
    plan = ex.change_mode(neg[0], pos[0])
    assert not plan.found and "opposite aspects" in ex.plan_message.value
    plan = ex.change_mode(neg[0], neg[1])
    assert plan.found and ex.view.frame_count == len(plan.poses)
    # the drawn path starts and ends at the two modes (same point of image space)
    C = np.column_stack([ex.trace("path").x, ex.trace("path").y, ex.trace("path").z])
    for end, k in ((C[0], neg[0]), (C[-1], neg[1])):
        assert np.allclose(end, chart_coordinates(ex.modes[k].image_point)[0], atol=1e-7)
    # the joint loop is closed and the animation frame draws the pose at that sample
    assert np.allclose(ex.trace("loop1").y[0], 0) and np.allclose(ex.trace("loop1").y[-1], 0, atol=1e-7)
    ex.show_frame(5)
    lines = mechanism_lines(ex.manipulator, plan.poses[5], plan.joint_loop[5])
    assert np.allclose(np.asarray(ex.trace("moving").x[:2], dtype=float), lines.legs[0][:, 0])
    # a failed plan afterwards clears the previous one (no stale animation or joint loop)
    assert not ex.change_mode(neg[0], pos[0]).found
    assert ex.view.frame_count == 0 and len(ex.trace("loop1").x) == 0 and len(ex.trace("path").x) == 0
    with pytest.raises(InputError, match="b must be in"):
        ex.change_mode(0, 17)


def test_save_html_is_standalone(seed002_explorer, tmp_path):
    p = seed002_explorer.save_html(tmp_path / "ex.html")
    text = p.read_text()
    assert text.startswith("<!DOCTYPE html>") and text.count("Plotly.newPlot(") == 4   # the four panels
    assert "plotly.js v" in text and "<script src" not in text     # plotly.js inlined: no network, no kernel
    assert "isp-count" in text and '"singularity surface (joint-free, 48^3 grid)"' in text


def test_design_without_example_needs_q():
    m = isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(0, 0)), isp.RPR(base=(4, 0), platform=(1, 0)),
                            isp.RPR(base=(0, 4), platform=(0, 1))])
    with pytest.raises(InputError, match="q is needed"):
        explore(m)
    ex = explore(m, q=m.inverse_kinematics([1.0, 1.0, 0.2]))
    assert ex.status["count"] >= 1 and ex.status["certified"]
    with pytest.raises(InputError, match="name must be one of"):
        ex.trace("no such trace")


@pytest.mark.slow
def test_joint_dependent_surface_is_remeshed():
    m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                            isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])
    q = m.inverse_kinematics([2.0, 1.5, 0.3], working_modes=(1, 0, 0))
    ex = explore(m, q=q, resolution=16)
    assert ex.wait(120)
    first = np.asarray(ex.trace("surface").x).copy()
    ex.set_q(q + np.array([0.2, 0.0, 0.0]))
    assert "given-joints" in ex.trace("surface").name
    second = np.asarray(ex.trace("surface").x).copy()
    assert not np.array_equal(first, second)
    # dragging: the slider's event re-meshes in the background, fine once the sliders rest
    ex.sliders[0].value = ex.sliders[0].value + 0.1
    assert ex.wait(120)
    assert ex.trace("surface").opacity == 0.5 and "16^3" in ex.trace("surface").name
    assert not np.array_equal(second, np.asarray(ex.trace("surface").x))
    # the mesh shown is the surface at the slider's joint values, not at the earlier ones
    q_now = np.array([s.value for s in ex.sliders])
    V = np.column_stack([ex.trace("surface").x, ex.trace("surface").y, ex.trace("surface").z])[::25]
    X = np.column_stack([np.ones(len(V)), V[:, 2], V[:, 0], V[:, 1]])      # chart (x2/x0, x3/x0, x1/x0)
    now = np.abs([float(m.singularity_surface(q=q_now)(x)) for x in X])
    before = np.abs([float(m.singularity_surface(q=q + np.array([0.2, 0.0, 0.0]))(x)) for x in X])
    assert np.median(now) < 1e-3 * np.median(before)


def _uncertifiable_q(m):
    """Seed-002 joint values next to a double root that the exact per-call path cannot certify.

    Bisects q3 onto the place where two real modes merge (the count drops 6 -> 4) and returns the
    last midpoint at which ``direct_kinematics(q, certify=True)`` raised NearSingularWarning."""
    import warnings

    from imagespace.exceptions import NearSingularWarning

    q = m.q_example_float.copy()
    lo, hi, warned = 13.25, 13.65, []
    for _ in range(60):
        q[2] = 0.5 * (lo + hi)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            n = len(m.direct_kinematics(q, certify=True))
        if any(issubclass(w.category, NearSingularWarning) for w in caught):
            warned.append(q.copy())
        lo, hi = (q[2], hi) if n == 6 else (lo, q[2])
    assert warned, "the bisection should meet joint values the exact path cannot certify"
    return warned[-1]


@pytest.mark.slow
def test_near_singular_badge_next_to_a_double_root(seed002_explorer):
    ex = seed002_explorer
    m = ex.manipulator
    ex.set_q(_uncertifiable_q(m))
    assert ex.status["near_singular"] and not ex.status["certified"]
    assert "isp-near-singular" in ex.status_line.value and "NOT certified" in ex.status_line.value
    ex.set_q(m.q_example_float)
    assert not ex.status["near_singular"] and "isp-near-singular" not in ex.status_line.value


@pytest.mark.slow
@pytest.mark.skipif(not msolve_available(), reason="msolve binary not installed")
@pytest.mark.parametrize("name", ["stigger_husty", "collinear_3rpr", "choi_3ppr", "general_3rpr"])
def test_every_example_opens(name):
    m = getattr(isp.examples, name)()
    ex = explore(m)
    ref = planar_dk_reference(m, m.q_example_float)
    assert ex.status["count"] == len(ref.poses) and ex.status["certified"]
    assert ex.wait(120) and len(ex.trace("surface").i) > 100          # a meshed surface with triangles
    shown = sorted(int(v) for t in ex.trace("numbers").text if t for v in t.split(", "))
    assert shown == list(range(1, len(ref.poses) + 1))


def test_typed_values_give_way_to_a_moved_slider(seed002_explorer):
    ex = seed002_explorer
    ex.set_q(isp.examples.stigger_husty().q_example_float)
    ex.exact_boxes[2].value = "53/4"
    assert ex.status["exact"]
    ex.sliders[2].value = 16.0                         # the user drags q3 ...
    assert ex.exact_boxes[2].value == "" and not ex.status["exact"]
    ex.exact_boxes[0].value = "10"                     # ... then types q1: q3 stays where it was dragged
    assert ex.q[2] == pytest.approx(16.0) and ex.status["exact"]
    ex.exact_boxes[0].value = "1e400"
    assert "q1 must be" in ex.status_line.value
    ex.exact_boxes[0].value = ""


def test_set_q_validates_exact(seed002_explorer):
    ex = seed002_explorer
    with pytest.raises(InputError, match="either q"):
        ex.set_q([10.0, 15.0, 13.25], exact=[10, 15, 13])
    with pytest.raises(InputError, match="exact must be three"):
        ex.set_q(exact=[10, 15])
    with pytest.raises(InputError, match="exact must hold numbers"):
        ex.set_q(exact=[10, 15, sp.Symbol("t")])
    with pytest.raises(TypeError):
        ex.set_q(exact=[10, 15, "13"])
    ex.set_q(exact=[10, sp.Rational(61, 4), sp.Rational(53, 4)])
    assert ex.q.tolist() == [10.0, 15.25, 13.25] and ex.status["exact"]


@pytest.mark.slow
def test_exact_path_that_cannot_certify_says_so(seed002_explorer):
    ex = seed002_explorer
    m = ex.manipulator
    ex.set_q(exact=list(_uncertifiable_q(m)))
    assert ex.status["exact"] and not ex.status["certified"]
    assert "NOT certified" in ex.status_line.value and "certified on the exact" not in ex.status_line.value
    ex.set_q(m.q_example_float)


def test_close_stops_the_explorer():
    ex = explore(isp.examples.collinear_3rpr())
    ex.close()
    assert ex.wait(5) and ex.comm is None and ex.view.comm is None


# -- issue [16]: what a user tripped over ----------------------------------------------------------
def _grid(slider, v):
    """Where the browser shows ``v``: noUiSlider snaps to min + k * step (the nearest k)."""
    return slider.min + round((v - slider.min) / slider.step) * slider.step


def test_slider_snap_of_a_typed_value_is_not_a_user_move(seed002_explorer):
    ex = seed002_explorer
    ex.set_q(isp.examples.stigger_husty().q_example_float)
    ex.exact_boxes[2].value = "27/2"                  # 13.5 is off q3's slider grid
    assert ex.status["exact"] and ex.q[2] == 13.5
    s = ex.sliders[2]
    snapped = _grid(s, 13.5)
    assert snapped != 13.5
    s.value = snapped                                 # what the browser sends back after showing 13.5
    assert ex.status["exact"] and ex.q[2] == 13.5 and ex.exact_boxes[2].value == "27/2"
    s.value = snapped + s.step                        # the user moves the slider one step
    assert not ex.status["exact"] and ex.exact_boxes[2].value == "" and ex.q[2] == pytest.approx(snapped + s.step)


@pytest.mark.slow
@pytest.mark.skipif(not msolve_available(), reason="msolve binary not installed")
def test_modes_keep_their_numbers_across_a_count_change(seed002_explorer):
    ex = seed002_explorer
    m = ex.manipulator
    q = np.array([10.0, 15.23154621, 13.25])
    ex.set_q(q)
    prev = {n: mm.pose.copy() for n, mm in zip(ex.mode_numbers, ex.modes)}
    prev_aspect = {n: mm.aspect for n, mm in zip(ex.mode_numbers, ex.modes)}
    crossed = False
    for q3 in np.linspace(13.25, 13.8, 12)[1:]:
        q = np.array([10.0, 15.23154621, q3])
        ex.set_q(q)
        ref = planar_dk_reference(m, q).poses            # msolve: the real modes here
        assert len(ex.modes) == len(ref)
        now = {n: mm.pose for n, mm in zip(ex.mode_numbers, ex.modes)}
        for n, pose in now.items():
            assert np.min(np.abs(ref - pose).sum(axis=1)) < 1e-6
            if n in prev:       # the surviving mode numbered n is the one nearest to mode n before
                same = [k for k in now if prev_aspect.get(k) == prev_aspect[n]]
                d = {k: np.hypot(*(now[k][:2] - prev[n][:2])) for k in same}
                assert min(d, key=d.get) == n
        gone = set(prev) - set(now)
        if gone:
            crossed = True
            assert set(now) < set(prev)              # no survivor renumbered
            for g in gone:
                assert f"{g}" in ex.status["events"]
            assert "merged" in ex.status["events"] and "merged" in ex.status_line.value
        prev = {n: p.copy() for n, p in now.items()}
        prev_aspect = {n: mm.aspect for n, mm in zip(ex.mode_numbers, ex.modes)}
    assert crossed


@pytest.mark.skipif(not msolve_available(), reason="msolve binary not installed")
def test_no_real_mode_is_explained_and_the_last_drawing_greyed(seed002_explorer):
    ex = seed002_explorer
    m = ex.manipulator
    ex.set_q(m.q_example_float)
    drawn = np.asarray(ex.trace("legs+1").x, dtype=float)
    q = np.array([10.0, 15.23154621, 40.0])
    assert len(planar_dk_reference(m, q).poses) == 0
    ex.set_q(q)
    assert ex.status["count"] == 0 and ex.status["certified"]
    assert "no real assembly mode for these joint values" in ex.status_line.value
    assert len(ex.trace("legs+1").x) == 0 and len(ex.trace("numbers").text) == 0
    grey = np.asarray(ex.trace("last drawing").x, dtype=float)
    # the greyed drawing holds the earlier legs (as drawn at q_example)
    assert np.isin(drawn[np.isfinite(drawn)], grey[np.isfinite(grey)]).all()
    assert "no real assembly mode" in ex.view.layout("pose")["annotations"][0]["text"]
    ex.set_q(m.q_example_float)
    assert len(ex.trace("last drawing").x) == 0 and ex.view.layout("pose")["annotations"] == []


def test_section_shading_fills_its_axes(seed002_explorer):
    ex = seed002_explorer
    ex.set_q(isp.examples.stigger_husty().q_example_float)
    for k in range(len(ex.modes)):
        ex.section_mode.value = k
        lay = ex.view.layout("section")
        xs, ys = np.asarray(ex.trace("regions").x), np.asarray(ex.trace("regions").y)
        # the axes show exactly the shaded grid, square; plotly shrinks the domain, not the range
        assert lay["xaxis"]["range"] == [xs[0], xs[-1]] and lay["yaxis"]["range"] == [ys[0], ys[-1]]
        assert lay["xaxis"]["constrain"] == lay["yaxis"]["constrain"] == "domain"
        assert np.isclose(xs[-1] - xs[0], ys[-1] - ys[0])


def test_an_update_sends_only_the_changed_traces(seed002_explorer):
    ex = seed002_explorer
    sent = []
    ex.view.send = lambda content, buffers=None: sent.append((content, buffers or []))
    try:
        ex.set_q([10.0, 15.23154621, 13.3])
    finally:
        del ex.view.send
    updates = [c for c, _ in sent if c["type"] == "update"]
    assert updates
    traces = {(p, int(k)) for c in updates for p, ch in c["panels"].items() for k in ch["traces"]}
    surface = ex.view.names["surface"]
    assert surface not in traces or all("x" not in c["panels"]["space"]["traces"].get(str(surface[1]), {})
                                        for c in updates if "space" in c["panels"])
    nbytes = sum(b.nbytes for _, bufs in sent for b in bufs)
    full = sum(np.asarray(v).nbytes for tr in ex.view.panels["space"]["data"] for v in tr.values()
               if isinstance(v, np.ndarray))
    assert nbytes < 0.5 * full                       # far less than the image-space panel alone
    # the pose panel comes first in each message (the browser redraws it before painting)
    assert all(list(c["panels"])[0] == "pose" for c in updates if "pose" in c["panels"])
