"""The planar explorer's atlas panel: the joint-space atlas (:mod:`imagespace.atlas`) in 3D, with the
current joint vector marked and its certified number of real modes.

``isp.widgets.explore(m, atlas=a)`` (a :class:`~imagespace.atlas.JointAtlas` of the design) or
``atlas=True`` (one computed in the background on :func:`default_atlas_box` at
:data:`ATLAS_RESOLUTION` nodes per axis) adds the panel. Its traces: the count-change surface, one
sheet per pair of counts it separates (:func:`~imagespace.atlas.atlas_sheets`, coloured by level),
the cusp curves, the joint box, the marker at ``q`` and, while a mode change is shown, its joint
loop. Per slider move only the marker's trace changes (a point and its legend text); the surface is
sent once.

The marker's count is the explorer's own certified count at ``q`` (the status line's), never the
atlas's grid label: near the surface the nearest grid node may lie on the other side. The grid's
region is shown beside it, with a note when the two differ.
"""

from __future__ import annotations

import numpy as np

from .._validate import _short
from ..exceptions import InputError, InputTypeError
from .inputs import joint_ranges

__all__ = ["ATLAS_RESOLUTION", "ATLAS_SPAN", "ATLAS_SLOTS", "atlas_panel", "default_atlas_box",
           "check_atlas_option", "AtlasPanel"]

ATLAS_RESOLUTION = 24
"""Grid nodes per axis of the atlas computed by ``explore(m, atlas=True)`` (a coarse atlas: a few
seconds in the background, cusp curves included)."""
ATLAS_SPAN = 0.2
"""Fraction of each slider's range covered by the default atlas box (centred on the starting ``q``)."""
ATLAS_SLOTS = 6
"""Surface sheets the panel can show (one per count threshold; a planar design has at most 6 modes,
so at most 6 thresholds)."""
_SAMPLE_CHECKS = 8               # regions whose sample count is proven again when an atlas is passed in


def _empty3d():
    return {"x": np.zeros(0), "y": np.zeros(0), "z": np.zeros(0)}


def atlas_panel(manipulator, box):
    """The atlas panel's traces (empty surface slots) and layout, for the explorer's
    :class:`~imagespace.widgets.view.PanelView`.

    Parameters
    ----------
    manipulator : PlanarParallel
    box : (3, 2) float
        The atlas's joint box (the scene's ranges).

    Returns
    -------
    dict
        ``{"data": [trace dicts], "layout": dict}``; each trace's internal name in ``meta``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.widgets.planar_atlas import atlas_panel
    >>> m = isp.examples.stigger_husty()
    >>> p = atlas_panel(m, [(6, 14), (11, 19), (9, 17)])
    >>> [t["meta"] for t in p["data"]][-3:]
    ['atlas loop', 'atlas position', 'atlas q']
    """
    from ..atlas.figures import box_edges

    box = np.asarray(box, dtype=float)
    data = []
    for k in range(ATLAS_SLOTS):
        data.append({"type": "mesh3d", "meta": f"atlas sheet {k}", "name": "", **_empty3d(),
                     "i": np.zeros(0, np.int32), "j": np.zeros(0, np.int32), "k": np.zeros(0, np.int32),
                     "color": "#999999", "opacity": 0.45, "flatshading": True, "showlegend": False,
                     "hoverinfo": "name"})
    data.append({"type": "scatter3d", "meta": "atlas cusps", "name": "cusp curves", "mode": "lines", **_empty3d(),
                 "line": {"color": "crimson", "width": 6}, "showlegend": False, "hoverinfo": "name"})
    E = box_edges(box)
    data.append({"type": "scatter3d", "meta": "atlas box", "name": "joint box", "mode": "lines",
                 "x": E[:, 0], "y": E[:, 1], "z": E[:, 2], "line": {"color": "#555555", "width": 2},
                 "hoverinfo": "skip"})
    data.append({"type": "scatter3d", "meta": "atlas loop", "name": "joint loop of the mode change",
                 "mode": "lines", **_empty3d(), "line": {"color": "#006d2c", "width": 6}, "showlegend": False,
                 "hoverinfo": "skip"})
    data.append({"type": "scatter3d", "meta": "atlas position", "name": "path sample", "mode": "markers",
                 **_empty3d(), "showlegend": False, "hoverinfo": "skip",
                 "marker": {"color": "#006d2c", "size": 6, "symbol": "circle"}})
    data.append({"type": "scatter3d", "meta": "atlas q", "name": "q", "mode": "markers", **_empty3d(),
                 "hovertext": "", "hoverinfo": "text",
                 "marker": {"color": "black", "size": 7, "symbol": "diamond", "line": {"color": "white", "width": 1}}})
    pad = 0.02 * (box[:, 1] - box[:, 0])
    axes = {}
    for i, (key, leg) in enumerate(zip(("xaxis", "yaxis", "zaxis"), manipulator.legs)):
        unit = "rad" if leg.actuated_is_angle else "length"
        axes[key] = {"title": {"text": f"q{i + 1} [{unit}]"},
                     "range": [float(box[i, 0] - pad[i]), float(box[i, 1] + pad[i])]}
    layout = {"width": 540, "height": 520, "margin": {"l": 0, "r": 0, "t": 50, "b": 0},
              "title": {"text": "joint-space atlas", "font": {"size": 13}}, "uirevision": "keep",
              "legend": {"font": {"size": 10}, "orientation": "h", "y": 0.0, "x": 0.02},
              "scene": {**axes, "aspectmode": "cube", "domain": {"x": [0.0, 1.0], "y": [0.1, 1.0]},
                        "camera": {"eye": {"x": 1.7, "y": -1.5, "z": 0.9}}}}
    return {"data": data, "layout": layout}


