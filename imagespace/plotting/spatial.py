"""Figures of spatial platforms: a Gough-Stewart platform, all its modes, a singularity mesh."""

from __future__ import annotations

import numpy as np

from .._validate import as_count, as_float_array
from ..drawing import ASPECT_COLOURS
from ..exceptions import InputError, InputTypeError
from .common import (pyplot, legend_once, axes3d, draw_mesh, GS_LEG_CMAP, GS_BASE_COLOUR, polygon_order,
    cube_limits, gough_stewart_points, LENGTH_UNIT)

__all__ = ['plot_gough_stewart', 'plot_gough_stewart_modes', 'plot_singularity_mesh']


def plot_gough_stewart(gs, s, ax=None, title=None, legend=True, platform_colour="tab:red", limits=None):
    """Draw a Gough-Stewart platform at one pose: the base and platform polygons and the six legs.

    Parameters
    ----------
    gs : GoughStewart
    s : (8,) float
        The pose as a Study point (:func:`imagespace.spatial.study.study_point`).
    ax : 3D matplotlib Axes, optional
    title : str, optional
    legend : bool
        Label the legs (with their lengths), base and platform.
    platform_colour : matplotlib colour
    limits : (m, 3) float, optional
        Points the equal-scaled axes must show (default: the drawn anchors); panels of one figure
        pass the same points to share a scale.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``s`` not ``(8,)``, not finite, or with ``x = 0``; ``ax`` not a 3D Axes.

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.plotting import plot_gough_stewart
    >>> rng = np.random.default_rng(0)
    >>> gs = isp.spatial.GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> fig = plot_gough_stewart(gs, [1, 0, 0, 0, 0, 0, 0, 1.0])
    >>> len(fig.axes), len(fig.axes[0].lines)
    (1, 8)
    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    plt = pyplot()
    z = as_float_array(s, "s", last=8, allow_batch=False)
    own = ax is None
    fig, ax = axes3d(ax)
    A, X = gough_stewart_points(gs, z)
    L = np.linalg.norm(X - A, axis=1)
    cmap = plt.get_cmap(GS_LEG_CMAP)
    for poly, colour, label in ((A, GS_BASE_COLOUR, "base"), (X, platform_colour, "platform")):
        ring = poly[polygon_order(poly)]
        ax.add_collection3d(Poly3DCollection([ring], facecolors=colour, alpha=0.25, edgecolor="none"))
        closed = np.vstack([ring, ring[:1]])
        ax.plot(*closed.T, color=colour, lw=1.5, label=label)
    for i in range(6):
        seg = np.stack([A[i], X[i]])
        ax.plot(*seg.T, "-", color=cmap(i % 8), lw=2.2, label=f"leg {i + 1}: L = {L[i]:.4g}")
    ax.scatter(*A.T, color="k", s=12, depthshade=False)
    ax.scatter(*X.T, color=platform_colour, s=12, depthshade=False)
    cube_limits(ax, np.vstack([A, X]) if limits is None else np.asarray(limits, dtype=float))
    ax.set_xlabel(f"x [{LENGTH_UNIT}]", fontsize=8)
    ax.set_ylabel(f"y [{LENGTH_UNIT}]", fontsize=8)
    ax.set_zlabel(f"z [{LENGTH_UNIT}]", fontsize=8)
    if title:
        ax.set_title(title, fontsize=9)
    if legend:
        legend_once(ax, fontsize=7, loc="upper left", bbox_to_anchor=(1.05, 1), borderaxespad=0)
        if own:
            fig.subplots_adjust(left=0.0, right=0.74)          # room for the legend on the right
    return fig


def plot_gough_stewart_modes(gs, study_points, aspects=None, ncols=4, panel_size=2.8, title=None):
    """All real assembly modes of a Gough-Stewart platform, one small 3D panel each.

    Panels share one equal scale (every mode's anchors fit in each panel) and are titled with the
    mode's index (from 1) and its aspect.

    Parameters
    ----------
    gs : GoughStewart
    study_points : (k, 8) float, or a direct-kinematics result
        The modes' Study points; an object with ``.study_points`` (and ``.aspects``), e.g. the
        result of ``gs.direct_kinematics``, is taken as it is.
    aspects : (k,) int, optional
        Default: the result's ``.aspects``, else
        :func:`imagespace.spatial.singularities.aspect`.
    ncols : int
    panel_size : float
        Inches per panel.
    title : str, optional
        Default: ``"<k> real assembly modes"``.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        No mode to draw, Study points of a wrong shape, or ``aspects`` of a length other than ``k``.

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.plotting import plot_gough_stewart_modes
    >>> rng = np.random.default_rng(0)
    >>> gs = isp.spatial.GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> S = isp.spatial.study_point(rng.normal(size=(3, 4)), rng.normal(size=(3, 3)))
    >>> fig = plot_gough_stewart_modes(gs, S, ncols=2)
    >>> [a.get_title().split(" (")[0] for a in fig.axes if a.get_visible()]
    ['mode 1', 'mode 2', 'mode 3']
    """
    from matplotlib.ticker import MaxNLocator

    from ..spatial.singularities import aspect

    plt = pyplot()
    if hasattr(study_points, "study_points"):
        if aspects is None:
            aspects = getattr(study_points, "aspects", None)
        study_points = study_points.study_points
    S = as_float_array(study_points, "study_points", last=8)
    S = S.reshape(-1, 8)
    k = len(S)
    if k == 0:
        raise InputError("study_points holds no assembly mode to plot (shape (0, 8))")
    asp = aspect(gs, S) if aspects is None else np.asarray(aspects).reshape(-1)
    if len(asp) != k:
        raise InputError(f"aspects must have one entry per mode ({k}), got {len(asp)}")
    ncol = max(1, min(as_count(ncols, "ncols"), k))
    nrows = int(np.ceil(k / ncol))
    fig = plt.figure(figsize=(panel_size * ncol, panel_size * nrows + 0.5))
    pts = np.vstack([np.vstack(gough_stewart_points(gs, s)) for s in S])
    for i, s in enumerate(S):
        a = fig.add_subplot(nrows, ncol, i + 1, projection="3d")
        plot_gough_stewart(gs, s, ax=a, legend=False, limits=pts,
                           platform_colour=ASPECT_COLOURS.get(int(asp[i]), "tab:red"),
                           title=f"mode {i + 1} (aspect {int(asp[i]):+d})")
        a.tick_params(labelsize=5, pad=-2)
        for axis, name in ((a.xaxis, "x"), (a.yaxis, "y"), (a.zaxis, "z")):
            axis.set_major_locator(MaxNLocator(3))
            axis.set_label_text(name, fontsize=7)       # the unit is in the figure's title
            axis.labelpad = -8
    height = panel_size * nrows + 0.5
    fig.suptitle(title or f"{k} real assembly mode{'s' if k != 1 else ''} "
                          f"(platform red: aspect +1, blue: -1; axes x, y, z in {LENGTH_UNIT})", fontsize=10,
                 y=1 - 0.1 / height, va="top")
    fig.subplots_adjust(left=0.02, right=0.98, bottom=0.02, top=1 - 0.75 / height, wspace=0.05, hspace=0.15)
    return fig


def plot_singularity_mesh(mesh, ax=None, colour="0.6", alpha=0.45, points=None, aspects=None, title=None,
                          labels=(f"x [{LENGTH_UNIT}]", f"y [{LENGTH_UNIT}]", f"z [{LENGTH_UNIT}]")):
    """Draw a triangle mesh in 3D (e.g. the constant-orientation singularity surface), shaded.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        E.g. from :func:`imagespace.spatial_surfaces.mesh_constant_orientation_singularity` or
        :func:`imagespace.singular.meshing.mesh_implicit`; its box (``metadata["imagespace"]["box"]``)
        sets the limits when present.
    ax : 3D matplotlib Axes, optional
    colour : matplotlib colour
    alpha : float
    points : (m, 3) float, optional
        Points to mark (e.g. platform positions), coloured by ``aspects`` when given.
    aspects : (m,) int, optional
    title : str, optional
    labels : three str

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    TypeError
        ``mesh`` not a :class:`trimesh.Trimesh`.
    InputError
        ``ax`` not a 3D Axes; ``points`` not ``(m, 3)``; ``aspects`` of another length.

    Examples
    --------
    >>> import trimesh
    >>> from imagespace.plotting import plot_singularity_mesh
    >>> fig = plot_singularity_mesh(trimesh.creation.icosphere(subdivisions=1))
    >>> len(fig.axes[0].collections)
    1
    """
    import trimesh

    if not isinstance(mesh, trimesh.Trimesh):
        raise InputTypeError(f"mesh must be a trimesh.Trimesh, got {type(mesh).__name__}")
    fig, ax = axes3d(ax)
    if len(mesh.faces):
        draw_mesh(ax, mesh, colour, alpha)
    ax.plot([], [], "s", color=colour, label=f"det J = 0 ({len(mesh.faces)} triangles)")
    box = mesh.metadata.get("imagespace", {}).get("box") if isinstance(mesh.metadata, dict) else None
    if points is not None:
        P = as_float_array(points, "points", last=3).reshape(-1, 3)
        if aspects is None:
            ax.scatter(*P.T, color="k", s=30, depthshade=False, label=f"{len(P)} points")
        else:
            asp = np.asarray(aspects).reshape(-1)
            if len(asp) != len(P):
                raise InputError(f"aspects must have one entry per point ({len(P)}), got {len(asp)}")
            for sign in (1, -1, 0):
                sel = asp == sign
                if sel.any():
                    ax.scatter(*P[sel].T, color=ASPECT_COLOURS[sign], s=30, depthshade=False,
                               label=f"aspect {sign:+d} ({int(sel.sum())})")
    if box is not None:
        b = np.asarray(box, dtype=float)
        ax.set_xlim(*b[0])
        ax.set_ylim(*b[1])
        ax.set_zlim(*b[2])
        ax.set_box_aspect(tuple(b[:, 1] - b[:, 0]))
    elif len(mesh.vertices):
        cube_limits(ax, np.asarray(mesh.vertices), pad=0.02)
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_zlabel(labels[2])
    if title:
        ax.set_title(title, fontsize=10)
    legend_once(ax, loc="upper left")
    return fig
