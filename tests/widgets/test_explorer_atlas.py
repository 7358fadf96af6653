"""The planar explorer's atlas panel (``explore(m, atlas=...)``) without a browser.

The count on the marker is refereed by certified counts computed here at the marker's q
(``certified_root_counts``), and by msolve at a few points; the atlas's grid label is not the
referee: the points include pairs on either side of the count-change surface (the atlas's evidence
brackets), where the nearest grid node has the wrong count for one of the two, and the test checks
that it does.
"""

import subprocess
import sys
import textwrap

import numpy as np
import pytest

pytest.importorskip("ipywidgets")
pytest.importorskip("plotly")

import imagespace as isp  # noqa: E402
from imagespace.atlas import joint_atlas  # noqa: E402
from imagespace.exceptions import InputError  # noqa: E402
from imagespace.solve import front  # noqa: E402
from imagespace.widgets import explore  # noqa: E402
from msolve_ref import msolve_available, planar_dk_reference  # noqa: E402

BOX = [(6.0, 14.0), (11.0, 19.0), (9.0, 17.0)]        # around seed 002's six-mode q_example


@pytest.fixture(scope="module")
def design():
    return isp.examples.stigger_husty()


@pytest.fixture(scope="module")
def coarse(design):
    return joint_atlas(design, BOX, 10, cusps=False)    # 10^3 nodes: coarse on purpose


@pytest.fixture(scope="module")
def explorer(design, coarse):
    ex = explore(design, atlas=coarse, resolution=16)
    assert ex.wait(120)
    yield ex
    ex.close()


def _sent(ex, action):
    sent = []
    ex.view.send = lambda content, buffers=None: sent.append((content, buffers or []))
    try:
        action()
    finally:
        del ex.view.send
    return [c for c, _ in sent if c["type"] == "update"], sent


@pytest.mark.slow
def test_marker_follows_q_and_shows_the_certified_count_not_the_grid_label(explorer, design, coarse):
    ex = explorer
    rng = np.random.default_rng(20261203)
    box = np.array(BOX)
    random_q = box[:, 0] + rng.random((12, 3)) * (box[:, 1] - box[:, 0])
    # both ends of a few evidence brackets: a hair apart, proven counts that differ, one grid label
    E = coarse.evidence_points
    inner = np.flatnonzero(np.all((E > box[:, 0]) & (E < box[:, 1]), axis=(1, 2)))
    picks = rng.choice(inner, 8, replace=False)
    brackets = coarse.evidence_points[picks].reshape(-1, 3)
    Q = np.vstack([random_q, brackets])
    reference, _ = front.certified_root_counts(design, Q)
    grid = coarse.count_at(Q)
    assert np.all(reference >= 0)
    # the grid's label is wrong for at least a few of these points: the test can tell the two apart
    assert int((grid != reference).sum()) >= 4
    shown = []
    for q, ref in zip(Q, reference):
        ex.set_q(q)
        marker = ex.trace("atlas q")
        assert marker.x.tolist() == [q[0]] and marker.y.tolist() == [q[1]] and marker.z.tolist() == [q[2]]
        info = ex.status["atlas"]
        assert info["inside"] and info["certified"] and info["state"] == "ready"
        assert info["count"] == ref == ex.status["count"]
        assert marker.name.startswith(f"q: {ref} modes (certified at q)")
        assert f"{ref} real modes" in marker.hovertext
        assert f'data-count="{ref}"' in ex.status_line.value
        shown.append(info["count"])
    # where the grid disagrees the status line says so
    k = int(np.flatnonzero(grid != reference)[0])
    ex.set_q(Q[k])
    assert "within a grid cell of the count-change surface" in ex.status_line.value
    assert ex.status["atlas"]["region_count"] == grid[k] != ex.status["atlas"]["count"]


def test_the_count_against_msolve_at_a_few_points(explorer, design):
    if not msolve_available():
        pytest.skip("msolve binary not installed")
    for q in ([10.0, 15.23154621, 13.25], [8.0, 17.0, 10.0], [12.5, 12.0, 16.0]):
        explorer.set_q(q)
        assert explorer.status["atlas"]["count"] == len(planar_dk_reference(design, np.array(q)).poses)


def test_outside_the_box_and_the_exact_path(explorer):
    ex = explorer
    ex.set_q([20.0, 15.0, 13.25])
    info = ex.status["atlas"]
    assert not info["inside"] and info["region"] is None
    assert len(ex.trace("atlas q").x) == 0 and "outside the atlas box" in ex.trace("atlas q").name
    assert "outside its joint box" in ex.status_line.value
    ex.set_q(exact=[10, 15, 13])
    assert ex.trace("atlas q").name.startswith(f"q: {ex.status['count']} modes (certified at the exact q)")


