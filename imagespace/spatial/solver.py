"""Direct kinematics of a family of quadrics in Study coordinates: fast, certified and exact paths.

A mechanism (:class:`~imagespace.spatial.GoughStewart`, :class:`~imagespace.spatial.ThreeRPS`)
describes itself as a :class:`QuadricFamily`: ``m = 7`` quadrics ``z^T (A_k - p_k E) z = 0`` whose
parameters ``p`` are its squared leg lengths. This module

* solves the family once at generic complex parameters (:func:`~imagespace.spatial.homotopy.solve_start_system`),
* tracks those solutions to every target row in the compiled tracker (the fast path),
* sorts the endpoints into real and non-real modes with float checks that say when they are not
  sure (``reliable``),
* proves a row on request (``certify=True``): Krawczyk boxes in arb on the exact quadrics; when all
  ``bound`` solutions are certified the real count is proven (:mod:`imagespace.spatial.certify`),
  otherwise msolve decides exactly (:mod:`imagespace.spatial.exact`).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from fractions import Fraction
from typing import Callable, Optional

import numpy as np

from ..exceptions import NearSingularWarning
from .homotopy import PATH_OK, StartSystem, solve_start_system, track_parameters
from .results import SpatialDKBatch, SpatialDKResult
from .study import normalize_study

__all__ = ["QuadricFamily", "solve_rows", "certify_row", "classify_endpoints", "exact_study_solver",
           "exact_result", "quadric_polynomials"]


@dataclass(frozen=True)
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
        ``aspect(study_points (k, 8)) -> (k,) int8``.
    """

    A: np.ndarray
    E: np.ndarray
    pidx: np.ndarray
    nparams: int
    bound: Optional[int]
    exact: Callable
    aspect: Callable


def start_system(family, seed=0):
    """The family's solutions at generic complex parameters (computed once per design).

    Parameters
    ----------
    family : QuadricFamily
    seed : int

    Returns
    -------
    StartSystem

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> gs = isp.GoughStewart(np.random.default_rng(0).normal(size=(6, 3)),
    ...                       np.random.default_rng(1).normal(size=(6, 3)))
    >>> len(start_system(gs.family()).solutions)
    40
    """
    return solve_start_system(family.A, family.E, family.pidx, family.nparams, seed=seed,
                              expected=family.bound)


def classify_endpoints(Z, status, tolerances):
    """Float classification of one row's endpoints into real modes.

    Parameters
    ----------
    Z : (k, 8) complex
        Endpoints on the tracker's patch.
    status : (k,) int
    tolerances : Tolerances
        ``spatial_real_imag``, ``spatial_nonreal_imag``, ``spatial_distinct``.

    Returns
    -------
    real_points : (r, 8) float
        Normalised real Study points.
    distinct : int
        Number of pairwise distinct endpoints among the paths that arrived.
    reliable : bool
        All paths arrived, endpoints pairwise distinct, every endpoint clearly real or clearly not.

    Examples
    --------
    >>> from imagespace.tolerances import Tolerances
    >>> Z = np.array([[1, 0, 0, 0, 0, 0, 0, 0], [1, 1j, 0, 0, 0, 0, 0, 0]], dtype=complex)
    >>> pts, distinct, ok = classify_endpoints(Z, np.zeros(2, int), Tolerances())
    >>> pts.shape, distinct, ok
    ((1, 8), 2, True)
    """
    arrived = status == PATH_OK
    W = Z[arrived]
    reliable = bool(np.all(arrived))
    if W.shape[0] == 0:
        return np.zeros((0, 8)), 0, reliable
    j = np.argmax(np.abs(W[:, :4]), axis=1)
    W = W / W[np.arange(W.shape[0]), j][:, None]
    size = np.abs(W).max(axis=1)
    imag = np.abs(W.imag).max(axis=1) / size
    is_real = imag <= tolerances.spatial_real_imag
    ambiguous = (~is_real) & (imag < tolerances.spatial_nonreal_imag)
    if np.any(ambiguous):
        reliable = False
    # distinct endpoints (path jumping sends two paths to one solution)
    Wn = W / np.linalg.norm(W, axis=1)[:, None]
    distinct = W.shape[0]
    for a in range(W.shape[0]):
        d = np.linalg.norm(Wn[a + 1:] - Wn[a], axis=1)
        if np.any(d <= tolerances.spatial_distinct):
            distinct -= 1
            reliable = False
    pts = W[is_real].real
    return (normalize_study(pts) if pts.shape[0] else np.zeros((0, 8))), distinct, reliable


def _residuals(family, P_row, pts):
    if not pts.shape[0]:
        return np.zeros(0)
    Q = family.A - P_row[np.maximum(family.pidx, 0)][:, None, None] * (family.pidx >= 0)[:, None, None] * family.E
    return np.abs(np.einsum("ni,kij,nj->nk", pts, Q, pts)).max(axis=1)


