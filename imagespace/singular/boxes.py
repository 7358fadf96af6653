"""Default boxes of the singularity-surface views: scaled to a design (one home for the box that
:func:`~imagespace.singular.meshing.mesh_surface` and the command line use when none is given)."""

from __future__ import annotations

import numpy as np

from ..exceptions import InputError

__all__ = ["design_scale", "default_box"]


def design_scale(manipulator):
    """A length for default boxes: the largest anchor coordinate or example joint length.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.boxes import design_scale
    >>> round(design_scale(isp.examples.stigger_husty()), 3)
    15.232
    """
    vals = [1.0]
    for leg in manipulator.legs:
        for v in leg.geometry(exact=False).values():
            vals += [abs(c) for c in np.atleast_1d(v)]
    if manipulator.q_example is not None:
        vals += [abs(float(v)) for v, leg in zip(manipulator.q_example, manipulator.legs) if not leg.actuated_is_angle]
    return float(max(vals))


def default_box(manipulator, chart="image"):
    """The default meshing box of a chart, scaled by the design (:func:`design_scale` ``L``):
    image ``x2/x0, x3/x0 in [-0.8 L, 0.8 L]`` and ``x1/x0 in [-3, 3]`` (``|phi| <= 143 deg``); pose
    ``x, y in [-L, L]`` and ``phi in [-pi, pi]``. The box of :func:`mesh_surface` and of the CLI
    when none is given.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.boxes import default_box
    >>> default_box(isp.examples.stigger_husty(), "pose")[2]
    (-3.141592653589793, 3.141592653589793)
    """
    if chart not in ("image", "pose"):
        raise InputError(f"chart must be 'image' or 'pose', got {chart!r}")
    L = design_scale(manipulator)
    if chart == "image":
        return ((-0.8 * L, 0.8 * L), (-0.8 * L, 0.8 * L), (-3.0, 3.0))
    return ((-L, L), (-L, L), (-np.pi, np.pi))
