"""The planar back ends of the direct kinematics (:class:`~imagespace.core.mechanism.Backends` of
:class:`~imagespace.PlanarParallel`): the numpy path and the compiled kernel (float stage), the
certified batch (proof stage), the certified per-row path (exact stage), the certified counts, the
reach bound and the rows beyond the float paths. The front end (:mod:`imagespace.solve.front`)
validates and calls them; they never call a facade method.
"""

from __future__ import annotations

from typing import Any, Optional, TypeVar

import numpy as np
import numpy.typing as npt

from ..core.certify import RealRootCertificate
from ..core.form_bounds import form_signs_on, no_common_real_root
from ..core.mechanism import Backends
from ..core.reach import ReachObstruction, planar_design_scale, planar_reach_obstruction, prismatic_magnitude
from ..exceptions import DegenerateDesignError, InputError
from .._validate import finite_rows
from .certified import certified_modes, certify_batch, exact_certificate, exact_mode_count, pp_genuine_forms
from .numpy_path import complex_modes, check_rows, solve_batch
from .proof import batch_kernel, have_numba as _have_numba
from .results import AssemblyModes, CertifiedModes, DKBatchResult, MAX_MODES, SOLVER_NAMES


_KERNEL_MIN_ROWS = 2000
# a per-call answer (AssemblyModes or CertifiedModes: lists of modes with attributes)
_Modes = TypeVar("_Modes", bound=list)


#: Peak bytes per row of a batch, measured with tracemalloc on 20,000 rows of the general 3-RPR
#: (2026-12-02, ragged result of 0.14 kB a row: numpy path 4.2 kB; kernel 0.71 kB on one chunk of
#: 20,000 rows, 0.32 kB on 200,000 rows and 0.25 kB on 10**6 rows of seed 002, its padded arrays
#: compacted chunk by chunk (KERNEL_CHUNK_ROWS); certify=True on the kernel path 3.1 kB in all, so
#: it adds 2.4 kB; 2026-12-01 it added 3.5 kB), rounded up; the memory check before a batch
#: multiplies them by the rows (the large batches it guards are the chunked regime).
BATCH_PEAK_BYTES_PER_ROW = {"numpy": 5000, "kernel": 500, "certify": 4000}




def reach_obstruction(m: Any, q: Any) -> Optional[ReachObstruction]:
    """The reach bound's proof that the design ``m`` has no real mode at ``q``, or None.

    :func:`imagespace.core.reach.planar_reach_obstruction` on the design's legs, with ``q`` as
    given (floats are exact binary rationals, sympy numbers exact); None for a design with free
    symbols. Costs a fraction of a millisecond; decides nothing when it returns None.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.planar import reach_obstruction
    >>> m = isp.examples.general_3rpr()
    >>> reach_obstruction(m, [1e300, 5, 10]).legs, reach_obstruction(m, m.q_example) is None
    ((0, 1), True)
    """
    if not m.is_numeric:
        return None
    return planar_reach_obstruction(m.legs, q)


def far_rows(m: Any, Q: npt.ArrayLike) -> np.ndarray:
    """Rows of ``Q`` (n, 3) whose prismatic joint values exceed ``tolerances.far_reach_ratio``
    times the design's size: the float paths do not resolve the design there (its geometry
    falls below their relative resolution next to the legs), so these rows are answered by the
    reach bound or the certified per-row path. Non-finite rows are not far (they are invalid).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.solve.planar import far_rows
    >>> m = isp.examples.general_3rpr()
    >>> far_rows(m, np.array([m.q_example_float, [1e300, 5, 10], [np.nan, 1, 1]])).tolist()
    [False, True, False]
    """
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    if not m.is_numeric or Q.shape[0] == 0:
        return np.zeros(Q.shape[0], dtype=bool)
    scale = m.cached("design_scale", lambda: planar_design_scale(m.legs))
    mag = prismatic_magnitude(m.legs, Q)
    return finite_rows(Q) & (mag > m.tolerances.far_reach_ratio * scale)


def reach_certificate(obstruction: ReachObstruction) -> RealRootCertificate:
    """The certificate of a row a reach bound proves empty: count 0, certified, exact.

    Its count is the number of real assembly modes (0); the kinematic polynomial itself is not
    examined (a root of it without a real pose, e.g. one whose positions are complex, is not
    counted).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.planar import reach_certificate, reach_obstruction
    >>> m = isp.examples.general_3rpr()
    >>> c = reach_certificate(reach_obstruction(m, [1e300, 5, 10]))
    >>> c.certified, c.count, c.method.split(":")[0]
    (True, 0, 'reach bound')
    """
    return RealRootCertificate(True, 0, (), (), 0, f"reach bound: {obstruction}", (), True)


