"""The spatial back ends of the direct kinematics (:class:`~imagespace.core.mechanism.Backends` of
:class:`~imagespace.spatial.GoughStewart` and :class:`~imagespace.spatial.ThreeRPS`).

* float stage: the parameter homotopy from the design's start system, every row's endpoints
  proven by the compiled Krawczyk test where it can (``reliable``; ``certified`` where that
  reaches the family's bound) (:func:`~imagespace.spatial.solver.solve_rows`);
* proof stage: one compiled pass, Krawczyk boxes in arb for the rows it does not prove, msolve last
  (:func:`~imagespace.spatial.solver.certify_rows`);
* exact stage: one row on the certified path (:func:`~imagespace.spatial.solver.certify_row`), or
  msolve alone for ``method="exact"`` and for lengths far beyond the design's size;
* a reach bound first (:func:`imagespace.core.reach.point_pairs_obstruction`): two legs that cannot
  meet prove that no pose exists.

The front end (:mod:`imagespace.solve.front`) validates and calls them; they never call a facade
method.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

from ..core.mechanism import Backends
from ..core.reach import point_pairs_obstruction
from ..exceptions import InputError
from .results import SpatialDKBatch, SpatialDKResult
from .solver import certify_row, certify_rows, exact_result, exact_study_solver, solve_rows

__all__ = ["BACKENDS", "SPATIAL_PEAK_BYTES_PER_ROW"]

#: Peak bytes per row of a spatial batch: the tracker's endpoints (40 complex 8-vectors, 5.1 kB),
#: its status and the certificate's boxes (about 3 kB), the parameters and the result (under 1 kB),
#: rounded up generously; the memory guard multiplies it by the rows (a knob of the guard only).
SPATIAL_PEAK_BYTES_PER_ROW = 16000


def _exact_solver(m):
    from ..core.msolve import msolve_available

    return exact_study_solver if msolve_available() else None


def _design_size(m):
    size = float(np.abs(np.concatenate([m.base_points, m.platform_points])).max())
    return size if size > 0 else 1.0


def _beyond(m, L, exact):
    """Rows beyond ``tolerances.exact_reach_ratio`` (``exact``) or ``far_reach_ratio`` times the
    design's size."""
    tol = m.tolerances
    ratio = tol.exact_reach_ratio if exact else tol.far_reach_ratio
    L = np.atleast_2d(L)
    top = L.max(axis=1) if L.size else np.zeros(L.shape[0])
    return np.isfinite(top) & (top > ratio * _design_size(m))


def _beyond_message(m, L, exact):
    tol = m.tolerances
    limit = tol.exact_reach_ratio if exact else tol.far_reach_ratio
    what = ("exact arithmetic on it would take minutes" if exact else
            "the fast path does not resolve it; certify=True or method='exact' decide it (msolve)")
    return (f"lengths = {np.asarray(L).tolist()} reach beyond {limit:g} times the size of the "
            f"design (its largest anchor coordinate is {_design_size(m):g}) and no reach bound proves "
            f"that no pose exists: {what}; expected lengths within that range")


def reach(m: Any, lengths: Any):
    """A reach bound's proof that no pose exists for these leg lengths, or None.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.spatial.backends import reach
    >>> m = isp.spatial.ThreeRPS(np.eye(3), 0.5 * np.eye(3))
    >>> reach(m, [1e-300] * 3) is not None, reach(m, [1.0, 1.0, 1.0]) is None
    (True, True)
    """
    L = np.asarray(lengths, dtype=float)
    return point_pairs_obstruction(m.base_points, m.platform_points, L)


def far(m: Any, L: np.ndarray) -> np.ndarray:
    """Rows whose longest leg exceeds ``tolerances.far_reach_ratio`` times the design's size, or
    whose shortest leg is below the size divided by it: the fast path does not resolve them
    (they are answered one by one: a reach bound, else the exact stage)."""
    L = np.atleast_2d(np.asarray(L, dtype=float))
    low = L.min(axis=1) if L.size else np.zeros(L.shape[0])
    tiny = np.isfinite(low) & (low > 0) & (low * m.tolerances.far_reach_ratio < _design_size(m))
    return _beyond(m, L, exact=False) | tiny


def solve(m: Any, L: np.ndarray, rows: np.ndarray, method: str, per_call: bool) -> SpatialDKBatch:
    """The float stage: track every row of ``rows`` from the start system and prove it with the
    compiled certificate where it can.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.spatial.backends import solve
    >>> gs, L = isp.examples.dietmaier_1998()
    >>> b = solve(gs, np.array([L]), np.array([True]), "fast", False)
    >>> b.count.tolist(), b.certified.tolist()
    ([40], [True])
    """
    m.check_design()
    rows = np.asarray(rows, dtype=bool)
    Lv = np.where(rows[:, None], L, 1.0)
    return solve_rows(m.family(), m.start_system, Lv ** 2, m.tolerances, valid=rows, lengths=Lv)


