"""Performance indices from the dimensionless Jacobian ``J_h`` (seed 004).

``J_h = dq/d(x, y, L phi)`` (:meth:`PoseJacobians.homogeneous`): joint rates from the platform's
velocity with the rotation measured as a length through the characteristic length ``L``.

* manipulability ``w_m = |det J_h|`` (seed 004's ``|det J_h^-1|``: its ``J^-1`` is our ``J``);
* resistivity ``w_r = 1 / w_m``;
* isotropy, two forms: the inverse condition number ``sigma_min / sigma_max`` and the inverse of
  the weighted-Frobenius condition number ``kappa_F = (1/n) sqrt(tr(J^T J) tr((J^T J)^-1))``;
  both are 1 exactly at an isotropic configuration and 0 at a singularity.

Global indices are means over a range of orientations (seed 004: ``psi in [-17 pi/36, 17 pi/36]``).
"""

from __future__ import annotations

import numpy as np

import warnings

from .._validate import _short, as_count, as_float_array, as_scalar
from ..exceptions import InputError, InputTypeError
from ..core.mechanism import check_mechanism
from ..singular.jacobians import jacobians
from .workspace import MAX_ORIENTATIONS, check_phi_range

__all__ = ["manipulability", "resistivity", "isotropy", "local_indices", "global_indices"]


def _stack(Jh):
    J = as_float_array(Jh, "Jh", finite=False)
    if J.shape[-2:] != (3, 3):
        raise InputError(f"Jh must have shape (3, 3) or (n, 3, 3), got {J.shape}")
    return J


def manipulability(Jh):
    """``|det J_h|``.

    Raises
    ------
    TypeError
        For non-numeric ``Jh``.
    InputError
        For ``Jh`` not of shape ``(3, 3)`` or ``(n, 3, 3)``.

    Examples
    --------
    >>> from imagespace.design.indices import manipulability
    >>> float(manipulability(2 * np.eye(3)))
    8.0
    """
    return np.abs(np.linalg.det(_stack(Jh)))


def resistivity(Jh):
    """``1 / |det J_h|`` (``inf`` at a singularity).

    Raises
    ------
    TypeError
        For non-numeric ``Jh``.
    InputError
        For ``Jh`` not of shape ``(3, 3)`` or ``(n, 3, 3)``.

    Examples
    --------
    >>> from imagespace.design.indices import resistivity
    >>> float(resistivity(2 * np.eye(3)))
    0.125
    """
    with np.errstate(divide="ignore"):
        return 1.0 / manipulability(Jh)


def isotropy(Jh, kind="condition"):
    """Isotropy in ``[0, 1]``: ``"condition"`` (``sigma_min / sigma_max``) or ``"frobenius"``
    (``1 / kappa_F``, the weighted Frobenius condition number).

    Raises
    ------
    TypeError
        For non-numeric ``Jh`` or a ``kind`` that is not a string.
    InputError
        For ``Jh`` not of shape ``(3, 3)`` or ``(n, 3, 3)``, or an unknown ``kind``.

    Examples
    --------
    >>> from imagespace.design.indices import isotropy
    >>> float(isotropy(np.diag([1.0, 1.0, 2.0]))), round(float(isotropy(np.diag([1.0, 1.0, 2.0]), "frobenius")), 6)
    (0.5, 0.8)
    """
    J = _stack(Jh)
    if not isinstance(kind, str):
        raise InputTypeError(f"kind must be 'condition' or 'frobenius', got {type(kind).__name__} {_short(kind)}")
    if kind == "condition":
        sv = np.linalg.svd(J, compute_uv=False)
        return sv[..., -1] / sv[..., 0]
    if kind == "frobenius":
        A = np.swapaxes(J, -1, -2) @ J
        with np.errstate(divide="ignore", invalid="ignore"):
            det = np.linalg.det(A)
            inv_tr = np.where(np.abs(det) > 0, np.trace(np.linalg.pinv(A), axis1=-2, axis2=-1), np.inf)
            kappa = np.sqrt(np.trace(A, axis1=-2, axis2=-1) * inv_tr) / 3
            return np.where(np.isfinite(kappa), 1.0 / kappa, 0.0)
    raise InputError(f"kind must be 'condition' or 'frobenius', got {kind!r}")


