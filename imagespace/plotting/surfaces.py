"""Figures in the image space: the singularity surface, constraint quadrics, conic sections, a path's det J."""

from __future__ import annotations

import numpy as np

from ..drawing import ASPECT_COLOURS
from .common import (pyplot, legend_once, mode_labels, LEG_COLOURS, axes3d, chart_coords, modes_for,
    draw_mesh, label_modes_3d, set_box, LENGTH_UNIT)

__all__ = ['plot_singularity_surface', 'plot_constraint_quadrics', 'plot_conic_section', 'plot_path_singularity']


def plot_singularity_surface(surface, box, chart="image", resolution=48, q=None, modes=None, ax=None,
                             alpha=0.35):
    """The singularity surface with the assembly modes coloured by aspect (seed 002, Abb. 4).

    Parameters
    ----------
    surface : SingularitySurface
    box : (3, 2) float
        In chart coordinates (see :func:`imagespace.singular.meshing.mesh_surface`).
    chart : {"image", "pose"}
    resolution : int
        Grid points per axis of the mesh (48 draws quickly).
    q : (3,) float, optional
        Joint values whose assembly modes are drawn (red: aspect +1, blue: -1).
    modes : list of AssemblyMode, optional
        Instead of ``q``.
    ax : 3D matplotlib Axes, optional
    alpha : float

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``ax`` not a 3D Axes; an invalid box (see
        :func:`imagespace.singular.meshing.mesh_surface`).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.plotting import plot_singularity_surface
    >>> m = isp.examples.stigger_husty()
    >>> fig = plot_singularity_surface(m.singularity_surface(), [(-12, 12), (-12, 12), (-3, 3)],
    ...                                resolution=24, q=m.q_example)
    >>> len(fig.axes)
    1
    """
    from ..singular.meshing import mesh_surface

    b = np.asarray(box, dtype=float)
    mesh = mesh_surface(surface, box, chart=chart, resolution=resolution)
    fig, ax = axes3d(ax)
    draw_mesh(ax, mesh, "0.6", alpha)
    ms = modes_for(surface.manipulator, q, modes)
    if ms:
        P = chart_coords(ms, chart)
        for sign in (1, -1):
            sel = np.array([mm.aspect == sign for mm in ms])
            if sel.any():
                ax.scatter(*P[sel].T, color=ASPECT_COLOURS[sign], s=40, depthshade=False,
                           label=f"modes with aspect {sign:+d} ({sel.sum()})")
        label_modes_3d(ax, P)
    ax.plot([], [], "s", color="0.6", label="det J = 0")
    legend_once(ax, loc="upper left")
    set_box(ax, b, chart)
    ax.set_title(f"{surface.manipulator.name}: det J = 0 ({surface.kind})", fontsize=10)
    return fig


def plot_constraint_quadrics(manipulator, q, box, resolution=40, modes=None, ax=None, alpha=0.25):
    """The three constraint quadrics in the image chart and their intersection points (seed 002, Abb. 2).

    Parameters
    ----------
    manipulator : PlanarParallel
    q : (3,) float or exact numbers
    box : (3, 2) float
        Ranges of ``(x2/x0, x3/x0, x1/x0)``.
    resolution : int
    modes : list of AssemblyMode, optional
        Default: the direct kinematics at ``q``.
    ax : 3D matplotlib Axes, optional
    alpha : float

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``ax`` not a 3D Axes; an invalid box (see
        :func:`imagespace.singular.meshing.mesh_implicit`).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.plotting import plot_constraint_quadrics
    >>> m = isp.examples.stigger_husty()
    >>> fig = plot_constraint_quadrics(m, m.q_example, [(-12, 12), (-12, 12), (-3, 3)], resolution=20)
    >>> len(fig.axes)
    1
    """
    import sympy as sp

    from ..core.quadrics import image_symbols
    from ..singular.meshing import PolynomialImplicit, mesh_implicit

    b = np.asarray(box, dtype=float)
    fig, ax = axes3d(ax)
    x0, x1, x2, x3 = image_symbols()
    u, v, w = sp.symbols("u v w", real=True)
    kinds = [qd.kind for qd in manipulator.quadrics(q)]
    for i, e in enumerate(manipulator.constraint_equations(q)):
        expr = sp.expand(e.xreplace({x0: 1, x1: w, x2: u, x3: v}))
        mesh = mesh_implicit(PolynomialImplicit(expr, (u, v, w), tolerances=manipulator.tolerances), box,
                             resolution=resolution, tolerances=manipulator.tolerances)
        if len(mesh.faces):
            draw_mesh(ax, mesh, LEG_COLOURS[i % 3], alpha)
        ax.plot([], [], color=LEG_COLOURS[i % 3], lw=6, alpha=0.5,
                label=f"H{i + 1}: {manipulator.legs[i].joints} ({kinds[i]} dyad)")
    ms = modes_for(manipulator, q, modes)
    if ms:
        P = chart_coords(ms, "image")
        ax.scatter(*P.T, color="k", s=30, depthshade=False, label=f"{len(ms)} assembly modes")
        label_modes_3d(ax, P)
    legend_once(ax, loc="upper left")
    set_box(ax, b, "image")
    ax.set_title(f"{manipulator.name}: constraint quadrics", fontsize=10)
    return fig


