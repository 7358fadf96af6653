"""Drawing geometry shared by the matplotlib figures and the Jupyter explorer (no plotting library).

:func:`mechanism_lines` turns a pose into the polylines of a drawing: legs, base anchors, the
platform triangle and the prismatic guides; :func:`chart_coordinates` puts image points into the
affine chart ``(x2/x0, x3/x0, x1/x0)`` used for the image-space views (the chart of Stigger &
Husty's Abb. 4, see ``docs/references.md``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._validate import as_float_array
from .core.leg_geometry import rotate_vector
from .core.mechanism import check_mechanism

__all__ = ["MechanismLines", "mechanism_lines", "chart_coordinates", "ASPECT_COLOURS", "CHART_LABELS",
           "GUIDE_OVERHANG"]

ASPECT_COLOURS = {1: "#d62728", -1: "#1f77b4", 0: "#444444"}
"""Colour of an assembly mode by its aspect (sign of det J): red +1, blue -1, grey for 0."""

CHART_LABELS = ("x2/x0 [length units]", "x3/x0 [length units]", "x1/x0 = tan(phi/2) [-]")
"""Axis titles of the image-space chart ``(x2/x0, x3/x0, x1/x0)``: the first two are half the
platform position rotated by ``-phi/2`` (length units), the third is ``tan(phi/2)`` (no unit)."""

GUIDE_OVERHANG = 0.25
"""A prismatic guide is drawn this fraction of the drawing's size beyond the joints that ride on it."""


@dataclass(frozen=True)
class MechanismLines:
    """The polylines of one drawing of a manipulator at one pose (base frame, length units).

    Attributes
    ----------
    legs : list of (k, 2) float
        Each leg from its base joint to its platform anchor, through the intermediate joints.
    joints : list of str
        Each leg's joint string (``"RPR"``, ``"PPR"`` ...).
    guides : list of (2, 2) float
        Segments of the prismatic guides: the line a slider travels on, drawn through the joints
        that ride on it and :data:`GUIDE_OVERHANG` of the drawing's size beyond them.
    platform : (4, 2) float
        The platform triangle through the three anchors, closed.
    centre : (2,) float
        The platform's reference point ``(x, y)``.
    """

    legs: list
    joints: list
    guides: list
    platform: np.ndarray
    centre: np.ndarray


def _guide(points, direction, reach):
    """The segment along ``direction`` covering ``points`` (projected) plus ``reach`` at each end."""
    u = np.asarray(direction, dtype=float)
    n = np.hypot(*u)
    if not n > 0:
        return None
    u = u / n
    P = np.asarray(points, dtype=float)
    t = (P - P[0]) @ u
    return np.array([P[0] + (t.min() - reach) * u, P[0] + (t.max() + reach) * u])


def mechanism_lines(manipulator, pose, q=None):
    """The legs, platform and prismatic guides of ``manipulator`` drawn at ``pose``.

    Parameters
    ----------
    manipulator : PlanarParallel
    pose : (3,) float
        ``(x, y, phi)``.
    q : (3,) float, optional
        Joint values, used to draw each leg on the branch that matches them (an RRR elbow).

    Returns
    -------
    MechanismLines

    Raises
    ------
    TypeError
        ``manipulator`` is not a :class:`PlanarParallel`; ``pose`` is not numeric.
    InputError
        ``pose`` is not of shape ``(3,)`` or not finite.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.drawing import mechanism_lines
    >>> m = isp.examples.stigger_husty()
    >>> lines = mechanism_lines(m, [1.0, 2.0, 0.5])
    >>> [leg.shape for leg in lines.legs], len(lines.guides)
    ([(2, 2), (2, 2), (3, 2)], 4)
    """
    check_mechanism(manipulator)
    p = as_float_array(pose, "pose", last=3, allow_batch=False)
    legs = [np.asarray(L, dtype=float) for L in manipulator.leg_points(p, q)]
    anchors = np.array([L[-1] for L in legs])
    everything = np.concatenate(legs)
    size = float(np.max(np.ptp(everything, axis=0))) or 1.0
    reach = GUIDE_OVERHANG * size
    guides = []
    for leg, pts in zip(manipulator.legs, legs):
        g = leg.geometry(exact=False)
        kind = leg.joints
        segs = []
        if kind == "RPR":
            segs.append(_guide(pts, pts[-1] - pts[0], 0.0))
        if kind[0] == "P" and "axis" in g:
            segs.append(_guide(pts[:2], g["axis"], reach))
        if "second_axis" in g:                      # PPR: the second slider moves along it
            segs.append(_guide(pts[1:], g["second_axis"], reach))
        if kind == "RPP":                           # the slider along the rotating arm
            segs.append(_guide(pts[:2], pts[1] - pts[0], reach))
        if kind[-1] == "P" and "direction" in g:    # a slider along a platform line
            d = np.array(rotate_vector(p[2], g["direction"]))
            segs.append(_guide(pts[-2:], d, reach))
        guides.extend(s for s in segs if s is not None)
    platform = np.vstack([anchors, anchors[:1]])
    return MechanismLines(legs, [leg.joints for leg in manipulator.legs], guides, platform, p[:2].copy())


def chart_coordinates(image_points):
    """Image points ``(n, 4)`` in the affine chart ``(x2/x0, x3/x0, x1/x0)``; NaN where ``x0 = 0``.

    Parameters
    ----------
    image_points : (4,) or (n, 4) float

    Returns
    -------
    (n, 3) float

    Raises
    ------
    InputError
        A wrong shape or a non-finite entry.

    Examples
    --------
    >>> from imagespace.drawing import chart_coordinates
    >>> chart_coordinates([2.0, 1.0, 4.0, -2.0]).tolist()
    [[2.0, -1.0, 0.5]]
    """
    X = np.atleast_2d(as_float_array(image_points, "image_points", last=4))
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.column_stack([X[:, 2] / X[:, 0], X[:, 3] / X[:, 0], X[:, 1] / X[:, 0]])
    out[X[:, 0] == 0] = np.nan
    return out
