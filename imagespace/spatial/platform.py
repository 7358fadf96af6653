"""What every spatial parallel platform of this package shares: anchors, leg vectors, the
:class:`~imagespace.core.mechanism.Mechanism` contract and the direct kinematics of its quadric
family through the one front end (:mod:`imagespace.solve.front`) and the spatial back ends
(:mod:`imagespace.spatial.backends`: fast, certified, exact; one row or a batch).

A platform subclass (:class:`~imagespace.spatial.GoughStewart`,
:class:`~imagespace.spatial.ThreeRPS`) supplies ``leg_count``, :meth:`QuadricPlatform.family` and,
where it has one, a design check (:meth:`QuadricPlatform.check_design`).
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
import numpy.typing as npt

from .._validate import as_float_array
from ..core.mechanism import Mechanism
from ..core.reach import point_pairs_obstruction
from ..exceptions import InputError
from ..solve.front import (certified_root_counts, direct_kinematics, direct_kinematics_batch,
                           direct_kinematics_chunks)
from . import backends as _backends
from .solver import start_system
from .study import rotation_matrix, translation

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray
    from .homotopy import StartSystem
    from .solver import QuadricFamily

__all__ = ["QuadricPlatform", "anchor_points", "check_lengths", "DK_METHODS"]

#: the direct kinematics' methods
DK_METHODS = ("fast", "exact")


def anchor_points(value: npt.ArrayLike, name: str, count: int) -> FloatArray:
    """Anchor coordinates as a private read-only ``(count, 3)`` float copy.

    Parameters
    ----------
    value : (count, 3) float
    name : str
    count : int

    Returns
    -------
    (count, 3) float

    Raises
    ------
    InputError
        On a wrong shape or non-finite entries.

    Examples
    --------
    >>> anchor_points([[0, 0, 0], [1, 0, 0], [0, 1, 0]], "base_points", 3).shape
    (3, 3)
    """
    P = np.array(as_float_array(value, name, allow_batch=True), dtype=float, copy=True)
    if P.shape != (count, 3):
        raise InputError(f"{name} must have shape ({count}, 3), got {P.shape}")
    P.setflags(write=False)
    return P


def check_lengths(lengths: npt.ArrayLike, name: str = "lengths", count: int = 6,
                  allow_batch: bool = False) -> FloatArray:
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
    L = as_float_array(lengths, name, last=count, allow_batch=allow_batch, finite=False)
    bad = np.argwhere(~(np.isfinite(L) & (L > 0)))
    if bad.size:
        idx = tuple(int(v) for v in bad[0])
        raise InputError(f"{name} must be positive finite leg lengths, got {L[idx]} at index "
                         f"{idx if len(idx) > 1 else idx[0]}")
    return L


class QuadricPlatform(Mechanism):
    """Base of the spatial platforms: ``base_points``, ``platform_points``, ``tolerances``; a
    :class:`~imagespace.core.mechanism.Mechanism` of the image space ``"study"``.

    Subclasses set ``leg_count`` and define :meth:`family` and :meth:`inverse_kinematics`.
    """

    leg_count = 0
    image_space = "study"
    base_points: FloatArray       # (legs, 3): set by the subclass's constructor
    platform_points: FloatArray
    #: the spatial back ends (imagespace.spatial.backends); the front end reads them
    backends = _backends.BACKENDS
    # the direct kinematics: the one front end (docstrings and examples at imagespace.solve.front)
    direct_kinematics = direct_kinematics
    direct_kinematics_batch = direct_kinematics_batch
    direct_kinematics_chunks = direct_kinematics_chunks
    certified_root_counts = certified_root_counts

    @property
    def joint_count(self) -> int:
        """Number of legs (the length of a row of leg lengths)."""
        return self.leg_count

    @property
    def name(self) -> str:  # type: ignore[override]  # read-only here: the name follows the class and legs
        """The design's name (its class, the number of legs and anchors)."""
        return f"{type(self).__name__} ({self.leg_count} legs)"

    def check_q(self, q: Any, name: str = "q (leg lengths)") -> FloatArray:
        """One row of leg lengths as checked floats: real, finite, positive (see :func:`check_lengths`).

        Examples
        --------
        >>> import imagespace as isp
        >>> gs, L = isp.examples.dietmaier_1998()
        >>> gs.check_q(L).shape
        (6,)
        """
        return check_lengths(q, name, count=self.leg_count)

    def joint_rows(self, Q: npt.ArrayLike) -> tuple[npt.NDArray[np.bool_], dict[int, str]]:
        """Which rows of a float array ``Q`` (n, legs) hold positive finite leg lengths:
        ``(ok, errors)`` (a batch never raises on one bad row).

        Examples
        --------
        >>> import numpy as np, imagespace as isp
        >>> gs, L = isp.examples.dietmaier_1998()
        >>> ok, errors = gs.joint_rows(np.array([L, -np.asarray(L)]))
        >>> ok.tolist(), sorted(errors)
        ([True, False], [1])
        """
        Q = np.atleast_2d(as_float_array(Q, "Q (rows of leg lengths)", last=self.leg_count, finite=False))
        ok = np.all(np.isfinite(Q) & (Q > 0), axis=1)
        errors = {int(i): f"lengths[{i}] must be positive finite leg lengths, got {Q[i].tolist()}"
                  for i in np.flatnonzero(~ok)}
        return ok, errors

    def direct_kinematics_dask(self, *args: Any, **kwargs: Any) -> Any:
        """The dask front end (:func:`imagespace.solve.distributed.direct_kinematics_dask`) for
        the rows of leg lengths of a dask array."""
        from ..solve.distributed import direct_kinematics_dask

        return direct_kinematics_dask(self, *args, **kwargs)

    def family(self) -> QuadricFamily:
        """The direct kinematics as a :class:`~imagespace.spatial.solver.QuadricFamily`."""
        raise NotImplementedError

    def check_design(self) -> None:
        """Refuse designs whose direct kinematics is not finite (a hook; nothing by default).

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.ThreeRPS(np.eye(3), 0.5 * np.eye(3)).check_design()
        """

    def leg_vectors(self, s: npt.ArrayLike) -> FloatArray:
        """The leg vectors ``R b_i + t - a_i`` at Study points.

        Parameters
        ----------
        s : (8,) or (n, 8) float

        Returns
        -------
        (legs, 3) or (n, legs, 3) float

        Raises
        ------
        InputError
            If ``x = 0``, on wrong shapes or non-finite entries.

        Examples
        --------
        >>> import imagespace as isp
        >>> gs = isp.GoughStewart(np.eye(6, 3), np.eye(6, 3)[::-1] + 1)
        >>> gs.leg_vectors([1, 0, 0, 0, 0, 0, 0, 0]).shape
        (6, 3)
        """
        s = as_float_array(s, "s", last=8)
        R, t = rotation_matrix(s), translation(s)
        # R b_k for every anchor as one matrix product (einsum's own loop is ~4x slower)
        return np.swapaxes(R @ self.platform_points.T, -1, -2) + t[..., None, :] - self.base_points

    @cached_property
    def _scale(self):
        # a power of two near the anchors' size: dividing by it is exact
        size = float(np.abs(np.concatenate([self.base_points, self.platform_points])).max())
        return float(2.0 ** np.round(np.log2(size))) if size > 0 else 1.0

    @cached_property
    def _size(self):
        # the design's size: its largest anchor coordinate (the reach limits are relative to it)
        size = float(np.abs(np.concatenate([self.base_points, self.platform_points])).max())
        return size if size > 0 else 1.0

    def reach_check(self, lengths: npt.ArrayLike) -> tuple[list[Any], npt.NDArray[np.bool_], npt.NDArray[np.bool_]]:
        """What the reach bounds say about rows of leg lengths, before any solving.

        Parameters
        ----------
        lengths : (legs,) or (n, legs) float
            Positive finite leg lengths (checked by the caller).

        Returns
        -------
        obstruction : list of ReachObstruction or None
            Per row, the proof that no real pose exists (two legs cannot meet:
            :func:`imagespace.core.reach.point_pairs_obstruction`), or None.
        far : (n,) bool
            Rows whose longest leg exceeds ``tolerances.far_reach_ratio`` times the design's
            size (its largest anchor coordinate): the fast path does not resolve them.
        beyond_exact : (n,) bool
            Rows beyond ``tolerances.exact_reach_ratio`` times the size: exact arithmetic on them
            would take minutes (msolve on coefficients of hundreds of digits).

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.spatial.ThreeRPS(np.eye(3), 0.5 * np.eye(3))
        >>> ob, far, beyond = m.reach_check([[1.0, 1.0, 1.0], [1e-300] * 3, [1e300] * 3])
        >>> [o is None for o in ob], far.tolist(), beyond.tolist()
        ([True, False, True], [False, False, True], [False, False, True])
        """
        L = np.atleast_2d(as_float_array(lengths, "lengths", last=self.leg_count, finite=False))
        obstruction = [point_pairs_obstruction(self.base_points, self.platform_points, row)
                       for row in L]
        top = L.max(axis=1) if L.size else np.zeros(L.shape[0])
        tol = self.tolerances
        far = np.array([o is None for o in obstruction], dtype=bool) & (top > tol.far_reach_ratio * self._size)
        beyond = far & (top > tol.exact_reach_ratio * self._size)
        return obstruction, far, beyond

    @property
    def start_system(self) -> StartSystem:
        """The family's solutions at generic complex lengths, computed once per design.

        40 for a general Gough-Stewart platform, 16 for a 6-3 or 3-3 one or a general 3-RPS.
        Carried from the family kind's generic start in milliseconds
        (:mod:`imagespace.spatial.families`); a design whose carried start falls short of its
        bound is solved by a total-degree homotopy (:func:`imagespace.spatial.solver.start_system`).

        Returns
        -------
        imagespace.spatial.homotopy.StartSystem

        Examples
        --------
        >>> import imagespace as isp
        >>> rng = np.random.default_rng(0)
        >>> len(isp.GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3))).start_system.solutions)
        40
        """
        return self.cached("start_system", lambda: start_system(self.family()))