def plot_conic_section(surface, phi, xlim, ylim, q=None, modes=None, ax=None, n=300):
    """The singularity curve at a fixed orientation over the workspace, aspects shaded.

    Parameters
    ----------
    surface : SingularitySurface
        ``"joint-free"`` or ``"given-joints"``.
    phi : float
        Orientation (radians).
    xlim, ylim : (2,) float
        The workspace window.
    q : (3,) float, optional
        Joint values: the assembly modes with orientation ``phi`` (to
        ``Tolerances.plot_orientation``, default 1e-6 rad) are marked.
    modes : list of AssemblyMode, optional
        Instead of ``q``.
    ax : matplotlib Axes, optional
    n : int
        Samples per axis for the shading and the curve.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.plotting import plot_conic_section
    >>> m = isp.examples.stigger_husty()
    >>> mode = m.direct_kinematics(m.q_example)[0]
    >>> fig = plot_conic_section(m.singularity_surface(), mode.pose[2], (-15, 15), (-15, 15), q=m.q_example)
    >>> fig.axes[0].get_title().startswith("phi")
    True
    """
    plt = pyplot()
    from matplotlib.colors import ListedColormap

    con = surface.section(phi)
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(8, 5.5))
    else:
        fig = ax.figure
    xs = np.linspace(*xlim, n)
    ys = np.linspace(*ylim, n)
    Xg, Yg = np.meshgrid(xs, ys)
    Z = con(Xg, Yg)
    ax.contourf(Xg, Yg, np.sign(Z), levels=[-1.5, 0, 1.5],
                cmap=ListedColormap(["#c6dbef", "#fcbba1"]), alpha=0.8)
    if np.nanmin(Z) < 0 < np.nanmax(Z):
        ax.contour(Xg, Yg, Z, levels=[0.0], colors="k", linewidths=1.5)
    near = surface.manipulator.tolerances.plot_orientation
    ms = [(k, mm) for k, mm in enumerate(modes_for(surface.manipulator, q, modes))
          if abs(np.remainder(mm.pose[2] - float(phi) + np.pi, 2 * np.pi) - np.pi) < near]
    for k, mm in ms:
        ax.plot(mm.pose[0], mm.pose[1], "o", color=ASPECT_COLOURS[mm.aspect], mec="k", ms=8)
        ax.annotate(f"mode {k + 1}", mm.pose[:2], textcoords="offset points", xytext=(7, 7), fontsize=9)
    ax.plot([], [], "s", color="#fcbba1", label="det J > 0 (aspect +1)")
    ax.plot([], [], "s", color="#c6dbef", label="det J < 0 (aspect -1)")
    ax.plot([], [], "k-", lw=1.5, label="det J = 0")
    for sign in sorted({mm.aspect for _, mm in ms}, reverse=True):
        ax.plot([], [], "o", color=ASPECT_COLOURS[sign], mec="k", label=f"assembly mode, aspect {sign:+d}")
    if own:
        ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0, fontsize=8)
    else:
        ax.legend(loc="best", fontsize=8)
    ax.set_xlabel(f"x [{LENGTH_UNIT}]")
    ax.set_ylabel(f"y [{LENGTH_UNIT}]")
    ax.set_aspect("equal")
    ax.set_title(f"phi = {np.degrees(float(phi)):.2f} deg: {con.type}", fontsize=10)
    if own:
        fig.tight_layout()
    return fig


def plot_path_singularity(target, path, ax=None, per_piece=200, modes=None):
    """``det J`` along a path and its distance estimate ``|S|/|grad S|`` (seed 002, Abb. 6).

    Parameters
    ----------
    target : PlanarParallel or SingularitySurface
    path : ImagePath
    ax : matplotlib Axes, optional
    per_piece : int
        Samples per piece (the picture only; the certificate is :func:`imagespace.paths.check.check_path`).
    modes : (a, b), optional
        The assembly modes the path joins, named in the title as ``"mode a -> mode b"`` (an
        integer ``a`` becomes ``"mode a"``, anything else is shown as given). Default:
        ``"start -> end"``.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``modes`` not a pair.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.check import pose_segment
    >>> from imagespace.plotting import plot_path_singularity
    >>> m = isp.examples.stigger_husty()
    >>> fig = plot_path_singularity(m, pose_segment([0, 0, 0.2], [3, 1, 0.5]), modes=(1, 4))
    >>> len(fig.axes), fig.axes[0].get_title()
    (2, 'det J along the path: mode 1 -> mode 4')
    """
    plt = pyplot()
    start, end = mode_labels(modes)
    S = target.singularity_surface() if hasattr(target, "singularity_surface") else target
    X, s = path.sample(per_piece)
    X = X / np.hypot(X[:, 0], X[:, 1])[:, None]
    v, G = S.value_and_gradient(X)
    if ax is None:
        fig, ax = plt.subplots(figsize=(8, 4))
    else:
        fig = ax.figure
    ax.plot(s, v, color="k", lw=1.5, label="det J (normalised image point)")
    ax.axhline(0, color="tab:red", lw=0.8, label="det J = 0 (singular)")
    for k in range(1, len(path)):
        ax.axvline(k, color="0.7", lw=0.8, ls="--", label="piece boundary")
    ax.set_xlabel("path parameter s [pieces]")
    ax.set_ylabel("det J [arbitrary units]")
    ax2 = ax.twinx()
    ax2.plot(s, np.abs(v) / np.linalg.norm(G, axis=1), color="tab:blue", lw=1.2,
             label="|det J| / |grad det J|")
    ax2.set_ylabel("distance estimate [image-space units]", color="tab:blue")
    ax2.set_ylim(bottom=0)
    ax.set_xlim(s[0], s[-1])
    ax.set_title(f"det J along the path: {start} -> {end}", fontsize=10)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    seen = dict(zip(l1 + l2, h1 + h2))
    ax.legend(list(seen.values()), list(seen), fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.18),
              ncol=min(4, len(seen)), frameon=False)
    fig.tight_layout()
    return fig


