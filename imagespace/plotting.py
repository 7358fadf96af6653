"""Matplotlib figures. Imported lazily: ``import imagespace`` does not import matplotlib.

Every figure function returns the :class:`matplotlib.figure.Figure` and accepts an optional
``ax`` to draw into.
"""

from __future__ import annotations

import numpy as np

from ._validate import as_count, as_float_array
from .drawing import ASPECT_COLOURS, CHART_LABELS, chart_coordinates
from .exceptions import InputError

__all__ = ["plot_mechanism", "plot_assembly_modes", "plot_singularity_surface", "plot_constraint_quadrics",
           "plot_conic_section", "plot_path_singularity", "plot_joint_loop", "animate_path", "plot_backlash",
           "plot_mode_count_map", "plot_workspaces", "plot_design_map", "plot_gough_stewart",
           "plot_gough_stewart_modes", "plot_singularity_mesh"]

_LEG_COLOURS = ("tab:blue", "tab:orange", "tab:green")
_ASPECT_COLOURS = ASPECT_COLOURS          # the explorer's colours (drawing.py): red +1, blue -1
LENGTH_UNIT = "length units"
"""Unit named on the axes that show lengths (the manipulator's own length unit, whatever it is)."""
_CHART_LABELS = {"image": CHART_LABELS,
                 "pose": (f"x [{LENGTH_UNIT}]", f"y [{LENGTH_UNIT}]", "phi [rad]")}
GUIDE_STYLE = {"ls": "--", "color": "0.55", "lw": 1.0, "zorder": 1}
"""How a prismatic guide from :func:`imagespace.drawing.mechanism_lines` is drawn (dashed grey);
the only dashed lines of a mechanism drawing."""
UNSOLVED_COLOUR = "0.75"
"""Colour of the mode-count cells whose row could not be solved (count ``-1``)."""


def _pyplot():
    import matplotlib.pyplot as plt

    return plt


def _legend(ax, **kwargs):
    """A legend with each label once (figures drawn repeatedly into one Axes repeat labels)."""
    handles, labels = ax.get_legend_handles_labels()
    seen = {}
    for h, lab in zip(handles, labels):
        seen.setdefault(lab, h)
    kwargs.setdefault("fontsize", 8)
    return ax.legend(list(seen.values()), list(seen), **kwargs)


def _joint_unit(manipulator, i):
    """``"rad"`` or ``"length units"`` for leg ``i``'s actuated joint; ``"length units or rad"``
    without a manipulator."""
    if manipulator is None:
        return f"{LENGTH_UNIT} or rad"
    return "rad" if manipulator.legs[i].actuated_is_angle else LENGTH_UNIT


def _joint_label(manipulator, i):
    """``"q1 [rad]"`` / ``"q1 [length units]"``: joint ``i`` with its unit (see :func:`_joint_unit`)."""
    return f"q{i + 1} [{_joint_unit(manipulator, i)}]"


def _mode_labels(modes):
    """``"start", "end"`` or ``"mode a", "mode b"`` for :func:`plot_path_singularity`."""
    if modes is None:
        return "start", "end"
    try:
        pair = list(modes)
    except TypeError:
        pair = None
    if pair is None or len(pair) != 2:
        raise InputError(f"modes must be a pair (a, b) naming the modes the path joins, got {modes!r}")
    out = []
    for v in pair:
        if isinstance(v, (int, np.integer)) and not isinstance(v, bool):
            out.append(f"mode {int(v)}")
        else:
            out.append(str(v))
    return tuple(out)


