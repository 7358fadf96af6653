r"""The seven planar leg types and the dyad each leaves when its actuated joint is locked.

A leg is a serial chain of three joints from the base (first letter) to the platform (last
letter). Locking the actuated joint leaves a dyad of the two passive joints, i.e. one quadric of
:mod:`imagespace.core.quadrics`. Every leg accepts any of its three joints as the actuated one
(``actuated=0, 1, 2``); the default is the joint the seed papers actuate.

Joint values (``q`` of the leg, in joint order) and their conventions:

========  ==========================================  ==============================  ========
leg       joints (base -> platform)                    geometry                        default
========  ==========================================  ==============================  ========
RPR       theta (leg direction), rho (length),         base, platform                  1 (rho)
          psi = phi - theta
RRR       theta1 (link 1 direction), theta2 (elbow,    base, platform, lengths         0
          relative), theta3 = phi - theta1 - theta2
PRR       s (travel along axis), theta2 (link         base, axis, platform, length    0
          direction relative to axis), theta3
          = phi - axis angle - theta2
RRP       theta1 (link direction), theta2 (platform    base, length, platform,         0
          line direction minus theta1), s (travel      direction
          along the platform line from ``platform``)
RPP       theta1 (first slider direction), s1, s2      base, platform, direction,      1 (s1)
          (travel along the platform line)             angle (between the sliders)
PRP       s1 (travel along axis), theta2 (platform     base, axis, platform,           0
          line direction minus axis angle), s2         direction
PPR       s1 (travel along axis), s2 (travel along     base, axis, platform, angle     0
          the second slider), theta3 = phi
========  ==========================================  ==============================  ========

Angles are radians measured counter-clockwise; "direction" vectors are normalised on
construction; ``platform`` points and ``direction`` vectors of platform lines are given in the
moving frame. Relative angles are wrapped to ``(-pi, pi]``.

Branches of the leg inverse kinematics (:meth:`Leg.inverse_kinematics` returns all of them, in
this order, NaN where a branch does not exist):

* RPR: ``rho >= 0`` and its mirror ``(theta + pi, -rho)`` (the slider passed through the base
  pivot). The mirror only matters when a revolute joint is actuated.
* RRR: elbow ``+`` and ``-`` (the elbow on the left / right of the line from base to platform
  anchor). RRP: the two intersections of the link circle with the platform line.
  PRR: the two intersections of the platform anchor's circle with the axis.
* RPP, PRP, PPR: one branch (two lines meet once).

Geometry may be given as floats, exact sympy numbers (``sympy.sqrt(232)``) or sympy symbols;
floats are turned into exact binary rationals for the symbolic paths, and angles given as
floats enter the exact paths through the binary rationals of their cosine and sine.
"""

from __future__ import annotations

from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt
import sympy as sp

from .._validate import as_count, as_exact, as_flag, as_float_array, as_sympy_entry, check_positive, is_symbolic
from .._validate import as_tolerances
from .leg_geometry import (Arithmetic, circle_line, direction_angle, exact_cos_sin, floatify,
                           geometry_number, geometry_point, in_float_range, lines_meet, rotate_vector, short_text,
                           unit_direction, world_point, wrap_angle)
from .quadrics import Quadric, pp_quadric, pr_quadric, rp_quadric, rr_quadric
from ..exceptions import DegenerateDesignError, InputError, InputTypeError
from ..tolerances import Tolerances

__all__ = ["Leg", "RPR", "RRR", "PRR", "RRP", "RPP", "PRP", "PPR", "LEG_TYPES"]