def _certified_refusing_overflow(m, q, qf):
    """The certified per-call path, with the overflow of its float stages (joint values whose
    squares leave the float range) refused by an error that names ``q``."""
    try:
        with np.errstate(over="ignore", invalid="ignore"):     # overflow is reported below
            return certified_modes(m, q, qf)
    except (InputError, OverflowError) as exc:
        if isinstance(exc, InputError) and "finite" not in str(exc):
            raise
        raise InputError(
            f"q = {qf.tolist()} of {m.name} is beyond the float range of the direct kinematics "
            f"(the poses of its modes cannot be computed in double precision) and no reach bound "
            f"proves it has no real mode; expected joint values within about "
            f"{m.tolerances.far_reach_ratio:g} times the design's size") from None


def counts(m: Any, Q: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The counting stage (``certified_root_counts``) on the rows ``rows`` of ``Q`` (n, 3):
    proven numbers of real assembly modes, ``(counts, path)``.

    First the distinct real roots of the kinematic polynomial: with the compiled kernel proven
    inside it (quadric coefficients, elimination and Bernstein root isolation with a rigorous
    error bound on every value), otherwise by inclusion discs on the enclosed general-q
    polynomial. A root is one mode where the Cramer denominator ``D`` does not vanish there:
    proven for the whole row when ``D`` and the kinematic form have no common real root
    (:func:`imagespace.core.form_bounds.no_common_real_root`, on the kernel's bounded forms
    :meth:`~imagespace.solve.kernel.BatchKernel.cramer_forms` or the enclosed general-q ones),
    and, on a design with a PP dyad, the root is proven not to be the dyad's spurious
    ``phi_c + pi`` (the sign of ``cos(phi - phi_c)`` on its interval): such rows count their
    roots. Every
    other row (a root the bounds cannot decide, a Cramer case where an orientation carries 0, 1
    or 2 positions, a spurious root, rows beyond the float paths :func:`far_rows`) is counted
    exactly by the certified per-row path (:func:`imagespace.solve.certified.exact_mode_count`).
    A continuum reports count -1, path ``"continuum"``.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.solve.planar import counts
    >>> m = isp.examples.stigger_husty()
    >>> c, p = counts(m, np.array([m.q_example_float]), np.array([True]))
    >>> c.tolist(), p.tolist()
    ([6], ['kernel'])
    """
    from ..core.certify import certify_real_roots_batch

    n = Q.shape[0]
    row_ok = np.asarray(rows, dtype=bool).copy()
    out = np.full(n, -1, dtype=np.int8)
    path = np.full(n, "invalid", dtype=object)
    far = np.flatnonzero(row_ok & far_rows(m, Q))
    row_ok[far] = False
    ok = np.flatnonzero(row_ok)
    todo = list(far)
    kernel = batch_kernel(m) if ok.size else None
    # case (a) (D identically zero: every orientation root carries 0, 1 or 2 positions): in the
    # kernel no row passes no_common_real_root (D's bounds hold zero); without a kernel the general
    # elimination says so once per design
    if kernel is None and ok.size and m.exact_forms(None)[2]:
        todo += list(ok)
        ok = ok[:0]
    if kernel is not None:
        c = kernel.certified_counts(Q[ok])[0]
        good = c >= 0
        good[good] = no_common_real_root(*kernel.cramer_forms(Q[ok[good]]))
        out[ok[good]] = c[good]
        path[ok[good]] = "kernel"
        todo += list(ok[~good])
    elif ok.size:
        F, E = m.enclosure().evaluate(Q[ok])
        c, p, iv = certify_real_roots_batch(F, E, lambda i: exact_certificate(m, Q[ok[i]]),
                                            return_intervals=True)
        good = (c >= 0) & (p == "discs")
        if good.any():
            good[good] = _one_mode_per_root(m, Q[ok[good]], F[good], E[good], iv[good])
        out[ok[good]] = c[good]
        path[ok[good]] = "discs"
        todo += list(ok[~good])
    for i in todo:
        try:
            out[i], path[i] = exact_mode_count(m, Q[i])
        except DegenerateDesignError:
            out[i], path[i] = -1, "continuum"
    return out, path


def _one_mode_per_root(m, Q, F, E, iv):
    """Rows (n,) of the disc path whose every real root carries exactly one assembly mode: the
    Cramer denominator ``D`` has no real root in common with the kinematic form ``F +- E``
    (:func:`imagespace.core.form_bounds.no_common_real_root`) and, for each PP dyad, the sign of
    ``cos(phi - phi_c)`` is proven positive on each root's interval ``iv`` ((n, d, 2) of
    ``t = x1/x0``, not the spurious root)."""
    from ..core.codegen import CoefficientEnclosure

    Den = m.cached("exact_cramer_denominator", lambda: CoefficientEnclosure(
        list(m.exact_forms(None)[1].D), m.joint_symbols))
    good = no_common_real_root(F, E, *Den.evaluate(Q))
    genuine = m.cached("pp_genuine_forms", lambda: _pp_genuine_forms(m))
    if genuine:
        used = np.isfinite(iv[..., 0])
        at_inf = np.isinf(iv[..., 0])
        chart = np.where(used, np.where(at_inf, 1, 0), -1).astype(np.int8)
        lo = np.where(at_inf, 0.0, iv[..., 0])
        hi = np.where(at_inf, 0.0, iv[..., 1])
        for g in genuine:
            G, EG = g.evaluate(Q)
            good &= np.all(~used | (form_signs_on(G, EG, lo, hi, chart) > 0), axis=1)
    return good


def _pp_genuine_forms(m):
    """For each PP dyad, :func:`~imagespace.solve.certified.pp_genuine_forms` general in the joint
    values as an enclosure (positive at the dyad's orientation, negative at ``phi_c + pi``)."""
    from ..core.codegen import CoefficientEnclosure

    return [CoefficientEnclosure(list(f), m.joint_symbols) for f in pp_genuine_forms(m)]


def solve(m: Any, Q: np.ndarray, rows: np.ndarray, method: str, per_call: bool) -> DKBatchResult:
    """The float stage on the rows ``rows`` of ``Q`` (n, 3): the compiled kernel (``method``
    ``"kernel"``, or ``"auto"`` for batches of at least 2,000 rows of a design it takes) or the
    numpy path. Other rows come back empty with ``row_ok`` False. ``per_call`` raises on a
    continuum instead of masking the row.

    Raises
    ------
    InputError
        ``method="kernel"`` where the kernel does not apply (no numba, a PP dyad, a Cramer
        denominator vanishing identically).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.solve.planar import solve
    >>> m = isp.examples.general_3rpr()
    >>> solve(m, np.array([m.q_example_float]), np.array([True]), "numpy", False).count.tolist()
    [6]
    """
    Qf = Q if np.all(rows) else np.where(np.asarray(rows, bool)[:, None], Q, np.nan)
    if per_call:
        return solve_batch(m, Qf, raise_degenerate=True, exact_check=_exact_check)
    kernel = _chosen_kernel(m, method, Q.shape[0])
    return (_solve_kernel(m, Qf, kernel) if kernel is not None else
            solve_batch(m, Qf, raise_degenerate=False, exact_check=_exact_check))


def _exact_check(m, q):
    """The certified per-row path on a float row, for the float stage's continuum test of
    Cramer-case rows it cannot decide itself (raises on a continuum)."""
    certified_modes(m, q, np.asarray(q, dtype=float))


def _chosen_kernel(m, method, n):
    """The design's compiled kernel where ``method`` (and the batch size, for ``"auto"``) asks for
    it, else None."""
    if method == "numpy" or (method == "auto" and n < _KERNEL_MIN_ROWS):
        return None
    kernel = batch_kernel(m)
    if kernel is None and method == "kernel":
        raise InputError(
            f"method='kernel' is not available for {m.name}: "
            + ("numba is not installed" if not _have_numba() else
               "the design has a PP dyad or a Cramer denominator vanishing identically")
            + "; use method='numpy' or 'auto'")
    return kernel


def prove(m: Any, Q: np.ndarray, res: DKBatchResult, rows: np.ndarray, method: str) -> DKBatchResult:
    """The proof stage (``certify=True``) of a batch solved by :func:`solve`: certified counts per
    row on the exact input and the modes held to them (:func:`imagespace.solve.certified.certify_batch`).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.solve.planar import prove, solve
    >>> m = isp.examples.general_3rpr()
    >>> Q, rows = np.array([m.q_example_float]), np.array([True])
    >>> prove(m, Q, solve(m, Q, rows, "numpy", False), rows, "numpy").certified_roots.tolist()
    [6]
    """
    Qf = Q if np.all(rows) else np.where(np.asarray(rows, bool)[:, None], Q, np.nan)
    kernel = _chosen_kernel(m, method, Q.shape[0])
    certify_batch(m, Qf, res, kernel if kernel is not None else batch_kernel(m))
    return res


def exact(m: Any, q: Any, qf: np.ndarray, method: str, certify: bool) -> CertifiedModes:
    """The exact stage for one joint vector: the certified per-call path
    (:func:`imagespace.solve.certified.certified_modes`), its float stages' overflow refused by
    an error naming ``q``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.planar import exact
    >>> m = isp.examples.general_3rpr()
    >>> len(exact(m, m.q_example, m.q_example_float, "auto", True))
    6
    """
    return _certified_refusing_overflow(m, q, qf)


def empty(m: Any, obstruction: ReachObstruction, certify: bool) -> Any:
    """The per-call answer "no real mode" a reach bound proved.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.planar import empty, reach_obstruction
    >>> m = isp.examples.general_3rpr()
    >>> empty(m, reach_obstruction(m, [1e300, 5, 10]), True).certificate.count
    0
    """
    return CertifiedModes([], reach_certificate(obstruction), ()) if certify else AssemblyModes([])


def store(res: DKBatchResult, rows: list, results: list, certify: bool) -> DKBatchResult:
    """Write per-row answers of the exact stage (or of a reach bound) into a batch: each a
    :class:`CertifiedModes`, or the exception that masks the row with its message.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.solve.planar import solve, store, exact
    >>> m = isp.examples.general_3rpr()
    >>> Q = np.array([m.q_example_float, m.q_example_float])
    >>> res = solve(m, Q, np.array([True, False]), "numpy", False)
    >>> store(res, [1], [exact(m, Q[1], Q[1], "auto", True)], False).count.tolist()
    [6, 6]
    """
    got, modes = [], []
    near = res.near_singular
    if near is None:
        raise ValueError("store: the batch has no near_singular column")
    # the certificate columns, filled in with certify=True (the batch was solved with it)
    counts_: Optional[np.ndarray] = None
    paths: Optional[np.ndarray] = None
    consistent: Optional[np.ndarray] = None
    if certify:
        counts_, paths, consistent = res.certified_roots, res.certificate_path, res.consistent
        if counts_ is None or paths is None or consistent is None:
            raise ValueError("store(certify=True): the batch has no certificate columns")
        counts_, paths = counts_.copy(), paths.astype(object)
    for i, ms in zip(rows, results):
        i = int(i)
        if isinstance(ms, Exception):
            res.row_ok[i] = False
            res.errors[i] = str(ms)
            if counts_ is not None and paths is not None:
                counts_[i] = -1
                paths[i] = "continuum" if isinstance(ms, DegenerateDesignError) else "invalid"
            continue
        res.row_ok[i] = True
        res.errors.pop(i, None)
        near[i] = not ms.certificate.certified
        got.append(i)
        modes.append(list(ms))
        if counts_ is not None and paths is not None and consistent is not None:
            cert = ms.certificate
            counts_[i] = cert.count if cert.certified else -1
            paths[i] = ("reach" if cert.method.startswith("reach") else
                        "flint" if cert.certified and cert.exact else
                        "arb" if cert.certified else "uncertified")
            consistent[i] = bool(cert.certified)
    store_rows = [int(i) for i in rows]
    res.set_modes(store_rows, [modes[got.index(i)] if i in got else [] for i in store_rows])
    if res.solver is not None:
        res.set_solver(got, "certified")
        res.set_solver([i for i in store_rows if i not in got], "invalid")
    if counts_ is not None:
        res.certified_roots, res.certificate_path = counts_, np.asarray(paths).astype(str)
    return res


def peak_bytes(m: Any, method: str, certify: bool, n: int) -> int:
    """Peak memory per row of an ``n``-row batch (:data:`BATCH_PEAK_BYTES_PER_ROW`).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.planar import peak_bytes
    >>> peak_bytes(isp.examples.general_3rpr(), "numpy", True, 10)
    9000
    """
    kernel = method == "kernel" or (method == "auto" and n >= _KERNEL_MIN_ROWS and _have_numba())
    return (BATCH_PEAK_BYTES_PER_ROW["kernel" if kernel else "numpy"]
            + (BATCH_PEAK_BYTES_PER_ROW["certify"] if certify else 0))


def doubt(m: Any, qf: np.ndarray, modes: Any) -> str:
    """The warning of a per-call float answer whose count is not proven."""
    return (f"{m.name} at q = {qf.tolist()}: the floating-point direct kinematics could "
            f"not separate the roots of the kinematic polynomial (a singular or nearly "
            f"singular configuration); the {len(modes)} mode(s) returned may not be all. "
            "Use direct_kinematics(q, certify=True) for the proven answer.")


def with_complex(m: Any, qf: np.ndarray, modes: _Modes) -> _Modes:
    """The per-call answer with the complex solutions added (back-substituted, not polished)."""
    cls = type(modes)
    out = cls.__new__(cls)
    out.__dict__.update(getattr(modes, "__dict__", {}))
    list.__init__(out, list(modes) + complex_modes(m, qf))
    return out


#: The planar back ends, bound by :class:`~imagespace.PlanarParallel`.
BACKENDS = Backends(methods=("auto", "kernel", "numpy"), solve=solve, prove=prove, exact=exact,
                    counts=counts, empty=empty, store=store, peak_bytes=peak_bytes, doubt=doubt,
                    reach=reach_obstruction, far=far_rows, complex_modes=with_complex)

#: Rows per kernel call in :func:`_solve_kernel`: each chunk's padded arrays (~0.4 kB a row) are
#: compacted into the ragged result before the next chunk is solved, which bounds the peak memory
#: of a large batch (a memory knob, not a decision).
KERNEL_CHUNK_ROWS = 65536


def _kernel_chunk(m, Q, row_ok, kernel):
    """One chunk of :func:`_solve_kernel`: the kernel on the rows ``row_ok`` of ``Q``, compacted."""
    n = Q.shape[0]
    ok = np.flatnonzero(row_ok)
    if ok.size == n:                       # the usual case: the kernel's arrays are the chunk
        X, P, R, A8, cnt, flag = kernel(Q)
    else:                                  # masked rows stay NaN / 0
        X = np.full((n, MAX_MODES, 4), np.nan)
        P = np.full((n, MAX_MODES, 3), np.nan)
        R = np.full((n, MAX_MODES), np.nan)
        A8 = np.zeros((n, MAX_MODES), dtype=np.int8)
        cnt = np.zeros(n, dtype=np.int64)
        flag = np.zeros(n, dtype=np.int8)
        if ok.size:
            X[ok], P[ok], R[ok], A8[ok], cnt[ok], flag[ok] = kernel(Q[ok])
    solver = np.where(row_ok, SOLVER_NAMES.index("kernel"), SOLVER_NAMES.index("invalid")).astype(np.uint8)
    special = row_ok & (flag != 0)
    valid = np.arange(MAX_MODES) < cnt[:, None]
    # a row the kernel answers itself has a proven count (its roots isolated on the rigorous
    # enclosure of the kinematic form, one mode per root): never near-singular; the rows it
    # hands on get the numpy path's mask in _solve_kernel
    near = np.zeros(n, dtype=bool)
    return DKBatchResult.from_padded(P, valid, R, A8, row_ok, count=cnt, special=special,
                                     solver=solver, near_singular=near)


def _solve_kernel(m, Q, kernel):
    """Batch DK through the compiled kernel: masked rows stay empty, rows the kernel flags (1: a
    float decision failed; 2: its bounds cannot separate the roots) go to the numpy path
    (``special``), which masks the ones whose count it cannot prove ``near_singular``.
    The kernel runs on chunks of :data:`KERNEL_CHUNK_ROWS` rows, each compacted at once."""
    n = Q.shape[0]
    row_ok, errors = check_rows(m, Q)
    parts = [_kernel_chunk(m, Q[s:s + KERNEL_CHUNK_ROWS], row_ok[s:s + KERNEL_CHUNK_ROWS], kernel)
             for s in range(0, max(n, 1), KERNEL_CHUNK_ROWS)]
    res = parts[0] if len(parts) == 1 else DKBatchResult.concatenate(parts)
    del parts
    res.errors = errors
    # rows the kernel could not decide in floating point (flag 1: Cramer denominator small
    # at a root, Newton not converging; flag 2: a root touching the axis) take the numpy path,
    # which solves case (b) per row and computes its own near_singular mask
    careful = np.flatnonzero(res.special)
    if careful.size:
        sub = solve_batch(m, Q[careful], raise_degenerate=False, exact_check=_exact_check)
        res.replace_rows(careful, sub)      # modes, count, row_ok, near_singular, solver, errors
        res.special[careful] = True         # the kernel handed them on: special whatever sub says
    return res