def _drawing_extent(manipulator, poses, qs=None):
    """Lower-left and upper-right corners of the drawings (legs, platform, guides) at ``poses``."""
    from .drawing import mechanism_lines

    pts = []
    for k, p in enumerate(poses):
        lines = mechanism_lines(manipulator, p, None if qs is None else qs[k])
        pts.extend(lines.legs)
        pts.extend(lines.guides)
    pts = np.concatenate(pts)
    return pts.min(axis=0), pts.max(axis=0)


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
    from .drawing import mechanism_lines

    plt = _pyplot()
    p = as_float_array(pose, "pose", last=3, allow_batch=False)
    lines = mechanism_lines(manipulator, p, q)
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(6.5, 5))
    else:
        fig = ax.figure
    for i, pts in enumerate(lines.legs):
        ax.plot(pts[:, 0], pts[:, 1], "-o", color=_LEG_COLOURS[i % 3], lw=2, ms=4,
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
        _legend(ax, fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0)
        fig.tight_layout()
    elif legend:
        _legend(ax, fontsize=7, loc="best")
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
    plt = _pyplot()
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
        _legend(ax, fontsize=7, loc="best")
        return ax.figure
    ncol = min(ncols, len(modes))
    nrows = int(np.ceil(len(modes) / ncols))
    height = 4.5 * nrows + 0.6                                  # 0.6 in at the bottom for the legend
    fig, axes = plt.subplots(nrows, ncol, figsize=(4 * ncol, height), squeeze=False)
    lo, hi = _drawing_extent(manipulator, [mm.pose for mm in modes], [qf] * len(modes))
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


def _axes3d(ax):
    plt = _pyplot()
    if ax is None:
        fig = plt.figure(figsize=(7, 6))
        return fig, fig.add_subplot(projection="3d")
    if getattr(ax, "name", "") != "3d":
        raise InputError("ax must be a 3D Axes (fig.add_subplot(projection='3d')), "
                         f"got {type(ax).__name__}")
    return ax.figure, ax


def _chart_coords(modes, chart):
    if chart == "pose":
        return np.array([mm.pose for mm in modes])
    return chart_coordinates(np.array([mm.image_point for mm in modes]))


def _modes_for(manipulator, q, modes):
    if modes is not None:
        return list(modes)
    if q is None:
        return []
    return list(manipulator.direct_kinematics(np.array([float(v) for v in q])))


def _draw_mesh(ax, mesh, colour, alpha):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from matplotlib.colors import to_rgb

    light = np.array([-0.4, -0.5, 0.77])
    shade = 0.55 + 0.45 * np.abs(mesh.face_normals @ light)       # two-sided Lambert shading
    rgb = np.clip(np.outer(shade, to_rgb(colour)), 0, 1)
    coll = Poly3DCollection(mesh.triangles, facecolors=np.column_stack([rgb, np.full(len(rgb), alpha)]),
                            edgecolor="none")
    ax.add_collection3d(coll)
    return coll


def _label_modes_3d(ax, P):
    """``mode 1`` ... next to the points ``P`` (chart coordinates, in the order of the modes)."""
    for k, pt in enumerate(P):
        if np.all(np.isfinite(pt)):
            ax.text(*pt, f"  mode {k + 1}", fontsize=7, zorder=10)


def _set_box(ax, box, chart):
    for k, setter in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
        setter(*box[k])
    ax.set_xlabel(_CHART_LABELS[chart][0])
    ax.set_ylabel(_CHART_LABELS[chart][1])
    ax.set_zlabel(_CHART_LABELS[chart][2])


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
    from .singular.meshing import mesh_surface

    b = np.asarray(box, dtype=float)
    mesh = mesh_surface(surface, box, chart=chart, resolution=resolution)
    fig, ax = _axes3d(ax)
    _draw_mesh(ax, mesh, "0.6", alpha)
    ms = _modes_for(surface.manipulator, q, modes)
    if ms:
        P = _chart_coords(ms, chart)
        for sign in (1, -1):
            sel = np.array([mm.aspect == sign for mm in ms])
            if sel.any():
                ax.scatter(*P[sel].T, color=_ASPECT_COLOURS[sign], s=40, depthshade=False,
                           label=f"modes with aspect {sign:+d} ({sel.sum()})")
        _label_modes_3d(ax, P)
    ax.plot([], [], "s", color="0.6", label="det J = 0")
    _legend(ax, loc="upper left")
    _set_box(ax, b, chart)
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

    from .core.quadrics import image_symbols
    from .singular.meshing import PolynomialImplicit, mesh_implicit

    b = np.asarray(box, dtype=float)
    fig, ax = _axes3d(ax)
    x0, x1, x2, x3 = image_symbols()
    u, v, w = sp.symbols("u v w", real=True)
    kinds = [qd.kind for qd in manipulator.quadrics(q)]
    for i, e in enumerate(manipulator.constraint_equations(q)):
        expr = sp.expand(e.xreplace({x0: 1, x1: w, x2: u, x3: v}))
        mesh = mesh_implicit(PolynomialImplicit(expr, (u, v, w), tolerances=manipulator.tolerances), box,
                             resolution=resolution, tolerances=manipulator.tolerances)
        if len(mesh.faces):
            _draw_mesh(ax, mesh, _LEG_COLOURS[i % 3], alpha)
        ax.plot([], [], color=_LEG_COLOURS[i % 3], lw=6, alpha=0.5,
                label=f"H{i + 1}: {manipulator.legs[i].joints} ({kinds[i]} dyad)")
    ms = _modes_for(manipulator, q, modes)
    if ms:
        P = _chart_coords(ms, "image")
        ax.scatter(*P.T, color="k", s=30, depthshade=False, label=f"{len(ms)} assembly modes")
        _label_modes_3d(ax, P)
    _legend(ax, loc="upper left")
    _set_box(ax, b, "image")
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
    plt = _pyplot()
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
    ms = [(k, mm) for k, mm in enumerate(_modes_for(surface.manipulator, q, modes))
          if abs(np.remainder(mm.pose[2] - float(phi) + np.pi, 2 * np.pi) - np.pi) < near]
    for k, mm in ms:
        ax.plot(mm.pose[0], mm.pose[1], "o", color=_ASPECT_COLOURS[mm.aspect], mec="k", ms=8)
        ax.annotate(f"mode {k + 1}", mm.pose[:2], textcoords="offset points", xytext=(7, 7), fontsize=9)
    ax.plot([], [], "s", color="#fcbba1", label="det J > 0 (aspect +1)")
    ax.plot([], [], "s", color="#c6dbef", label="det J < 0 (aspect -1)")
    ax.plot([], [], "k-", lw=1.5, label="det J = 0")
    for sign in sorted({mm.aspect for _, mm in ms}, reverse=True):
        ax.plot([], [], "o", color=_ASPECT_COLOURS[sign], mec="k", label=f"assembly mode, aspect {sign:+d}")
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
    plt = _pyplot()
    start, end = _mode_labels(modes)
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
    fig, ax = _axes3d(ax)
    ax.plot(*Q.T, color="tab:purple", lw=2, label="joint loop")
    q0 = Q[0] if q is None else np.asarray(q, float)
    ax.scatter(*q0, color="k", s=40, depthshade=False, label="q (start = end)")
    ax.set_xlabel(_joint_label(manipulator, 0))
    ax.set_ylabel(_joint_label(manipulator, 1))
    ax.set_zlabel(_joint_label(manipulator, 2))
    _legend(ax)
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
    plt = _pyplot()
    from matplotlib.animation import FuncAnimation

    P = as_float_array(poses, "poses", last=3)
    P = np.atleast_2d(P)
    Qp = None if q_path is None else np.atleast_2d(as_float_array(q_path, "q_path", last=3, finite=False))
    fig, ax = plt.subplots(figsize=(6.5, 5))
    every = slice(None, None, max(1, len(P) // 20))
    lo, hi = _drawing_extent(manipulator, P[every])
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
        _legend(ax, fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0)
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
        From :func:`imagespace.clearance.backlash`.
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
    plt = _pyplot()
    from .core.kinematic_map import pose_of

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
        ax.plot(cx, cy, "o", color=_ASPECT_COLOURS[mm.aspect], mec="k", ms=8,
                label=f"assembly mode, aspect {mm.aspect:+d}")
        ax.annotate(f"mode {k + 1}", (cx, cy), textcoords="offset points", xytext=(6, 6), fontsize=9)
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x of leg {analysis.leg + 1}'s platform anchor [{LENGTH_UNIT}]")
    ax.set_ylabel(f"y of leg {analysis.leg + 1}'s platform anchor [{LENGTH_UNIT}]")
    if own:
        _legend(ax, fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0)
    else:
        _legend(ax, fontsize=8, loc="best")
    ax.set_title(f"{manipulator.name}: play +-{analysis.delta:g} {_joint_unit(manipulator, analysis.leg)} "
                 f"in leg {analysis.leg + 1}", fontsize=10)
    if own:
        fig.tight_layout()
    return fig


def plot_mode_count_map(count_map, cusps=(), loops=(), ax=None, manipulator=None):
    """Real assembly modes over a joint-space section, the discriminant curve as the region
    boundaries, cusps and loops around them.

    The counts are whole numbers, so the colour map is discrete: one colour per count that occurs
    (grey for ``-1``, a row that could not be solved), and the colour bar's ticks are the counts.

    Parameters
    ----------
    count_map : ModeCountMap
        From :func:`imagespace.singular.cusps.mode_count_map`.
    cusps : sequence of Cusp
    loops : sequence of CuspLoop
    ax : matplotlib Axes, optional
    manipulator : PlanarParallel, optional
        Names the joint axes' units (``rad`` or length units); without it the axes say
        ``[length units or rad]``.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.cusps import mode_count_map
    >>> from imagespace.plotting import plot_mode_count_map
    >>> m = isp.examples.general_3rpr()
    >>> fig = plot_mode_count_map(mode_count_map(m, 2, 10.0, [(6, 16), (1, 9)], 30), manipulator=m)
    >>> len(fig.axes), fig.axes[0].get_xlabel()
    (2, 'q1 [length units]')
    """
    plt = _pyplot()
    from matplotlib.colors import BoundaryNorm, ListedColormap

    if ax is None:
        fig, ax = plt.subplots(figsize=(6.5, 5))
    else:
        fig = ax.figure
    a, b = count_map.axes
    C = np.asarray(count_map.counts)
    values = np.unique(C).astype(int)
    solved = values[values >= 0]
    shades = plt.get_cmap("Blues")(np.linspace(0.15, 0.85, max(1, len(solved))))[: len(solved)]
    colours = ([UNSOLVED_COLOUR] if (values < 0).any() else []) + [tuple(c) for c in shades]
    mids = (values[1:] + values[:-1]) / 2.0
    bounds = np.concatenate([[values[0] - 0.5], mids, [values[-1] + 0.5]])
    cmap = ListedColormap(colours)
    norm = BoundaryNorm(bounds, cmap.N)
    mesh = ax.pcolormesh(a, b, C.T, shading="nearest", cmap=cmap, norm=norm)
    unsolved = " (-1: not solved)" if (values < 0).any() else ""
    fig.colorbar(mesh, ax=ax, ticks=values, format="%d", label=f"real assembly modes{unsolved}")
    fa, fb = count_map.free
    if len(cusps):
        Cq = np.array([c.q for c in cusps])
        ax.plot(Cq[:, fa], Cq[:, fb], "r*", ms=12, label="cusps")
    for lp in loops:
        ax.plot(lp.q[:, fa], lp.q[:, fb], color="tab:green" if lp.changed else "0.4", lw=1.5,
                label="loop that changes the mode" if lp.changed else "loop, mode unchanged")
    ax.set_xlabel(_joint_label(manipulator, fa))
    ax.set_ylabel(_joint_label(manipulator, fb))
    unit = "" if manipulator is None else f" {_joint_unit(manipulator, count_map.fixed)}"
    ax.set_title(f"section q{count_map.fixed + 1} = {count_map.value:g}{unit}", fontsize=10)
    if len(cusps) or len(loops):
        _legend(ax)
    return fig


def plot_workspaces(workspaces, labels=None, ax=None):
    """Workspace regions drawn over each other (seed 004, Fig. 5).

    Parameters
    ----------
    workspaces : sequence of Workspace
    labels : sequence of str, optional
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.design.workspace import reachable_workspace, dexterous_workspace
    >>> from imagespace.plotting import plot_workspaces
    >>> m = isp.examples.choi_3ppr()
    >>> lim = [[-np.sqrt(3), np.sqrt(3)]] * 3
    >>> fig = plot_workspaces([reachable_workspace(m, (-1, 1), lim), dexterous_workspace(m, (-1, 1), lim)])
    >>> len(fig.axes)
    1
    """
    plt = _pyplot()
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(5.5, 6))
    else:
        fig = ax.figure
    cmap = plt.get_cmap("tab10")
    for k, ws in enumerate(workspaces):
        lab = labels[k] if labels is not None else f"{ws.kind} (area {ws.area:.3g} {LENGTH_UNIT}^2)"
        col = cmap(k % 10)
        for j, curve in enumerate(ws.boundary):
            ax.plot(curve[:, 0], curve[:, 1], color=col, lw=1.8, label=lab if j == 0 else None)
            if ws.polygon is not None:
                ax.fill(curve[:, 0], curve[:, 1], color=col, alpha=0.12)
    ax.set_aspect("equal")
    ax.set_xlabel(f"x [{LENGTH_UNIT}]")
    ax.set_ylabel(f"y [{LENGTH_UNIT}]")
    ax.grid(True, alpha=0.3)
    if own:
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.12), frameon=False)
        fig.tight_layout()
    else:
        ax.legend(fontsize=8, loc="best")
    return fig