class Leg:
    """Base class of the planar legs; see the module docstring for the conventions.

    Subclasses define ``joints`` (e.g. ``"RPR"``), ``default_actuated``, the geometry, the
    inverse kinematics and the dyad for each choice of actuated joint.

    Raises
    ------
    TypeError
        ``actuated`` is not an integer; a geometry entry is not a real number or expression.
    InputError
        ``actuated`` is not 0, 1 or 2; a geometry entry is not finite, a point is not a 2-vector,
        a direction is zero, or a length is not positive.
    DegenerateDesignError
        The geometry makes the leg degenerate (RPP, PPR: sliders at angle 0 or pi).

    Examples
    --------
    >>> import imagespace as isp
    >>> isinstance(isp.RPR(base=(0, 0), platform=(1, 0)), isp.Leg)
    True
    """

    joints = "???"
    default_actuated = 0
    joint_names = ("q0", "q1", "q2")
    n_branches = 1

    def __init__(self, actuated: Optional[int] = None) -> None:
        if actuated is None:
            actuated = self.default_actuated
        if isinstance(actuated, (bool, np.bool_)) or not isinstance(actuated, (int, np.integer)):
            raise InputTypeError(f"actuated must be 0, 1 or 2 (the index of the actuated joint of "
                                 f"{self.joints}), got {type(actuated).__name__} {short_text(repr(actuated))}")
        if not 0 <= actuated <= 2:
            raise InputError(f"actuated must be 0, 1 or 2 (the index of the actuated joint of "
                             f"{self.joints}), got {short_text(repr(actuated))}")
        self.actuated = int(actuated)
        self._float: Optional[dict[str, Any]] = None

    # -- geometry access --------------------------------------------------------
    def _geometry(self):
        """Dict of the exact geometry (sympy)."""
        raise NotImplementedError

    def geometry(self, exact: bool = True) -> dict[str, Any]:
        """The leg's geometry as a dict: exact sympy values, or floats with ``exact=False``.

        Raises
        ------
        InputError
            ``exact=False`` and the geometry holds sympy symbols (substitute numbers first).

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.RPR(base=(1, 2), platform=(0, 0)).geometry(exact=False)
        {'base': (1.0, 2.0), 'platform': (0.0, 0.0)}
        """
        g = self._geometry()
        if as_flag(exact, "exact"):
            return dict(g)
        if self._float is None:
            fl = {k: floatify(v) for k, v in g.items()}
            if any(v is None or (isinstance(v, tuple) and None in v) for v in fl.values()):
                free = sorted(str(s) for s in self.free_symbols)
                raise InputError(f"the {self.joints} leg has symbolic design parameters {free}; "
                                 "substitute numbers before numeric computations")
            self._float = fl
        return dict(self._float)

    @property
    def free_symbols(self) -> set[sp.Basic]:
        """Set of sympy symbols in the design parameters."""
        out = set()
        for v in self._geometry().values():
            for s in (v if isinstance(v, tuple) else (v,)):
                if isinstance(s, sp.Basic):
                    out |= s.free_symbols
        return out

    @property
    def actuated_is_angle(self) -> bool:
        """True if the actuated joint is revolute."""
        return self.joints[self.actuated] == "R"

    @property
    def actuated_name(self) -> str:
        """Name of the actuated joint variable."""
        return self.joint_names[self.actuated]

    def __repr__(self):
        g = ", ".join(f"{k}={v}" for k, v in self._geometry().items())
        return f"{type(self).__name__}({g}, actuated={self.actuated})"

    # -- the dyad ---------------------------------------------------------------
    def joint_values_ok(self, q: npt.ArrayLike) -> npt.NDArray[np.bool_]:
        """Boolean mask: which actuated joint values are inside the joint's domain (every finite
        value, by default; NaN and infinities never are).

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.RPR(base=(0, 0), platform=(0, 0)).joint_values_ok([-1.0, 2.0]).tolist()
        [False, True]
        """
        return np.isfinite(as_float_array(q, "q", finite=False))

    def check_joint_value(self, q: Any, name: str = "q") -> Any:
        """Raise InputError if a value of the actuated joint is not finite or outside its domain.

        Raises
        ------
        InputError
            a value is not finite, or is outside the actuated joint's domain (for the RPR
            leg's length: negative).

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.RPR(base=(0, 0), platform=(0, 0)).check_joint_value(2.0)
        2.0
        """
        arr = as_float_array(q, name, finite=False)
        if not np.all(np.isfinite(arr)):
            raise InputError(f"{name} (the actuated joint {self.actuated_name} of {self.joints}) must be "
                             f"finite, got {q}")
        if not np.all(self.joint_values_ok(arr)):
            raise InputError(f"{name} is outside the domain of the actuated joint "
                             f"{self.actuated_name} of {self.joints}, got {q}")
        return q

    def dyad(self, q: Any) -> Quadric:
        """The quadric left when the actuated joint is locked at ``q``.

        Parameters
        ----------
        q : float, (n,) float array, or sympy expression / symbol
            The actuated joint value. Numeric ``q`` gives float coefficients (arrays for a
            batch); sympy ``q`` gives exact or symbolic coefficients.

        Returns
        -------
        Quadric

        Raises
        ------
        InputError
            ``q`` is outside the actuated joint's domain or not finite, is an array of more
            than one dimension, or is too large for the float dyad.
        TypeError
            ``q`` is not a number, an array of numbers or a real sympy expression.

        Examples
        --------
        >>> import imagespace as isp
        >>> leg = isp.RPR(base=(0, 0), platform=(0, 0))
        >>> leg.dyad(10).expr()
        -100*x0**2 - 100*x1**2 + 4*x2**2 + 4*x3**2
        """
        symbolic = is_symbolic(q) or isinstance(q, (int, np.integer)) and not isinstance(q, (bool, np.bool_))
        if symbolic:
            if isinstance(q, sp.Basic):
                q = as_sympy_entry(q, "q")
            q = as_exact(q, "q")
            if not q.free_symbols:
                if self.actuated_is_angle:
                    in_float_range(q, "q")      # cos/sin stay exact atoms of its rational value
                qf = float(q)
                self.check_joint_value(qf if np.isfinite(qf) else float(np.sign(qf)))
            g = self._geometry()
            return self._dyad(q, g, Arithmetic(symbolic))
        q = as_float_array(q, "q", finite=False)
        if q.ndim > 1:
            raise InputError(f"q must be a number or a 1-d array of values of the actuated joint, "
                             f"got shape {q.shape}")
        self.check_joint_value(q)
        g = self.geometry(exact=False)
        with np.errstate(over="ignore", invalid="ignore"):
            try:
                return self._dyad(q, g, Arithmetic(symbolic))
            except InputError as exc:
                if q.ndim == 0 and "finite" in str(exc):
                    raise InputError(f"q = {float(q)} is too large for the float dyad of the {self.joints} "
                                     f"leg: {exc}") from None
                raise

    def _dyad(self, q, g, ops) -> Quadric:
        raise NotImplementedError

    # -- inverse kinematics -----------------------------------------------------
    def inverse_kinematics(self, pose: npt.ArrayLike,
                           tolerances: Optional[Tolerances] = None) -> npt.NDArray[np.float64]:
        """All branches of the leg's inverse kinematics.

        Parameters
        ----------
        pose : (3,) or (n, 3) float
            ``(x, y, phi)``.
        tolerances : Tolerances, optional
            The thresholds of the branch decisions (``ik_parallel``, ``ik_tangent``); default
            :data:`~imagespace.tolerances.TOLERANCES`. A mechanism passes its own.

        Returns
        -------
        (n_branches, 3) or (n, n_branches, 3) float
            The three joint values of every branch (see the module docstring for the order);
            NaN where a branch does not exist (pose out of reach of this leg).

        Raises
        ------
        InputError
            ``pose`` is not of shape ``(3,)`` or ``(n, 3)``, or not finite; the leg's geometry is
            symbolic.
        TypeError
            ``pose`` is not numeric; ``tolerances`` is not a :class:`~imagespace.tolerances.Tolerances`.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.RPR(base=(0, 0), platform=(1, 0)).inverse_kinematics([0.0, 0.0, 0.0])
        array([[ 0.        ,  1.        ,  0.        ],
               [ 3.14159265, -1.        ,  3.14159265]])
        """
        p = as_float_array(pose, "pose", last=3)
        tol = as_tolerances(tolerances)
        single = p.ndim == 1
        p2 = np.atleast_2d(p)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            out = self._ik(p2[:, 0], p2[:, 1], p2[:, 2], self.geometry(exact=False), tol)
        return out[0] if single else out

    def actuated_values(self, pose: npt.ArrayLike,
                        tolerances: Optional[Tolerances] = None) -> npt.NDArray[np.float64]:
        """Actuated joint value of every branch at ``pose``: ``(n_branches,)`` or ``(n, n_branches)``.

        ``tolerances`` as in :meth:`inverse_kinematics`, which raises for this method.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.RPR(base=(0, 0), platform=(3, 4)).actuated_values([0.0, 0.0, 0.0])
        array([ 5., -5.])
        """
        return self.inverse_kinematics(pose, tolerances)[..., self.actuated]

    def joint_difference(self, a: npt.ArrayLike, b: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """``a - b`` for the actuated joint: plain for a prismatic joint, wrapped to ``(-pi, pi]``
        for an angle (radians). Broadcasts; NaN stays NaN.

        Examples
        --------
        >>> import numpy as np, imagespace as isp
        >>> leg = isp.RRR(base=(0, 0), lengths=(1, 1), platform=(0, 0), actuated=0)
        >>> round(float(leg.joint_difference(3.1, -3.1)), 6)          # across the cut at pi
        -0.083185
        """
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        if not self.actuated_is_angle:
            return a - b
        # each angle is wrapped first (accurately at any size): ``a - b`` of a huge angle would
        # keep only its ulp
        return wrap_angle(wrap_angle(a) - wrap_angle(b))

    def joint_distance(self, a: npt.ArrayLike, b: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """``|a - b|`` for the actuated joint (angles compared modulo ``2 pi``); see
        :meth:`joint_difference`.

        Examples
        --------
        >>> import imagespace as isp
        >>> float(isp.RPR(base=(0, 0), platform=(3, 4)).joint_distance(5.0, 4.5))
        0.5
        """
        return np.abs(self.joint_difference(a, b))

    def nearest_branch(self, pose: npt.ArrayLike, q: npt.ArrayLike,
                       tolerances: Optional[Tolerances] = None) -> Union[int, npt.NDArray[np.intp]]:
        """The IK branch whose actuated value is nearest to ``q`` at ``pose``: an int for one pose,
        ``(n,)`` ints for ``(n, 3)`` poses (with ``q`` a number or ``(n,)``); ``-1`` where no branch
        reaches the pose. ``tolerances`` as in :meth:`inverse_kinematics`.

        Raises
        ------
        InputError, TypeError
            As :meth:`inverse_kinematics`.

        Examples
        --------
        >>> import imagespace as isp
        >>> leg = isp.RPR(base=(0, 0), platform=(3, 4))         # branches rho = +5 and -5
        >>> leg.nearest_branch([0.0, 0.0, 0.0], -4.0)
        1
        """
        vals = self.actuated_values(pose, tolerances)           # (nb,) or (n, nb)
        q = np.asarray(q, dtype=float)
        d = self.joint_distance(vals, q[..., None] if q.ndim else q)
        d = np.where(np.isnan(d), np.inf, d)
        best = np.argmin(d, axis=-1)
        best = np.where(np.isfinite(np.min(d, axis=-1)), best, -1)
        return int(best) if np.ndim(best) == 0 else best

    def _ik(self, x, y, phi, g, tol):
        raise NotImplementedError

    def joint_points(self, pose: npt.ArrayLike, branch: int = 0,
                     tolerances: Optional[Tolerances] = None) -> npt.NDArray[np.float64]:
        """The leg drawn as a polyline in the base frame: ``(k, 2)`` points from base to platform.

        ``branch`` is the inverse-kinematics branch drawn; ``tolerances`` as in
        :meth:`inverse_kinematics`.

        Raises
        ------
        InputError
            ``pose`` is not one finite pose ``(3,)``; ``branch`` is negative or not below
            :attr:`n_branches`.
        TypeError
            ``branch`` is not an integer; ``tolerances`` is not a Tolerances.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.RPR(base=(0, 0), platform=(0, 0)).joint_points([3.0, 4.0, 0.0])
        array([[0., 0.],
               [3., 4.]])
        """
        p = as_float_array(pose, "pose", last=3, allow_batch=False)
        branch = as_count(branch, "branch", minimum=0)
        if branch >= self.n_branches:
            raise InputError(f"branch must be below {self.n_branches} (the {self.joints} leg's inverse "
                             f"kinematics has {self.n_branches} branch{'es' if self.n_branches > 1 else ''}), "
                             f"got {branch}")
        q = self.inverse_kinematics(p, tolerances)[branch]
        return self._points(p, q, self.geometry(exact=False))

    def _points(self, pose, q, g):
        raise NotImplementedError


# --------------------------------------------------------------------------- leg types

class RPR(Leg):
    """RPR leg: passive revolute at ``base``, prismatic (length ``rho``), revolute at ``platform``.

    Parameters
    ----------
    base : (2,) base anchor A (base frame)
    platform : (2,) platform anchor a (moving frame)
    actuated : int, default 1
        1: the prismatic joint (an RR dyad: ``a`` on the circle about ``A`` of radius ``rho``);
        0: the base revolute (PR dyad); 2: the platform revolute (RP dyad).

    Examples
    --------
    >>> import imagespace as isp
    >>> leg = isp.RPR(base=(7, 0), platform=(5, 0))
    >>> float(leg.actuated_values([2.0, 0.0, 0.0])[0])
    0.0
    """

    joints = "RPR"
    default_actuated = 1
    joint_names = ("theta", "rho", "psi")
    n_branches = 2

    def __init__(self, base: Any, platform: Any,
                 actuated: Optional[int] = None) -> None:
        super().__init__(actuated)
        self.base = geometry_point(base, "base")
        self.platform = geometry_point(platform, "platform")

    def _geometry(self):
        return {"base": self.base, "platform": self.platform}

    def joint_values_ok(self, q: npt.ArrayLike) -> npt.NDArray[np.bool_]:
        q = as_float_array(q, "q", finite=False)
        return (np.isfinite(q) & (q >= 0)) if self.actuated == 1 else np.isfinite(q)

    def check_joint_value(self, q: Any, name: str = "q") -> Any:
        """Raise InputError if a leg length is not finite, or negative when ``rho`` is actuated.

        Raises
        ------
        InputError
            a value is not finite, or ``rho`` (``actuated=1``) is negative.

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.RPR(base=(0, 0), platform=(0, 0)).check_joint_value(2.0)
        2.0
        """
        arr = as_float_array(q, name, finite=False)
        if not np.all(np.isfinite(arr)):
            raise InputError(f"{name} (the actuated joint {self.actuated_name} of RPR) must be finite, got {q}")
        if not np.all(self.joint_values_ok(arr)):
            raise InputError(f"{name} (the RPR leg length rho) must be >= 0, got {q}")
        return q

    def _dyad(self, q, g, ops):
        A, a = g["base"], g["platform"]
        if self.actuated == 1:
            return rr_quadric(A, q * q, a)
        c, s = ops.cs(q)
        if self.actuated == 0:
            return pr_quadric(a, A, (c, s))
        return rp_quadric(a, (c, -s), A)

    def _ik(self, x, y, phi, g, tol):
        A, a = g["base"], g["platform"]
        ax, ay = world_point(x, y, phi, a)
        dx, dy = ax - A[0], ay - A[1]
        th = np.arctan2(dy, dx)
        rho = np.hypot(dx, dy)
        b0 = np.stack([th, rho, wrap_angle(phi - th)], -1)
        b1 = np.stack([wrap_angle(th + np.pi), -rho, wrap_angle(phi - th - np.pi)], -1)
        return np.stack([b0, b1], -2)

    def _points(self, pose, q, g):
        return np.array([g["base"], world_point(*pose, g["platform"])], dtype=float)


class RRR(Leg):
    """RRR leg: revolute at ``base``, elbow, revolute at ``platform``; links ``lengths = (l1, l2)``.

    Parameters
    ----------
    base : (2,) base pivot A
    platform : (2,) platform anchor a (moving frame)
    lengths : (2,) positive link lengths (A to elbow, elbow to a)
    actuated : int, default 0
        0: base revolute (RR dyad about the elbow); 1: elbow (RR dyad about A with radius
        ``|l1 + l2 e^{i q}|``); 2: platform revolute (RR dyad about A, radius l1, for the elbow
        seen as a platform point).

    Examples
    --------
    >>> import imagespace as isp
    >>> leg = isp.RRR(base=(0, 0), platform=(0, 0), lengths=(1, 1))
    >>> leg.inverse_kinematics([1.0, 1.0, 0.0]).round(6)
    array([[ 1.570796, -1.570796,  0.      ],
           [ 0.      ,  1.570796, -1.570796]])
    """

    joints = "RRR"
    default_actuated = 0
    joint_names = ("theta1", "theta2", "theta3")
    n_branches = 2

    def __init__(self, base: Any, platform: Any, lengths: Any,
                 actuated: Optional[int] = None) -> None:
        super().__init__(actuated)
        self.base = geometry_point(base, "base")
        self.platform = geometry_point(platform, "platform")
        l1, l2 = geometry_point(lengths, "lengths")
        self.lengths = (check_positive(l1, "lengths[0]"), check_positive(l2, "lengths[1]"))

    def _geometry(self):
        return {"base": self.base, "platform": self.platform, "lengths": self.lengths}

    def _dyad(self, q, g, ops):
        A, a, (l1, l2) = g["base"], g["platform"], g["lengths"]
        c, s = ops.cs(q)
        if self.actuated == 0:
            return rr_quadric((A[0] + l1 * c, A[1] + l1 * s), l2 * l2, a)
        if self.actuated == 1:
            return rr_quadric(A, l1 * l1 + l2 * l2 + 2 * l1 * l2 * c, a)
        return rr_quadric(A, l1 * l1, (a[0] - l2 * c, a[1] + l2 * s))

    def _ik(self, x, y, phi, g, tol):
        A, a, (l1, l2) = g["base"], g["platform"], g["lengths"]
        ax, ay = world_point(x, y, phi, a)
        dx, dy = ax - A[0], ay - A[1]
        d = np.hypot(dx, dy)
        along = (l1 * l1 - l2 * l2 + d * d) / (2 * d)
        h2 = l1 * l1 - along * along
        h2 = np.where((h2 < 0) & (h2 > -tol.ik_tangent * l1 * l1), 0.0, h2)
        h = np.sqrt(np.where(h2 >= 0, h2, np.nan))
        ex, ey = dx / d, dy / d
        out = []
        for sign in (1.0, -1.0):
            Ex = A[0] + along * ex - sign * h * ey
            Ey = A[1] + along * ey + sign * h * ex
            t1 = np.arctan2(Ey - A[1], Ex - A[0])
            t12 = np.arctan2(ay - Ey, ax - Ex)
            out.append(np.stack([t1, wrap_angle(t12 - t1), wrap_angle(phi - t12)], -1))
        return np.stack(out, -2)

    def _points(self, pose, q, g):
        A, (l1, _) = g["base"], g["lengths"]
        E = (A[0] + l1 * np.cos(q[0]), A[1] + l1 * np.sin(q[0]))
        return np.array([A, E, world_point(*pose, g["platform"])], dtype=float)


class PRR(Leg):
    """PRR leg: slider along ``axis`` from ``base``, revolute on the slider, link ``length``, revolute at ``platform``.

    Parameters
    ----------
    base : (2,) start point of the slider
    axis : (2,) slider direction (normalised)
    platform : (2,) platform anchor a (moving frame)
    length : positive link length
    actuated : int, default 0
        0: slider travel (RR dyad about ``base + q axis``); 1: link angle relative to the axis
        (PR dyad); 2: platform revolute (PR dyad of the slider pivot seen on the platform).

    Examples
    --------
    >>> import imagespace as isp
    >>> leg = isp.PRR(base=(0, 0), axis=(1, 0), platform=(0, 0), length=5)
    >>> leg.actuated_values([3.0, 4.0, 0.0]).tolist()
    [6.0, 0.0]
    """

    joints = "PRR"
    default_actuated = 0
    joint_names = ("s", "theta2", "theta3")
    n_branches = 2

    def __init__(self, base: Any, axis: Any, platform: Any, length: Any,
                 actuated: Optional[int] = None) -> None:
        super().__init__(actuated)
        self.base = geometry_point(base, "base")
        self.axis = unit_direction(axis, "axis")
        self.platform = geometry_point(platform, "platform")
        self.length = check_positive(geometry_number(length, "length"), "length")

    def _geometry(self):
        return {"base": self.base, "axis": self.axis, "platform": self.platform, "length": self.length}

    def _dyad(self, q, g, ops):
        A, u, a, l = g["base"], g["axis"], g["platform"], g["length"]
        if self.actuated == 0:
            return rr_quadric((A[0] + q * u[0], A[1] + q * u[1]), l * l, a)
        c, s = ops.cs(q)
        if self.actuated == 1:
            P = (A[0] + l * (u[0] * c - u[1] * s), A[1] + l * (u[1] * c + u[0] * s))
            return pr_quadric(a, P, u)
        return pr_quadric((a[0] - l * c, a[1] + l * s), A, u)

    def _ik(self, x, y, phi, g, tol):
        A, u, a, l = g["base"], g["axis"], g["platform"], g["length"]
        ax, ay = world_point(x, y, phi, a)
        gam = direction_angle(u)
        out = []
        for s in circle_line((ax, ay), l, A, u, tol.ik_tangent):
            Sx, Sy = A[0] + s * u[0], A[1] + s * u[1]
            t = np.arctan2(ay - Sy, ax - Sx)
            out.append(np.stack([s, wrap_angle(t - gam), wrap_angle(phi - t)], -1))
        return np.stack(out, -2)

    def _points(self, pose, q, g):
        A, u = g["base"], g["axis"]
        S = (A[0] + q[0] * u[0], A[1] + q[0] * u[1])
        return np.array([A, S, world_point(*pose, g["platform"])], dtype=float)


class RRP(Leg):
    """RRP leg: revolute at ``base``, link ``length``, revolute at the elbow, prismatic along a platform line.

    Parameters
    ----------
    base : (2,) base pivot A
    length : positive link length (A to the elbow E)
    platform : (2,) a point b of the platform line (moving frame); the travel ``s`` is measured from it
    direction : (2,) direction v of the platform line (moving frame, normalised)
    actuated : int, default 0
        0: base revolute (RP dyad: the platform line through E); 1: elbow (RP dyad of a parallel
        platform line through A); 2: the platform slider (RR dyad).

    Examples
    --------
    >>> import imagespace as isp
    >>> leg = isp.RRP(base=(0, 0), length=1, platform=(0, 0), direction=(1, 0))
    >>> leg.actuated_values([0.0, 0.5, 0.0]).round(6)
    array([0.523599, 2.617994])
    """

    joints = "RRP"
    default_actuated = 0
    joint_names = ("theta1", "theta2", "s")
    n_branches = 2

    def __init__(self, base: Any, length: Any, platform: Any, direction: Any,
                 actuated: Optional[int] = None) -> None:
        super().__init__(actuated)
        self.base = geometry_point(base, "base")
        self.length = check_positive(geometry_number(length, "length"), "length")
        self.platform = geometry_point(platform, "platform")
        self.direction = unit_direction(direction, "direction")

    def _geometry(self):
        return {"base": self.base, "length": self.length, "platform": self.platform,
                "direction": self.direction}

    def _dyad(self, q, g, ops):
        A, l, b, v = g["base"], g["length"], g["platform"], g["direction"]
        if self.actuated == 2:
            return rr_quadric(A, l * l, (b[0] + q * v[0], b[1] + q * v[1]))
        c, s = ops.cs(q)
        if self.actuated == 0:
            return rp_quadric(b, v, (A[0] + l * c, A[1] + l * s))
        w = (v[0] * c + v[1] * s, v[1] * c - v[0] * s)   # e^{i(angle(v) - q)}
        return rp_quadric((b[0] - l * w[0], b[1] - l * w[1]), v, A)

    def _ik(self, x, y, phi, g, tol):
        A, l, b, v = g["base"], g["length"], g["platform"], g["direction"]
        bw = world_point(x, y, phi, b)
        vw = rotate_vector(phi, v)
        out = []
        for s in circle_line(A, l, bw, vw, tol.ik_tangent):
            Ex, Ey = bw[0] + s * vw[0], bw[1] + s * vw[1]
            t1 = np.arctan2(Ey - A[1], Ex - A[0])
            out.append(np.stack([t1, wrap_angle(phi + direction_angle(v) - t1), s], -1))
        return np.stack(out, -2)

    def _points(self, pose, q, g):
        A, l, b, v = g["base"], g["length"], g["platform"], g["direction"]
        E = (A[0] + l * np.cos(q[0]), A[1] + l * np.sin(q[0]))
        return np.array([A, E, world_point(*pose, b)], dtype=float)


class RPP(Leg):
    """RPP leg: revolute at ``base``, a slider along the rotating arm, a second slider at a fixed ``angle`` to it along a platform line.

    Parameters
    ----------
    base : (2,) base pivot A
    platform : (2,) a point b of the platform line (moving frame)
    direction : (2,) direction v of the platform line (moving frame)
    angle : fixed angle beta from the first slider to the second (not 0 or pi)
    actuated : int, default 1
        0: base revolute (PP dyad: orientation fixed); 1: first slider (RP dyad of a parallel
        platform line through A); 2: second slider (RP dyad).

    Examples
    --------
    >>> import imagespace as isp
    >>> import numpy as np
    >>> leg = isp.RPP(base=(0, 0), platform=(0, 0), direction=(1, 0), angle=np.pi / 2)
    >>> leg.inverse_kinematics([0.0, 2.0, 0.0]).round(6)
    array([[-1.570796, -2.      ,  0.      ]])
    """

    joints = "RPP"
    default_actuated = 1
    joint_names = ("theta1", "s1", "s2")

    def __init__(self, base: Any, platform: Any, direction: Any, angle: Any,
                 actuated: Optional[int] = None) -> None:
        super().__init__(actuated)
        self.base = geometry_point(base, "base")
        self.platform = geometry_point(platform, "platform")
        self.direction = unit_direction(direction, "direction")
        self.angle = geometry_number(angle, "angle")
        self._beta_cs = exact_cos_sin(angle, "angle")
        if not self._beta_cs[1].free_symbols and float(self._beta_cs[1]) == 0.0:
            raise DegenerateDesignError(f"angle (between the two sliders of RPP) must not be 0 or pi, got {angle}")

    def _geometry(self):
        return {"base": self.base, "platform": self.platform, "direction": self.direction,
                "angle_cs": self._beta_cs}

    def _dyad(self, q, g, ops):
        A, b, v, (cb, sb) = g["base"], g["platform"], g["direction"], g["angle_cs"]
        # e^{i(angle(v) - beta)}: the first slider's direction seen from the platform
        w = (v[0] * cb + v[1] * sb, v[1] * cb - v[0] * sb)
        if self.actuated == 1:
            return rp_quadric((b[0] - q * w[0], b[1] - q * w[1]), v, A)
        if self.actuated == 2:
            return rp_quadric((b[0] + q * v[0], b[1] + q * v[1]), w, A)
        c, s = ops.cs(q)
        # phi_c = q + beta - angle(v): cos/sin through e^{iq} * conj(w)
        return pp_quadric(c * w[0] + s * w[1], s * w[0] - c * w[1])

    def _ik(self, x, y, phi, g, tol):
        A, b, v, (cb, sb) = g["base"], g["platform"], g["direction"], g["angle_cs"]
        beta = np.arctan2(sb, cb)
        t1 = wrap_angle(phi + direction_angle(v) - beta)
        d1 = (np.cos(t1), np.sin(t1))
        bw = world_point(x, y, phi, b)
        vw = rotate_vector(phi, v)
        s1, s2 = lines_meet(A, d1, bw, vw, tol.ik_parallel)
        return np.stack([t1, s1, s2], -1)[..., None, :]

    def _points(self, pose, q, g):
        A = g["base"]
        S = (A[0] + q[1] * np.cos(q[0]), A[1] + q[1] * np.sin(q[0]))
        return np.array([A, S, world_point(*pose, g["platform"])], dtype=float)


class PRP(Leg):
    """PRP leg: slider along ``axis`` from ``base``, revolute on it, prismatic along a platform line.

    Parameters
    ----------
    base : (2,) start of the slider
    axis : (2,) slider direction u
    platform : (2,) point b of the platform line (moving frame)
    direction : (2,) direction v of the platform line (moving frame)
    actuated : int, default 0
        0: slider travel (RP dyad: the platform line through ``base + q u``); 1: the revolute
        (PP dyad); 2: travel along the platform line (PR dyad).

    Examples
    --------
    >>> import imagespace as isp
    >>> leg = isp.PRP(base=(0, 0), axis=(1, 0), platform=(0, 0), direction=(0, 1))
    >>> leg.inverse_kinematics([2.0, 1.0, 0.0]).round(6)
    array([[ 2.      ,  1.570796, -1.      ]])
    """

    joints = "PRP"
    default_actuated = 0
    joint_names = ("s1", "theta2", "s2")

    def __init__(self, base: Any, axis: Any, platform: Any, direction: Any,
                 actuated: Optional[int] = None) -> None:
        super().__init__(actuated)
        self.base = geometry_point(base, "base")
        self.axis = unit_direction(axis, "axis")
        self.platform = geometry_point(platform, "platform")
        self.direction = unit_direction(direction, "direction")

    def _geometry(self):
        return {"base": self.base, "axis": self.axis, "platform": self.platform,
                "direction": self.direction}

    def _dyad(self, q, g, ops):
        A, u, b, v = g["base"], g["axis"], g["platform"], g["direction"]
        if self.actuated == 0:
            return rp_quadric(b, v, (A[0] + q * u[0], A[1] + q * u[1]))
        if self.actuated == 2:
            return pr_quadric((b[0] + q * v[0], b[1] + q * v[1]), A, u)
        c, s = ops.cs(q)
        # phi_c = angle(u) + q - angle(v): e^{i phi_c} = u e^{iq} conj(v)
        ux, uy = u[0] * c - u[1] * s, u[1] * c + u[0] * s
        return pp_quadric(ux * v[0] + uy * v[1], uy * v[0] - ux * v[1])

    def _ik(self, x, y, phi, g, tol):
        A, u, b, v = g["base"], g["axis"], g["platform"], g["direction"]
        bw = world_point(x, y, phi, b)
        vw = rotate_vector(phi, v)
        s1, s2 = lines_meet(A, u, bw, vw, tol.ik_parallel)
        t2 = wrap_angle(phi + direction_angle(v) - direction_angle(u))
        return np.stack([s1, t2, s2], -1)[..., None, :]

    def _points(self, pose, q, g):
        A, u = g["base"], g["axis"]
        S = (A[0] + q[0] * u[0], A[1] + q[0] * u[1])
        return np.array([A, S, world_point(*pose, g["platform"])], dtype=float)


class PPR(Leg):
    """PPR leg: slider along ``axis`` from ``base``, a second slider at ``angle`` to it, revolute at ``platform``.

    Parameters
    ----------
    base : (2,) start C of the first slider
    axis : (2,) direction u of the first slider (normalised); the first joint value is the
        travel along ``axis`` from ``base``
    platform : (2,) platform anchor c (moving frame)
    angle : angle beta from the first slider to the second (not 0 or pi)
    actuated : int, default 0
        0: first slider (PR dyad: c on the line through ``base + q u`` along the second slider);
        1: second slider (PR dyad); 2: the revolute (PP dyad).

    Examples
    --------
    >>> import imagespace as isp
    >>> import numpy as np
    >>> leg = isp.PPR(base=(0, 0), axis=(1, 0), platform=(0, 0), angle=np.pi / 2)
    >>> leg.inverse_kinematics([2.0, 3.0, 0.5]).round(6)
    array([[2. , 3. , 0.5]])
    """

    joints = "PPR"
    default_actuated = 0
    joint_names = ("s1", "s2", "theta3")

    def __init__(self, base: Any, axis: Any, platform: Any, angle: Any,
                 actuated: Optional[int] = None) -> None:
        super().__init__(actuated)
        self.base = geometry_point(base, "base")
        self.axis = unit_direction(axis, "axis")
        self.platform = geometry_point(platform, "platform")
        self.angle = geometry_number(angle, "angle")
        cb, sb = exact_cos_sin(angle, "angle")
        if not sb.free_symbols and float(sb) == 0.0:
            raise DegenerateDesignError(f"angle (between the two sliders of PPR) must not be 0 or pi, got {angle}")
        u = self.axis
        self.second_axis = (sp.radsimp(u[0] * cb - u[1] * sb), sp.radsimp(u[1] * cb + u[0] * sb))

    def _geometry(self):
        return {"base": self.base, "axis": self.axis, "platform": self.platform,
                "second_axis": self.second_axis}

    def _dyad(self, q, g, ops):
        C, u, c, w = g["base"], g["axis"], g["platform"], g["second_axis"]
        if self.actuated == 0:
            return pr_quadric(c, (C[0] + q * u[0], C[1] + q * u[1]), w)
        if self.actuated == 1:
            return pr_quadric(c, (C[0] + q * w[0], C[1] + q * w[1]), u)
        cq, sq = ops.cs(q)
        return pp_quadric(cq, sq)

    def _ik(self, x, y, phi, g, tol):
        C, u, c, w = g["base"], g["axis"], g["platform"], g["second_axis"]
        cw = world_point(x, y, phi, c)
        s1, t = lines_meet(C, u, cw, w, tol.ik_parallel)
        return np.stack([s1, -t, wrap_angle(phi)], -1)[..., None, :]

    def _points(self, pose, q, g):
        C, u = g["base"], g["axis"]
        S = (C[0] + q[0] * u[0], C[1] + q[0] * u[1])
        return np.array([C, S, world_point(*pose, g["platform"])], dtype=float)


LEG_TYPES = {cls.joints: cls for cls in (RPR, RRR, PRR, RRP, RPP, PRP, PPR)}