def prove(m: Any, L: np.ndarray, batch: SpatialDKBatch, rows: np.ndarray, method: str) -> SpatialDKBatch:
    """The proof stage: every row of ``rows`` proven. The rows :func:`solve` already certified
    (the compiled certificate on the exact squares of the lengths, reaching the family's bound)
    are kept; the others go through :func:`~imagespace.spatial.solver.certify_rows` (second
    starts, arb, msolve).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.spatial.backends import prove, solve
    >>> gs, L = isp.examples.dietmaier_1998()
    >>> rows = np.array([True])
    >>> prove(gs, np.array([L]), solve(gs, np.array([L]), rows, "fast", False), rows, "fast").certified.tolist()
    [True]
    """
    m.check_design()
    rows = np.asarray(rows, bool)
    todo = rows & ~np.asarray(batch.certified, bool)
    if not np.any(todo):
        return batch
    sub = certify_rows(m.family(), m.start_system, L[todo], m.tolerances, exact_solver=_exact_solver(m))
    results: list[Optional[SpatialDKResult]] = [batch[i] if rows[i] else None for i in range(len(batch))]
    for j, i in enumerate(np.flatnonzero(todo)):
        results[i] = sub[j]
    return SpatialDKBatch.from_results(results)


def exact(m: Any, q: Any, qf: np.ndarray, method: str, certify: bool) -> SpatialDKResult:
    """The exact stage for one row of leg lengths: msolve for ``method="exact"`` and for lengths
    beyond the fast path's range, else the certified path (compiled, arb, msolve).

    Raises
    ------
    InputError
        The lengths reach beyond ``tolerances.exact_reach_ratio`` times the design's size, or
        beyond ``far_reach_ratio`` without ``certify`` and ``method="exact"``.
    """
    m.check_design()
    L = np.asarray(qf, dtype=float)
    if _beyond(m, L, exact=True)[0]:
        raise InputError(_beyond_message(m, L, exact=True))
    is_far = _beyond(m, L, exact=False)[0]
    if is_far and not certify and method != "exact":
        raise InputError(_beyond_message(m, L, exact=False))
    if method == "exact" or is_far:
        return exact_result(m.family(), L)
    return certify_row(m.family(), m.start_system, L, m.tolerances, exact_solver=_exact_solver(m))


def counts(m: Any, L: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Proven numbers of real modes per row (the proof stage's counts), ``(counts, path)``; rows
    beyond the fast path's range go to msolve, those beyond exact arithmetic's are refused
    (``"invalid"``)."""
    n = L.shape[0]
    rows = np.asarray(rows, dtype=bool)
    out = np.full(n, -1, dtype=np.int8)
    path = np.full(n, "invalid", dtype=object)
    alone = rows & far(m, L)
    todo = rows & ~alone
    if todo.any():
        b = prove(m, L, solve(m, L, todo, "fast", False), todo, "fast")
        out[todo] = b.certified_roots[todo]
        path[todo] = b.certificate_path[todo]
    for i in np.flatnonzero(alone):
        try:
            r = exact(m, L[i], L[i], "exact", True)
        except InputError:
            continue
        out[i], path[i] = r.count, "msolve"
    return out, path


def empty(m: Any, obstruction: Any, certify: bool) -> SpatialDKResult:
    """No real pose, proven by a reach bound (``complex_count`` -1: not computed)."""
    return SpatialDKResult(np.zeros((0, 8)), np.zeros(0), np.zeros(0, np.int8), -1, True, True, "reach")


def store(batch: SpatialDKBatch, rows: list, results: list, certify: bool) -> SpatialDKBatch:
    """A batch with the per-row answers ``results`` (a :class:`SpatialDKResult`, or the exception
    that masks the row) in the rows ``rows``."""
    per_row = [batch[i] if batch.row_ok[i] else None for i in range(len(batch))]
    errors = dict(batch.errors)
    for i, r in zip(rows, results):
        if isinstance(r, Exception):
            per_row[i] = None
            errors[int(i)] = str(r)
        else:
            per_row[i] = r
            errors.pop(int(i), None)
    return SpatialDKBatch.from_results(per_row, errors)


def peak_bytes(m: Any, method: str, certify: bool, n: int) -> int:
    """Peak memory per batch row (:data:`SPATIAL_PEAK_BYTES_PER_ROW`)."""
    return SPATIAL_PEAK_BYTES_PER_ROW


def doubt(m: Any, qf: np.ndarray, result: SpatialDKResult) -> str:
    """The warning of a fast answer its compiled certificate did not prove."""
    return (f"the fast path could not prove this row: its {result.count} real modes may be wrong "
            "(the compiled Krawczyk test did not prove every solution distinct and decided: a "
            "double mode near, or a lost path); use certify=True")


#: The spatial back ends, bound by :class:`~imagespace.spatial.platform.QuadricPlatform`.
BACKENDS = Backends(methods=("fast", "exact"), solve=solve, prove=prove, exact=exact, counts=counts,
                    empty=empty, store=store, peak_bytes=peak_bytes, doubt=doubt, reach=reach,
                    far=far, complex_modes=None, exact_methods=("exact",))
