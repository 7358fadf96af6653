"""What every spatial parallel platform of this package shares: anchors, leg vectors, and the
direct kinematics of its quadric family (fast, certified, exact; one row or a batch).

A platform subclass (:class:`~imagespace.spatial.GoughStewart`,
:class:`~imagespace.spatial.ThreeRPS`) supplies ``leg_count``, :meth:`QuadricPlatform.family` and,
where it has one, a design check (:meth:`QuadricPlatform.check_design`).
"""

from __future__ import annotations

import warnings
from functools import cached_property

import numpy as np

from .._validate import as_flag, as_float_array
from ..core.reach import point_pairs_obstruction
from ..exceptions import InputError, NearSingularWarning
from .results import SpatialDKBatch, SpatialDKResult
from .solver import (certify_row, certify_rows, exact_result, exact_study_solver, solve_rows,
                     start_system)
from .study import rotation_matrix, translation

__all__ = ["QuadricPlatform", "anchor_points", "check_lengths", "DK_METHODS"]

#: the direct kinematics' methods
DK_METHODS = ("fast", "exact")


def anchor_points(value, name, count):
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
    L = as_float_array(lengths, name, last=count, allow_batch=allow_batch, finite=False)
    bad = np.argwhere(~(np.isfinite(L) & (L > 0)))
    if bad.size:
        idx = tuple(int(v) for v in bad[0])
        raise InputError(f"{name} must be positive finite leg lengths, got {L[idx]} at index "
                         f"{idx if len(idx) > 1 else idx[0]}")
    return L


