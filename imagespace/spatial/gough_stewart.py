r"""The Gough-Stewart platform (6-SPS) in Study's image space.

Six legs join base points ``a_i`` (base frame) to platform points ``b_i`` (moving frame) through
spherical joints; the prismatic joint sets the leg length ``L_i``. Each leg is the sphere quadric of
:func:`imagespace.spatial.quadrics.sphere_quadric`; the direct kinematics is the intersection of the
six of them with Study's quadric in ``P^7``: 40 complex solutions for a general design (Husty 1996;
Raghavan 1993), and designs with 40 real assembly modes exist (Dietmaier 1998).

Special cases are the same class: a 6-3 platform has its platform points coincident in pairs, a 3-3
(octahedral) platform both. They have at most 16 assembly modes (:data:`PAIRED_BOUND`), which the
certificate uses to prove a row complete. Degenerate designs are refused at construction
(:class:`~imagespace.exceptions.DegenerateDesignError`): two identical legs, all base or all platform
points on one line (the platform turns freely about it).

References
----------
M. L. Husty, An algorithm for solving the direct kinematics of general Stewart-Gough platforms,
Mechanism and Machine Theory 31(4), 1996, doi:10.1016/0094-114X(95)00091-C.
M. Raghavan, The Stewart platform of general geometry has 40 configurations, ASME J. Mech. Des.
115(2), 1993, doi:10.1115/1.2919188.
P. Dietmaier, The Stewart-Gough platform of general geometry can have 40 real postures, Advances
in Robot Kinematics 1998, doi:10.1007/978-94-015-9064-8_1.
M. Griffis, J. Duffy, A forward displacement analysis of a class of Stewart platforms, J. Robotic
Systems 6(6), 703-720, 1989 (the 3-3 octahedral platform: 16 solutions).
P. Nanua, K. J. Waldron, V. Murthy, Direct kinematic solution of a Stewart platform, IEEE Trans.
Robotics and Automation 6(4), 438-444, 1990 (the 6-3 platform: a polynomial of degree 16).
J.-C. Faugere, D. Lazard, Combinatorial classes of parallel manipulators, Mechanism and Machine
Theory 30(6), 765-776, 1995 (the complex counts of the classes with coincident joints: 16 for 6-3).
A. J. Sommese, C. W. Wampler, The Numerical Solution of Systems of Polynomials Arising in
Engineering and Science, World Scientific, 2005, Theorem 7.1.1 (coefficient-parameter theorem).
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING, Optional, Union

import numpy as np
import numpy.typing as npt

from .._validate import as_float_array, as_tolerances, check_squares
from ..exceptions import DegenerateDesignError
from .certify import exact_matrix
from .platform import QuadricPlatform, anchor_points, check_lengths
from .quadrics import sphere_quadric, sphere_quadric_exact, study_quadric_matrix
from .solver import QuadricFamily
from .study import rotation_entries, vector_norm

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray
    from ..tolerances import Tolerances

__all__ = ["GoughStewart", "GOUGH_STEWART_BOUND", "PAIRED_BOUND"]

#: Every Gough-Stewart platform has at most 40 isolated assembly modes over C (Raghavan 1993;
#: Ronga & Vust 1992, Lazard 1993, Mourrain 1993): the generic design has 40 complex solutions with
#: ``x.x != 0`` (msolve confirms it on random designs, ``tests/spatial/test_exact.py``), and the
#: coefficient-parameter theorem (Morgan & Sommese 1989; Sommese & Wampler 2005, Thm 7.1.1) bounds
#: the isolated solutions in the open set ``x.x != 0`` of every member of the family (designs
#: and lengths) by the generic count.
GOUGH_STEWART_BOUND = 40

#: A 6-3 platform (the six platform points are three distinct points, each shared by two legs), a
#: 3-6 platform (the same for the base) and a 3-3 platform (both; a special 6-3) have at most 16
#: isolated assembly modes over C with ``x.x != 0``: 16 is the generic count of the 6-3 family
#: (Nanua, Waldron & Murthy 1990; Faugere & Lazard 1995; the 3-3: Griffis & Duffy 1989; msolve
#: confirms 16 on random 6-3, 3-6 and 3-3 designs, ``tests/spatial/test_fast_certificate.py``), and
#: the coefficient-parameter theorem carries it to every member of the family. A 3-6 platform is a
#: 6-3 platform for the inverse motion (``(x, y) -> (x~, y~)``, a linear map of ``P^7`` keeping
#: ``x.x``), so the bound is the same.
PAIRED_BOUND = 16


def _study_points(s):
    """The numeric face's Study points: a float ``(8,)`` or ``(n, 8)`` array (sympy numbers become
    floats, symbols and strings are refused); the Study-map functions check ``x != 0``."""
    return as_float_array(s, "s", last=8)


def _paired(P):
    """True when the six points are three distinct points, each taken exactly twice."""
    rows = [tuple(float(v) for v in p) for p in P]
    distinct = set(rows)
    return len(distinct) == 3 and all(rows.count(p) == 2 for p in distinct)


def _collinear(P, tol):
    """True when every point lies on one line (all coincident included), relative to the size of the
    coordinates (scaled first: the same answer in any unit, no overflow at any magnitude)."""
    scale = float(np.abs(P).max())
    if scale == 0.0:
        return True
    Ps = P / scale
    sv = np.linalg.svd(Ps - Ps.mean(axis=0), compute_uv=False)
    return sv[1] <= tol


class GoughStewart(QuadricPlatform):
    """A 6-SPS Gough-Stewart platform.

    Parameters
    ----------
    base_points : (6, 3) float
        The base anchors ``a_i`` in the base frame.
    platform_points : (6, 3) float
        The platform anchors ``b_i`` in the moving frame. Coincident pairs give the 6-3 and 3-3
        special cases.
    tolerances : Tolerances, optional

    Raises
    ------
    InputError
        On wrong shapes or non-finite coordinates.
    DegenerateDesignError
        If two legs are identical (same base and platform anchor), or all base points or all
        platform points lie on one line (within ``Tolerances.spatial_collinear`` relative to the
        coordinates' size).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> gs = GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> gs.inverse_kinematics([1, 0, 0, 0, 0, 0, 0, 0]).shape
    (6,)
    """

    leg_count = 6

    def __init__(self, base_points: npt.ArrayLike, platform_points: npt.ArrayLike,
                 tolerances: Optional[Tolerances] = None) -> None:
        self.tolerances = as_tolerances(tolerances)
        self.base_points = anchor_points(base_points, "base_points", 6)
        self.platform_points = anchor_points(platform_points, "platform_points", 6)
        tol = self.tolerances.spatial_collinear
        for i in range(6):
            for j in range(i):
                if (np.array_equal(self.base_points[i], self.base_points[j])
                        and np.array_equal(self.platform_points[i], self.platform_points[j])):
                    raise DegenerateDesignError(
                        f"legs {j} and {i} are identical (base point {self.base_points[i].tolist()}, "
                        f"platform point {self.platform_points[i].tolist()}): the design has five "
                        "distinct legs and a continuum of poses")
        if _collinear(self.base_points, tol):
            raise DegenerateDesignError("base_points all lie on one line: the platform can turn about "
                                        "it (a continuum of poses); expected anchors spanning a plane")
        if _collinear(self.platform_points, tol):
            raise DegenerateDesignError("platform_points all lie on one line: the platform can turn "
                                        "about it (a continuum of poses); expected anchors spanning a plane")

    def __repr__(self):
        return (f"GoughStewart(base_points={self.base_points.tolist()}, "
                f"platform_points={self.platform_points.tolist()})")

    # ------------------------------------------------------------------ kinematics

    def inverse_kinematics(self, s: npt.ArrayLike) -> FloatArray:
        """The six leg lengths ``L_i = |R b_i + t - a_i|`` at Study points.

        Parameters
        ----------
        s : (8,) or (n, 8) float
            Study points (:func:`imagespace.spatial.study.study_point`).

        Returns
        -------
        (6,) or (n, 6) float

        Raises
        ------
        InputError
            If ``x = 0``, on wrong shapes or non-finite entries.

        Examples
        --------
        >>> gs = GoughStewart(np.eye(6, 3), np.eye(6, 3)[::-1] + 1)
        >>> gs.inverse_kinematics([1, 0, 0, 0, 0, 0, 0, 0]).round(6)
        array([1.414214, 1.414214, 1.414214, 2.44949 , 2.44949 , 2.44949 ])
        """
        return vector_norm(self.leg_vectors(_study_points(s)))

    def constraint_quadrics(self, lengths: npt.ArrayLike) -> FloatArray:
        """The seven quadrics of the direct kinematics: six legs, then Study's quadric.

        Parameters
        ----------
        lengths : (6,) float
            Leg lengths, positive.

        Returns
        -------
        (7, 8, 8) float
            ``z^T Q_k z = 0`` for every assembly mode ``z``.

        Raises
        ------
        InputError
            If ``lengths`` is not six positive finite numbers.

        Examples
        --------
        >>> gs = GoughStewart(np.eye(6, 3), np.eye(6, 3)[::-1] + 1)
        >>> gs.constraint_quadrics(np.ones(6)).shape
        (7, 8, 8)
        """
        L = check_lengths(lengths)
        check_squares(L, "lengths")
        return np.concatenate([sphere_quadric(self.base_points, self.platform_points, L),
                               study_quadric_matrix()[None]], axis=0)

    def jacobian(self, s: npt.ArrayLike) -> FloatArray:
        """The ``6 x 6`` Jacobian whose rows are the legs' line coordinates ``(s_i, a_i x s_i)``.

        ``s_i = R b_i + t - a_i`` is leg ``i``'s vector; ``L_i dL_i/dt = s_i . v_O + (a_i x s_i) . w``
        for a platform twist with angular velocity ``w`` and ``v_O`` the velocity of the platform
        point at the base origin.

        Parameters
        ----------
        s : (8,) or (n, 8) float

        Returns
        -------
        (6, 6) or (n, 6, 6) float

        Raises
        ------
        InputError
            If ``x = 0``, on wrong shapes or non-finite entries.

        Examples
        --------
        >>> gs = GoughStewart(np.eye(6, 3), np.eye(6, 3)[::-1] + 1)
        >>> gs.jacobian([1, 0, 0, 0, 0, 0, 0, 0]).shape
        (6, 6)
        """
        V = self.leg_vectors(_study_points(s))
        return np.concatenate([V, np.cross(self.base_points, V)], axis=-1)

    def aspects(self, s: npt.ArrayLike, tolerances: Optional[Tolerances] = None) -> Union[int, npt.NDArray[np.int8]]:
        """The aspect of poses: the sign of ``det J`` (+1, -1), or 0 at a singularity.

        The decision is scale-free: the moment columns are divided by the design's length scale
        ``c = max |a_i|`` (both halves of a row are then lengths; this multiplies ``det J`` by
        ``c^-3 > 0`` and keeps its sign), and the pose is singular (aspect 0) when
        ``|det| <= Tolerances.spatial_aspect * prod(row norms)`` for these balanced rows (Hadamard's
        bound). Without the balancing the ratio would change with the unit of length (rows mix
        lengths and squared lengths): the same design in micrometres would look singular
        everywhere. Moving the base origin adds cross products of the first three columns to the
        last three, which leaves ``det J`` unchanged.

        Parameters
        ----------
        s : (8,) or (n, 8) float
        tolerances : Tolerances, optional
            Default: the design's own ``tolerances``.

        Returns
        -------
        int or (n,) int8

        Raises
        ------
        InputError
            If ``x = 0``, on wrong shapes or non-finite entries.
        TypeError
            If ``tolerances`` is not a Tolerances.

        Examples
        --------
        >>> gs = GoughStewart(np.eye(6, 3), np.eye(6, 3)[::-1] + 1)
        >>> int(gs.aspects([1, 0, 0, 0, 0, 0, 0, 0])) in (-1, 0, 1)
        True
        """
        tol = (self.tolerances if tolerances is None else as_tolerances(tolerances)).spatial_aspect
        # the rows (s_i, a_i x s_i / c) divided by c: lengths of order 1 at any size of the design
        # (det scaled by c^-6 > 0, the Hadamard ratio unchanged); the products never see the
        # square of a tiny or huge coordinate
        amax = float(np.max(np.abs(self.base_points)))
        c = amax * float(np.max(vector_norm(self.base_points / amax)))      # max |a_i|
        V = self.leg_vectors(_study_points(s)) / c
        J = np.concatenate([V, np.cross(self.base_points / c, V)], axis=-1)
        # |det J| / prod(row norms) is det of the rows scaled to unit length: no overflow or
        # underflow at any magnitude (a far pose, a design in micrometres or light years)
        n = vector_norm(J)[..., None]
        d = np.linalg.det(J / np.where(n > 0, n, 1.0))
        out = np.where(np.abs(d) > tol, np.sign(d), 0).astype(np.int8)
        return int(out) if out.ndim == 0 else out

    @cached_property
    def architecturally_singular(self) -> bool:
        """True when ``det J`` vanishes at every pose (an architecture singularity).

        Decided in exact rational arithmetic: ``det J`` at three seeded rational poses (rational
        quaternions and translations, the anchors as their binary rationals). One non-zero value
        proves the design is not architecturally singular; three exact zeros at independent random
        rational poses are taken as the identically vanishing determinant (a non-singular design
        would need all three random poses on its singularity surface). Such designs have a
        continuum of poses for reachable leg lengths: :meth:`direct_kinematics` refuses them.

        Returns
        -------
        bool

        Examples
        --------
        >>> xs = np.array([-1.0, -0.5, 0.25, 0.5, 1.0, 1.5])      # six points on y = x^2
        >>> a = np.stack([xs, xs ** 2, np.zeros(6)], axis=1)
        >>> GoughStewart(a, a / 2).architecturally_singular          # a similar copy: singular
        True
        >>> GoughStewart(a, a[::-1] / 2).architecturally_singular
        False
        """
        from fractions import Fraction

        rng = np.random.default_rng(20261202)
        A = [[Fraction(float(v)) for v in p] for p in self.base_points]
        B = [[Fraction(float(v)) for v in p] for p in self.platform_points]
        for _ in range(3):
            q = [Fraction(int(v)) for v in rng.integers(-9, 10, 4)]
            if not any(q):
                q[0] = Fraction(1)
            t = [Fraction(int(v), 8) for v in rng.integers(-16, 17, 3)]
            if _exact_det(_exact_jacobian(q, t, A, B)) != 0:
                return False
        return True

    def check_design(self) -> None:
        """Refuse an architecturally singular design (the direct kinematics calls this).

        Raises
        ------
        DegenerateDesignError
            If :attr:`architecturally_singular`.

        Examples
        --------
        >>> rng = np.random.default_rng(0)
        >>> GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3))).check_design()
        """
        if self.architecturally_singular:
            raise DegenerateDesignError(
                "the design is architecturally singular (det J vanishes at every pose, e.g. "
                "affinely related planar hexagons on a conic): its leg lengths fix a continuum of "
                "poses, not finitely many; expected a design with det J not identically zero")

    # ------------------------------------------------------------------ direct kinematics

    def family(self) -> QuadricFamily:
        """The direct kinematics as a :class:`~imagespace.spatial.solver.QuadricFamily`.

        Parameters are the squared leg lengths; quadric 6 is Study's.

        Returns
        -------
        QuadricFamily

        Examples
        --------
        >>> gs = GoughStewart(np.eye(6, 3), np.eye(6, 3)[::-1] + 1)
        >>> gs.family().bound
        40
        """
        return self._family

    @cached_property
    def _family(self):
        # built once per design: every direct-kinematics call (and every certified batch row)
        # reads it
        sc = self._scale
        A = np.concatenate([sphere_quadric(self.base_points / sc, self.platform_points / sc, 0.0),
                            study_quadric_matrix()[None]], axis=0)
        E = np.diag([1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0])
        return QuadricFamily(A, E, np.array([0, 1, 2, 3, 4, 5, -1]), 6, self.solution_bound,
                             self._exact_quadrics, self._aspects_or_empty, sc)

    @property
    def solution_bound(self) -> int:
        """A theorem's bound on the isolated complex assembly modes of every length vector.

        :data:`PAIRED_BOUND` (16) for a 6-3, 3-6 or 3-3 platform (anchors coincident in three
        pairs on one side), :data:`GOUGH_STEWART_BOUND` (40) otherwise. The certificates prove a
        row complete when they prove this many distinct solutions.

        Returns
        -------
        int

        Examples
        --------
        >>> b = [[1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [1, 1, 0], [-1, 1, 0]]
        >>> p = [[0.5, 0, 0]] * 2 + [[0, 0.5, 0]] * 2 + [[-0.5, -0.5, 0]] * 2
        >>> GoughStewart(b, p).solution_bound, GoughStewart(b, b[::-1]).solution_bound
        (16, 40)
        """
        if _paired(self.platform_points) or _paired(self.base_points):
            return PAIRED_BOUND
        return GOUGH_STEWART_BOUND

    def _aspects_or_empty(self, pts):
        return np.atleast_1d(self.aspects(pts)).astype(np.int8) if pts.shape[0] else np.zeros(0, np.int8)

    def _exact_quadrics(self, squared_lengths):
        out = np.empty((7, 8, 8), dtype=object)
        for i in range(6):
            Q = self._exact_design[i].copy()
            for d in range(4):
                Q[d, d] -= squared_lengths[i]
            out[i] = Q
        out[6] = exact_matrix(study_quadric_matrix())
        return out

    @cached_property
    def _exact_design(self):
        # the legs' exact quadrics at length zero (the length enters as -L^2 on the x.x diagonal)
        sc = self._scale
        return [sphere_quadric_exact(self.base_points[i] / sc, self.platform_points[i] / sc, 0)
                for i in range(6)]


def _exact_det(rows):
    """Determinant of a square matrix of Fractions, exactly (python-flint's ``fmpq_mat``)."""
    import flint

    return flint.fmpq_mat([[flint.fmpq(v.numerator, v.denominator) for v in r] for r in rows]).det()


def _exact_jacobian(q, t, A, B):
    """Rows ``(s_i, a_i x s_i)`` at the rational pose (quaternion ``q``, translation ``t``)."""
    n = sum(v * v for v in q)
    R = rotation_entries(*q)
    rows = []
    for a, b in zip(A, B):
        s = [sum(R[i][j] * b[j] for j in range(3)) / n + t[i] - a[i] for i in range(3)]
        m = [a[1] * s[2] - a[2] * s[1], a[2] * s[0] - a[0] * s[2], a[0] * s[1] - a[1] * s[0]]
        rows.append(s + m)
    return rows
