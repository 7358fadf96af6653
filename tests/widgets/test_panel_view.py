"""The panel widget's message protocol: per-panel content revisions (the browser redraws only the
panels whose content changed) and the reply to a stale view's "hello"."""

import numpy as np

from imagespace.widgets.view import PanelView


def _view():
    panels = {"pose": {"data": [{"type": "scatter", "name": "legs", "x": [], "y": []}], "layout": {}},
              "space": {"data": [{"type": "scatter3d", "name": "surface", "x": [], "y": [], "z": []}],
                        "layout": {}}}
    v = PanelView(panels, order=["pose", "space"], columns=[300, 300], urgent=["pose"])
    sent = []
    v.send = lambda content, buffers=None: sent.append(content)
    return v, sent


def test_a_change_bumps_only_its_panels_revision_and_the_update_says_so():
    v, sent = _view()
    before = dict(v.spec["revs"])
    with v.batch():
        v.set("legs", x=np.array([0.0, 1.0]), y=np.array([1.0, 2.0]))
    (update,) = [c for c in sent if c["type"] == "update"]
    assert set(update["panels"]) == {"pose"}
    assert update["revs"] == {"pose": before["pose"] + 1}
    v.relayout("space", "title.text", "image space")
    v.publish()
    assert v.spec["revs"] == {"pose": before["pose"] + 1, "space": before["space"] + 1}
    assert v.spec["urgent"] == ["pose"]


def test_hello_from_a_stale_view_gets_the_whole_state_with_its_revisions():
    v, sent = _view()
    current = v.spec["version"]
    v._on_front(v, {"type": "hello", "version": current}, [])
    assert [c for c in sent if c["type"] == "full"] == []
    # a view opened after updates (which it missed) asks with the version it was built from
    v.set("legs", x=np.array([0.0]), y=np.array([0.0]))
    v._on_front(v, {"type": "hello", "version": current}, [])
    (full,) = [c for c in sent if c["type"] == "full"]
    assert full["spec"]["version"] == current + 1
    assert full["spec"]["revs"]["pose"] == v.spec["revs"]["pose"] + 1
    assert full["spec"]["revs"]["space"] == v.spec["revs"]["space"]
