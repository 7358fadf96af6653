"""Figures of the atlas: matplotlib (static, for papers and notebooks) and plotly (interactive,
for the explorer). Both libraries are imported lazily, inside the functions.

:func:`atlas_figure` is the explorer's panel: the singularity surface of the joint box (one
colour per count threshold), the cusp curves, and the current joint vector ``q`` marked with its
certified number of modes.
"""

from __future__ import annotations

import numpy as np

from .._validate import _short, as_float_array
from ..exceptions import InputError, InputTypeError
from ..solve import front

__all__ = ["plot_atlas", "atlas_figure", "atlas_traces", "plot_atlas_section", "atlas_sheets", "cusp_polyline",
           "box_edges", "q_marker_text", "LEVEL_COLOURS", "COUNT_COLOURS"]

LEVEL_COLOURS = {1.0: "#4C72B0", 3.0: "#DD8452", 5.0: "#55A868", 2.0: "#8172B3", 4.0: "#C44E52"}
"""Colour of the sheet separating ``k - 1`` from ``k + 1`` modes, by level ``k`` (layout only)."""

COUNT_COLOURS = {0: "#f0f0f0", 2: "#9ecae1", 4: "#fdae6b", 6: "#a1d99b", 1: "#dadaeb", 3: "#fcbba1",
                 5: "#c7e9c0"}
"""Colour of a region by its number of real modes (layout only)."""


_ATLAS_FIELDS = ("box", "axes", "counts", "vertices", "faces", "vertex_level", "cusp_curves")


def _check_atlas(atlas):
    # duck-typed (the class lives in .jointspace, which draws through this module)
    if type(atlas).__name__ != "JointAtlas" or not all(hasattr(atlas, f) for f in _ATLAS_FIELDS):
        raise InputTypeError(f"atlas must be a JointAtlas (imagespace.atlas.joint_atlas), got "
                             f"{type(atlas).__name__} {_short(atlas)}")


def _level_name(level, counts=None):
    """``"2 | 4 modes"``: the two counts a sheet at ``level`` separates, i.e. the consecutive counts
    present in ``counts`` (the atlas's grid) whose midpoint the level is (a jump ``2 | 6`` has level
    4); without ``counts``, the odd level's neighbours."""
    if counts is not None:
        present = np.unique(counts[counts >= 0])
        below, above = present[present < level], present[present > level]
        if len(below) and len(above):
            return f"{int(below[-1])} | {int(above[0])} modes"
    lo, hi = int(np.floor(level)), int(np.ceil(level))
    if lo == hi:
        lo, hi = lo - 1, lo + 1
    return f"{lo} | {hi} modes"


def _check_q(atlas, q):
    if q is None:
        return None
    Q = as_float_array(q, "q", last=3)
    if Q.ndim != 1:
        raise InputError(f"q must be one joint vector (3,), got shape {Q.shape}")
    return Q


def _q_count(atlas, q, manipulator=None):
    """Certified count at q: proven anew when the design is at hand, else the atlas's grid."""
    if manipulator is not None:
        c, _ = front.certified_root_counts(manipulator, q[None, :])
        return int(c[0]), "certified at q"
    inside = np.all(q >= atlas.box[:, 0]) and np.all(q <= atlas.box[:, 1])
    return (atlas.count_at(q), "nearest grid node") if inside else (None, "outside the box")


