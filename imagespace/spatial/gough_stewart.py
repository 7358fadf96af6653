r"""The Gough-Stewart platform (6-SPS) in Study's image space.

Six legs join base points ``a_i`` (base frame) to platform points ``b_i`` (moving frame) through
spherical joints; the prismatic joint sets the leg length ``L_i``. Each leg is the sphere quadric of
:func:`imagespace.spatial.quadrics.sphere_quadric`; the direct kinematics is the intersection of the
six of them with Study's quadric in ``P^7``: 40 complex solutions for a general design (Husty 1996;
Raghavan 1993), and designs with 40 real assembly modes exist (Dietmaier 1998).

Special cases are the same class: a 6-3 platform has its platform points coincident in pairs, a 3-3
(octahedral) platform both. Degenerate designs are refused at construction
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
"""

from __future__ import annotations

import numpy as np

from .._validate import as_float_array, as_tolerances
from ..exceptions import DegenerateDesignError, InputError
from .quadrics import sphere_quadric, study_quadric_matrix
from .study import rotation_matrix, translation

__all__ = ["GoughStewart"]


def _check_points(value, name, count):
    P = as_float_array(value, name, allow_batch=True)
    if P.shape != (count, 3):
        raise InputError(f"{name} must have shape ({count}, 3), got {P.shape}")
    return P


def _collinear(P, tol):
    """True when every point lies on one line (all coincident included), relative to the spread."""
    c = P - P.mean(axis=0)
    scale = max(float(np.abs(P).max()), 1.0)
    sv = np.linalg.svd(c, compute_uv=False)
    return sv[1] <= tol * scale


class GoughStewart:
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

    def __init__(self, base_points, platform_points, tolerances=None):
        self.tolerances = as_tolerances(tolerances)
        self.base_points = _check_points(base_points, "base_points", 6)
        self.platform_points = _check_points(platform_points, "platform_points", 6)
        self.base_points.setflags(write=False)
        self.platform_points.setflags(write=False)
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

    def leg_vectors(self, s):
        """The leg vectors ``R b_i + t - a_i`` at Study points.

        Parameters
        ----------
        s : (8,) or (n, 8) float

        Returns
        -------
        (6, 3) or (n, 6, 3) float

        Raises
        ------
        InputError
            If ``x = 0``, on wrong shapes or non-finite entries.

        Examples
        --------
        >>> gs = GoughStewart(np.eye(6, 3), np.eye(6, 3)[::-1] + 1)
        >>> gs.leg_vectors([1, 0, 0, 0, 0, 0, 0, 0]).shape
        (6, 3)
        """
        R, t = rotation_matrix(s), translation(s)
        return np.einsum("...ij,kj->...ki", R, self.platform_points) + t[..., None, :] - self.base_points

    def inverse_kinematics(self, s):
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
        return np.linalg.norm(self.leg_vectors(s), axis=-1)

    def constraint_quadrics(self, lengths):
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
        return np.concatenate([sphere_quadric(self.base_points, self.platform_points, L),
                               study_quadric_matrix()[None]], axis=0)


def check_lengths(lengths, name="lengths", count=6, allow_batch=False):
    """Leg lengths as a checked float array: finite and positive.

    Parameters
    ----------
    lengths : (count,) or (n, count) float
    name : str
    count : int
    allow_batch : bool

    Returns
    -------
    (count,) or (n, count) float

    Raises
    ------
    InputError
        On a wrong shape, NaN/inf, or a length <= 0 (named by its index).

    Examples
    --------
    >>> check_lengths([1, 2, 3, 4, 5, 6])
    array([1., 2., 3., 4., 5., 6.])
    """
    L = as_float_array(lengths, name, last=count, allow_batch=allow_batch)
    bad = np.argwhere(~(L > 0))
    if bad.size:
        idx = tuple(int(v) for v in bad[0])
        raise InputError(f"{name} must be positive leg lengths, got {L[idx]} at index "
                         f"{idx if len(idx) > 1 else idx[0]}")
    return L