class QuadricPlatform:
    """Base of the spatial platforms: ``base_points``, ``platform_points``, ``tolerances``.

    Subclasses set ``leg_count`` and define :meth:`family`.
    """

    leg_count = 0

    def family(self):  # pragma: no cover - every subclass defines it
        """The direct kinematics as a :class:`~imagespace.spatial.solver.QuadricFamily`."""
        raise NotImplementedError

    def check_design(self):
        """Refuse designs whose direct kinematics is not finite (a hook; nothing by default).

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.ThreeRPS(np.eye(3), 0.5 * np.eye(3)).check_design()
        """

    def leg_vectors(self, s):
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
        R, t = rotation_matrix(s), translation(s)
        return np.einsum("...ij,kj->...ki", R, self.platform_points) + t[..., None, :] - self.base_points

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

    def reach_check(self, lengths):
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
        L = np.atleast_2d(np.asarray(lengths, dtype=float))
        obstruction = [point_pairs_obstruction(self.base_points, self.platform_points, row)
                       for row in L]
        top = L.max(axis=1) if L.size else np.zeros(L.shape[0])
        tol = self.tolerances
        far = np.array([o is None for o in obstruction], dtype=bool) & (top > tol.far_reach_ratio * self._size)
        beyond = far & (top > tol.exact_reach_ratio * self._size)
        return obstruction, far, beyond

    def _beyond_message(self, L, exact):
        tol = self.tolerances
        limit = tol.exact_reach_ratio if exact else tol.far_reach_ratio
        what = ("exact arithmetic on it would take minutes" if exact else
                "the fast path does not resolve it; certify=True or method='exact' decide it (msolve)")
        return (f"lengths = {np.asarray(L).tolist()} reach beyond {limit:g} times the size of the "
                f"design (its largest anchor coordinate is {self._size:g}) and no reach bound proves "
                f"that no pose exists: {what}; expected lengths within that range")

    @staticmethod
    def _reach_result(obstruction):
        return SpatialDKResult(np.zeros((0, 8)), np.zeros(0), np.zeros(0, np.int8), -1, True, True,
                               "reach")

    @cached_property
    def start_system(self):
        """The family's solutions at generic complex lengths, computed once per design.

        40 for a general Gough-Stewart platform, 16 for a 6-3 or 3-3 one or a general 3-RPS.

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
        return start_system(self.family())

    def _exact_solver_or_none(self):
        from ..core.msolve import msolve_available

        return exact_study_solver if msolve_available() else None

    def direct_kinematics(self, lengths, certify=False, method="fast"):
        """Every real assembly mode for given leg lengths.

        Parameters
        ----------
        lengths : (legs,) float
            Leg lengths, positive. Floats are taken as the exact binary rationals they are.
        certify : bool
            Prove the count and every mode, whatever it takes. The fast path already proves most
            rows (``certified`` True: its compiled Krawczyk test on the exact quadrics reached
            the family's bound, 40 for Gough-Stewart, 16 for 6-3, 3-3 and 3-RPS); a row it does
            not prove (near a double mode) goes to Krawczyk boxes in arb (0.05-0.2 s), then to
            msolve on the exact system (1-20 s; needs ``imagespace[exact]``).
        method : {"fast", "exact"}
            ``"fast"``: the parameter homotopy (one start system per design, then one compiled
            path per start solution). ``"exact"``: msolve on the exact system; always certified.

        Returns
        -------
        SpatialDKResult
            ``study_points``, ``rotations``, ``translations``, ``residuals``, ``aspects``,
            ``count``, ``complex_count``, ``certified``, ``reliable``, ``method``.

        Raises
        ------
        InputError
            If ``lengths`` is not ``legs`` positive finite numbers, or ``method`` is unknown; if
            the lengths exceed ``tolerances.far_reach_ratio`` times the design's size without
            ``certify`` or ``method="exact"`` (the fast path does not resolve them), or
            ``tolerances.exact_reach_ratio`` times it at all, and no reach bound decides them.
        DegenerateDesignError
            If the design check refuses the design (an architecture singularity), or with
            ``method="exact"`` (or a certification that falls back to it) if the solution set is
            positive-dimensional.

        Warns
        -----
        NearSingularWarning
            When the fast path's answer is not ``reliable`` (its compiled certificate did not
            prove the row: a double mode near, a path that did not arrive, two paths at one
            endpoint), so its count may be wrong, or when a requested certificate is not
            available.

        Notes
        -----
        Every call first tries a reach bound (:mod:`imagespace.core.reach`): when two legs cannot
        meet (a leg ``1e300`` long next to one of length 2 on anchors a unit apart), the answer is
        no mode, proven at once (``method="reach"``, ``certified``, ``complex_count`` -1: not
        computed). Far lengths are decided by msolve directly (no tracking).

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.spatial.study import study_point
        >>> rng = np.random.default_rng(0)
        >>> gs = isp.GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
        >>> s = study_point([1.0, 0.2, -0.1, 0.3], [0.1, 0.2, 1.5])
        >>> res = gs.direct_kinematics(gs.inverse_kinematics(s), certify=True)
        >>> res.certified, res.complex_count
        (True, 40)
        >>> bool(np.min(np.abs(res.study_points - s).max(axis=1)) < 1e-9)
        True
        """
        L = check_lengths(lengths, count=self.leg_count)
        certify = as_flag(certify, "certify")
        if method not in DK_METHODS:
            raise InputError(f"method must be one of {DK_METHODS}, got {method!r}")
        self.check_design()
        (obstruction,), (far,), (beyond,) = self.reach_check(L)
        if obstruction is not None:
            return self._reach_result(obstruction)
        if beyond:
            raise InputError(self._beyond_message(L, exact=True))
        if far:
            if not certify and method != "exact":
                raise InputError(self._beyond_message(L, exact=False))
            return exact_result(self.family(), L)
        if method == "exact":
            return exact_result(self.family(), L)
        if certify:
            return certify_row(self.family(), self.start_system, L, self.tolerances,
                               exact_solver=self._exact_solver_or_none())
        res = solve_rows(self.family(), self.start_system, (L ** 2)[None], self.tolerances,
                         lengths=L[None])[0]
        if not res.reliable:
            warnings.warn(f"the fast path could not prove this row: its {res.count} real modes may be "
                          "wrong (the compiled Krawczyk test did not prove every solution distinct "
                          "and decided: a double mode near, or a lost path); use certify=True",
                          NearSingularWarning, stacklevel=2)
        return res

    def direct_kinematics_batch(self, lengths, certify=False):
        """Real assembly modes of many rows of leg lengths (the fast path, per-row masks).

        Parameters
        ----------
        lengths : (n, legs) float
            One row per problem. Rows with a non-positive or non-finite length are marked invalid
            (``valid[i] = False``, no modes) instead of raising; so are rows beyond
            ``tolerances.far_reach_ratio`` times the design's size (without ``certify``) or
            ``tolerances.exact_reach_ratio`` times it (with ``certify``) that no reach bound
            decides. Rows a reach bound proves empty are valid, certified, with no mode and
            ``complex_count`` -1.
        certify : bool
            Prove every valid row (see :meth:`direct_kinematics`): one compiled pass for all
            rows, arb and msolve only for the rows it does not prove.

        Returns
        -------
        SpatialDKBatch
            ``counts``, ragged ``study_points`` (row ``i``: ``batch[i]``), ``reliable``,
            ``certified``, ``valid`` masks.

        Raises
        ------
        InputError
            If ``lengths`` does not have shape ``(n, legs)``.
        DegenerateDesignError
            If the design check refuses the design.

        Examples
        --------
        >>> import imagespace as isp
        >>> rng = np.random.default_rng(0)
        >>> gs = isp.GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
        >>> b = gs.direct_kinematics_batch([[2.0] * 6, [float("nan")] * 6])
        >>> b.valid.tolist()
        [True, False]
        """
        L = np.asarray(lengths, dtype=float)
        k = self.leg_count
        if L.ndim != 2 or L.shape[1] != k:
            raise InputError(f"lengths must have shape (n, {k}), got {L.shape}")
        certify = as_flag(certify, "certify")
        self.check_design()
        valid = np.all(np.isfinite(L) & (L > 0), axis=1)
        n = L.shape[0]
        reach = [None] * n
        far = np.zeros(n, dtype=bool)
        if valid.any():
            ob, f, beyond = self.reach_check(L[valid])
            rows_ok = np.flatnonzero(valid)
            for k, i in enumerate(rows_ok):
                reach[i] = ob[k]
            far[rows_ok] = f
            # masked: beyond what the fast path (or, certifying, exact arithmetic) resolves
            valid[rows_ok[beyond if certify else f]] = False
        empty = np.array([r is not None for r in reach], dtype=bool)
        if not certify:
            todo = valid & ~empty
            Lv = np.where(todo[:, None], L, 1.0)
            out = solve_rows(self.family(), self.start_system, Lv ** 2, self.tolerances, valid=todo,
                             lengths=Lv)
            if empty.any():                 # proven empty: certified, no complex count
                out.certified[empty] = True
                out.reliable[empty] = True
                out.complex_count[empty] = -1
                out.valid[empty] = True
            return out
        todo = valid & ~empty & ~far
        proven = certify_rows(self.family(), self.start_system, L, self.tolerances, valid=todo,
                              exact_solver=self._exact_solver_or_none())
        if not (empty.any() or (far & valid).any()):
            return proven

        def one(i):
            if reach[i] is not None:
                return self._reach_result(reach[i])
            if far[i]:
                return exact_result(self.family(), L[i])
            return proven[i]

        rows = [one(i) if valid[i] else None for i in range(n)]
        done = [r for r in rows if r is not None]
        counts = np.array([r.count if r is not None else 0 for r in rows], dtype=np.int64)
        return SpatialDKBatch(
            counts, np.concatenate([[0], np.cumsum(counts)]),
            np.vstack([r.study_points for r in done]) if done else np.zeros((0, 8)),
            np.concatenate([r.residuals for r in done]) if done else np.zeros(0),
            np.concatenate([r.aspects for r in done]).astype(np.int8) if done else np.zeros(0, np.int8),
            np.array([r.complex_count if r is not None else 0 for r in rows]),
            np.array([r.reliable if r is not None else False for r in rows]),
            np.array([r.certified if r is not None else False for r in rows]), valid)
