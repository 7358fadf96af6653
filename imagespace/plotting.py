"""Matplotlib figures. Imported lazily: ``import imagespace`` does not import matplotlib.

Every figure function returns the :class:`matplotlib.figure.Figure` and accepts an optional
``ax`` to draw into.
"""

from __future__ import annotations

import numpy as np

from ._validate import as_float_array
from .exceptions import InputError

__all__ = ["plot_mechanism", "plot_assembly_modes"]

_LEG_COLOURS = ("tab:blue", "tab:orange", "tab:green")


def _pyplot():
    import matplotlib.pyplot as plt

    return plt


def plot_mechanism(manipulator, pose, q=None, ax=None, title=None, platform_colour="tab:red"):
    """Draw the manipulator at one pose: base anchors, legs, platform.

    Parameters
    ----------
    manipulator : PlanarParallel
    pose : (3,) float
    q : (3,) float, optional
        Joint values; used to pick each leg's branch (e.g. the elbow of an RRR leg).
    ax : matplotlib Axes, optional
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.plotting import plot_mechanism
    >>> m = isp.examples.stigger_husty()
    >>> fig = plot_mechanism(m, m.direct_kinematics(m.q_example)[0].pose)
    >>> len(fig.axes)
    1
    """
    plt = _pyplot()
    p = as_float_array(pose, "pose", last=3, allow_batch=False)
    if ax is None:
        fig, ax = plt.subplots(figsize=(5, 5))
    else:
        fig = ax.figure
    legs = manipulator.leg_points(p, q)
    anchors = []
    for i, pts in enumerate(legs):
        ax.plot(pts[:, 0], pts[:, 1], "-o", color=_LEG_COLOURS[i % 3], lw=2, ms=4,
                label=f"leg {i + 1} ({manipulator.legs[i].joints})")
        ax.plot(*pts[0], "ks", ms=7)
        anchors.append(pts[-1])
    poly = np.array(anchors + [anchors[0]])
    ax.fill(poly[:, 0], poly[:, 1], color=platform_colour, alpha=0.25)
    ax.plot(poly[:, 0], poly[:, 1], color=platform_colour, lw=1.5)
    ax.plot(p[0], p[1], "+", color="k", ms=10)
    ax.set_aspect("equal")
    ax.grid(True, alpha=0.3)
    if title:
        ax.set_title(title, fontsize=9)
    return fig


def plot_assembly_modes(manipulator, q, modes=None, ax=None, ncols=3):
    """All real assembly modes for the joint values ``q``, one panel each (or overlaid on ``ax``).

    Parameters
    ----------
    manipulator : PlanarParallel
    q : (3,) float or exact numbers
    modes : list of AssemblyMode, optional
        Default: ``manipulator.direct_kinematics(q)``.
    ax : matplotlib Axes, optional
        Draw every mode into this one axes instead of a grid.
    ncols : int

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.plotting import plot_assembly_modes
    >>> m = isp.examples.stigger_husty()
    >>> len(plot_assembly_modes(m, m.q_example).axes)
    6
    """
    plt = _pyplot()
    qf = np.array([float(v) for v in q])
    if modes is None:
        modes = manipulator.direct_kinematics(qf)
    if not modes:
        raise InputError(f"q = {qf.tolist()} has no real assembly mode to plot")
    if ax is not None:
        cmap = plt.get_cmap("viridis")
        for k, mode in enumerate(modes):
            plot_mechanism(manipulator, mode.pose, qf, ax=ax, platform_colour=cmap(k / max(1, len(modes) - 1)))
        return ax.figure
    nrows = int(np.ceil(len(modes) / ncols))
    fig, axes = plt.subplots(nrows, min(ncols, len(modes)), figsize=(4 * min(ncols, len(modes)), 4 * nrows),
                             squeeze=False)
    pts = np.concatenate([np.concatenate(manipulator.leg_points(mm.pose, qf)) for mm in modes])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.08 * np.max(hi - lo)
    for k, mode in enumerate(modes):
        a = axes.flat[k]
        x, y, phi = mode.pose
        plot_mechanism(manipulator, mode.pose, qf, ax=a,
                       title=f"mode {k + 1}: x={x:.3f}, y={y:.3f}, phi={np.degrees(phi):.2f} deg, "
                             f"aspect {mode.aspect:+d}")
        a.set_xlim(lo[0] - pad, hi[0] + pad)
        a.set_ylim(lo[1] - pad, hi[1] + pad)
    for a in list(axes.flat)[len(modes):]:
        a.set_visible(False)
    fig.suptitle(f"{manipulator.name}: {len(modes)} assembly modes")
    fig.tight_layout()
    return fig