def default_atlas_box(manipulator, q):
    """The joint box of ``explore(m, atlas=True)``: ``q`` plus or minus :data:`ATLAS_SPAN` / 2 of each
    slider's range (:func:`~imagespace.widgets.joint_ranges`), kept inside the slider's range.

    Parameters
    ----------
    manipulator : PlanarParallel
    q : (3,) float

    Returns
    -------
    (3, 2) float

    Raises
    ------
    InputError
        ``q`` not three finite numbers, or the box leaving a joint's domain.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.widgets.planar_atlas import default_atlas_box
    >>> m = isp.examples.stigger_husty()
    >>> default_atlas_box(m, m.q_example_float).round(2).tolist()
    [[6.0, 14.0], [11.23, 19.23], [9.25, 17.25]]
    """
    from ..atlas.boxes import check_joint_box

    ranges = joint_ranges(manipulator, q)
    q = np.asarray(q, dtype=float)
    half = 0.5 * ATLAS_SPAN * (ranges[:, 1] - ranges[:, 0])
    box = np.column_stack([np.maximum(q - half, ranges[:, 0]), np.minimum(q + half, ranges[:, 1])])
    return check_joint_box(manipulator, box, "the default atlas box")


def check_atlas_option(atlas, manipulator):
    """Validate the explorer's ``atlas`` argument.

    Parameters
    ----------
    atlas : JointAtlas, True, False or None
    manipulator : PlanarParallel

    Returns
    -------
    (JointAtlas or None, bool)
        The atlas given (None for True/False/None) and whether one is to be computed.

    Raises
    ------
    TypeError
        ``atlas`` neither a JointAtlas nor True/False/None (a string is never read).
    InputError
        A JointAtlas of another design: its box leaves this design's joint domains, or a region's
        count differs from this design's certified count at the region's sample point.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.widgets.planar_atlas import check_atlas_option
    >>> check_atlas_option(True, isp.examples.stigger_husty())
    (None, True)
    """
    if atlas is None:
        return None, False
    if isinstance(atlas, (bool, np.bool_)):
        return None, bool(atlas)
    from ..atlas.jointspace import JointAtlas

    if not isinstance(atlas, JointAtlas):
        raise InputTypeError(f"atlas must be a JointAtlas (imagespace.atlas.joint_atlas(m, joint_box)), True "
                             f"(compute one in the background) or None, got {type(atlas).__name__} {_short(atlas)}")
    from ..atlas.boxes import check_joint_box
    from ..solve import front

    check_joint_box(manipulator, atlas.box, "atlas.box")
    regions = [r for r in atlas.regions[:_SAMPLE_CHECKS]]
    if regions:
        counts, _ = front.certified_root_counts(manipulator, np.array([r.sample for r in regions], dtype=float))
        for r, c in zip(regions, np.asarray(counts).astype(int)):
            if c >= 0 and c != r.count:
                raise InputError(f"atlas must be an atlas of this design ({manipulator.name!r}); the one given "
                                 f"(of {atlas.name!r}) says {r.count} modes in its region {r.label} at "
                                 f"q = {np.round(r.sample, 6).tolist()}, where this design has {c} (certified)")
    return atlas, False


