"""Seed 003's Jacobians ``Jx``, ``Jq``, ``J`` at poses and the singularity type of each pose
(direct-kinematic, inverse-kinematic, both, regular), numeric and symbolic."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from .._validate import as_float_array, as_scalar
from ..core.quadrics import image_symbols
from ..exceptions import InputError
from ..core.mechanism import check_mechanism
from .pointwise import constraint_values, pose_chart_point
from .._html import dataclass_html, dataclass_repr

__all__ = ["PoseJacobians", "jacobians", "symbolic_jacobians"]


@dataclass(frozen=True)
class PoseJacobians:
    """Seed 003's Jacobians at poses: ``Jx xdot = Jq qdot``, ``J = Jq^-1 Jx``.

    One pose in (``pose`` of shape ``(3,)``), one pose out: the arrays below then have no batch
    axis (``Jx`` is ``(3, 3)``, ``det_Jx`` a number, ``kind`` a string) and ``single`` is True.

    ``F_i(x, y, phi, q) = Q_i(image_point(x, y, phi), q_i)`` with the normalised image point; for
    an RR dyad this is ``|P_i - A_i|**2 - r_i**2`` exactly, for a line constraint the signed
    distance times the line's scale.

    Attributes
    ----------
    pose : (n, 3) float
    q : (n, 3) float
    Jx : (n, 3, 3) float
        ``dF/d(x, y, phi)``.
    Jq : (n, 3, 3) float
        ``-dF/dq`` (diagonal: each leg's constraint contains only its own joint).
    J : (n, 3, 3) float
        ``Jq^-1 Jx``; NaN where ``Jq`` is singular.
    det_Jx, det_Jq : (n,) float
    ratio_Jx, ratio_Jq : (n,) float
        ``|det| / prod(row norms)`` of ``Jx`` and of ``[Jx | Jq]`` rows' ``Jq`` parts relative to
        the rows' norms: dimensionless, in ``[0, 1]``; a leg whose whole row vanishes counts as 0.
    direct_kinematic, inverse_kinematic : (n,) bool
        ``ratio_Jx <= tol`` / ``ratio_Jq <= tol``.
    kind : (n,) str
        ``"regular"``, ``"inverse-kinematic"``, ``"direct-kinematic"``, ``"both"``, or
        ``"unreachable"`` where a leg cannot reach the pose (batch rows are not raised on).
    valid : (n,) bool
        The rows with finite joint values (the others are NaN).
    tol : float
        The threshold used (``Tolerances.singular``).
    single : bool
        One pose was given: the arrays have no leading batch axis.
    """

    pose: np.ndarray
    q: np.ndarray
    Jx: np.ndarray
    Jq: np.ndarray
    J: np.ndarray
    det_Jx: np.ndarray
    det_Jq: np.ndarray
    ratio_Jx: np.ndarray
    ratio_Jq: np.ndarray
    direct_kinematic: np.ndarray
    inverse_kinematic: np.ndarray
    kind: np.ndarray
    valid: np.ndarray
    tol: float
    single: bool = False

    def homogeneous(self, length):
        """The dimensionless Jacobian ``J_h = J diag(1, 1, 1/L)`` (seed 004, eq. 24).

        ``J = dq/d(x, y, phi)`` mixes lengths and an angle; with the characteristic length
        ``L`` the platform velocity is measured as ``(xdot, ydot, L phidot)``, all lengths, and
        ``qdot = J_h (xdot, ydot, L phidot)``. Seed 004 writes it ``J_h^-1 = J^-1 diag(1, 1, 1/R)``
        (its ``J^-1`` is our ``J``).

        Parameters
        ----------
        length : float
            The characteristic length ``L > 0`` (seed 004: the base's inscribed radius ``R``).

        Returns
        -------
        (n, 3, 3) float, or (3, 3) for one pose

        Raises
        ------
        TypeError
            ``length`` not a number.
        InputError
            ``length`` not positive and finite.

        Examples
        --------
        >>> import imagespace as isp
        >>> jac = isp.jacobians(isp.examples.choi_3ppr(), [0.1, 0.0, 0.2])
        >>> jac.homogeneous(1.0).shape
        (3, 3)
        """
        L = as_scalar(length, "length", finite=False)
        if not np.isfinite(L) or L <= 0:
            raise InputError(f"length must be a positive characteristic length, got {length!r}")
        return self.J * np.array([1.0, 1.0, 1.0 / L])

    def wrench(self, tau):
        """Statics: the platform wrench ``F_ext = J^T tau`` balanced by actuator efforts ``tau``.

        Virtual power: ``tau . qdot = F . (xdot, ydot, phidot)`` for every motion, so
        ``F = J^T tau`` (forces along x, y and the moment about the moving frame's origin).

        Parameters
        ----------
        tau : (3,) or (n, 3) float
            Actuator forces (prismatic) or torques (revolute).

        Returns
        -------
        (n, 3) float, or (3,) for one pose and one ``tau``

        Raises
        ------
        TypeError
            ``tau`` not numeric.
        InputError
            ``tau`` of the wrong shape or not finite.

        Examples
        --------
        >>> import imagespace as isp
        >>> jac = isp.jacobians(isp.examples.general_3rpr(), [0.5, 1.0, 0.2])
        >>> jac.wrench([1.0, 0.0, 0.0]).shape
        (3,)
        """
        tau = as_float_array(tau, "tau", last=3)
        J = self.J[None] if self.single else self.J
        t = np.broadcast_to(tau, (len(J), 3))
        F = np.einsum("nji,nj->ni", J, t)
        return F[0] if self.single and tau.ndim == 1 else F

    # short summaries (arrays as shape and dtype) for the terminal and Jupyter; see imagespace._html
    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


def jacobians(manipulator, pose, q=None, working_modes=None):
    """``Jx``, ``Jq``, ``J`` and the singularity type at poses (seed 003).

    Parameters
    ----------
    manipulator : PlanarParallel
    pose : (3,) or (n, 3) float
    q : (3,) or (n, 3) float, optional
        Joint values; by default the inverse kinematics at ``pose`` on ``working_modes``.
    working_modes : sequence of three ints, optional

    Returns
    -------
    PoseJacobians
        For one pose ``(3,)`` (and one ``q``): one pose's matrices (``Jx`` of shape ``(3, 3)``,
        ``det_Jx`` a number, ``kind`` a string); otherwise arrays with a leading batch axis.

    Raises
    ------
    TypeError
        ``manipulator`` not a design; non-numeric ``P`` or ``q``; bad ``working_modes``.
    InputError
        ``P`` not ``(3,)`` or ``(n, 3)``; ``q`` not one row or one row per pose, or outside
        a joint's domain; a design with free symbols.

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.examples.general_3rpr()
    >>> jac = isp.jacobians(m, [0.5, 1.0, 0.2])
    >>> jac.kind, jac.Jx.shape
    ('regular', (3, 3))
    >>> isp.jacobians(m, [[0.5, 1.0, 0.2], [0.4, 1.0, 0.1]]).Jx.shape
    (2, 3, 3)
    """
    check_mechanism(manipulator)
    P = as_float_array(pose, "pose", last=3)
    single = P.ndim == 1 and (q is None or np.ndim(q) == 1)
    P = np.atleast_2d(P)
    if working_modes is not None:
        working_modes = manipulator.check_working_modes(working_modes)
    if q is None:
        Q = np.atleast_2d(manipulator.inverse_kinematics(P, working_modes))
    else:
        Q = np.atleast_2d(manipulator.check_q(q))
        if len(Q) != len(P) and len(Q) != 1 and len(P) != 1:
            raise InputError(f"q must have shape (3,) or (n, 3) with n = {len(P)} (one row per pose), "
                             f"got shape {Q.shape}")
        n = max(len(P), len(Q))
        P = np.broadcast_to(P, (n, 3)).copy()
        Q = np.broadcast_to(Q, (n, 3)).copy()
    valid = np.all(np.isfinite(Q), axis=-1)
    X, dX = pose_chart_point(P)
    _, dQdx, dQdq = constraint_values(manipulator, X, Q)
    Jx = np.einsum("nij,njk->nik", dQdx, dX)
    Jq = np.zeros_like(Jx)
    idx = np.arange(3)
    Jq[:, idx, idx] = -dQdq
    with np.errstate(divide="ignore", invalid="ignore"):
        det_Jx = np.full(len(P), np.nan)
        det_Jx[valid] = np.linalg.det(Jx[valid])
        det_Jq = np.prod(-dQdq, axis=-1)
        rows = np.linalg.norm(Jx, axis=-1)                    # (n, 3)
        ratio_x = np.where(np.all(rows > 0, -1), np.abs(det_Jx) / np.prod(rows, -1), 0.0)
        full = np.hypot(rows, np.abs(dQdq))
        ratio_q = np.where(np.all(full > 0, -1), np.min(np.abs(dQdq) / full, -1), 0.0)
        J = np.where(np.abs(det_Jq)[:, None, None] > 0,
                     Jx / np.where(dQdq == 0, np.nan, -dQdq)[:, :, None], np.nan)
    tol = manipulator.tolerances.singular
    dk, ik = ratio_x <= tol, ratio_q <= tol
    dk, ik = dk & valid, ik & valid
    kind = np.where(dk & ik, "both", np.where(dk, "direct-kinematic",
                                               np.where(ik, "inverse-kinematic", "regular")))
    kind = np.where(valid, kind, "unreachable")
    fields = (P, Q, Jx, Jq, J, det_Jx, det_Jq, ratio_x, ratio_q, dk, ik, kind, valid)
    if single:          # one pose in, one pose out
        fields = tuple(f[0].item() if f[0].ndim == 0 else f[0] for f in fields)
    return PoseJacobians(*fields, tol, single)


def symbolic_jacobians(manipulator):
    """``Jx``, ``Jq`` as sympy matrices in ``(x, y, phi)`` and the joint symbols.

    ``F_i = Q_i(image_point(x, y, phi), q_i)`` with ``x0 = cos(phi/2)``, ``x1 = sin(phi/2)`` (the
    normalised image point), the same definition as :func:`jacobians`.

    Parameters
    ----------
    manipulator : PlanarParallel

    Returns
    -------
    Jx, Jq : sympy.Matrix (3, 3)
    symbols : tuple
        ``(x, y, phi)``.

    Raises
    ------
    TypeError
        ``manipulator`` not a design.

    Examples
    --------
    >>> import sympy as sp, imagespace as isp
    >>> from imagespace.singular.jacobians import symbolic_jacobians
    >>> Jx, Jq, (x, y, phi) = symbolic_jacobians(isp.examples.collinear_3rpr(2, 1))
    >>> sp.simplify(Jx.det() - 16 * 2 * sp.sin(phi) * (2 * y + x * sp.sin(phi) - y * sp.cos(phi)))
    0
    """
    check_mechanism(manipulator)
    x, y, phi = sp.symbols("x y phi", real=True)
    x0, x1, x2, x3 = image_symbols()
    c, s = sp.cos(phi / 2), sp.sin(phi / 2)
    sub = {x0: c, x1: s, x2: (s * x - c * y) / 2, x3: (c * x + s * y) / 2}
    qs = manipulator.joint_symbols
    F = [sp.expand(leg.dyad(qi).expr().xreplace(sub)) for leg, qi in zip(manipulator.legs, qs)]
    Jx = sp.Matrix(F).jacobian([x, y, phi]).applyfunc(lambda e: sp.simplify(sp.expand_trig(e)))
    Jq = sp.diag(*[-sp.diff(f, qi) for f, qi in zip(F, qs)]).applyfunc(sp.simplify)
    return Jx, Jq, (x, y, phi)
