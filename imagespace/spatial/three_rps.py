r"""The 3-RPS parallel manipulator in Study's image space.

Three legs: a revolute joint at base point ``a_i`` with axis ``u_i``, a prismatic joint of length
``L_i`` (actuated) and a spherical joint at platform point ``b_i``. The revolute joint keeps leg
``i`` in the plane through ``a_i`` normal to ``u_i``, so its platform point satisfies

* a sphere condition, ``|R b_i + t - a_i| = L_i`` (:func:`~imagespace.spatial.quadrics.sphere_quadric`),
* a plane condition, ``u_i . (R b_i + t - a_i) = 0`` (:func:`~imagespace.spatial.quadrics.point_on_plane_quadric`),

six quadrics that with Study's quadric cut out the assembly modes in ``P^7``: 16 complex
displacements for a general design (Schadlbauer, Walter & Husty 2014; our exact path confirms 16
on random designs, see the tests). The plane quadrics must be exact: rounded to floats, the
structure that sends 24 of the 40 solutions of seven general quadrics to the exceptional
generator ``x = 0`` is lost, and msolve then counts 40.

At most 16 isolated complex solutions with ``x.x != 0`` for every design and lengths
(:data:`THREE_RPS_BOUND`): 16 is the generic count (Schadlbauer, Walter & Husty 2014; msolve
confirms it on random designs, ``tests/spatial/test_three_rps.py``), and the coefficient-parameter
theorem (Sommese & Wampler 2005, Thm 7.1.1) bounds every member of the family by it. So
``certify=True`` proves a row with Krawczyk boxes (compiled, then arb) when 16 distinct solutions
are proven, and needs msolve only where they are not (at or very near a double mode).

References
----------
J. Schadlbauer, D. R. Walter, M. L. Husty, The 3-RPS parallel manipulator from an algebraic
viewpoint, Mechanism and Machine Theory 75, 2014, doi:10.1016/j.mechmachtheory.2014.01.006.
A. J. Sommese, C. W. Wampler, The Numerical Solution of Systems of Polynomials Arising in
Engineering and Science, World Scientific, 2005, Theorem 7.1.1 (coefficient-parameter theorem).
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING, Optional

import numpy as np
import numpy.typing as npt

from .._validate import as_float_array, as_tolerances, check_squares
from ..exceptions import DegenerateDesignError, InputError
from .certify import exact_matrix
from .platform import QuadricPlatform, anchor_points, check_lengths
from .quadrics import (point_on_plane_quadric, sphere_quadric, sphere_quadric_exact,
                       study_quadric_matrix)
from .solver import QuadricFamily, study_jacobian_signs
from .study import vector_norm

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray
    from ..tolerances import Tolerances

__all__ = ["ThreeRPS", "THREE_RPS_BOUND"]

#: Every 3-RPS has at most 16 isolated complex assembly modes with ``x.x != 0`` (the generic
#: count, Schadlbauer, Walter & Husty 2014, carried to every member by the coefficient-parameter
#: theorem).
THREE_RPS_BOUND = 16


def _tangent_axes(a):
    """Axes tangent to the base triangle's circumcircle (the classic 3-RPS), in its plane (computed
    on the scaled triangle, then scaled back: no overflow or underflow at any size)."""
    scale = float(np.abs(a).max())
    a = a / scale
    n = np.cross(a[1] - a[0], a[2] - a[0])
    n = n / np.linalg.norm(n)
    c = a.mean(axis=0)
    return np.cross(n, a - c) * scale


class ThreeRPS(QuadricPlatform):
    """A 3-RPS parallel manipulator.

    Parameters
    ----------
    base_points : (3, 3) float
        Revolute joint centres ``a_i`` (base frame); not collinear.
    platform_points : (3, 3) float
        Spherical joint centres ``b_i`` (moving frame); not collinear.
    base_axes : (3, 3) float, optional
        Revolute axes ``u_i`` (non-zero). Default: tangent to the circumcircle of the base triangle,
        in its plane (each leg then moves in a plane through the base's centre line).
    tolerances : Tolerances, optional

    Raises
    ------
    InputError
        On wrong shapes, non-finite entries or a zero axis.
    DegenerateDesignError
        If the base or platform points are collinear (within ``Tolerances.spatial_collinear``).

    Examples
    --------
    >>> m = ThreeRPS([[1, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0]],
    ...              [[0.5, 0, 0], [-0.25, 0.4, 0], [-0.25, -0.4, 0]])
    >>> m.inverse_kinematics([1, 0, 0, 0, 0, 0, 0, 1.0]).round(3)      # platform raised by 2
    array([2.062, 2.055, 2.055])
    """

    leg_count = 3

    def __init__(self, base_points: npt.ArrayLike, platform_points: npt.ArrayLike,
                 base_axes: Optional[npt.ArrayLike] = None, tolerances: Optional[Tolerances] = None) -> None:
        self.tolerances = as_tolerances(tolerances)
        self.base_points = anchor_points(base_points, "base_points", 3)
        self.platform_points = anchor_points(platform_points, "platform_points", 3)
        tol = self.tolerances.spatial_collinear
        for name, P in (("base_points", self.base_points), ("platform_points", self.platform_points)):
            Ps = P / max(float(np.abs(P).max()), np.finfo(float).tiny)    # unit-free, no overflow
            if np.linalg.norm(np.cross(Ps[1] - Ps[0], Ps[2] - Ps[0])) <= tol:
                raise DegenerateDesignError(f"{name} are collinear: the platform can turn about their "
                                            "line; expected a triangle")
        if base_axes is None:
            self.base_axes = _tangent_axes(self.base_points)
            self.base_axes.setflags(write=False)
        else:
            self.base_axes = anchor_points(base_axes, "base_axes", 3)
            if np.any(np.all(self.base_axes == 0, axis=1)):
                raise InputError("base_axes must be non-zero vectors, got a zero row")

    def __repr__(self):
        return (f"ThreeRPS(base_points={self.base_points.tolist()}, "
                f"platform_points={self.platform_points.tolist()}, base_axes={self.base_axes.tolist()})")

    def inverse_kinematics(self, s: npt.ArrayLike) -> FloatArray:
        """Leg lengths ``|R b_i + t - a_i|``; the pose must keep each leg in its plane.

        Parameters
        ----------
        s : (8,) or (n, 8) float

        Returns
        -------
        (3,) or (n, 3) float

        Raises
        ------
        InputError
            If ``x = 0``, on wrong shapes or non-finite entries, or if a leg leaves its revolute
            joint's plane (``|u_i . leg| > Tolerances.spatial_plane`` times ``|u_i| |leg|``): such a
            pose is not reachable.

        Examples
        --------
        >>> m = ThreeRPS(np.eye(3), 0.5 * np.eye(3), base_axes=[[0, 1, -1], [1, 0, -1], [1, -1, 0]])
        >>> m.inverse_kinematics([1, 0, 0, 0, 0, 0, 0, 0]).round(3)
        array([0.5, 0.5, 0.5])
        """
        V = self.leg_vectors(as_float_array(s, "s", last=8))     # numeric face: symbols refused
        # the cosine of the angle between axis and leg, from unit vectors (no overflow at any size)
        norms = vector_norm(V)
        u = self.base_axes / vector_norm(self.base_axes)[:, None]
        with np.errstate(invalid="ignore"):
            cos = np.abs(np.einsum("ki,...ki->...k", u, V / np.where(norms > 0, norms, 1.0)[..., None]))
        if np.any(cos > self.tolerances.spatial_plane):
            off = np.abs(np.einsum("ki,...ki->...k", u, V))
            raise InputError("s must keep every leg in the plane of its revolute joint, got a pose "
                             f"{float(np.max(off)):.3g} off it (|u_i . leg| / |leg| up to {float(np.max(cos)):.3g})")
        return norms

    def constraint_quadrics(self, lengths: npt.ArrayLike) -> FloatArray:
        """Seven quadrics: three spheres, three planes, Study's quadric.

        Parameters
        ----------
        lengths : (3,) float

        Returns
        -------
        (7, 8, 8) float

        Raises
        ------
        InputError
            If ``lengths`` is not three positive finite numbers.

        Examples
        --------
        >>> ThreeRPS(np.eye(3), 0.5 * np.eye(3)).constraint_quadrics([1, 1, 1]).shape
        (7, 8, 8)
        """
        L = check_lengths(lengths, count=3)
        check_squares(L, "lengths")
        return np.concatenate([sphere_quadric(self.base_points, self.platform_points, L),
                               self._planes(1.0, self.base_axes), study_quadric_matrix()[None]], axis=0)

    @cached_property
    def _axes_scaled(self):
        # each axis divided by a power of two near its size: the same plane (u . leg = 0 is
        # homogeneous in u), exactly, with entries of order one at any design size
        size = np.abs(self.base_axes).max(axis=1)
        return self.base_axes / (2.0 ** np.round(np.log2(size)))[:, None]

    def _planes(self, sc, axes=None):
        axes = self._axes_scaled if axes is None else axes
        return np.array([point_on_plane_quadric(self.platform_points[i] / sc, self.base_points[i] / sc,
                                                axes[i]) for i in range(3)])

    @cached_property
    def _family(self):
        import sympy as sp

        sc = self._scale
        planes = self._planes(sc)
        A = np.concatenate([sphere_quadric(self.base_points / sc, self.platform_points / sc, 0.0),
                            planes, study_quadric_matrix()[None]], axis=0)
        E = np.diag([1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0])
        spheres = [sphere_quadric_exact(self.base_points[i] / sc, self.platform_points[i] / sc, 0)
                   for i in range(3)]
        fixed = [exact_matrix(np.array(point_on_plane_quadric(
            [sp.Rational(float(v)) for v in self.platform_points[i] / sc],
            [sp.Rational(float(v)) for v in self.base_points[i] / sc],
            [sp.Rational(float(v)) for v in self._axes_scaled[i]]).tolist(), dtype=object))
                 for i in range(3)] + [exact_matrix(study_quadric_matrix())]

        def exact(squared):
            out = np.empty((7, 8, 8), dtype=object)
            for i in range(3):
                Q = spheres[i].copy()
                for d in range(4):
                    Q[d, d] -= squared[i]
                out[i] = Q
            for k in range(4):
                out[3 + k] = fixed[k]
            return out

        fam = QuadricFamily(A, E, np.array([0, 1, 2, -1, -1, -1, -1]), 3, THREE_RPS_BOUND, exact,
                            lambda pts: study_jacobian_signs(fam, pts), sc)
        return fam

    def family(self) -> QuadricFamily:
        """The direct kinematics as a :class:`~imagespace.spatial.solver.QuadricFamily`.

        Returns
        -------
        QuadricFamily

        Examples
        --------
        >>> ThreeRPS(np.eye(3), 0.5 * np.eye(3)).family().nparams
        3
        """
        return self._family
