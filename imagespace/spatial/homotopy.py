r"""A compiled path tracker for systems of quadrics in Study coordinates (the spatial fast path).

The systems are ``H_k(z) = z^T A_k z - p_k z^T E z = 0`` (``k = 0..m-1``, ``m = 7``) on the
affine patch ``c . z = 1`` of ``P^7`` (``c`` a random complex vector, so every finite solution and
half-turns alike are ordinary points): ``A_k`` real symmetric ``8 x 8`` (a leg's quadric at length
zero, Study's quadric, a plane ...), ``E`` real symmetric (``x . x`` for legs) and ``p_k`` a
parameter (a squared leg length ``L_k^2``) or zero.

Why a parameter homotopy (the issue's choice between it and Husty's degree-40 elimination).
The family's parameters enter linearly, the design's matrices do not change between poses, and the
number of isolated solutions of a general Gough-Stewart platform, 40, is a theorem (Raghavan 1993;
Ronga & Vust, Lazard, Mourrain 1992-93). So the solutions are computed ONCE per design at random
complex parameters ``p*`` (:func:`solve_start_system`, a total-degree homotopy from
``(u_k . z)^2 - (c . z)^2``: 128 paths, 40 of them finite and non-singular, the others run into the
two-dimensional component ``x = 0, y . y = 0`` that every leg quadric contains) and each target ``p``
is reached along the segment ``p(s) = (1 - s) p + s p*`` (:func:`track_parameters`). Because ``p*`` is
generic and complex, the segment avoids the discriminant for ``0 < s <= 1`` with probability one
(the "gamma trick" of Morgan & Sommese 1989), so the 40 paths are regular and end at every
isolated solution of the target (coefficient-parameter homotopy). The design's matrices may move
too: :func:`move_start_system` carries the solutions of one member of a family LINEAR in its
coefficients to another (the gamma trick between the two members), which is how a Gough-Stewart
design gets its start system from its family kind's generic member in milliseconds
(:mod:`imagespace.spatial.families`) instead of a total-degree homotopy of its own. Husty's elimination instead builds
a degree-40 univariate per pose from ~20 symbolic resultant steps, and its coefficients lose
accuracy exactly where modes come close; the tracker's per-path cost is fixed and small.

Nothing here is a proof. Every endpoint is a float; :mod:`imagespace.spatial.certify` proves them
(Krawczyk in arb) or the result says it is not proven.

References
----------
A. P. Morgan, A. J. Sommese, Coefficient-parameter polynomial continuation, Appl. Math. Comput.
29(2), 1989, doi:10.1016/0096-3003(89)90099-4.
P. Breiding, S. Timme, HomotopyContinuation.jl, ICMS 2018, doi:10.1007/978-3-319-96418-8_54.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional

import numpy as np
import numpy.typing as npt

from ..exceptions import InputTypeError
from ..core._numba import njit
from .tracker import DIM, PATH_FAILED, PATH_OK, complex_norm, track_many

if TYPE_CHECKING:
    from ..core.kinematic_map import FloatArray
    from ..tolerances import Tolerances

__all__ = ["StartSystem", "solve_start_system", "move_start_system", "track_parameters", "classify_batch", "recentre",
           "RECENTRE_SPREAD", "PATH_OK", "PATH_FAILED", "TRACK_KERNELS", "TRACK_KERNEL",
           "LANES_MIN_ROWS", "check_seed", "MOVE_MAX_ENTRY"]

# start system: thresholds between the regular solutions and the degenerate component
# (measured, see :func:`_regular`)
_START_X = 1e-4          # |x| / |z| above this is not the degenerate component
_START_COND = 1e-9       # sigma_min / sigma_max of the Jacobian above this is regular
_START_DISTINCT = 1e-6   # two solutions closer than this relative to their size are one

#: the largest entry a member's matrix may have in :func:`move_start_system`: the tracker forms
#: products of entries (its LU), which must stay in the float range; a family's matrices are
#: scaled to the design's length scale, so theirs are of order one
MOVE_MAX_ENTRY = 1e150


def check_seed(seed: object, name: str = "seed") -> int:
    """``seed`` as an int in ``[0, 2**63)``, else an :class:`~imagespace.exceptions.InputError`
    naming it (bools, floats, strings and negative numbers are refused).

    Examples
    --------
    >>> check_seed(3)
    3
    >>> check_seed(-1)
    Traceback (most recent call last):
    ...
    imagespace.exceptions.InputError: seed must be an integer in [0, 2**63), got -1
    """
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2 ** 63:
        from ..exceptions import InputError
        raise InputError(f"{name} must be an integer in [0, 2**63), got {seed!r}")
    return int(seed)


@dataclass(frozen=True)
class StartSystem:
    """The solutions of a quadric family at generic complex parameters, computed once per design.

    Attributes
    ----------
    A : (m, 8, 8) float
        The parameter-free parts of the quadrics.
    E : (8, 8) float
        The form multiplied by each parameter; diagonal (the tracker reads its diagonal only).
    pidx : (m,) int
        Which parameter multiplies ``E`` in quadric ``k`` (``-1``: none).
    p_star : (p,) complex
        The generic complex parameters.
    patch : (8,) complex
        The affine patch ``patch . z = 1``.
    solutions : (k, 8) complex
        The non-singular finite solutions at ``p_star`` (40 for a general Gough-Stewart).
    paths : int
        Paths tracked to find them (total degree ``2^m`` per attempt).
    """

    A: np.ndarray
    E: np.ndarray
    pidx: np.ndarray
    p_star: np.ndarray
    patch: np.ndarray
    solutions: np.ndarray
    paths: int


def _random_complex(rng, shape):
    return rng.normal(size=shape) + 1j * rng.normal(size=shape)


def _distinct(Z, scale_tol):
    """Indices of pairwise distinct rows (relative distance above ``scale_tol``): each row is kept
    when it is farther than ``scale_tol * (1 + |z_i|)`` from every row kept before it."""
    keep: list[int] = []
    if not Z.shape[0]:
        return keep
    D = np.linalg.norm(Z[:, None, :] - Z[None, :, :], axis=2)
    thr = scale_tol * (1 + np.linalg.norm(Z, axis=1))
    for i in range(Z.shape[0]):
        if np.all(D[i, keep] > thr[i]):
            keep.append(i)
    return keep


def _regular(A, E, pidx, p, patch, Z, tol):
    """Per row of ``Z`` (k, 8): residual small, ``x`` not tiny and the Jacobian not singular (not
    the degenerate part); a (k,) bool mask.

    Measured on general 6-6 designs (anchors of unit size, the family's scaling): endpoints on the
    degenerate component have ``|x| / |z| <= 1.3e-6`` and ``sigma_min / sigma_max <= 2.3e-12``;
    the 40 regular solutions ``|x| / |z| >= 3e-2`` and ``sigma_min / sigma_max >= 1.5e-6``.
    The thresholds sit between: ``_START_X`` and ``_START_COND``.
    """
    Z = np.asarray(Z, dtype=complex).reshape(-1, DIM)
    n = Z.shape[0]
    ok = np.all(np.isfinite(Z), axis=1)
    if not np.any(ok):
        return ok
    W = Z[ok]
    pk = np.where(pidx >= 0, np.asarray(p)[np.maximum(pidx, 0)], 0.0)
    M = A - pk[:, None, None] * E
    MW = np.einsum("kij,nj->nki", M, W)
    H = np.concatenate([np.einsum("ni,nki->nk", W, MW), (W @ patch - 1)[:, None]], axis=1)
    J = np.concatenate([2 * MW, np.broadcast_to(patch, (W.shape[0], 1, DIM))], axis=1)
    nz = np.linalg.norm(W, axis=1)
    good = (np.linalg.norm(H, axis=1) <= tol * (1 + nz) ** 2) & (np.linalg.norm(W[:, :4], axis=1) > _START_X * nz)
    if np.any(good):
        sv = np.linalg.svd(J[good], compute_uv=False)
        good[good] = sv[:, -1] > _START_COND * sv[:, 0]
    out = np.zeros(n, dtype=bool)
    out[ok] = good
    return out


def solve_start_system(A: npt.ArrayLike, E: npt.ArrayLike, pidx: npt.ArrayLike, nparams: int, seed: int = 0,
                       attempts: int = 4, expected: Optional[int] = None, tol: float = 1e-10) -> StartSystem:
    """Solve the family once at random complex parameters (total-degree homotopy, ``2^m`` paths).

    Parameters
    ----------
    A : (m, 8, 8) float
    E : (8, 8) float
    pidx : (m,) int
    nparams : int
        Length of the parameter vector.
    seed : int
        Seeds the random parameters, patch and start system (results are reproducible).
    attempts : int
        Total-degree runs (new random start system each) until ``expected`` solutions are found.
    expected : int, optional
        Stop once this many distinct regular solutions are known (40 for a general 6-SPS).
    tol : float
        Relative residual / separation used to keep an endpoint (a numerical choice for the start
        system only; the targets' answers are checked and certified separately).

    Returns
    -------
    StartSystem

    Raises
    ------
    InputError
        If ``E`` is not diagonal.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.quadrics import sphere_quadric, study_quadric_matrix
    >>> rng = np.random.default_rng(1)
    >>> A = np.concatenate([sphere_quadric(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)), 0.0),
    ...                     study_quadric_matrix()[None]])
    >>> E = np.diag([1.0, 1, 1, 1, 0, 0, 0, 0])
    >>> st = solve_start_system(A, E, np.array([0, 1, 2, 3, 4, 5, -1]), 6, expected=40)
    >>> len(st.solutions)
    40
    """
    rng = np.random.default_rng(seed)
    A = np.ascontiguousarray(A, dtype=float)
    E = np.ascontiguousarray(E, dtype=float)
    if np.any(E - np.diag(np.diag(E))):
        from ..exceptions import InputError
        raise InputError("E must be a diagonal matrix (the tracker reads its diagonal), got "
                         "off-diagonal entries")
    pidx = np.ascontiguousarray(pidx, dtype=np.int64)
    m = A.shape[0]
    p_star = _random_complex(rng, nparams)
    patch = _random_complex(rng, DIM)
    found = np.zeros((0, DIM), dtype=complex)
    paths = 0
    for _ in range(attempts):
        U = _random_complex(rng, (m, DIM))
        gamma = np.exp(2j * np.pi * rng.random())
        signs = np.array(np.meshgrid(*[[1.0, -1.0]] * m, indexing="ij")).reshape(m, -1).T
        M = np.vstack([U, patch])
        starts = np.linalg.solve(M[None], np.concatenate([signs, np.ones((signs.shape[0], 1))], axis=1)
                                 .astype(complex)[..., None])[..., 0]
        Z = np.zeros((1, starts.shape[0], DIM), dtype=complex)
        status = np.zeros((1, starts.shape[0]), dtype=np.int64)
        steps = np.zeros((1, starts.shape[0]), dtype=np.int64)
        track_many(np.ascontiguousarray(starts), 1, A, E, pidx, np.zeros((1, nparams), complex), p_star,
                   U, A, patch, gamma, Z, status, steps)
        paths += starts.shape[0]
        arrived = Z[0][status[0] == PATH_OK]
        good = arrived[_regular(A, E, pidx, p_star, patch, arrived, tol)]
        if len(good):
            allz = np.vstack([found, good])
            found = allz[_distinct(allz, _START_DISTINCT)]
        if expected is not None and len(found) >= expected:
            break
    return StartSystem(A, E, pidx, p_star, patch, np.ascontiguousarray(found), paths)


def move_start_system(start: StartSystem, A: npt.ArrayLike, seed: int = 0, tol: float = 1e-10) -> StartSystem:
    """Carry a start system to another member of its family (coefficient-parameter homotopy).

    ``start`` holds the solutions of one member ``z^T (A1_k - p*_k E) z`` (``A1 = start.A``) of a
    family whose matrices depend LINEARLY on coefficients (:mod:`imagespace.spatial.families`); the
    target is the member ``A`` at the same parameters ``p*``. The homotopy is
    ``H = (1 - s) F_A + s gamma F_A1`` with ``gamma`` a seeded random unit complex number: a path
    in the complex line through the two members (every scalar multiple of a member's equations is
    that member again), which avoids the finitely many degenerate members of that line for
    ``0 < s <= 1`` with probability one when ``start`` is a generic member (Morgan & Sommese 1989).
    Every isolated solution of the target is then an endpoint; the regular finite ones are kept
    (the same test as :func:`solve_start_system`). The caller compares their count with the
    family's bound: fewer means a special member or a lost path, never to be used silently.

    Parameters
    ----------
    start : StartSystem
        A generic member's solutions.
    A : (m, 8, 8) float
        The target member's parameter-free parts (same ``E``, ``pidx``, ``p_star`` and patch).
    seed : int
        Seeds ``gamma``.
    tol : float
        As in :func:`solve_start_system`.

    Returns
    -------
    StartSystem
        ``A``'s regular finite solutions at ``start.p_star``; ``paths`` is the number tracked.

    Raises
    ------
    TypeError
        If ``start`` is not a StartSystem.
    InputError
        If ``A`` is not a finite real array of ``start.A``'s shape with entries up to
        :data:`MOVE_MAX_ENTRY`, on a bad ``seed`` (:func:`check_seed`) or a ``tol`` that is not
        a positive number.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.quadrics import sphere_quadric, study_quadric_matrix
    >>> rng = np.random.default_rng(1)
    >>> legs = lambda: np.concatenate([sphere_quadric(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)),
    ...                                               0.0), study_quadric_matrix()[None]])
    >>> st = solve_start_system(legs(), np.diag([1.0, 1, 1, 1, 0, 0, 0, 0]), np.r_[np.arange(6), -1], 6,
    ...                         expected=40)
    >>> moved = move_start_system(st, legs())
    >>> len(moved.solutions), moved.paths
    (40, 40)
    """
    from ..exceptions import InputError

    if not isinstance(start, StartSystem):
        raise InputTypeError(f"start must be a StartSystem, got {type(start).__name__}")
    A = np.asarray(A)
    if A.shape != start.A.shape or A.dtype.kind not in "iuf" or not np.all(np.isfinite(A)):
        raise InputError(f"A must be a finite real array of shape {start.A.shape} (the start member's), "
                         f"got shape {A.shape} and dtype {A.dtype}")
    if np.abs(A).max() > MOVE_MAX_ENTRY:
        raise InputError(f"A's entries must be at most MOVE_MAX_ENTRY = {MOVE_MAX_ENTRY:g} in magnitude, got "
                         f"{float(np.abs(A).max()):.3g} (a family's matrices are scaled to the design's size)")
    seed = check_seed(seed)
    if isinstance(tol, (bool, np.bool_)) or not isinstance(tol, (int, float, np.integer, np.floating)) \
            or not 0 < tol < np.inf:
        raise InputError(f"tol must be a positive number, got {tol!r}")
    A = np.ascontiguousarray(A, dtype=float)
    rng = np.random.default_rng(seed)
    gamma = np.exp(2j * np.pi * rng.random())
    k = start.solutions.shape[0]
    Z = np.zeros((1, k, DIM), dtype=complex)
    status = np.zeros((1, k), dtype=np.int64)
    steps = np.zeros((1, k), dtype=np.int64)
    if k:
        track_many(start.solutions, 2, A, start.E, start.pidx,
                   np.ascontiguousarray(start.p_star, dtype=complex)[None], start.p_star,
                   np.zeros((A.shape[0], DIM), complex), start.A, start.patch, gamma, Z, status, steps)
    arrived = Z[0][status[0] == PATH_OK]
    found = arrived[_regular(A, start.E, start.pidx, start.p_star, start.patch, arrived, tol)]
    found = found[_distinct(found, _START_DISTINCT)]
    return StartSystem(A, start.E, start.pidx, start.p_star, start.patch, np.ascontiguousarray(found), k)


#: the trackers of :func:`track_parameters`: ``"lanes"`` the lockstep tracker
#: (:mod:`imagespace.spatial.lanes`), ``"scalar"`` the one-path tracker
#: (:mod:`imagespace.spatial.tracker`), ``"auto"`` the lockstep one from :data:`LANES_MIN_ROWS`
#: rows on, the one-path one below (a lone row fills a block of lanes poorly); they take the same
#: decisions on every path
TRACK_KERNELS = ("auto", "lanes", "scalar")
#: the default tracker
TRACK_KERNEL = "auto"
#: rows from which ``kernel="auto"`` tracks in lockstep (measured on Dietmaier's design, median of
#: 15 calls on a loaded 2-core machine: 1 row 8.0 ms one path at a time vs 12.8 ms in lockstep, 2 rows
#: 10.6 vs 12.8 ms, 4 rows 21.5 vs 17.3 ms, 16 rows 56 vs 29 ms)
LANES_MIN_ROWS = 3


def check_kernel(kernel: object) -> str:
    """``kernel`` if it names a tracker of :data:`TRACK_KERNELS`, else an error.

    Raises
    ------
    InputError
        Naming the parameter, the value given and the trackers expected.

    Examples
    --------
    >>> check_kernel("lanes")
    'lanes'
    >>> check_kernel("simd")
    Traceback (most recent call last):
    ...
    imagespace.exceptions.InputError: kernel must be one of 'auto', 'lanes', 'scalar', got 'simd'
    """
    if not isinstance(kernel, str) or kernel not in TRACK_KERNELS:
        from ..exceptions import InputError
        raise InputError(f"kernel must be one of {', '.join(map(repr, TRACK_KERNELS))}, got {kernel!r}")
    return kernel


def track_parameters(start: StartSystem, P: npt.ArrayLike, kernel: str = TRACK_KERNEL
                     ) -> tuple[npt.NDArray[np.complex128], npt.NDArray[np.integer], npt.NDArray[np.integer]]:
    """Track the start solutions to real (or complex) target parameters, row by row.

    Parameters
    ----------
    start : StartSystem
    P : (n, p) float or complex
        Target parameters (squared leg lengths).
    kernel : {"auto", "lanes", "scalar"}, optional
        ``"lanes"``: the lockstep tracker (:mod:`imagespace.spatial.lanes`, ``LANES`` paths
        advanced together, vectorised); ``"scalar"``: one path at a time
        (:mod:`imagespace.spatial.tracker`); ``"auto"`` (default, :data:`TRACK_KERNEL`): lanes from
        :data:`LANES_MIN_ROWS` rows on. Both take the same decisions on every path; the
        endpoints agree to rounding.

    Returns
    -------
    Z : (n, k, 8) complex
        Endpoints on the patch (one per start solution).
    status : (n, k) int
        :data:`PATH_OK` or :data:`PATH_FAILED`.
    steps : (n, k) int

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.quadrics import sphere_quadric, study_quadric_matrix
    >>> rng = np.random.default_rng(1)
    >>> A = np.concatenate([sphere_quadric(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)), 0.0),
    ...                     study_quadric_matrix()[None]])
    >>> st = solve_start_system(A, np.diag([1.0, 1, 1, 1, 0, 0, 0, 0]), np.arange(7) - (np.arange(7) == 6) * 7,
    ...                         6, expected=40)
    >>> Z, status, steps = track_parameters(st, np.full((1, 6), 4.0))
    >>> Z.shape
    (1, 40, 8)
    >>> Zl, status_l, _ = track_parameters(st, np.full((1, 6), 4.0), kernel="lanes")
    >>> bool(np.array_equal(status, status_l) and np.allclose(Z, Zl, rtol=1e-9, atol=1e-12))
    True
    """
    kernel = check_kernel(kernel)
    P = np.ascontiguousarray(np.atleast_2d(P), dtype=complex)
    n, k = P.shape[0], start.solutions.shape[0]
    Z = np.zeros((n, k, DIM), dtype=complex)
    status = np.zeros((n, k), dtype=np.int64)
    steps = np.zeros((n, k), dtype=np.int64)
    if not n or not k:
        return Z, status, steps
    if kernel == "auto":
        kernel = "lanes" if n >= LANES_MIN_ROWS else "scalar"
    if kernel == "lanes":
        from .lanes import track_lanes
        track_lanes(start.solutions, start.A, start.E, start.pidx, P, start.p_star, start.patch, Z, status,
                    steps)
    else:
        track_many(start.solutions, 0, start.A, start.E, start.pidx, P, start.p_star,
                   np.zeros((start.A.shape[0], DIM), complex), start.A, start.patch, 1.0 + 0j, Z, status,
                   steps)
    return Z, status, steps


@njit(cache=True)
def _classify_rows(Z, status, real_imag, nonreal_imag, distinct_tol, W, real, distinct, reliable):
    """Per row: scale each endpoint by its largest ``x`` entry, flag real ones, count distinct ones.

    ``W`` receives the scaled endpoints' real parts, ``real[r, j]`` the real flags, ``distinct[r]``
    the number of pairwise distinct arrived endpoints and ``reliable[r]`` the float checks.
    """
    n, k = status.shape
    U = np.zeros((k, DIM), dtype=np.complex128)
    for r in range(n):
        ok = True
        for j in range(k):
            if status[r, j] != PATH_OK:
                ok = False
                real[r, j] = False
                continue
            big = 0.0
            jj = 0
            for i in range(4):
                a = abs(Z[r, j, i])
                if a > big:
                    big = a
                    jj = i
            piv = Z[r, j, jj]
            size = 0.0
            im = 0.0
            for i in range(DIM):
                v = Z[r, j, i] / piv
                U[j, i] = v
                size = max(size, abs(v))
                im = max(im, abs(v.imag))
            rel = im / size
            real[r, j] = rel <= real_imag
            if rel > real_imag and rel < nonreal_imag:
                ok = False
            for i in range(DIM):
                W[r, j, i] = U[j, i].real
        count = 0
        for j in range(k):
            if status[r, j] != PATH_OK:
                continue
            nj = complex_norm(U[j])
            dup = False
            for l in range(j + 1, k):
                if status[r, l] != PATH_OK:
                    continue
                nl = complex_norm(U[l])
                acc = 0.0
                for i in range(DIM):
                    d = U[j, i] / nj - U[l, i] / nl
                    acc += d.real * d.real + d.imag * d.imag
                if np.sqrt(acc) <= distinct_tol:
                    dup = True
                    break
            if dup:
                ok = False
            else:
                count += 1
        distinct[r] = count
        reliable[r] = ok


def classify_batch(Z: npt.NDArray[np.complex128], status: npt.NDArray[np.integer], tolerances: Tolerances
                   ) -> tuple[FloatArray, npt.NDArray[np.bool_], npt.NDArray[np.integer], npt.NDArray[np.bool_]]:
    """Sort every row's endpoints into real modes (compiled; float checks, not a proof).

    Parameters
    ----------
    Z : (n, k, 8) complex
    status : (n, k) int
    tolerances : Tolerances
        ``spatial_real_imag``, ``spatial_nonreal_imag``, ``spatial_distinct``.

    Returns
    -------
    W : (n, k, 8) float
        Endpoints scaled so their largest ``|x_i|`` is 1 (real parts).
    real : (n, k) bool
    distinct : (n,) int
    reliable : (n,) bool
        All paths arrived, endpoints distinct, none between the two realness thresholds.

    Examples
    --------
    >>> from imagespace.tolerances import Tolerances
    >>> Z = np.array([[[1, 0, 0, 0, 0, 0, 0, 0], [1, 1j, 0, 0, 0, 0, 0, 0]]], dtype=complex)
    >>> W, real, distinct, ok = classify_batch(Z, np.zeros((1, 2), np.int64), Tolerances())
    >>> real.tolist(), distinct.tolist(), ok.tolist()
    ([[True, False]], [2], [True])
    """
    n, k = status.shape
    W = np.zeros((n, k, DIM))
    real = np.zeros((n, k), dtype=np.bool_)
    distinct = np.zeros(n, dtype=np.int64)
    reliable = np.zeros(n, dtype=np.bool_)
    if n and k:
        _classify_rows(np.ascontiguousarray(Z), np.ascontiguousarray(status, dtype=np.int64),
                       tolerances.spatial_real_imag, tolerances.spatial_nonreal_imag,
                       tolerances.spatial_distinct, W, real, distinct, reliable)
    return W, real, distinct, reliable


#: relative spread of the re-centred complex parameters (measured on a general 6-6 design with
#: 300 random-pose rows: 46 Jacobian evaluations a path from the design's start parameters,
#: 21 from parameters re-centred at the batch's median with this spread, 19 with 0.1)
RECENTRE_SPREAD = 0.3


def recentre(start: StartSystem, centre: npt.ArrayLike, seed: int = 0, kernel: str = TRACK_KERNEL
             ) -> StartSystem:
    """Move the start system to generic complex parameters near ``centre`` (fewer steps to targets).

    The new parameters are ``centre * (1 + RECENTRE_SPREAD * g)`` with ``g`` seeded complex normal:
    as generic as the old ones (a continuous random choice), but close to the targets, so their
    paths are shorter. The start solutions are carried along one complex parameter path.

    Parameters
    ----------
    start : StartSystem
    centre : (p,) float
        Typical target parameters (e.g. a batch's median).
    seed : int
    kernel : {"auto", "lanes", "scalar"}, optional
        The tracker (:func:`track_parameters`).

    Returns
    -------
    StartSystem
        ``start`` itself when the move does not bring every solution across (all paths arrived,
        endpoints pairwise distinct).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.quadrics import sphere_quadric, study_quadric_matrix
    >>> rng = np.random.default_rng(1)
    >>> A = np.concatenate([sphere_quadric(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)), 0.0),
    ...                     study_quadric_matrix()[None]])
    >>> st = solve_start_system(A, np.diag([1.0, 1, 1, 1, 0, 0, 0, 0]), np.r_[np.arange(6), -1], 6,
    ...                         expected=40)
    >>> len(recentre(st, np.full(6, 4.0)).solutions)
    40
    """
    rng = np.random.default_rng(seed)
    centre = np.asarray(centre, dtype=float)
    p_new = centre * (1.0 + RECENTRE_SPREAD * _random_complex(rng, centre.shape[0]))
    Z, status, _ = track_parameters(start, p_new[None], kernel=kernel)
    Z = Z[0]
    if np.any(status[0] != PATH_OK) or not np.all(np.isfinite(Z)):
        return start
    if len(_distinct(Z, _START_DISTINCT)) != Z.shape[0]:
        return start
    return StartSystem(start.A, start.E, start.pidx, p_new, start.patch, np.ascontiguousarray(Z),
                       start.paths)