def plot_atlas(atlas, q=None, ax=None, manipulator=None, max_faces=40000, alpha=0.35, labels=None):
    """Matplotlib 3D figure: the singularity surface in joint space, cusp curves, and ``q``.

    Parameters
    ----------
    atlas : JointAtlas
    q : (3,) float, optional
        A joint vector to mark (its count is certified anew when ``manipulator`` is given).
    ax : matplotlib 3D Axes, optional
    manipulator : PlanarParallel, optional
    max_faces : int
        Faces drawn per sheet at most (an even subsample beyond; layout only).
    alpha : float
        Surface transparency.
    labels : sequence of str, optional
        Axis labels (default ``q1, q2, q3``).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    TypeError
        ``atlas`` not a JointAtlas; non-numeric ``q``.
    InputError
        ``q`` not a single joint vector.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import joint_atlas, plot_atlas
    >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
    >>> len(plot_atlas(a, q=[11, 5, 10]).axes)
    1
    """
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    _check_atlas(atlas)
    q = _check_q(atlas, q)
    if ax is None:
        fig = plt.figure(figsize=(7.5, 6.5))
        ax = fig.add_subplot(projection="3d")
    fig = ax.figure
    handles = []
    for level in np.unique(atlas.vertex_level):
        vmask = atlas.vertex_level == level
        fmask = vmask[atlas.faces].all(axis=1)
        F = atlas.faces[fmask]
        if len(F) > max_faces:
            F = F[np.linspace(0, len(F) - 1, max_faces).astype(int)]
        colour = LEVEL_COLOURS.get(float(level), "#999999")
        coll = Poly3DCollection(atlas.vertices[F], facecolor=colour, edgecolor="none", alpha=alpha)
        ax.add_collection3d(coll)
        handles.append(plt.Line2D([], [], color=colour, lw=6, alpha=0.6, label=_level_name(level, atlas.counts)))
    for k, c in enumerate(atlas.cusp_curves):
        ax.plot(c[:, 0], c[:, 1], c[:, 2], color="crimson", lw=2.2)
    if atlas.cusp_curves:
        handles.append(plt.Line2D([], [], color="crimson", lw=2.2, label="cusp curves"))
    if q is not None:
        count, how = _q_count(atlas, q, manipulator)
        ax.scatter(*q, color="black", s=60, depthshade=False)
        handles.append(plt.Line2D([], [], color="black", marker="o", lw=0,
                                  label=f"q: {count} modes ({how})"))
    labels = labels or ("q1", "q2", "q3")
    ax.set_xlim(*atlas.box[0])
    ax.set_ylim(*atlas.box[1])
    ax.set_zlim(*atlas.box[2])
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_zlabel(labels[2])
    fr = atlas.fractions()
    ax.set_title(f"{atlas.name}: joint-space atlas\n" +
                 ", ".join(f"{c} modes {100 * v:.1f}%" for c, v in sorted(fr.items())), fontsize=10)
    ax.legend(handles=handles, loc="upper left", fontsize=8)
    return fig


