"""Direct kinematics of a family of quadrics in Study coordinates: fast, certified and exact paths.

A mechanism (:class:`~imagespace.spatial.GoughStewart`, :class:`~imagespace.spatial.ThreeRPS`)
describes itself as a :class:`QuadricFamily`: ``m = 7`` quadrics ``z^T (A_k - p_k E) z = 0`` whose
parameters ``p`` are its squared leg lengths. This module

* solves the family once at generic complex parameters (:func:`start_system`: carried from the
  family kind's generic member, :mod:`imagespace.spatial.families`, or by a total-degree homotopy,
  :func:`~imagespace.spatial.homotopy.solve_start_system`),
* tracks those solutions to every target row in the compiled tracker (the fast path),
* proves each row's endpoints with a compiled Krawczyk test on rigorous error bounds
  (:mod:`imagespace.spatial.fastcert`): ``reliable`` means it proved as many distinct solutions
  as :func:`completeness_target` asks (the family's theorem bound), each real or not real, so
  the count is right; where it fails, the row is tracked again from other generic starts (a lost
  or merged path is far more common than a true double mode: :data:`RETRY_STARTS`) and certified
  anew; where that fails too (near a double mode), float checks sort the endpoints and the row is
  flagged (``reliable`` False, a warning per call),
* marks the rows whose certificate reached the family's theorem bound ``certified`` (a certified
  answer at the fast path's cost); ``certify=True`` proves the other rows one by one: Krawczyk
  boxes in arb on the exact quadrics (:mod:`imagespace.spatial.certify`), otherwise msolve
  decides exactly (:mod:`imagespace.spatial.exact`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any, Callable, Optional

import numpy as np
import numpy.typing as npt

from ..exceptions import NearSingularWarning
from .families import design_start_system
from .homotopy import (PATH_OK, TRACK_KERNEL, check_kernel, classify_batch, recentre, solve_start_system,
                       track_parameters)
from .results import SpatialDKBatch, SpatialDKResult
from .study import normalize_study

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray
    from ..tolerances import Tolerances
    from .homotopy import StartSystem

__all__ = ["QuadricFamily", "solve_rows", "certify_row", "certify_rows", "completeness_target", "exact_study_solver",
           "exact_result", "quadric_polynomials", "study_jacobian_signs"]


#: batches of at least this many rows first move the start system next to their median
#: parameters (:func:`~imagespace.spatial.homotopy.recentre`, one extra row of tracking); a
#: speed choice, the answers do not depend on it
RECENTRE_MIN_ROWS = 32

#: rows whose endpoints the compiled certificate does not prove (a path lost or two paths merged
#: on the way, far more often than a true double mode) are tracked again from this many other
#: generic start systems (the design's own, then re-centred ones with fresh random offsets), each
#: time certified anew; a speed choice before arb and msolve, the answers do not depend on it
RETRY_STARTS = 3

#: the real modes of a batch are normalised, checked and given their aspects this many at a time
#: (a speed choice: 160,000 modes at once spent 3x longer in fresh large temporaries)
MODE_CHUNK = 8192


@dataclass(frozen=True, eq=False)
class QuadricFamily:
    """A system of quadrics in ``P^7`` whose parameters enter linearly.

    Attributes
    ----------
    A : (m, 8, 8) float
        Parameter-free parts.
    E : (8, 8) float
        The form each parameter multiplies (``x . x`` for legs).
    pidx : (m,) int
        Parameter of quadric ``k`` (``-1``: none).
    nparams : int
    bound : int or None
        A theorem's upper bound on the number of isolated complex solutions of every member of the
        family (40 for Gough-Stewart); ``None`` if none is known, then only msolve certifies.
    exact : callable
        ``exact(params_exact) -> (m, 8, 8)`` object array of Fraction: the exact quadrics for
        exact parameters (squared lengths as Fractions).
    aspect : callable
        ``aspect(study_points (k, 8)) -> (k,) int8``, on unscaled points.
    scale : float
        A power of two: the family is written for the design divided by ``scale`` (lengths too), so
        its solutions are well scaled whatever the units; a solution ``(x, y)`` of the family is
        the displacement ``(x, scale * y)``. Exact, since the scale is a power of two.
    """

    A: np.ndarray
    E: np.ndarray
    pidx: np.ndarray
    nparams: int
    bound: Optional[int]
    exact: Callable
    aspect: Callable
    scale: float = 1.0

    def unscale(self, pts: FloatArray) -> FloatArray:
        """Family solutions ``(k, 8)`` -> displacements of the design (``y`` times ``scale``)."""
        out = np.array(pts, dtype=float).reshape(-1, 8)
        out[:, 4:] *= self.scale
        return out


#: the routes of :func:`start_system`: ``"family"`` carries the family kind's generic start to the
#: design (:mod:`imagespace.spatial.families`), ``"design"`` solves the design by a total-degree
#: homotopy; they give the same solutions (``tests/spatial/test_families.py``)
START_ROUTES = ("family", "design")


def start_system(family: QuadricFamily, seed: int = 0, route: str = "family") -> StartSystem:
    """The family's solutions at generic complex parameters (computed once per design).

    Parameters
    ----------
    family : QuadricFamily
    seed : int
    route : {"family", "design"}, optional
        ``"family"`` (default): the family kind's generic start carried to the design
        (:func:`~imagespace.spatial.families.design_start_system`, milliseconds), where the family
        has a kind and the moved start holds the family's bound; the total-degree route
        otherwise. ``"design"``: always the total-degree route
        (:func:`~imagespace.spatial.homotopy.solve_start_system`).

    Returns
    -------
    StartSystem

    Raises
    ------
    InputError
        On an unknown route.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> gs = isp.GoughStewart(np.random.default_rng(0).normal(size=(6, 3)),
    ...                       np.random.default_rng(1).normal(size=(6, 3)))
    >>> len(start_system(gs.family()).solutions), len(start_system(gs.family(), route="design").solutions)
    (40, 40)
    """
    if not isinstance(route, str) or route not in START_ROUTES:
        from ..exceptions import InputError
        raise InputError(f"route must be one of {', '.join(map(repr, START_ROUTES))}, got {route!r}")
    if route == "family":
        st = design_start_system(family, seed=seed)
        if st is not None:
            return st
    return solve_start_system(family.A, family.E, family.pidx, family.nparams, seed=seed,
                              expected=family.bound)


def _mode_residuals(family, P_modes, pts):
    """``max_k |z^T (A_k - p_k E) z|`` for normalised family points ``pts`` (k, 8) with their rows'
    parameters ``P_modes`` (k, p)."""
    if not pts.shape[0]:
        return np.zeros(0)
    # matrix products, then one row-wise dot (a three-operand einsum loops ~7x slower)
    zAz = np.einsum("kni,ni->nk", pts @ family.A, pts)
    zEz = np.einsum("ni,ni->n", pts @ family.E, pts)
    has = family.pidx >= 0
    p = np.where(has[None, :], P_modes[:, np.maximum(family.pidx, 0)], 0.0)
    return np.abs(zAz - p * zEz[:, None]).max(axis=1)


def _residuals(family, P_row, pts):
    return _mode_residuals(family, np.broadcast_to(P_row, (pts.shape[0], len(P_row))), pts)


def completeness_target(family: QuadricFamily, start: StartSystem) -> tuple[int, bool]:
    """How many distinct proven solutions make a row complete, and whether a theorem says so.

    The family's bound (a theorem on the isolated solutions with ``x . x != 0`` of every member,
    e.g. 40 for Gough-Stewart) when the design's start system attains it; otherwise (no bound
    known, or a special design with fewer generic solutions) the start system's count, which a
    total-degree homotopy found once per design: completeness then rests on that count.

    Parameters
    ----------
    family : QuadricFamily
    start : StartSystem

    Returns
    -------
    target : int
    theorem : bool

    Examples
    --------
    >>> import imagespace as isp
    >>> gs = isp.examples.dietmaier_1998()[0]
    >>> completeness_target(gs.family(), gs.start_system)
    (40, True)
    """
    found = int(start.solutions.shape[0])
    if family.bound is not None and found >= family.bound:
        return int(family.bound), True
    return found, False


def _parameters_enclosure(family, P, lengths):
    """Enclosures ``pm +- pr`` of the exact parameters of the rows (family scaling)."""
    from .fastcert import parameter_enclosure

    if lengths is not None:
        return parameter_enclosure(lengths, family.scale)
    # the floats P are the exact parameters: P / scale^2 is exact unless it underflows
    P = np.atleast_2d(np.asarray(P, dtype=float))
    with np.errstate(all="ignore"):
        pm = P / family.scale ** 2
        pr = np.where((pm * family.scale ** 2 == P) & np.isfinite(pm), 0.0, np.inf)
    return np.ascontiguousarray(pm), np.ascontiguousarray(pr)


def _modes(family, pts, P_rows, mode_rows):
    """The real modes' normalised Study points (unscaled), residuals and aspects, in chunks of
    :data:`MODE_CHUNK` modes (the per-mode arrays of a large batch stay small)."""
    if pts.shape[0] == 0:
        return np.zeros((0, 8)), np.zeros(0), np.zeros(0, np.int8)
    out_p, out_r, out_a = [], [], []
    for a in range(0, pts.shape[0], MODE_CHUNK):
        p = normalize_study(pts[a:a + MODE_CHUNK])
        out_r.append(_mode_residuals(family, P_rows[mode_rows[a:a + MODE_CHUNK]], p))
        p = family.unscale(p)
        out_p.append(p)
        out_a.append(np.atleast_1d(np.asarray(family.aspect(p), np.int8)))
    return np.concatenate(out_p), np.concatenate(out_r), np.concatenate(out_a)


def _second_chances(family, start, tracked, P, pm, pr, Z, status, cert, target, kernel):
    """Track the rows ``cert`` leaves incomplete again from other generic starts (the design's own
    ``start`` unless they were ``tracked`` from it, then re-centred ones near those rows, up to
    :data:`RETRY_STARTS` starts) and certify them anew;
    ``Z``, ``status`` and ``cert`` are updated in place on every row that becomes complete.

    Sound whichever start the endpoints come from: a row counts as complete only when the compiled
    certificate proves ``target`` distinct solutions on its own endpoints.
    """
    from .fastcert import certify_endpoints, family_enclosure

    enclosure = family_enclosure(family)
    for attempt in range(RETRY_STARTS):
        todo = np.flatnonzero(~cert.complete)
        if todo.size == 0:
            return
        if attempt == 0:
            if tracked is start:
                continue
            other = start
        else:
            other = recentre(start, np.median(P[todo], axis=0), seed=attempt, kernel=kernel)
            if other is start:
                continue                       # the move did not carry every solution across
        Z2, st2, _ = track_parameters(other, P[todo], kernel=kernel)
        if Z2.shape[1] != Z.shape[1]:
            return
        c2 = certify_endpoints(enclosure, Z2, st2, pm[todo], pr[todo], target)
        won = np.flatnonzero(c2.complete)
        if won.size == 0:
            continue
        Z[todo[won]], status[todo[won]] = Z2[won], st2[won]
        for f in cert.__dataclass_fields__:
            getattr(cert, f)[todo[won]] = getattr(c2, f)[won]


def _batch(family, start, P, rows, n, Z, status, tolerances, valid, pm, pr, with_certificate=False,
           retry=None, tracked=None, kernel=TRACK_KERNEL):
    """Classify tracked rows into a :class:`SpatialDKBatch` (``P`` already divided by scale^2).

    ``reliable`` is the compiled certificate (:mod:`imagespace.spatial.fastcert`) on the exact
    parameters ``pm +- pr``: where it is complete, the real modes are its proven real boxes'
    centres, and the row is ``certified`` too when the completeness target is a theorem's bound;
    elsewhere the float classification gives the (unproven) count. With ``with_certificate`` the
    :class:`~imagespace.spatial.fastcert.FastCertificate` of the rows is returned as well. With
    ``retry`` (the design's start system; ``tracked``: the start the rows were tracked from) the
    rows the certificate leaves incomplete get second chances (:func:`_second_chances`) before the
    float classification.
    """
    from .fastcert import certify_endpoints, family_enclosure

    target, theorem = completeness_target(family, start)
    cert = certify_endpoints(family_enclosure(family), Z, status, pm[rows], pr[rows], target)
    if retry is not None and not np.all(cert.complete):
        Z, status = Z.copy(), status.copy()
        _second_chances(family, retry, tracked, P[rows], pm[rows], pr[rows], Z, status, cert, target, kernel)
    done = cert.complete
    W = cert.points.real.copy()
    real = cert.certified & (cert.real == 1)
    distinct = np.full(len(rows), target, dtype=np.int64)
    if not np.all(done):
        # the float classification of the rows the certificate did not prove (unproven counts)
        Wf, realf, distinctf, _ = classify_batch(Z[~done], status[~done], tolerances)
        W[~done], real[~done], distinct[~done] = Wf, realf, distinctf
    counts = np.zeros(n, np.int64)
    counts[rows] = real.sum(axis=1)
    cplx = np.zeros(n, np.int64)
    cplx[rows] = distinct
    reliable = np.zeros(n, bool)
    reliable[rows] = done
    certified = np.zeros(n, bool)
    certified[rows] = done & theorem
    pts, res, asp = _modes(family, W[real], P[rows], np.repeat(np.arange(len(rows)), real.sum(axis=1)))
    offsets = np.concatenate([[0], np.cumsum(counts)])
    batch = SpatialDKBatch(counts, offsets, pts, res, np.asarray(asp, np.int8), cplx, reliable,
                           certified, valid)
    return (batch, cert) if with_certificate else batch


def solve_rows(family: QuadricFamily, start: StartSystem, P: npt.ArrayLike, tolerances: Tolerances,
               valid: Optional[npt.ArrayLike] = None, lengths: Optional[npt.ArrayLike] = None,
               kernel: str = TRACK_KERNEL) -> SpatialDKBatch:
    """The fast path on many rows: track, certify (compiled), classify, residuals and aspects.

    Parameters
    ----------
    family : QuadricFamily
    start : StartSystem
    P : (n, p) float
        Target parameters (squared lengths of the design, unscaled).
    tolerances : Tolerances
    valid : (n,) bool, optional
        Rows to solve (others get no modes).
    lengths : (n, p) float, optional
        The leg lengths whose exact squares are the parameters (``P = lengths ** 2`` rounded):
        the certificate then proves the user's problem. Without it the floats ``P`` are taken as
        the exact parameters.
    kernel : {"auto", "lanes", "scalar"}, optional
        The tracker (:func:`~imagespace.spatial.homotopy.track_parameters`); the answers do not
        depend on it beyond rounding.

    Returns
    -------
    SpatialDKBatch
        ``reliable[i]``: the compiled Krawczyk test
        (:mod:`imagespace.spatial.fastcert`, rigorous error bounds, on the exact quadrics) proved
        as many distinct solutions as :func:`completeness_target` asks, in pairwise disjoint
        boxes, each proven real or not real and (non-real ones) not a null rotation. The count
        is then the number of proven real boxes. Rows where it fails (near a double mode, a path
        lost, a cluster) keep the float classification's count with ``reliable`` False.
        ``certified[i]``: ``reliable[i]`` with the family's theorem bound as the target (a
        certified answer at the fast path's cost).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> gs = isp.GoughStewart(np.random.default_rng(0).normal(size=(6, 3)),
    ...                       np.random.default_rng(1).normal(size=(6, 3)))
    >>> fam = gs.family()
    >>> b = solve_rows(fam, start_system(fam), np.full((2, 6), 4.0), gs.tolerances)
    >>> len(b)
    2
    """
    kernel = check_kernel(kernel)
    pm, pr = _parameters_enclosure(family, P, lengths)
    if lengths is not None:         # the scaled squares from the lengths: no overflow at any size
        P = np.array(pm, dtype=float)
    else:
        P = np.atleast_2d(np.asarray(P, dtype=float)) / family.scale / family.scale
    n = P.shape[0]
    valid = np.ones(n, bool) if valid is None else np.asarray(valid, bool)
    rows = np.flatnonzero(valid)
    own = start
    if rows.size >= RECENTRE_MIN_ROWS:
        start = recentre(start, np.median(P[rows], axis=0), kernel=kernel)
    Z, status, _ = track_parameters(start, P[rows], kernel=kernel)
    return _batch(family, start, P, rows, n, Z, status, tolerances, valid, pm, pr, retry=own, tracked=start,
                  kernel=kernel)


def _exact_params(lengths, scale=1.0):
    return [(Fraction(float(v)) / Fraction(scale)) ** 2 for v in lengths]


def certify_row(family: QuadricFamily, start: StartSystem, lengths: npt.ArrayLike, tolerances: Tolerances,
                Z: Optional[npt.NDArray[np.complex128]] = None, status: Optional[npt.NDArray[np.integer]] = None,
                exact_solver: Optional[Callable[..., Any]] = None, fast: Optional[tuple] = None
                ) -> SpatialDKResult:
    """Prove one row: the compiled Krawczyk test, then Krawczyk in arb, then msolve.

    Parameters
    ----------
    family : QuadricFamily
    start : StartSystem
    lengths : (p,) float
        Leg lengths (the parameters are their exact squares).
    tolerances : Tolerances
    Z, status : optional
        The row's tracked endpoints (tracked here when omitted).
    exact_solver : callable, optional
        ``exact_solver(Q_exact) -> (study_points (k, 8) float, complex_count)``, raising on
        positive-dimensional systems (:func:`exact_study_solver`); used when Krawczyk does not
        prove the row.
    fast : tuple, optional
        ``(SpatialDKResult, FastCertificate)`` of the row from the compiled path, when the
        caller has them (:func:`certify_rows`); computed here otherwise.

    Returns
    -------
    SpatialDKResult
        ``certified`` False (with a :class:`~imagespace.exceptions.NearSingularWarning`) only when
        neither proof is available.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> gs = isp.GoughStewart(np.random.default_rng(0).normal(size=(6, 3)),
    ...                       np.random.default_rng(1).normal(size=(6, 3)))
    >>> fam = gs.family()
    >>> certify_row(fam, start_system(fam), np.full(6, 2.0), gs.tolerances).certified
    True
    """
    from .certify import krawczyk_certify
    from .fastcert import CHARTS

    lengths = np.asarray(lengths, dtype=float)
    P = (lengths / family.scale) ** 2
    if Z is None or status is None:
        Zs, sts, _ = track_parameters(start, P[None])
        Z, status = Zs[0], sts[0]
    if fast is None:
        pm, pr = _parameters_enclosure(family, None, lengths[None])
        b, fc = _batch(family, start, P[None], np.array([0]), 1, Z[None], status[None], tolerances,
                       np.ones(1, bool), pm, pr, with_certificate=True)
        fast = (b[0], fc)
    res, fc = fast
    if res.certified:
        return res
    Qx = family.exact(_exact_params(lengths, family.scale))
    ok = status == PATH_OK
    arrived = Z[ok]
    if family.bound is not None and arrived.shape[0] >= family.bound:
        cert = krawczyk_certify(Qx, arrived)
        if not cert.complete(family.bound) and fc.chart[0] >= 0:
            # near a double mode arb's own box sizes may fail where the compiled test's succeed:
            # prove its boxes (polished centres, chart, radii: proposals only) in arb
            cert = krawczyk_certify(Qx, fc.points[0][ok], chart=CHARTS[fc.chart[0]],
                                    radii=fc.radii[0][ok])
        if cert.complete(family.bound):
            real = cert.points[cert.certified & (cert.real == 1)].real
            pts = normalize_study(real) if real.shape[0] else np.zeros((0, 8))
            res = _residuals(family, P, pts)
            pts = family.unscale(pts)
            return SpatialDKResult(pts, res,
                                   family.aspect(pts) if pts.shape[0] else np.zeros(0, np.int8),
                                   family.bound, True, True, "homotopy+krawczyk")
    if exact_solver is not None:
        pts, complex_count = exact_solver(Qx)
        res = _residuals(family, P, pts)
        pts = family.unscale(pts)
        return SpatialDKResult(pts, res,
                               family.aspect(pts) if pts.shape[0] else np.zeros(0, np.int8),
                               int(complex_count), True, True, "msolve")
    warnings.warn("the row could not be certified: Krawczyk did not prove every solution and no exact "
                  "solver is available (pip install imagespace[exact]); the modes are the fast path's",
                  NearSingularWarning, stacklevel=3)
    return res


def certify_rows(family: QuadricFamily, start: StartSystem, lengths: npt.ArrayLike, tolerances: Tolerances,
                 valid: Optional[npt.ArrayLike] = None, exact_solver: Optional[Callable[..., Any]] = None
                 ) -> SpatialDKBatch:
    """Prove many rows: one compiled pass (tracking and certificate), arb and msolve per row only
    where it does not settle the row.

    Parameters
    ----------
    family : QuadricFamily
    start : StartSystem
    lengths : (n, p) float
    tolerances : Tolerances
    valid : (n,) bool, optional
        Rows to solve (others get no modes).
    exact_solver : callable, optional
        See :func:`certify_row`.

    Returns
    -------
    SpatialDKBatch
        ``certified[i]`` for every valid row proven (all, unless a row needs msolve and none is
        available: then a :class:`~imagespace.exceptions.NearSingularWarning` per such row).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> gs, L = isp.examples.dietmaier_1998()
    >>> b = certify_rows(gs.family(), gs.start_system, np.array([L, L]), gs.tolerances)
    >>> b.certified.tolist(), b.counts.tolist()
    ([True, True], [40, 40])
    """
    L = np.atleast_2d(np.asarray(lengths, dtype=float))
    n = L.shape[0]
    valid = np.ones(n, bool) if valid is None else np.asarray(valid, bool)
    Lv = np.where(valid[:, None], L, 1.0)
    pm, pr = _parameters_enclosure(family, None, Lv)
    P = (Lv / family.scale) ** 2
    rows = np.flatnonzero(valid)
    start_rows = start
    if rows.size >= RECENTRE_MIN_ROWS:
        start_rows = recentre(start, np.median(P[rows], axis=0))
    Z, status, _ = track_parameters(start_rows, P[rows])
    batch, fc = _batch(family, start, P, rows, n, Z, status, tolerances, valid, pm, pr,
                       with_certificate=True, retry=start, tracked=start_rows)
    if np.all(batch.certified[rows]):
        return batch
    from .fastcert import FastCertificate

    results = [batch[i] if valid[i] else None for i in range(n)]
    for j, i in enumerate(rows):
        if batch.certified[i]:
            continue
        one = FastCertificate(*(getattr(fc, f)[j:j + 1] for f in FastCertificate.__dataclass_fields__))
        results[i] = certify_row(family, start, L[i], tolerances, Z=Z[j], status=status[j],
                                 exact_solver=exact_solver, fast=(results[i], one))
    return SpatialDKBatch.from_results(results)


def quadric_polynomials(Q_exact: npt.NDArray[np.object_]) -> list[Any]:
    """The forms ``z^T Q_k z`` as sympy polynomials in the Study symbols (exact rational coefficients).

    Parameters
    ----------
    Q_exact : (m, 8, 8) object array of Fraction

    Returns
    -------
    list of sympy expressions

    Examples
    --------
    >>> from imagespace.spatial.quadrics import study_quadric_matrix
    >>> from imagespace.spatial.certify import exact_matrix
    >>> quadric_polynomials(exact_matrix(study_quadric_matrix()[None]))
    [x0*y0 + x1*y1 + x2*y2 + x3*y3]
    """
    import sympy as sp

    from .study import study_symbols

    z = study_symbols()
    out = []
    for Q in Q_exact:
        terms = []
        for i in range(8):
            for j in range(i, 8):
                c = Q[i, j] if i == j else Q[i, j] + Q[j, i]
                if c != 0:
                    terms.append(sp.Rational(c.numerator, c.denominator) * z[i] * z[j])
        out.append(sp.Add(*terms))
    return out


def exact_study_solver(Q_exact: npt.NDArray[np.object_], exclude_null_rotations: Optional[bool] = None
                       ) -> tuple[FloatArray, int]:
    """msolve on the exact quadrics (every real solution, the four strata of ``x``).

    Parameters
    ----------
    Q_exact : (m, 8, 8) object array of Fraction
        Study's quadric included.
    exclude_null_rotations : bool or None
        Passed to :func:`~imagespace.spatial.exact.exact_real_study_points`: True counts only
        complex solutions with ``x . x != 0`` (displacements) also where such points are isolated.

    Returns
    -------
    study_points : (k, 8) float
    complex_count : int
        Complex solutions with ``x != 0``: the sum over the four strata (a symmetric design can
        have modes with ``x0 = 0``, which the chart ``x0 = 1`` alone would not count).

    Raises
    ------
    DegenerateDesignError
        If the solution set is positive-dimensional.
    MsolveUnavailableError
        If msolve is not installed.

    Examples
    --------
    >>> from imagespace.core.msolve import msolve_available
    >>> import numpy as np, imagespace as isp, pytest
    >>> if not msolve_available(): pytest.skip("msolve is not installed")
    >>> gs = isp.GoughStewart(np.random.default_rng(0).integers(-3, 4, (6, 3)),
    ...                       np.random.default_rng(1).integers(-3, 4, (6, 3)))
    >>> pts, n = exact_study_solver(gs.family().exact([4] * 6))
    >>> n
    40
    """
    from .exact import exact_real_study_points

    res = exact_real_study_points(quadric_polynomials(Q_exact), study_quadric=False,
                                  exclude_null_rotations=exclude_null_rotations)
    # the strata x0 = 1, (x0 = 0, x1 = 1), ... hold every point with x != 0 exactly once
    return res.study_points, int(sum(res.stratum_complex_counts))


def exact_result(family: QuadricFamily, lengths: npt.ArrayLike, exclude_null_rotations: Optional[bool] = None
                 ) -> SpatialDKResult:
    """The exact path: msolve on the exact system, always certified.

    Parameters
    ----------
    family : QuadricFamily
    lengths : (p,) float
    exclude_null_rotations : bool or None
        See :func:`exact_study_solver`.

    Returns
    -------
    SpatialDKResult

    Raises
    ------
    DegenerateDesignError
        If the solution set is positive-dimensional.
    MsolveUnavailableError
        If msolve is not installed.

    Examples
    --------
    >>> from imagespace.core.msolve import msolve_available
    >>> import numpy as np, imagespace as isp, pytest
    >>> if not msolve_available(): pytest.skip("msolve is not installed")
    >>> gs = isp.GoughStewart(np.random.default_rng(0).integers(-3, 4, (6, 3)),
    ...                       np.random.default_rng(1).integers(-3, 4, (6, 3)))
    >>> exact_result(gs.family(), np.full(6, 2.0)).method
    'msolve'
    """
    lengths = np.asarray(lengths, dtype=float)
    pts, complex_count = exact_study_solver(family.exact(_exact_params(lengths, family.scale)),
                                            exclude_null_rotations)
    res = _residuals(family, (lengths / family.scale) ** 2, pts)
    pts = family.unscale(pts)
    return SpatialDKResult(pts, res,
                           family.aspect(pts) if pts.shape[0] else np.zeros(0, np.int8),
                           int(complex_count), True, True, "msolve")


def study_jacobian_signs(family: QuadricFamily, pts: npt.ArrayLike, tolerances: Optional[Tolerances] = None
                        ) -> npt.NDArray[np.int8]:
    """Aspects in Study coordinates: the sign of ``det [2 Q_k z ; (x, 0)]`` at normalised modes.

    ``Q_k = A_k - p_k E`` with ``p_k = z^T A_k z / z^T E z`` (the mode's own parameters); the last
    row ``(x, 0)`` is the gradient of ``x . x / 2``. Replacing ``z`` by ``-z`` flips all eight rows,
    so the sign is that of the displacement; it changes exactly across the singularities where the
    constraint Jacobian loses rank.

    Parameters
    ----------
    family : QuadricFamily
    pts : (k, 8) float
        Displacements (unscaled, as returned to the user).
    tolerances : Tolerances, optional
        ``spatial_aspect``: 0 where ``|det|`` is at most this times Hadamard's bound.

    Returns
    -------
    (k,) int8

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> m = isp.spatial.ThreeRPS(np.eye(3), 0.5 * np.eye(3))
    >>> study_jacobian_signs(m.family(), np.array([[1.0, 0, 0, 0, 0, 0, 0, 0]])).dtype
    dtype('int8')
    """
    from ..tolerances import Tolerances

    tol = (tolerances or Tolerances()).spatial_aspect
    z = np.array(pts, dtype=float).reshape(-1, 8)
    z[:, 4:] /= family.scale
    z /= np.linalg.norm(z[:, :4], axis=1)[:, None]
    out = np.zeros(z.shape[0], np.int8)
    for i, v in enumerate(z):
        zEz = v @ family.E @ v
        rows = []
        for k in range(family.A.shape[0]):
            Q = family.A[k]
            if family.pidx[k] >= 0:
                Q = Q - (v @ Q @ v) / zEz * family.E
            rows.append(2.0 * Q @ v)
        rows.append(np.concatenate([v[:4], np.zeros(4)]))
        J = np.array(rows)
        det = np.linalg.det(J)
        had = np.prod(np.linalg.norm(J, axis=1))
        out[i] = 0 if abs(det) <= tol * had else (1 if det > 0 else -1)
    return out