def plot_design_map(table, value, x, y, best=None, ax=None, title=None, units=None):
    """A design index (or the composite) over a two-parameter grid (seed 004, Figs. 7-9).

    Parameters
    ----------
    table : DesignTable
    value : str or (n,) float
        An index of the table, or values per row (e.g. ``FuzzyResult.composite``).
    x, y : str
        The two grid parameters (in the table's grid order: ``x`` first).
    best : sequence of int, optional
        Rows to mark (e.g. ``FuzzyResult.best``).
    ax : matplotlib Axes, optional
    title : str, optional
    units : dict of str, optional
        Unit of each parameter (and of the value, under the key ``value`` if it is a name, or
        ``"value"``), e.g. ``{"alpha": "rad", "r_over_R": "-"}``; a name without one is labelled
        ``[sweep units]``.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``x, y`` not the table's two grid parameters in order; ``units`` not a dict.

    Examples
    --------
    >>> from imagespace.design.sweep import sweep
    >>> from imagespace.plotting import plot_design_map
    >>> def index(a, b):
    ...     return {"sum": float(a + b)}
    >>> t = sweep(index, {"a": [1.0, 2.0, 3.0], "b": [0.0, 1.0]}, processes=0)
    >>> fig = plot_design_map(t, "sum", "a", "b", units={"a": "mm", "b": "mm", "sum": "mm"})
    >>> len(fig.axes), fig.axes[0].get_xlabel()
    (2, 'a [mm]')
    """
    plt = _pyplot()
    if units is None:
        units = {}
    if not isinstance(units, dict):
        raise InputError(f"units must be a dict of parameter name -> unit, got {type(units).__name__}")
    names = list(table.params)
    if [x, y] != names[:2] or len(names) != 2:
        raise InputError(f"x, y must be the table's two grid parameters in order {names}, got {[x, y]}")
    Z = table.grid(value) if isinstance(value, str) else np.asarray(value, float).reshape(table.shape)
    xs = table.params[x].reshape(table.shape)[:, 0]
    ys = table.params[y].reshape(table.shape)[0, :]
    if ax is None:
        fig, ax = plt.subplots(figsize=(6, 4.5))
    else:
        fig = ax.figure
    def label(name):
        return f"{name} [{units.get(name, 'sweep units')}]"

    mesh = ax.pcolormesh(xs, ys, Z.T, shading="nearest", cmap="viridis")
    fig.colorbar(mesh, ax=ax, label=label(value if isinstance(value, str) else "value"))
    if best is not None:
        ax.plot(table.params[x][list(best)], table.params[y][list(best)], "r*", ms=14, label="optimum")
        ax.legend(fontsize=8)
    ax.set_xlabel(label(x))
    ax.set_ylabel(label(y))
    if title:
        ax.set_title(title, fontsize=10)
    return fig