def test_the_surface_is_sent_once_and_a_move_sends_only_the_marker(explorer, coarse):
    ex = explorer
    sheets = [ex.trace(f"atlas sheet {k}") for k in range(6)]
    levels = np.unique(coarse.vertex_level)
    present = np.unique(coarse.counts[coarse.counts >= 0])
    # one sheet per count threshold, every vertex one of the atlas's, named by the counts it separates
    assert sum(len(s.x) > 0 for s in sheets) == len(levels)
    V = {tuple(v) for v in coarse.vertices}
    for s, level in zip(sheets, levels):
        assert len(s.x) and all((x, y, z) in V for x, y, z in zip(s.x, s.y, s.z))
        pair = [(a, b) for a, b in zip(present[:-1], present[1:]) if a + b == 2 * level]
        assert s.name == f"surface: {pair[0][0]} | {pair[0][1]} modes"
    updates, sent = _sent(ex, lambda: ex.set_q([10.0, 15.2, 13.3]))
    marker = str(ex.view.names["atlas q"][1])
    atlas_updates = [c["panels"]["atlas"] for c in updates if "atlas" in c["panels"]]
    assert atlas_updates
    for change in atlas_updates:
        assert list(change["traces"]) == [marker] and not change.get("layout")
        assert set(change["traces"][marker]) <= {"x", "y", "z", "name", "hovertext"}
    # the atlas adds three numbers to a message (its binary buffers), not the surface
    atlas_bytes = 0
    for content, bufs in sent:
        if content["type"] == "update" and "atlas" in content["panels"]:
            for prop in content["panels"]["atlas"]["traces"][marker].values():
                if isinstance(prop, dict) and "$b" in prop:
                    atlas_bytes += bufs[prop["$b"]].nbytes
    assert atlas_bytes == 3 * 8


@pytest.mark.slow
def test_without_atlas_nothing_changes_and_nothing_is_imported():
    # a fresh process: the explorer without an atlas neither imports imagespace.atlas nor adds a panel
    code = textwrap.dedent("""
        import sys, imagespace as isp
        ex = isp.widgets.explore(isp.examples.stigger_husty(), resolution=12)
        ex.wait(120)
        print(sorted(ex.figures()), ex.status["atlas"], "isp-atlas" in ex.status_line.value,
              "imagespace.atlas" in sys.modules)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=True)
    assert out.stdout.split() == ["['loop',", "'pose',", "'section',", "'space']", "None", "False", "False"]


@pytest.mark.slow
def test_bad_atlas_arguments(design):
    m = design
    with pytest.raises(TypeError, match="atlas must be a JointAtlas .* got str 'yes'"):
        explore(m, atlas="yes")
    with pytest.raises(TypeError, match="atlas must be a JointAtlas .* got int 1"):
        explore(m, atlas=1)
    with pytest.raises(TypeError, match="atlas must be a JointAtlas"):
        explore(m, atlas={"box": BOX})
    other = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 8, cusps=False)
    with pytest.raises(InputError, match="atlas must be an atlas of this design"):
        explore(m, atlas=other)
    base = np.array([[2.0, 0.1, 0.0], [1.1, 1.6, 0.05], [-0.9, 1.8, -0.1], [-2.1, 0.2, 0.0], [-1.0, -1.7, 0.1],
                     [0.8, -1.9, 0.0]])
    gs = isp.GoughStewart(base, 0.5 * base)
    with pytest.raises(InputError, match="atlas is for planar designs"):
        explore(gs, atlas=True)
    ex = explore(m, atlas=False, resolution=12)      # False: no panel
    assert "atlas" not in ex.figures() and ex.status["atlas"] is None
    ex.close()


@pytest.mark.slow
def test_atlas_true_is_computed_in_the_background(design, monkeypatch):
    from imagespace.widgets import planar_atlas

    monkeypatch.setattr(planar_atlas, "ATLAS_RESOLUTION", 12)
    ex = explore(design, atlas=True, resolution=12)
    assert ex.status["atlas"]["state"] == "computing"      # the panels show first
    assert "computing" in ex.view.layout("atlas")["title"]["text"]
    assert ex.wait(300) and ex.atlas is not None and ex.status["atlas"]["state"] == "ready"
    box = ex.atlas.box
    q = design.q_example_float
    assert np.all(box[:, 0] < q) and np.all(q < box[:, 1]) and ex.atlas.counts.shape == (12, 12, 12)
    # the sheets drawn are the computed atlas's surface, inside its box
    drawn = np.vstack([np.column_stack([t.x, t.y, t.z]) for t in (ex.trace(f"atlas sheet {k}") for k in range(6))
                       if len(t.x)])
    assert len(drawn) and np.all(drawn >= box[:, 0] - 1e-12) and np.all(drawn <= box[:, 1] + 1e-12)
    ref, _ = front.certified_root_counts(design, q[None])
    assert ex.status["atlas"]["count"] == int(ref[0])
    # a mode change's joint loop is drawn in the atlas and played there (the frames carry it)
    neg = [k for k, mm in enumerate(ex.modes) if mm.aspect < 0]
    plan = ex.change_mode(neg[0], neg[1])
    assert plan.found
    loop = ex.trace("atlas loop")
    assert np.array_equal(np.column_stack([loop.x, loop.y, loop.z]), plan.joint_loop)
    ex.show_frame(7)
    pos = ex.trace("atlas position")
    assert np.array_equal([pos.x[0], pos.y[0], pos.z[0]], plan.joint_loop[7])
    ex.set_q(q)                                            # a move hides the plan
    assert len(ex.trace("atlas loop").x) == 0
    ex.close()