class AtlasPanel:
    """The atlas panel's state and drawing, owned by the planar explorer.

    Attributes
    ----------
    atlas : JointAtlas or None
        None while it is computed in the background (or if that failed).
    box : (3, 2) float
    state : str
        ``"computing"``, ``"ready"`` or ``"failed: <reason>"``.
    info : dict
        What the marker shows (see :meth:`marker`).
    """

    def __init__(self, manipulator, box, atlas=None):
        self.manipulator = manipulator
        self.box = np.asarray(box, dtype=float)
        self.atlas = atlas
        self.state = "ready" if atlas is not None else "computing"
        self.info = {}
        self._loop_shown = False

    # -- the surface (sent once) ----------------------------------------------------------------
    def show_atlas(self, view, atlas):
        """Put ``atlas``'s sheets and cusp curves into the panel (inside the caller's batch)."""
        from ..atlas.figures import atlas_sheets, cusp_polyline

        self.atlas, self.state = atlas, "ready"
        sheets = atlas_sheets(atlas)
        for k in range(ATLAS_SLOTS):
            if k < len(sheets):
                s = sheets[k]
                V, F = s["vertices"], s["faces"]
                view.set(f"atlas sheet {k}", x=V[:, 0].copy(), y=V[:, 1].copy(), z=V[:, 2].copy(),
                         i=F[:, 0].copy(), j=F[:, 1].copy(), k=F[:, 2].copy(), color=s["colour"],
                         name=f"surface: {s['name']}", showlegend=True)
            else:
                view.set(f"atlas sheet {k}", **_empty3d(), i=np.zeros(0, np.int32), j=np.zeros(0, np.int32),
                         k=np.zeros(0, np.int32), name="", showlegend=False)
        C = cusp_polyline(atlas)
        view.set("atlas cusps", x=C[:, 0].copy(), y=C[:, 1].copy(), z=C[:, 2].copy(), showlegend=len(C) > 0)
        shape = atlas.counts.shape
        grid = f"{shape[0]}^3" if len(set(shape)) == 1 else "x".join(map(str, shape))
        fr = ", ".join(f"{c}: {100 * v:.0f}%" for c, v in sorted(atlas.fractions().items()))
        view.relayout("atlas", "title.text", f"joint-space atlas ({grid} certified nodes; modes {fr})")

    def failed(self, view, reason):
        self.state = f"failed: {reason}"
        view.relayout("atlas", "title.text", "joint-space atlas (failed; see the status line)")

    # -- the marker (per update) ----------------------------------------------------------------
    def _node(self, q):
        """Index of the grid node nearest to ``q`` (inside the box), or None."""
        a = self.atlas
        if a is None or np.any(q < a.box[:, 0]) or np.any(q > a.box[:, 1]):
            return None
        shape = np.array(a.counts.shape)
        step = (a.box[:, 1] - a.box[:, 0]) / np.maximum(shape - 1, 1)
        return tuple(int(v) for v in np.clip(np.rint((q - a.box[:, 0]) / step).astype(int), 0, shape - 1))

    def marker(self, view, q, status):
        """Move the marker to ``q`` and show the explorer's count there (``status``: the explorer's
        status dict: ``count``, ``certified``, ``exact``, ``error``). Sets :attr:`info`: ``state``,
        ``inside`` (q in the box), ``count`` (the count shown, or None when not certified),
        ``certified``, ``region`` and ``region_count`` (the grid region of the nearest node and its
        count; None while the atlas is computed or outside the box)."""
        from ..atlas.figures import q_marker_text

        q = np.asarray(q, dtype=float)
        inside = bool(np.all(q >= self.box[:, 0]) and np.all(q <= self.box[:, 1]))
        certified = bool(status["certified"]) and not status["error"]
        count = int(status["count"]) if certified else None
        how = ("certified at the exact q" if status["exact"] else "certified at q") if certified else "NOT certified"
        node = self._node(q)
        region = region_count = None
        if node is not None:
            label = int(self.atlas.labels[node])
            region = label if label >= 0 else None
            region_count = int(self.atlas.counts[node]) if self.atlas.counts[node] >= 0 else None
        name, hover = q_marker_text(q, count, how)
        if not inside:
            name += ", outside the atlas box"
            view.set("atlas q", **_empty3d(), name=name, hovertext=hover)
        else:
            view.set("atlas q", x=q[:1].copy(), y=q[1:2].copy(), z=q[2:3].copy(), name=name, hovertext=hover)
        self.info = {"state": self.state, "inside": inside, "count": count, "certified": certified,
                     "region": region, "region_count": region_count}
        return self.info

    def status_html(self):
        """The atlas part of the status line (HTML)."""
        import html

        info = self.info
        if not info:
            return ""
        attrs = (f'data-count="{"" if info["count"] is None else info["count"]}" '
                 f'data-region="{"" if info["region"] is None else info["region"]}"')
        if self.state == "computing":
            text = "atlas: computing in the background"
        elif self.state != "ready":
            text = "atlas " + self.state
        elif not info["inside"]:
            text = "atlas: q is outside its joint box"
        elif info["region"] is None:
            text = "atlas: the grid node nearest to q is not certified"
        else:
            shown = "?" if info["count"] is None else info["count"]
            text = f"atlas: q in region {info['region']} ({shown} modes)"
            if info["count"] is not None and info["region_count"] != info["count"]:
                text = (f"atlas: q has {info['count']} modes (certified); its nearest grid node, in region "
                        f"{info['region']}, has {info['region_count']}: q is within a grid cell of the "
                        f"count-change surface")
        return f'<span class="isp-atlas" {attrs}>{html.escape(text)}</span>'

    # -- a mode change ---------------------------------------------------------------------------
    def show_loop(self, view, joint_loop):
        J = np.asarray(joint_loop, dtype=float)
        view.set("atlas loop", x=J[:, 0].copy(), y=J[:, 1].copy(), z=J[:, 2].copy(), showlegend=True)
        self._loop_shown = True

    def hide_loop(self, view):
        """Remove a mode change's joint loop (nothing is sent when none is shown)."""
        if self._loop_shown:
            view.set("atlas loop", **_empty3d(), showlegend=False)
            view.set("atlas position", **_empty3d())
            self._loop_shown = False

    @staticmethod
    def frames(joint_loop):
        J = np.asarray(joint_loop, dtype=float)
        return {"atlas position": {"x": J[:, :1], "y": J[:, 1:2], "z": J[:, 2:3]}}
