"""What the figure modules share: matplotlib on demand, colours, units and axis helpers."""

from __future__ import annotations

import numpy as np

from ..drawing import CHART_LABELS, chart_coordinates
from ..exceptions import InputError

__all__ = ['pyplot', 'legend_once', 'joint_unit', 'joint_label', 'mode_labels', 'drawing_extent', 'LEG_COLOURS', 'CHART_AXES', 'axes3d', 'chart_coords', 'modes_for', 'draw_mesh', 'label_modes_3d', 'set_box', 'GS_LEG_CMAP', 'GS_BASE_COLOUR', 'MIN_HALF_WIDTH', 'polygon_order', 'cube_limits', 'gough_stewart_points', 'LENGTH_UNIT', 'GUIDE_STYLE', 'UNSOLVED_COLOUR']

LEG_COLOURS = ("tab:blue", "tab:orange", "tab:green")
LENGTH_UNIT = "length units"
"""Unit named on the axes that show lengths (the manipulator's own length unit, whatever it is)."""
CHART_AXES = {"image": CHART_LABELS,
                 "pose": (f"x [{LENGTH_UNIT}]", f"y [{LENGTH_UNIT}]", "phi [rad]")}
GUIDE_STYLE = {"ls": "--", "color": "0.55", "lw": 1.0, "zorder": 1}
"""How a prismatic guide from :func:`imagespace.drawing.mechanism_lines` is drawn (dashed grey);
the only dashed lines of a mechanism drawing."""
UNSOLVED_COLOUR = "0.75"
"""Colour of the mode-count cells whose row could not be solved (count ``-1``)."""


def pyplot():
    import matplotlib.pyplot as plt

    return plt


def legend_once(ax, **kwargs):
    """A legend with each label once (figures drawn repeatedly into one Axes repeat labels)."""
    handles, labels = ax.get_legend_handles_labels()
    seen = {}
    for h, lab in zip(handles, labels):
        seen.setdefault(lab, h)
    kwargs.setdefault("fontsize", 8)
    return ax.legend(list(seen.values()), list(seen), **kwargs)


def joint_unit(manipulator, i):
    """``"rad"`` or ``"length units"`` for leg ``i``'s actuated joint; ``"length units or rad"``
    without a manipulator."""
    if manipulator is None:
        return f"{LENGTH_UNIT} or rad"
    return "rad" if manipulator.legs[i].actuated_is_angle else LENGTH_UNIT


def joint_label(manipulator, i):
    """``"q1 [rad]"`` / ``"q1 [length units]"``: joint ``i`` with its unit (see :func:`joint_unit`)."""
    return f"q{i + 1} [{joint_unit(manipulator, i)}]"


def mode_labels(modes):
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


def drawing_extent(manipulator, poses, qs=None):
    """Lower-left and upper-right corners of the drawings (legs, platform, guides) at ``poses``."""
    from ..drawing import mechanism_lines

    pts = []
    for k, p in enumerate(poses):
        lines = mechanism_lines(manipulator, p, None if qs is None else qs[k])
        pts.extend(lines.legs)
        pts.extend(lines.guides)
    pts = np.concatenate(pts)
    return pts.min(axis=0), pts.max(axis=0)




def axes3d(ax):
    plt = pyplot()
    if ax is None:
        fig = plt.figure(figsize=(7, 6))
        return fig, fig.add_subplot(projection="3d")
    if getattr(ax, "name", "") != "3d":
        raise InputError("ax must be a 3D Axes (fig.add_subplot(projection='3d')), "
                         f"got {type(ax).__name__}")
    return ax.figure, ax


def chart_coords(modes, chart):
    if chart == "pose":
        return np.array([mm.pose for mm in modes])
    return chart_coordinates(np.array([mm.image_point for mm in modes]))


def modes_for(manipulator, q, modes):
    if modes is not None:
        return list(modes)
    if q is None:
        return []
    return list(manipulator.direct_kinematics(np.array([float(v) for v in q])))


def draw_mesh(ax, mesh, colour, alpha):
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from matplotlib.colors import to_rgb

    light = np.array([-0.4, -0.5, 0.77])
    shade = 0.55 + 0.45 * np.abs(mesh.face_normals @ light)       # two-sided Lambert shading
    rgb = np.clip(np.outer(shade, to_rgb(colour)), 0, 1)
    coll = Poly3DCollection(mesh.triangles, facecolors=np.column_stack([rgb, np.full(len(rgb), alpha)]),
                            edgecolor="none")
    ax.add_collection3d(coll)
    return coll


def label_modes_3d(ax, P):
    """``mode 1`` ... next to the points ``P`` (chart coordinates, in the order of the modes)."""
    for k, pt in enumerate(P):
        if np.all(np.isfinite(pt)):
            ax.text(*pt, f"  mode {k + 1}", fontsize=7, zorder=10)


def set_box(ax, box, chart):
    for k, setter in enumerate((ax.set_xlim, ax.set_ylim, ax.set_zlim)):
        setter(*box[k])
    ax.set_xlabel(CHART_AXES[chart][0])
    ax.set_ylabel(CHART_AXES[chart][1])
    ax.set_zlabel(CHART_AXES[chart][2])



# -- spatial: the Gough-Stewart platform --------------------------------------------------------
GS_LEG_CMAP = "Dark2"        # leg colours: none of them the aspect colours (red, blue)
GS_BASE_COLOUR = "0.45"
MIN_HALF_WIDTH = 1e-12            # numerical knob: 3D limits of coincident points still span an interval


def polygon_order(P):
    """Indices of the points ``P`` (m, 3) in angular order about their centroid, in their best-fit
    plane (draws the anchor hexagon as a simple polygon whatever the input order)."""
    c = P - P.mean(axis=0)
    _, _, vt = np.linalg.svd(c)
    ang = np.arctan2(c @ vt[1], c @ vt[0])
    return np.argsort(ang, kind="stable")


def cube_limits(ax, P, pad=0.08):
    """Equal-scaled 3D limits around the points ``P`` (m, 3)."""
    lo, hi = P.min(axis=0), P.max(axis=0)
    centre, half = (lo + hi) / 2, max(float(np.max(hi - lo)) / 2, MIN_HALF_WIDTH) * (1 + pad)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_box_aspect((1, 1, 1))


def gough_stewart_points(gs, s):
    from ..spatial.study import transform_points

    return gs.base_points, transform_points(s, gs.platform_points)

