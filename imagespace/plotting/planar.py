"""Figures of a planar mechanism: its drawing, all assembly modes, a joint loop, an animation, backlash."""

from __future__ import annotations

import numpy as np

from .._validate import as_float_array
from ..drawing import ASPECT_COLOURS
from ..exceptions import InputError
from .common import (pyplot, legend_once, joint_unit, joint_label, drawing_extent, LEG_COLOURS, axes3d,
    LENGTH_UNIT, GUIDE_STYLE)

__all__ = ['plot_mechanism', 'plot_assembly_modes', 'plot_joint_loop', 'animate_path', 'plot_backlash']


def plot_mechanism(manipulator, pose, q=None, ax=None, title=None, platform_colour="tab:red", legend=True):
    """Draw the manipulator at one pose: base anchors, legs, prismatic guides, platform.

    The geometry is :func:`imagespace.drawing.mechanism_lines`, the same the Jupyter explorer
    draws; prismatic guides are dashed grey lines.

    Parameters
    ----------
    manipulator : PlanarParallel
    pose : (3,) float
    q : (3,) float, optional
        Joint values; used to pick each leg's branch (e.g. the elbow of an RRR leg).
    ax : matplotlib Axes, optional
    title : str, optional
    platform_colour : matplotlib colour
    legend : bool
        Draw a legend (legs, base joints, guides, platform).

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    TypeError
        ``manipulator`` not a :class:`PlanarParallel`; ``pose`` not numeric.
    InputError
        ``pose`` not ``(3,)`` or not finite.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.plotting import plot_mechanism
    >>> m = isp.examples.stigger_husty()
    >>> fig = plot_mechanism(m, m.direct_kinematics(m.q_example)[0].pose)
    >>> len(fig.axes), fig.axes[0].get_xlabel()
    (1, 'x [length units]')
    """
    from ..drawing import mechanism_lines

    plt = pyplot()
    p = as_float_array(pose, "pose", last=3, allow_batch=False)
    lines = mechanism_lines(manipulator, p, q)
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(6.5, 5))
    else:
        fig = ax.figure
    for i, pts in enumerate(lines.legs):
        ax.plot(pts[:, 0], pts[:, 1], "-o", color=LEG_COLOURS[i % 3], lw=2, ms=4,
                label=f"leg {i + 1} ({lines.joints[i]})")
    for pts in lines.legs:
        ax.plot(*pts[0], "ks", ms=7, label="base joint")
    for g in lines.guides:
        ax.plot(g[:, 0], g[:, 1], label="prismatic guide", **GUIDE_STYLE)
    poly = lines.platform
    ax.fill(poly[:, 0], poly[:, 1], color=platform_colour, alpha=0.25)
    ax.plot(poly[:, 0], poly[:, 1], color=platform_colour, lw=1.5, label="platform")
    ax.plot(p[0], p[1], "+", color="k", ms=10, label="platform point (x, y)")
    ax.set_aspect("equal")
    ax.grid(True, alpha=0.3)
    ax.set_xlabel(f"x [{LENGTH_UNIT}]")
    ax.set_ylabel(f"y [{LENGTH_UNIT}]")
    if title:
        ax.set_title(title, fontsize=9)
    if legend and own:
        legend_once(ax, fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0)
        fig.tight_layout()
    elif legend:
        legend_once(ax, fontsize=7, loc="best")
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

    Raises
    ------
    InputError
        ``q`` without a real assembly mode (and no ``modes`` given), or invalid joint
        values.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.plotting import plot_assembly_modes
    >>> m = isp.examples.stigger_husty()
    >>> len(plot_assembly_modes(m, m.q_example).axes)
    6
    """
    plt = pyplot()
    qf = np.array([float(v) for v in q])
    if modes is None:
        modes = manipulator.direct_kinematics(qf)
    if not modes:
        raise InputError(f"q = {qf.tolist()} has no real assembly mode to plot")
    if ax is not None:
        cmap = plt.get_cmap("viridis")
        for k, mode in enumerate(modes):
            plot_mechanism(manipulator, mode.pose, qf, ax=ax, legend=False,
                           platform_colour=cmap(k / max(1, len(modes) - 1)))
            ax.annotate(f"mode {k + 1}", mode.pose[:2], textcoords="offset points", xytext=(6, 6), fontsize=8)
        legend_once(ax, fontsize=7, loc="best")
        return ax.figure
    ncol = min(ncols, len(modes))
    nrows = int(np.ceil(len(modes) / ncols))
    height = 4.5 * nrows + 0.6                                  # 0.6 in at the bottom for the legend
    fig, axes = plt.subplots(nrows, ncol, figsize=(4 * ncol, height), squeeze=False)
    lo, hi = drawing_extent(manipulator, [mm.pose for mm in modes], [qf] * len(modes))
    pad = 0.08 * np.max(hi - lo)
    for k, mode in enumerate(modes):
        a = axes.flat[k]
        x, y, phi = mode.pose
        plot_mechanism(manipulator, mode.pose, qf, ax=a, legend=False,
                       title=f"mode {k + 1} (aspect {mode.aspect:+d})\n"
                             f"x = {x:.3f}, y = {y:.3f}, phi = {np.degrees(phi):.2f} deg")
        a.set_xlim(lo[0] - pad, hi[0] + pad)
        a.set_ylim(lo[1] - pad, hi[1] + pad)
    for a in list(axes.flat)[len(modes):]:
        a.set_visible(False)
    fig.suptitle(f"{manipulator.name}: {len(modes)} assembly modes")
    handles, labels = axes.flat[0].get_legend_handles_labels()
    seen = dict(zip(labels[::-1], handles[::-1]))
    order = [lab for lab in dict.fromkeys(labels)]
    fig.legend([seen[lab] for lab in order], order, loc="lower center", ncol=min(len(order), 7), fontsize=8,
               frameon=False)
    fig.tight_layout(rect=(0, 0.6 / height, 1, 1), h_pad=1.5)
    return fig


def plot_joint_loop(plan, ax=None, q=None, manipulator=None):
    """The loop a mode change traces in joint space (3D), start/end marked.

    Parameters
    ----------
    plan : ModeChangePlan or (n, 3) float
        A found plan (``plan.joint_loop``), or any joint trajectory, e.g. from
        :func:`imagespace.paths.modechange.joint_trajectory`.
    ax : 3D matplotlib Axes, optional
    q : (3,) float, optional
        Joint values to mark (default: the loop's start).
    manipulator : PlanarParallel, optional
        Names each axis's unit (``rad`` for a revolute actuated joint, length units for a
        prismatic one); without it the axes say ``[length units or rad]``.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    TypeError
        A trajectory ``plan`` that is not numeric.
    InputError
        A ``plan`` without a joint loop, or a trajectory not ``(n, 3)``; ``ax`` not a 3D Axes.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.modechange import plan_mode_change
    >>> from imagespace.plotting import plot_joint_loop
    >>> m = isp.examples.stigger_husty()
    >>> modes = m.direct_kinematics(m.q_example)
    >>> fig = plot_joint_loop(plan_mode_change(m, m.q_example_float, modes[0], modes[3]))
    >>> len(fig.axes)
    1
    """
    if hasattr(plan, "joint_loop"):
        if plan.joint_loop is None:
            raise InputError(f"plan has no joint loop (found={plan.found}: {plan.reason})")
        Q = plan.joint_loop
    else:
        Q = np.atleast_2d(as_float_array(plan, "plan", last=3, finite=False))
    fig, ax = axes3d(ax)
    ax.plot(*Q.T, color="tab:purple", lw=2, label="joint loop")
    q0 = Q[0] if q is None else np.asarray(q, float)
    ax.scatter(*q0, color="k", s=40, depthshade=False, label="q (start = end)")
    ax.set_xlabel(joint_label(manipulator, 0))
    ax.set_ylabel(joint_label(manipulator, 1))
    ax.set_zlabel(joint_label(manipulator, 2))
    legend_once(ax)
    ax.set_title("the mode change as a loop in joint space", fontsize=10)
    return fig


def animate_path(manipulator, poses, q_path=None, interval=60, xlim=None, ylim=None):
    """A matplotlib animation of the mechanism moving through ``poses``.

    Parameters
    ----------
    manipulator : PlanarParallel
    poses : (n, 3) float
    q_path : (n, 3) float, optional
        Joint values along the way (pick the leg branches), e.g. ``plan.joint_loop``.
    interval : int
        Milliseconds per frame.
    xlim, ylim : (2,) float, optional

    Returns
    -------
    matplotlib.animation.FuncAnimation
        ``anim.to_jshtml()`` shows it in Jupyter without ffmpeg.

    Raises
    ------
    TypeError
        Non-numeric poses.
    InputError
        Poses not ``(n, 3)`` or not finite.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.plotting import animate_path
    >>> m = isp.examples.general_3rpr()
    >>> anim = animate_path(m, [[0, 0, 0], [0.5, 0, 0.1], [1, 0, 0.2]])
    >>> "<script" in anim.to_jshtml()
    True
    """
    plt = pyplot()
    from matplotlib.animation import FuncAnimation

    P = as_float_array(poses, "poses", last=3)
    P = np.atleast_2d(P)
    Qp = None if q_path is None else np.atleast_2d(as_float_array(q_path, "q_path", last=3, finite=False))
    fig, ax = plt.subplots(figsize=(6.5, 5))
    every = slice(None, None, max(1, len(P) // 20))
    lo, hi = drawing_extent(manipulator, P[every])
    pad = 0.1 * np.max(hi - lo)
    xlim = xlim or (lo[0] - pad, hi[0] + pad)
    ylim = ylim or (lo[1] - pad, hi[1] + pad)

    def draw(k):
        ax.clear()
        ax.plot(P[: k + 1, 0], P[: k + 1, 1], color="0.5", lw=1, label="path of (x, y)")
        plot_mechanism(manipulator, P[k], None if Qp is None else Qp[k], ax=ax, legend=False,
                       title=f"frame {k + 1}/{len(P)}: phi = {np.degrees(P[k, 2]):.1f} deg")
        ax.set_xlim(*xlim)
        ax.set_ylim(*ylim)
        legend_once(ax, fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0)
        return []

    draw(0)
    fig.tight_layout()

    anim = FuncAnimation(fig, draw, frames=len(P), interval=interval, blit=False)
    plt.close(fig)
    return anim


def plot_backlash(manipulator, analysis, ax=None, n=300):
    """Backlash in the workspace (seed 002, Abb. 3 and 7): the curve of the released leg's
    platform point, its parts inside the band, the band, and the assembly modes.

    Parameters
    ----------
    manipulator : PlanarParallel
    analysis : BacklashAnalysis
        From :func:`imagespace.paths.backlash.backlash`.
    ax : matplotlib Axes, optional
    n : int
        Grid size for drawing the band (legs ending in a platform revolute).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.paths.backlash import backlash
    >>> from imagespace.plotting import plot_backlash
    >>> m = isp.examples.stigger_husty()
    >>> fig = plot_backlash(m, backlash(m, m.q_example_float, 2, delta=0.5, samples=4000))
    >>> len(fig.axes)
    1
    """
    plt = pyplot()
    from ..core.kinematic_map import pose_of

    leg = manipulator.legs[analysis.leg]
    p = np.asarray(leg.geometry(exact=False)["platform"], dtype=float)
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(8.5, 6))
    else:
        fig = ax.figure
    pts_all = []
    for s in (0, 1):
        X = analysis.points[:, s]
        ok = np.all(np.isfinite(X), axis=1)
        P = np.full((len(X), 3), np.nan)
        P[ok] = pose_of(X[ok])
        c = np.column_stack([P[:, 0] + np.cos(P[:, 2]) * p[0] - np.sin(P[:, 2]) * p[1],
                             P[:, 1] + np.sin(P[:, 2]) * p[0] + np.cos(P[:, 2]) * p[1]])
        jump = np.r_[False, np.linalg.norm(np.diff(c, axis=0), axis=1) > 1.0]
        c_plot = c.copy()
        c_plot[jump] = np.nan
        ax.plot(c_plot[:, 0], c_plot[:, 1], color="0.55", lw=1, label="coupler curve" if s == 0 else None)
        inside = analysis.deviation[:, s] <= analysis.delta
        ci = np.where(inside[:, None], c_plot, np.nan)
        ax.plot(ci[:, 0], ci[:, 1], color="tab:red", lw=2.5, label="coupler curve inside the band" if s == 0 else None)
        pts_all.append(c[ok])
    allp = np.concatenate(pts_all)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    pad = 0.1 * np.max(hi - lo)
    if leg.joints[-1] == "R":
        xs = np.linspace(lo[0] - pad, hi[0] + pad, n)
        ys = np.linspace(lo[1] - pad, hi[1] + pad, n)
        G = np.stack(np.meshgrid(xs, ys), -1).reshape(-1, 2)
        vals = leg.actuated_values(np.column_stack([G - p, np.zeros(len(G))]))
        q0 = analysis.q[analysis.leg]
        best = np.take_along_axis(vals, np.nanargmin(np.where(np.isnan(vals), np.inf, leg.joint_distance(vals, q0)), axis=1)[:, None], 1)[:, 0]
        ax.contour(xs, ys, best.reshape(n, n), levels=[q0 - analysis.delta, q0, q0 + analysis.delta],
                   colors=["tab:orange", "tab:orange", "tab:orange"], linestyles=["--", "-", "--"], linewidths=1)
        name = f"q{analysis.leg + 1}"
        ax.plot([], [], color="tab:orange", lw=1, label=f"{name} = its value in q")
        ax.plot([], [], color="tab:orange", lw=1, ls="--", label=f"{name} +- {analysis.delta:g} (the band)")
    for k, mm in enumerate(analysis.modes):
        x, y, phi = mm.pose
        cx, cy = x + np.cos(phi) * p[0] - np.sin(phi) * p[1], y + np.sin(phi) * p[0] + np.cos(phi) * p[1]
        ax.plot(cx, cy, "o", color=ASPECT_COLOURS[mm.aspect], mec="k", ms=8,
                label=f"assembly mode, aspect {mm.aspect:+d}")
        ax.annotate(f"mode {k + 1}", (cx, cy), textcoords="offset points", xytext=(6, 6), fontsize=9)
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x of leg {analysis.leg + 1}'s platform anchor [{LENGTH_UNIT}]")
    ax.set_ylabel(f"y of leg {analysis.leg + 1}'s platform anchor [{LENGTH_UNIT}]")
    if own:
        legend_once(ax, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0)
    else:
        legend_once(ax, fontsize=8, loc="best")
    ax.set_title(f"{manipulator.name}: play +-{analysis.delta:g} {joint_unit(manipulator, analysis.leg)} "
                 f"in leg {analysis.leg + 1}", fontsize=10)
    if own:
        fig.tight_layout()
    return fig


