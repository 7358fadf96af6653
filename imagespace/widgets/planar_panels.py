"""The planar explorer's panels: their traces and layouts (plain plotly data, no plotly import), and
the helpers that place mode labels and join polylines."""

from __future__ import annotations

import html
import json

import numpy as np

from ..drawing import ASPECT_COLOURS

__all__ = ["merged_labels", "joined_polylines", "planar_panels", "GREY"]   # section_regions, status_html: the explorer's helpers, not API

GREY = "#9a9a9a"
"""Colour of the last drawing kept, greyed, when no real mode is left."""


def joined_polylines(polys):
    """Polylines as one ``(n, 2)`` array with NaN rows between them (gaps in a plotly line).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.widgets.planar_panels import joined_polylines
    >>> joined_polylines([np.zeros((2, 2)), np.ones((2, 2))]).shape
    (6, 2)
    """
    if not polys:
        return np.zeros((0, 2))
    gap = np.full((1, 2), np.nan)
    return np.concatenate([part for P in polys for part in (np.asarray(P, dtype=float), gap)])


def merged_labels(points, numbers, scale):
    """Labels for ``points`` (n, d) numbered ``numbers``: points closer than ``scale`` share one label
    ``"1, 3, 4"`` at the first of them; the others get an empty label (no overlapping numbers).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.widgets.planar_panels import merged_labels
    >>> merged_labels(np.array([[0.0, 0], [0.01, 0], [5, 5]]), [1, 3, 2], 0.1)
    ['1, 3', '', '2']
    """
    P = np.asarray(points, dtype=float)
    labels = [""] * len(P)
    done = np.zeros(len(P), dtype=bool)
    order = np.argsort(np.asarray(numbers), kind="stable")
    for i in order:
        if done[i]:
            continue
        group = [i]
        if np.all(np.isfinite(P[i])):
            group += [j for j in order if j != i and not done[j] and np.all(np.isfinite(P[j]))
                      and np.linalg.norm(P[j] - P[i]) <= scale]
        for j in group:
            done[j] = True
        labels[i] = ", ".join(str(numbers[j]) for j in group)
    return labels


def section_regions(coefficients, modes, k, grid):
    """The section view's aspect regions at the orientation of ``modes[k]``: a ``grid`` x ``grid``
    sample of the fixed-orientation conic ``A x^2 + B xy + C y^2 + D x + E y + F`` (``coefficients``,
    six numbers) on a square around the modes' positions, signed so that positive values are the
    aspect det J > 0 (the conic's sign at ``modes[k]`` times that mode's aspect).

    Returns ``(xs, ys, Z)`` with ``Z[i, j]`` at ``(xs[j], ys[i])`` (plotly's heatmap order).

    Examples
    --------
    >>> import numpy as np
    >>> from types import SimpleNamespace
    >>> from imagespace.widgets.planar_panels import section_regions
    >>> mode = SimpleNamespace(pose=np.array([0.0, 0.0, 0.0]), aspect=-1)
    >>> xs, ys, Z = section_regions([1, 0, 1, 0, 0, -1], [mode], 0, 5)    # x^2 + y^2 - 1
    >>> Z.shape, float(Z[2, 2])          # at the mode itself: its own aspect, det J < 0
    ((5, 5), -1.0)
    """
    c = np.asarray(coefficients, dtype=float).reshape(-1)
    mode = modes[k]
    P = np.array([mm.pose for mm in modes], dtype=float)
    lo, hi = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
    half = 0.75 * max(float(np.max(hi - lo)), 1.0)
    mid = (lo + hi) / 2
    xs = np.linspace(mid[0] - half, mid[0] + half, grid)
    ys = np.linspace(mid[1] - half, mid[1] + half, grid)
    X, Y = np.meshgrid(xs, ys)

    def conic(x, y):
        return c[0] * x * x + c[1] * x * y + c[2] * y * y + c[3] * x + c[4] * y + c[5]

    s0 = conic(mode.pose[0], mode.pose[1])
    flip = float(np.sign(s0)) * (1 if mode.aspect >= 0 else -1) if s0 != 0 and mode.aspect != 0 else 1.0
    return xs, ys, flip * conic(X, Y)