# -- spatial: the Gough-Stewart platform --------------------------------------------------------
_GS_LEG_CMAP = "Dark2"        # leg colours: none of them the aspect colours (red, blue)
_GS_BASE_COLOUR = "0.45"
_MIN_HALF_WIDTH = 1e-12            # numerical knob: 3D limits of coincident points still span an interval


def _polygon_order(P):
    """Indices of the points ``P`` (m, 3) in angular order about their centroid, in their best-fit
    plane (draws the anchor hexagon as a simple polygon whatever the input order)."""
    c = P - P.mean(axis=0)
    _, _, vt = np.linalg.svd(c)
    ang = np.arctan2(c @ vt[1], c @ vt[0])
    return np.argsort(ang, kind="stable")


def _cube_limits(ax, P, pad=0.08):
    """Equal-scaled 3D limits around the points ``P`` (m, 3)."""
    lo, hi = P.min(axis=0), P.max(axis=0)
    centre, half = (lo + hi) / 2, max(float(np.max(hi - lo)) / 2, _MIN_HALF_WIDTH) * (1 + pad)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))


def _gough_stewart_points(gs, s):
    from .spatial.study import transform_points

    return gs.base_points, transform_points(s, gs.platform_points)


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

    plt = _pyplot()
    z = as_float_array(s, "s", last=8, allow_batch=False)
    own = ax is None
    fig, ax = _axes3d(ax)
    A, X = _gough_stewart_points(gs, z)
    L = np.linalg.norm(X - A, axis=1)
    cmap = plt.get_cmap(_GS_LEG_CMAP)
    for poly, colour, label in ((A, _GS_BASE_COLOUR, "base"), (X, platform_colour, "platform")):
        ring = poly[_polygon_order(poly)]
        ax.add_collection3d(Poly3DCollection([ring], facecolors=colour, alpha=0.25, edgecolor="none"))
        closed = np.vstack([ring, ring[:1]])
        ax.plot(*closed.T, color=colour, lw=1.5, label=label)
    for i in range(6):
        seg = np.stack([A[i], X[i]])
        ax.plot(*seg.T, "-", color=cmap(i % 8), lw=2.2, label=f"leg {i + 1}: L = {L[i]:.4g}")
    ax.scatter(*A.T, color="k", s=12, depthshade=False)
    ax.scatter(*X.T, color=platform_colour, s=12, depthshade=False)
    _cube_limits(ax, np.vstack([A, X]) if limits is None else np.asarray(limits, dtype=float))
    ax.set_xlabel(f"x [{LENGTH_UNIT}]", fontsize=8)
    ax.set_ylabel(f"y [{LENGTH_UNIT}]", fontsize=8)
    ax.set_zlabel(f"z [{LENGTH_UNIT}]", fontsize=8)
    if title:
        ax.set_title(title, fontsize=9)
    if legend:
        _legend(ax, fontsize=7, loc="upper left", bbox_to_anchor=(1.05, 1), borderaxespad=0)
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

    from .spatial.singularities import aspect

    plt = _pyplot()
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
    pts = np.vstack([np.vstack(_gough_stewart_points(gs, s)) for s in S])
    for i, s in enumerate(S):
        a = fig.add_subplot(nrows, ncol, i + 1, projection="3d")
        plot_gough_stewart(gs, s, ax=a, legend=False, limits=pts,
                           platform_colour=_ASPECT_COLOURS.get(int(asp[i]), "tab:red"),
                           title=f"mode {i + 1} (aspect {int(asp[i]):+d})")
        a.tick_params(labelsize=5, pad=-2)
        for axis in (a.xaxis, a.yaxis, a.zaxis):
            axis.set_major_locator(MaxNLocator(3))
            axis.label.set_visible(False)
    height = panel_size * nrows + 0.5
    fig.suptitle(title or f"{k} real assembly mode{'s' if k != 1 else ''} "
                          "(platform red: aspect +1, blue: -1)", fontsize=10, y=1 - 0.1 / height, va="top")
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
        raise TypeError(f"mesh must be a trimesh.Trimesh, got {type(mesh).__name__}")
    fig, ax = _axes3d(ax)
    if len(mesh.faces):
        _draw_mesh(ax, mesh, colour, alpha)
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
                    ax.scatter(*P[sel].T, color=_ASPECT_COLOURS[sign], s=30, depthshade=False,
                               label=f"aspect {sign:+d} ({int(sel.sum())})")
    if box is not None:
        b = np.asarray(box, dtype=float)
        ax.set_xlim(*b[0])
        ax.set_ylim(*b[1])
        ax.set_zlim(*b[2])
        ax.set_box_aspect(tuple(b[:, 1] - b[:, 0]))
    elif len(mesh.vertices):
        _cube_limits(ax, np.asarray(mesh.vertices), pad=0.02)
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_zlabel(labels[2])
    if title:
        ax.set_title(title, fontsize=10)
    _legend(ax, loc="upper left")
    return fig
