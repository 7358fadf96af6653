"""Spatial poses the obvious ways: a rotation matrix and a translation, a quaternion and a
translation, roll-pitch-yaw angles (radians or degrees) and a translation, or a 4x4 homogeneous
matrix. Each returns the normalised Study point ``(x0:x1:x2:x3:y0:y1:y2:y3)`` that the spatial
functions take (:func:`~imagespace.spatial.study.study_point` does the work); a wrong shape says
which constructors exist.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Optional

import numpy as np
import numpy.typing as npt

from .._validate import as_flag, as_float_array, as_tolerances
from ..exceptions import InputError
from .study import quaternion_from_matrix, quaternion_multiply, study_point

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray
    from ..tolerances import Tolerances

__all__ = ["pose_from_rotation", "pose_from_quaternion", "pose_from_rpy", "pose_from_matrix", "CONSTRUCTORS"]

CONSTRUCTORS = ("pose_from_rotation(R, t) for a 3x3 rotation matrix R and a translation t; "
                "pose_from_quaternion(q, t) for a quaternion q = (w, x, y, z); "
                "pose_from_rpy(rpy, t, degrees=False) for roll, pitch, yaw; "
                "pose_from_matrix(T) for a 4x4 homogeneous matrix (all in imagespace.spatial)")
"""The constructors, as the error messages list them."""


def _guess(shape):
    if shape[-2:] == (4, 4):
        return " (a 4x4 matrix: pose_from_matrix(T))"
    if shape[-2:] == (3, 3):
        return " (a 3x3 matrix: pose_from_rotation(R, t))"
    if shape[-1:] == (4,):
        return " (4 numbers: a quaternion, pose_from_quaternion(q, t))"
    return ""


def _shape_error(name, wanted, got):
    return InputError(f"{name} must have shape {wanted}, got shape {got}{_guess(got)}. Spatial poses are "
                      f"built by {CONSTRUCTORS}")


def _translation(t):
    t = as_float_array(t, "t", finite=False)
    if t.shape[-1:] != (3,) or t.ndim > 2:
        raise _shape_error("t", "(3,) or (n, 3)", t.shape)
    if not np.all(np.isfinite(t)):
        raise InputError("t must be finite, got NaN or inf entries")
    return t


def pose_from_rotation(R: npt.ArrayLike, t: npt.ArrayLike) -> FloatArray:
    """The Study point of the displacement ``p -> R p + t``.

    Parameters
    ----------
    R : (3, 3) or (n, 3, 3) float
        Rotation matrices (orthogonal, det +1, to ``Tolerances.rotation_matrix``).
    t : (3,) or (n, 3) float

    Returns
    -------
    (8,) or (n, 8) float

    Raises
    ------
    InputError
        Wrong shapes (the message lists the constructors), not a rotation, not finite.
    TypeError
        Non-numeric input.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.poses import pose_from_rotation
    >>> pose_from_rotation(np.eye(3), [2.0, 0.0, 0.0])
    array([1., 0., 0., 0., 0., 1., 0., 0.])
    """
    R = as_float_array(R, "R", finite=False)
    if R.ndim not in (2, 3) or R.shape[-2:] != (3, 3):
        raise _shape_error("R", "(3, 3) or (n, 3, 3)", R.shape)
    return study_point(quaternion_from_matrix(R), _translation(t))     # checks R under its own name


def pose_from_quaternion(q: npt.ArrayLike, t: npt.ArrayLike) -> FloatArray:
    """The Study point of the rotation of the quaternion ``q = (w, x, y, z)`` (scalar first; need not
    be a unit quaternion) followed by the translation ``t``.

    Parameters
    ----------
    q : (4,) or (n, 4) float
    t : (3,) or (n, 3) float

    Returns
    -------
    (8,) or (n, 8) float

    Raises
    ------
    InputError
        Wrong shapes (the message lists the constructors), a zero quaternion, not finite.
    TypeError
        Non-numeric input.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.poses import pose_from_quaternion
    >>> from imagespace.spatial.study import transform_points
    >>> s = pose_from_quaternion([np.cos(0.25), 0.0, 0.0, np.sin(0.25)], [0.0, 0.0, 1.0])  # 0.5 rad about z
    >>> transform_points(s, [1.0, 0.0, 0.0]).round(6)
    array([0.877583, 0.479426, 1.      ])
    """
    x = as_float_array(q, "q", finite=False)
    if x.ndim not in (1, 2) or x.shape[-1] != 4:
        raise _shape_error("q", "(4,) or (n, 4)", x.shape)
    if not np.all(np.isfinite(x)):
        raise InputError("q must be finite, got NaN or inf entries")
    if np.any(np.all(x == 0, axis=-1)):
        raise InputError("q must be a non-zero quaternion, got zero")
    return study_point(x, _translation(t))


def pose_from_rpy(rpy: npt.ArrayLike, t: npt.ArrayLike, degrees: bool = False) -> FloatArray:
    """The Study point of roll, pitch and yaw angles and a translation.

    The rotation is ``R = Rz(yaw) Ry(pitch) Rx(roll)``: roll about the fixed x axis first, then
    pitch about the fixed y axis, then yaw about the fixed z axis (the aerospace convention; the
    same as intrinsic z-y'-x'' rotations by yaw, pitch, roll).

    Parameters
    ----------
    rpy : (3,) or (n, 3) float
        ``(roll, pitch, yaw)``.
    t : (3,) or (n, 3) float
    degrees : bool
        The angles are in degrees (default radians).

    Returns
    -------
    (8,) or (n, 8) float

    Raises
    ------
    InputError
        Wrong shapes (the message lists the constructors), angles not finite.
    TypeError
        Non-numeric input, ``degrees`` not a bool.

    Examples
    --------
    >>> from imagespace.spatial.poses import pose_from_rpy
    >>> from imagespace.spatial.study import rotation_matrix
    >>> rotation_matrix(pose_from_rpy([0, 0, 90], [0, 0, 0], degrees=True)).round(12) + 0.0   # yaw: x -> y
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    """
    degrees = as_flag(degrees, "degrees")
    a = as_float_array(rpy, "rpy", finite=False)
    if a.ndim not in (1, 2) or a.shape[-1] != 3:
        raise _shape_error("rpy", "(3,) or (n, 3) (roll, pitch, yaw)", a.shape)
    if not np.all(np.isfinite(a)):
        raise InputError("rpy must be finite, got NaN or inf entries")
    if degrees:
        a = np.radians(a)
    half = a / 2
    c, s = np.cos(half), np.sin(half)
    zero = np.zeros(a.shape[:-1])
    qx = np.stack([c[..., 0], s[..., 0], zero, zero], axis=-1)
    qy = np.stack([c[..., 1], zero, s[..., 1], zero], axis=-1)
    qz = np.stack([c[..., 2], zero, zero, s[..., 2]], axis=-1)
    return study_point(quaternion_multiply(qz, quaternion_multiply(qy, qx)), _translation(t))


def pose_from_matrix(T: npt.ArrayLike, tolerances: Optional[Tolerances] = None) -> FloatArray:
    """The Study point of a 4x4 homogeneous transform ``[[R, t], [0, 0, 0, 1]]``.

    Parameters
    ----------
    T : (4, 4) or (n, 4, 4) float
        The last row ``(0, 0, 0, 1)`` and ``R`` a rotation, to ``Tolerances.rotation_matrix``.
    tolerances : Tolerances, optional

    Returns
    -------
    (8,) or (n, 8) float

    Raises
    ------
    InputError
        Wrong shapes (the message lists the constructors), a last row other than ``(0, 0, 0, 1)``,
        ``R`` not a rotation, not finite.
    TypeError
        Non-numeric input.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.poses import pose_from_matrix
    >>> T = np.eye(4); T[:3, 3] = [2.0, 0.0, 0.0]
    >>> pose_from_matrix(T)
    array([1., 0., 0., 0., 0., 1., 0., 0.])
    """
    tol = as_tolerances(tolerances).rotation_matrix
    M = as_float_array(T, "T", finite=False)
    if M.ndim not in (2, 3) or M.shape[-2:] != (4, 4):
        raise _shape_error("T", "(4, 4) or (n, 4, 4)", M.shape)
    if not np.all(np.isfinite(M)):
        raise InputError("T must be finite, got NaN or inf entries")
    last = np.abs(M[..., 3, :] - np.array([0.0, 0.0, 0.0, 1.0])).max()
    if last > tol:
        raise InputError(f"T must end in the row (0, 0, 0, 1) (a homogeneous transform), got a deviation of "
                         f"{last:.3g}")
    # the rotation block checked at the caller's tolerance (study_point would use the default)
    try:
        x = quaternion_from_matrix(M[..., :3, :3], tolerances)
    except InputError as exc:                  # name the user's parameter
        raise InputError(str(exc).replace("R must", "T[:3, :3] must", 1)) from None
    return study_point(x, M[..., :3, 3])