def status_html(status, q, modes, mode_numbers, atlas_html=None):
    """The explorer's status line as HTML: the certified count (and on what it is certified), the
    near-singular badge, the error or events, the atlas region (``atlas_html``) and the kernel time.
    The joint values and the modes ride along as ``data-q`` / ``data-modes`` for the browser tests.

    ``status`` is the explorer's status dict (``count``, ``certified``, ``exact``, ``near_singular``,
    ``error``, ``events``, ``seconds``); ``modes`` carry ``pose`` and ``aspect``.

    Examples
    --------
    >>> from imagespace.widgets.planar_panels import status_html
    >>> st = dict(count=0, certified=True, exact=False, near_singular=False, error="", seconds=0.01)
    >>> "no real assembly mode" in status_html(st, [1.0, 2.0, 3.0], [], [])
    True
    """
    st = status
    badge = ('<span style="background:#f0ad4e;color:white;padding:1px 6px;border-radius:8px" '
             'class="isp-near-singular">near singular</span> ') if st["near_singular"] else ""
    if st["error"]:
        body = f'<b class="isp-error" style="color:#b00">{html.escape(st["error"])}</b>'
    else:
        if not st["certified"]:
            how = "NOT certified"
        else:
            how = "certified on the exact joint values" if st["exact"] else "certified on the float joint values"
        body = (f'<b><span class="isp-count">{st["count"]}</span> real assembly mode'
                f'{"" if st["count"] == 1 else "s"}</b> ({how})')
        if st["count"] == 0:
            body += (' &middot; <span class="isp-none">no real assembly mode for these joint values: the legs '
                     'cannot be assembled (the last drawing is shown greyed)</span>')
    if st.get("events"):
        body += f' &middot; <span class="isp-events">{html.escape(st["events"])}</span>'
    if atlas_html is not None:
        body += " &middot; " + atlas_html
    qs = ",".join(repr(float(v)) for v in q)
    data = json.dumps([[int(n), int(mm.aspect)] + [float(v) for v in mm.pose] for n, mm in zip(mode_numbers, modes)])
    return (f'<div class="isp-status" data-q="{qs}" data-modes="{html.escape(data)}">{badge}{body}'
            f' &middot; <span title="time in the kernel: certified direct kinematics and the '
            f'drawing data; the browser adds the round trip and the repaint">kernel time '
            f'<span class="isp-seconds">{1000 * st["seconds"]:.0f}</span> ms</span></div>')


def _scatter(name, **kw):
    return {"type": "scatter", "name": name, "x": np.zeros(0), "y": np.zeros(0), **kw}


def _scatter3d(name, **kw):
    return {"type": "scatter3d", "name": name, "x": np.zeros(0), "y": np.zeros(0), "z": np.zeros(0), **kw}