def plot_atlas_section(atlas, axis=2, index=None, ax=None, q=None):
    """Matplotlib 2D figure: the certified counts on one grid plane of the atlas.

    Parameters
    ----------
    atlas : JointAtlas
    axis : int
        The joint held constant (0, 1 or 2).
    index : int, optional
        Grid plane along ``axis`` (default the middle one; or the one nearest ``q``).
    ax : matplotlib Axes, optional
    q : (3,) float, optional
        A joint vector to mark (and to choose the plane).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    TypeError
        ``atlas`` not a JointAtlas, ``axis``/``index`` not whole numbers.
    InputError
        ``axis`` not 0, 1 or 2, ``index`` outside the grid.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import joint_atlas, plot_atlas_section
    >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
    >>> len(plot_atlas_section(a).axes) >= 1
    True
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap

    from .._validate import as_index
    from ..singular.cusps import free_joints

    _check_atlas(atlas)
    fa, fb = free_joints(axis)
    q = _check_q(atlas, q)
    n = len(atlas.axes[axis])
    if index is None:
        index = (int(np.argmin(np.abs(atlas.axes[axis] - q[axis]))) if q is not None else n // 2)
    index = as_index(index, "index", n)
    C = np.take(atlas.counts, index, axis=axis).astype(float)
    C[C < 0] = np.nan
    if ax is None:
        fig, ax = plt.subplots(figsize=(6, 5))
    fig = ax.figure
    top = 7
    cmap = ListedColormap([COUNT_COLOURS.get(k, "#cccccc") for k in range(top)])
    norm = BoundaryNorm(np.arange(-0.5, top), cmap.N)
    im = ax.pcolormesh(atlas.axes[fa], atlas.axes[fb], C.T, cmap=cmap, norm=norm, shading="nearest")
    cb = fig.colorbar(im, ax=ax, ticks=range(top))
    cb.set_label("certified number of real modes")
    value = atlas.axes[axis][index]
    for c in atlas.cusp_curves:
        near = np.abs(c[:, axis] - value) < 0.5 * atlas.cell[axis]
        if near.any():
            ax.plot(c[near, fa], c[near, fb], "o", color="crimson", ms=3)
    if q is not None:
        ax.plot(q[fa], q[fb], "k*", ms=12)
    ax.set_xlabel(f"q{fa + 1}")
    ax.set_ylabel(f"q{fb + 1}")
    ax.set_title(f"{atlas.name}: q{axis + 1} = {value:.4g}", fontsize=10)
    return fig


def atlas_sheets(atlas, max_faces=60000):
    """The atlas surface split into its sheets, one per count threshold, each with its own vertices.

    The data behind the plotly traces of :func:`atlas_traces` and of the explorer's atlas panel
    (plain arrays, no plotly import).

    Parameters
    ----------
    atlas : JointAtlas
    max_faces : int
        Faces per sheet at most (an even subsample beyond; layout only).

    Returns
    -------
    list of dict
        One per level, lowest first: ``level`` (float), ``name`` (``"2 | 4 modes"``), ``colour``,
        ``vertices`` ``(k, 3)`` float (the sheet's own, in joint space), ``faces`` ``(f, 3)`` int32
        (indices into ``vertices``).

    Raises
    ------
    TypeError
        ``atlas`` not a JointAtlas, ``max_faces`` not a whole number.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import joint_atlas, atlas_sheets
    >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
    >>> [s["name"] for s in atlas_sheets(a)]
    ['0 | 2 modes', '2 | 4 modes', '4 | 6 modes']
    """
    from .._validate import as_count

    _check_atlas(atlas)
    max_faces = as_count(max_faces, "max_faces")
    sheets = []
    for level in np.unique(atlas.vertex_level):
        vmask = atlas.vertex_level == level
        F = atlas.faces[vmask[atlas.faces].all(axis=1)]
        if len(F) > max_faces:
            F = F[np.linspace(0, len(F) - 1, max_faces).astype(int)]
        used = np.unique(F)
        index = np.full(len(atlas.vertices), -1, dtype=np.int64)
        index[used] = np.arange(len(used))
        sheets.append({"level": float(level), "name": _level_name(level, atlas.counts),
                       "colour": LEVEL_COLOURS.get(float(level), "#999999"),
                       "vertices": np.asarray(atlas.vertices[used], dtype=float),
                       "faces": index[F].astype(np.int32).reshape(-1, 3)})
    return sheets


def cusp_polyline(atlas):
    """The atlas's cusp curves as one ``(n, 3)`` polyline with NaN rows between the curves.

    Parameters
    ----------
    atlas : JointAtlas

    Returns
    -------
    (n, 3) float

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import joint_atlas, cusp_polyline
    >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
    >>> cusp_polyline(a).shape
    (0, 3)
    """
    _check_atlas(atlas)
    if not atlas.cusp_curves:
        return np.zeros((0, 3))
    gap = np.full((1, 3), np.nan)
    return np.concatenate([part for c in atlas.cusp_curves for part in (np.asarray(c, dtype=float), gap)])[:-1]


def box_edges(box):
    """The twelve edges of a ``(3, 2)`` box as one ``(36, 3)`` polyline (NaN rows between edges).

    Parameters
    ----------
    box : (3, 2) float

    Returns
    -------
    (36, 3) float

    Raises
    ------
    TypeError
        Non-numeric ``box``.
    InputError
        Not a ``(3, 2)`` box with ``low <= high``.

    Examples
    --------
    >>> from imagespace.atlas import box_edges
    >>> box_edges([(0, 1), (0, 2), (0, 3)]).shape
    (36, 3)
    """
    from .._validate import as_box

    b = as_box(as_float_array(box, "box"), "box", dim=3)
    rows = []
    for axis in range(3):
        others = [k for k in range(3) if k != axis]
        for u in b[others[0]]:
            for v in b[others[1]]:
                for t in b[axis]:
                    p = np.empty(3)
                    p[axis], p[others[0]], p[others[1]] = t, u, v
                    rows.append(p)
                rows.append(np.full(3, np.nan))
    return np.array(rows)


def q_marker_text(q, count, how):
    """Legend name and hover text of the marker at ``q``: ``("q: 6 modes (certified at q)", ...)``.

    Parameters
    ----------
    q : (3,) float
    count : int or None
        The number of real modes at ``q`` (None: not known).
    how : str
        Where the count comes from (``"certified at q"``, ``"nearest grid node"``, ...).

    Returns
    -------
    (str, str)

    Examples
    --------
    >>> from imagespace.atlas import q_marker_text
    >>> q_marker_text([10, 15.2315, 13.25], 6, "certified at q")[0]
    'q: 6 modes (certified at q)'
    """
    q = np.asarray(q, dtype=float).reshape(-1)
    shown = "?" if count is None else str(int(count))
    where = ", ".join(f"{v:.4g}" for v in q)
    return f"q: {shown} modes ({how})", f"q = ({where})<br>{shown} real modes ({how})"


def atlas_traces(atlas, q=None, manipulator=None, max_faces=60000):
    """Plotly traces of the atlas: one ``Mesh3d`` per sheet, ``Scatter3d`` cusp curves, the joint box
    and ``q``.

    Parameters
    ----------
    atlas : JointAtlas
    q : (3,) float, optional
    manipulator : PlanarParallel, optional
        When given, the count at ``q`` is certified anew (else read from the atlas grid).
    max_faces : int
        Faces per sheet at most (layout only).

    Returns
    -------
    list of plotly.graph_objects traces

    Raises
    ------
    TypeError
        ``atlas`` not a JointAtlas; non-numeric ``q``.
    InputError
        ``q`` not a single joint vector.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import joint_atlas, atlas_traces
    >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
    >>> [t.type for t in atlas_traces(a, q=[11, 5, 10])][-1]
    'scatter3d'
    """
    import plotly.graph_objects as go

    _check_atlas(atlas)
    q = _check_q(atlas, q)
    traces = []
    for sheet in atlas_sheets(atlas, max_faces):
        V, F = sheet["vertices"], sheet["faces"]
        traces.append(go.Mesh3d(x=V[:, 0], y=V[:, 1], z=V[:, 2], i=F[:, 0], j=F[:, 1], k=F[:, 2],
                                color=sheet["colour"], opacity=0.45, name=sheet["name"], showlegend=True,
                                hoverinfo="name", flatshading=True))
    for k, c in enumerate(atlas.cusp_curves):
        traces.append(go.Scatter3d(x=c[:, 0], y=c[:, 1], z=c[:, 2], mode="lines",
                                   line=dict(color="crimson", width=6), name="cusp curves",
                                   legendgroup="cusps", showlegend=k == 0))
    E = box_edges(atlas.box)
    traces.append(go.Scatter3d(x=E[:, 0], y=E[:, 1], z=E[:, 2], mode="lines", name="joint box",
                               line=dict(color="#555555", width=2), hoverinfo="skip"))
    if q is not None:
        count, how = _q_count(atlas, q, manipulator)
        name, hover = q_marker_text(q, count, how)
        traces.append(go.Scatter3d(x=[q[0]], y=[q[1]], z=[q[2]], mode="markers",
                                   marker=dict(size=7, color="black", symbol="diamond"),
                                   name=name, hovertext=hover, hoverinfo="text"))
    return traces


def atlas_figure(atlas, q=None, manipulator=None):
    """Plotly figure of the atlas with the current joint vector ``q`` marked (the explorer's panel).

    Parameters
    ----------
    atlas : JointAtlas
    q : (3,) float, optional
    manipulator : PlanarParallel, optional
        When given, the count at ``q`` is certified anew.

    Returns
    -------
    plotly.graph_objects.Figure

    Raises
    ------
    TypeError
        ``atlas`` not a JointAtlas; non-numeric ``q``.
    InputError
        ``q`` not a single joint vector.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import joint_atlas, atlas_figure
    >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
    >>> atlas_figure(a, q=[11, 5, 10]).layout.scene.xaxis.title.text
    'q1'
    """
    import plotly.graph_objects as go

    fig = go.Figure(atlas_traces(atlas, q=q, manipulator=manipulator))
    fr = atlas.fractions()
    fig.update_layout(
        title=f"{atlas.name}: joint-space atlas (" +
              ", ".join(f"{c} modes {100 * v:.1f}%" for c, v in sorted(fr.items())) + ")",
        scene=dict(xaxis=dict(title="q1", range=list(atlas.box[0])),
                   yaxis=dict(title="q2", range=list(atlas.box[1])),
                   zaxis=dict(title="q3", range=list(atlas.box[2])), aspectmode="cube"),
        legend=dict(x=0, y=1), margin=dict(l=0, r=0, t=40, b=0))
    return fig
