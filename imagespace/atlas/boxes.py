"""Joint boxes of the atlas: the one validation of a ``(3, 2)`` box of joint values."""

from __future__ import annotations

import numpy as np

from .._validate import as_box, as_float_array
from ..core.mechanism import check_mechanism
from ..exceptions import InputError

__all__ = ["check_joint_box"]


def check_joint_box(manipulator, joint_box, name="joint_box"):
    """A ``(3, 2)`` joint box inside the joints' domains (every corner a valid joint vector).

    Parameters
    ----------
    manipulator : PlanarParallel
    joint_box : (3, 2) float
        ``((q1_min, q1_max), (q2_min, q2_max), (q3_min, q3_max))``.
    name : str
        The parameter's name in error messages.

    Returns
    -------
    (3, 2) float

    Raises
    ------
    TypeError
        Non-numeric box.
    InputError
        Not ``(3, 2)``, an empty side, or a side leaving a joint's domain (an RPR leg's length
        must stay positive).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import check_joint_box
    >>> check_joint_box(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)]).shape
    (3, 2)
    """
    check_mechanism(manipulator)
    box = as_box(as_float_array(joint_box, name), name, dim=3)
    for i, leg in enumerate(manipulator.legs):
        ok = leg.joint_values_ok(box[i])
        if not np.all(ok):
            raise InputError(f"{name}[{i}] = {box[i].tolist()} leaves the domain of joint {i} "
                             f"({leg.actuated_name}); every value of the box must be a valid joint "
                             f"value")
    return box