def planar_panels():
    """The four panels' traces and layouts (empty data), by panel name.

    Examples
    --------
    >>> from imagespace.widgets.planar_panels import planar_panels
    >>> sorted(planar_panels())
    ['loop', 'pose', 'section', 'space']
    """
    pose = [_scatter("guides", mode="lines", hoverinfo="skip", line={"color": "#999999", "dash": "dash", "width": 2},
                     legendgroup="guides")]
    pose.append(_scatter("last drawing", mode="lines", hoverinfo="skip", opacity=0.6, showlegend=False,
                         line={"color": GREY, "width": 2}))
    for a in (1, -1):
        pose.append(_scatter(f"legs{a:+d}", mode="lines", hoverinfo="skip", legendgroup=f"aspect{a:+d}",
                             line={"color": ASPECT_COLOURS[a], "width": 2}, showlegend=False))
        pose.append(_scatter(f"platform{a:+d}", mode="lines", fill="toself", legendgroup=f"aspect{a:+d}",
                             hoverinfo="skip", opacity=0.35, line={"color": ASPECT_COLOURS[a], "width": 1}))
    pose += [_scatter("base", mode="markers", marker={"symbol": "square", "color": "black", "size": 8}),
             _scatter("numbers", mode="text", textfont={"size": 14}, showlegend=False, text=[], hoverinfo="skip"),
             _scatter("moving", mode="lines+markers", line={"color": "#1a9641", "width": 4}, showlegend=False)]
    legend = {"font": {"size": 10}, "orientation": "h", "y": -0.12}
    axis = {"title": {"text": "x [length units]"}}
    pose_layout = {"width": 540, "height": 560, "margin": {"l": 55, "r": 10, "t": 50, "b": 40},
                   "title": {"text": "pose view", "font": {"size": 13}}, "legend": legend, "xaxis": dict(axis),
                   "yaxis": {"title": {"text": "y [length units]"}, "scaleanchor": "x", "scaleratio": 1},
                   "uirevision": "keep", "annotations": [], "plot_bgcolor": "#fafafa"}
    space = [{"type": "mesh3d", "name": "surface", "x": np.zeros(0), "y": np.zeros(0), "z": np.zeros(0),
              "i": np.zeros(0, np.int32), "j": np.zeros(0, np.int32), "k": np.zeros(0, np.int32),
              "color": "#bbbbbb", "opacity": 0.5, "flatshading": True, "showlegend": True, "hoverinfo": "skip"}]
    for a in (1, -1):
        # labels above the red points and below the blue ones: near modes of opposite aspect do not
        # write over each other (near modes of one aspect share a label, merged_labels)
        space.append(_scatter3d(f"points{a:+d}", mode="markers+text", legendgroup=f"aspect{a:+d}", showlegend=False,
                                textposition="top center" if a > 0 else "bottom center", text=[],
                                textfont={"size": 13, "color": ASPECT_COLOURS[a]},
                                marker={"color": ASPECT_COLOURS[a], "size": 6}))
    # the path as a line and dots (a WebGL line alone can be thin or hidden by the surface)
    space += [_scatter3d("path", mode="lines+markers", line={"color": "#006d2c", "width": 8}, showlegend=True,
                         marker={"color": "#00a33a", "size": 3}),
              _scatter3d("position", mode="markers", showlegend=False,
                         marker={"color": "#006d2c", "size": 9, "symbol": "diamond", "line": {"color": "black", "width": 1}})]
    space_layout = {"width": 610, "height": 560, "margin": {"l": 0, "r": 0, "t": 50, "b": 0},
                    "title": {"text": "image space", "font": {"size": 13}}, "uirevision": "keep",
                    "legend": {"font": {"size": 10}, "orientation": "h", "y": 0.02, "x": 0.02},
                    "scene": {"domain": {"x": [0.02, 0.98], "y": [0.06, 1.0]},
                              "camera": {"eye": {"x": 1.9, "y": -1.3, "z": 0.8}}}}
    section = [{"type": "contour", "name": "regions", "x": np.zeros(0), "y": np.zeros(0), "z": np.zeros((0, 0)),
                "showscale": False, "hoverinfo": "skip", "contours": {"start": 0, "end": 0, "size": 1, "coloring": "fill"},
                "showlegend": True, "opacity": 0.45, "line": {"color": "black", "width": 2},
                "colorscale": [[0, ASPECT_COLOURS[-1]], [1, ASPECT_COLOURS[1]]]}]
    for a in (1, -1):
        section.append(_scatter(f"section{a:+d}", mode="markers+text", showlegend=False, textposition="top center",
                                text=[], marker={"color": ASPECT_COLOURS[a], "size": 10, "line": {"color": "black", "width": 1}}))
    section_layout = {"width": 540, "height": 440, "margin": {"l": 55, "r": 10, "t": 50, "b": 45},
                      "title": {"text": "section view", "font": {"size": 13}}, "uirevision": "keep",
                      "xaxis": {"title": {"text": "x [length units]"}, "constrain": "domain"},
                      "yaxis": {"title": {"text": "y [length units]"}, "scaleanchor": "x", "scaleratio": 1,
                                "constrain": "domain"},
                      "legend": {"font": {"size": 10}, "orientation": "h", "y": -0.15}}
    loop = [_scatter(f"loop{i + 1}", mode="lines") for i in range(3)]
    loop.append(_scatter("now", mode="markers", showlegend=False, marker={"color": "black", "size": 8}))
    loop_layout = {"width": 610, "height": 410, "margin": {"l": 60, "r": 10, "t": 50, "b": 45},
                   "title": {"text": "joint loop", "font": {"size": 13}}, "uirevision": "keep",
                   "xaxis": {"title": {"text": "path sample"}},
                   "yaxis": {"title": {"text": "joint change [rad or length units]"}},
                   "legend": {"font": {"size": 10}, "orientation": "h", "y": -0.2}}
    names = {"legs+1": "legs, aspect +1", "legs-1": "legs, aspect -1", "platform+1": "platform, aspect +1 (det J > 0)",
             "platform-1": "platform, aspect -1 (det J < 0)", "base": "base joints", "guides": "prismatic guides",
             "surface": "singularity surface", "path": "certified path", "regions": "singular conic (det J = 0)",
             "loop1": "q1 - q1 at the start", "loop2": "q2 - q2 at the start", "loop3": "q3 - q3 at the start"}
    for traces in (pose, space, section, loop):
        for tr in traces:
            tr["legend_name"] = names.get(tr["name"], tr["name"])
    panels = {"pose": {"data": pose, "layout": pose_layout}, "space": {"data": space, "layout": space_layout},
              "section": {"data": section, "layout": section_layout}, "loop": {"data": loop, "layout": loop_layout}}
    # plotly shows a trace's "name" in the legend; the explorer finds traces by their internal name
    for p in panels.values():
        for tr in p["data"]:
            tr["meta"] = tr["name"]
            tr["name"] = tr.pop("legend_name")
    return panels