def solve_rows(family, start, P, tolerances, valid=None):
    """The fast path on many rows: track, classify, residuals and aspects.

    Parameters
    ----------
    family : QuadricFamily
    start : StartSystem
    P : (n, p) float
        Target parameters (squared lengths).
    tolerances : Tolerances
    valid : (n,) bool, optional
        Rows to solve (others get no modes).

    Returns
    -------
    SpatialDKBatch
        ``certified`` all False.

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
    P = np.atleast_2d(np.asarray(P, dtype=float))
    n = P.shape[0]
    valid = np.ones(n, bool) if valid is None else np.asarray(valid, bool)
    rows = np.flatnonzero(valid)
    Z, status, _ = track_parameters(start, P[rows]) if rows.size else (None, None, None)
    counts = np.zeros(n, np.int64)
    cplx = np.zeros(n, np.int64)
    reliable = np.zeros(n, bool)
    pts_all, res_all, asp_all = [], [], []
    for r_i, r in enumerate(rows):
        pts, distinct, ok = classify_endpoints(Z[r_i], status[r_i], tolerances)
        counts[r] = pts.shape[0]
        cplx[r] = distinct
        reliable[r] = ok and (family.bound is None or distinct == family.bound or
                              distinct == start.solutions.shape[0])
        pts_all.append(pts)
        res_all.append(_residuals(family, P[r], pts))
        asp_all.append(family.aspect(pts) if pts.shape[0] else np.zeros(0, np.int8))
    offsets = np.concatenate([[0], np.cumsum(counts)])
    S = np.vstack(pts_all) if pts_all else np.zeros((0, 8))
    res = np.concatenate(res_all) if res_all else np.zeros(0)
    asp = np.concatenate(asp_all).astype(np.int8) if asp_all else np.zeros(0, np.int8)
    return SpatialDKBatch(counts, offsets, S.reshape(-1, 8), res, asp, cplx, reliable,
                          np.zeros(n, bool), valid)


def _exact_params(lengths):
    return [Fraction(float(v)) ** 2 for v in lengths]


def certify_row(family, start, lengths, tolerances, Z=None, status=None, exact_solver=None):
    """Prove one row: Krawczyk on every endpoint, or msolve when that does not settle it.

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
        ``exact_solver(Q_exact) -> (study_points (k, 8) float)``, raising on positive-dimensional
        systems; used when Krawczyk does not prove the row.

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

    lengths = np.asarray(lengths, dtype=float)
    P = lengths ** 2
    if Z is None:
        Zs, sts, _ = track_parameters(start, P[None])
        Z, status = Zs[0], sts[0]
    Qx = family.exact(_exact_params(lengths))
    arrived = Z[status == PATH_OK]
    if family.bound is not None and arrived.shape[0] >= family.bound:
        cert = krawczyk_certify(Qx, arrived)
        if cert.complete(family.bound):
            real = cert.points[cert.certified & (cert.real == 1)].real
            pts = normalize_study(real) if real.shape[0] else np.zeros((0, 8))
            return SpatialDKResult(pts, _residuals(family, P, pts),
                                   family.aspect(pts) if pts.shape[0] else np.zeros(0, np.int8),
                                   family.bound, True, True, "homotopy+krawczyk")
    if exact_solver is not None:
        pts, complex_count = exact_solver(Qx)
        return SpatialDKResult(pts, _residuals(family, P, pts),
                               family.aspect(pts) if pts.shape[0] else np.zeros(0, np.int8),
                               int(complex_count), True, True, "msolve")
    warnings.warn("the row could not be certified: Krawczyk did not prove every solution and no exact "
                  "solver is available (pip install imagespace[exact]); the modes are the fast path's",
                  NearSingularWarning, stacklevel=3)
    pts, distinct, ok = classify_endpoints(Z, status, tolerances)
    return SpatialDKResult(pts, _residuals(family, P, pts),
                           family.aspect(pts) if pts.shape[0] else np.zeros(0, np.int8),
                           distinct, False, ok, "homotopy")


def quadric_polynomials(Q_exact):
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


def exact_study_solver(Q_exact):
    """msolve on the exact quadrics (every real solution, the four strata of ``x``).

    Parameters
    ----------
    Q_exact : (m, 8, 8) object array of Fraction
        Study's quadric included.

    Returns
    -------
    study_points : (k, 8) float
    complex_count : int
        Complex solutions in the chart ``x0 = 1``.

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

    res = exact_real_study_points(quadric_polynomials(Q_exact), study_quadric=False)
    return res.study_points, res.complex_count


def exact_result(family, lengths):
    """The exact path: msolve on the exact system, always certified.

    Parameters
    ----------
    family : QuadricFamily
    lengths : (p,) float

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
    pts, complex_count = exact_study_solver(family.exact(_exact_params(lengths)))
    P = lengths ** 2
    return SpatialDKResult(pts, _residuals(family, P, pts),
                           family.aspect(pts) if pts.shape[0] else np.zeros(0, np.int8),
                           int(complex_count), True, True, "msolve")