def local_indices(manipulator, poses, length, working_modes=None):
    """All indices at poses.

    Parameters
    ----------
    manipulator : PlanarParallel
    poses : (3,) or (n, 3) float
    length : float
        Characteristic length of ``J_h``.
    working_modes : sequence of three ints, optional

    Returns
    -------
    dict of (n,) float
        ``manipulability, resistivity, isotropy, isotropy_frobenius``; NaN where a leg cannot
        reach the pose.

    Raises
    ------
    TypeError
        For a ``manipulator`` that is not a PlanarParallel, or non-numeric ``poses``/``length``.
    InputError
        For ``poses`` not ``(3,)``/``(n, 3)``, a non-positive ``length``, or bad
        ``working_modes``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.design.indices import local_indices
    >>> ind = local_indices(isp.examples.choi_3ppr(), [[0.0, 0.0, 0.2]], 1.0)
    >>> sorted(ind)
    ['isotropy', 'isotropy_frobenius', 'manipulability', 'resistivity']
    """
    check_mechanism(manipulator)
    poses = as_float_array(poses, "poses", last=3)
    L = as_scalar(length, "length")
    if not L > 0:
        raise InputError(f"length must be a positive characteristic length, got {length!r}")
    jac = jacobians(manipulator, np.atleast_2d(poses), working_modes=working_modes)
    Jh = jac.homogeneous(length)
    ok = jac.valid & np.all(np.isfinite(Jh), axis=(1, 2))
    out = {k: np.full(len(Jh), np.nan) for k in ("manipulability", "resistivity", "isotropy", "isotropy_frobenius")}
    if ok.any():
        out["manipulability"][ok] = manipulability(Jh[ok])
        out["resistivity"][ok] = resistivity(Jh[ok])
        out["isotropy"][ok] = isotropy(Jh[ok])
        out["isotropy_frobenius"][ok] = isotropy(Jh[ok], "frobenius")
    return out


def global_indices(manipulator, position, phi_range, length, n=73, working_modes=None):
    """Means of the local indices over orientations ``phi`` in a range, at one position.

    Parameters
    ----------
    manipulator : PlanarParallel
    position : (2,) float
    phi_range : (float, float)
    length : float
    n : int
        Orientations (midpoint rule over the range).

    Returns
    -------
    dict of float

    Raises
    ------
    TypeError
        For a ``manipulator`` that is not a PlanarParallel, non-numeric arguments or a
        non-integer ``n``.
    InputError
        For a malformed ``phi_range`` or ``position``, ``n`` outside ``2..MAX_ORIENTATIONS``, a
        non-positive ``length``, or bad ``working_modes``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.design.indices import global_indices
    >>> g = global_indices(isp.examples.choi_3ppr(), (0.0, 0.0), (-1.0, 1.0), 1.0)
    >>> 0 < g["isotropy"] <= 1
    True
    """
    check_mechanism(manipulator)
    lo, hi = check_phi_range(phi_range)
    n = as_count(n, "n", 2)
    if n > MAX_ORIENTATIONS:
        raise InputError(f"n must be at most {MAX_ORIENTATIONS} orientations, got {n}")
    p = as_float_array(position, "position", allow_batch=False)
    if p.shape != (2,):
        raise InputError(f"position must be (x, y), got shape {p.shape}")
    phis = lo + (np.arange(n) + 0.5) * (hi - lo) / n
    P = np.column_stack([np.full(n, p[0]), np.full(n, p[1]), phis])
    loc = local_indices(manipulator, P, length, working_modes)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)          # no reachable orientation: NaN
        return {k: float(np.nanmean(v)) for k, v in loc.items()}
