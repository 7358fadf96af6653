"""Direct kinematics entry points, bound as methods of :class:`~imagespace.PlanarParallel`: one
call (:func:`direct_kinematics`), a batch (:func:`direct_kinematics_batch`: compiled kernel or
numpy path, optionally certified) and chunks of a large batch."""

from __future__ import annotations

import warnings
from typing import Any, Iterator, Optional

import numpy as np
import numpy.typing as npt

from .._memory import check_memory
from .._validate import as_count, as_flag, as_float_array, warn_angle_units
from ..core.certify import RealRootCertificate
from ..core.reach import ReachObstruction, planar_design_scale, planar_reach_obstruction, prismatic_magnitude
from ..exceptions import DegenerateDesignError, InputError, NearSingularWarning
from .certified import certified_modes, certify_batch, exact_certificate, exact_root_count
from .numpy_path import complex_modes, check_rows, solve_batch
from .continuum import continuum_at
from .proof import batch_kernel, have_numba as _have_numba
from .results import AssemblyMode, AssemblyModes, CertifiedModes, DKBatchResult, MAX_MODES, SOLVER_NAMES


_KERNEL_MIN_ROWS = 2000


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
    >>> from imagespace.solve.dispatch import reach_obstruction
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
    >>> from imagespace.solve.dispatch import far_rows
    >>> m = isp.examples.general_3rpr()
    >>> far_rows(m, np.array([m.q_example_float, [1e300, 5, 10], [np.nan, 1, 1]])).tolist()
    [False, True, False]
    """
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    if not m.is_numeric or Q.shape[0] == 0:
        return np.zeros(Q.shape[0], dtype=bool)
    scale = m.cached("design_scale", lambda: planar_design_scale(m.legs))
    mag = prismatic_magnitude(m.legs, Q)
    return np.all(np.isfinite(Q), axis=1) & (mag > m.tolerances.far_reach_ratio * scale)


def reach_certificate(obstruction: ReachObstruction) -> RealRootCertificate:
    """The certificate of a row a reach bound proves empty: count 0, certified, exact.

    Its count is the number of real assembly modes (0); the kinematic polynomial itself is not
    examined (a root of it without a real pose, e.g. one whose positions are complex, is not
    counted).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.dispatch import reach_certificate, reach_obstruction
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


def direct_kinematics(m: Any, q: Any, include_complex: bool = False, certify: bool = False) -> list[AssemblyMode]:
    """All real assembly modes for the joint values ``q``.

    Parameters
    ----------
    q : (3,) float or exact numbers
    include_complex : bool
        Also return the complex solutions (back-substituted, not polished; ``is_real`` False).
    certify : bool
        Prove the answer at the exact joint values (floats taken as the binary rationals
        they are, sympy values as given): the real roots of the exact kinematic polynomial
        are isolated and refined (:func:`imagespace.core.certify.certify_real_roots`) and every
        mode is computed from its root (:mod:`imagespace.solve.certified`): one mode per
        simple root, a multiple root once as a singular mode with ``.multiplicity``, two
        modes even where they are closer than double precision can show. See
        :class:`CertifiedModes` for the semantics and their exceptions.

    Returns
    -------
    list of AssemblyMode, or CertifiedModes (a list with ``.certificate``) if ``certify``
        Sorted by ``phi``; empty when no real mode exists.

    Raises
    ------
    DegenerateDesignError
        When the design at these joint values has infinitely many modes (a continuum).
    InputError
        Joint values beyond the float range (their squares overflow) that no reach bound
        proves empty.

    Warns
    -----
    NearSingularWarning
        Without ``certify``: the floating-point count may be wrong. The count is checked
        against the proven real roots of the exact kinematic polynomial
        (:func:`imagespace.solve.proof.proven_roots`): the warning comes whenever the proof
        cannot decide them (a double or nearly double root) or the modes do not sit one per
        proven root, so a count returned without it is proven.

    Notes
    -----
    Every call first tries a reach bound (:mod:`imagespace.core.reach`): when two legs provably
    cannot meet (a leg ``1e300`` long next to one of length 5) the answer is no mode, exactly,
    at once (with ``certify`` a :class:`CertifiedModes` whose certificate names the bound).
    Joint values beyond ``tolerances.far_reach_ratio`` times the design's size are answered by
    the certified path also without ``certify``: the float path does not resolve them.

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.examples.stigger_husty()
    >>> len(m.direct_kinematics(m.q_example))
    6
    >>> cm = m.direct_kinematics(m.q_example, certify=True)
    >>> cm.certificate.count, sum(cm.modes_per_root)
    (6, 6)
    """
    include_complex = as_flag(include_complex, "include_complex")
    certify = as_flag(certify, "certify")
    qf = m.check_q(q)          # exact sympy numbers pass, free symbols are refused by name
    if qf.ndim != 1:
        raise InputError(f"q must have shape (3,), got {qf.shape}; use direct_kinematics_batch")
    obstruction = reach_obstruction(m, q if certify else qf)
    if obstruction is not None:
        modes = CertifiedModes([], reach_certificate(obstruction), ()) if certify else []
    elif certify or far_rows(m, qf)[0]:
        modes = _certified_refusing_overflow(m, q, qf)
    else:
        res = solve_batch(m, qf[None, :], raise_degenerate=True)
        modes = res.modes(0)
        if res.near_singular[0]:
            warnings.warn(
                f"{m.name} at q = {qf.tolist()}: the floating-point direct kinematics could "
                f"not separate the roots of the kinematic polynomial (a singular or nearly "
                f"singular configuration); the {len(modes)} mode(s) returned may not be all. "
                "Use direct_kinematics(q, certify=True) for the proven answer.",
                NearSingularWarning, stacklevel=2)
    if include_complex:
        if far_rows(m, qf)[0]:
            raise InputError(f"include_complex=True needs joint values within "
                             f"{m.tolerances.far_reach_ratio:g} times the size of {m.name} (the "
                             f"complex modes are computed in floating point), got q = {qf.tolist()}")
        modes += complex_modes(m, qf)
    return modes if certify else AssemblyModes(modes)


def direct_kinematics_batch(m: Any, Q: npt.ArrayLike, certify: bool = False, method: str = "auto") -> DKBatchResult:
    """Direct kinematics of many joint vectors at once.

    Parameters
    ----------
    Q : (n, 3) float
        One joint vector per row. Rows with NaN or out-of-domain values are masked
        (``row_ok`` False), not raised.
    certify : bool
        Also prove the number of real roots per row (:func:`~imagespace.core.certify.certify_real_roots_batch`
        on the compiled kinematic polynomial, floats taken as exact binary rationals) and
        hold the modes to it; rows that disagree are re-solved per row with the certified
        path. Fills ``certified_roots``, ``certificate_path`` and ``consistent``.
    method : {"auto", "kernel", "numpy"}
        ``"kernel"``: the compiled one-pass kernel of :mod:`imagespace.solve.kernel` (numba; real
        roots only, no eigenvalues; the roots isolated on a rigorous enclosure of the
        kinematic form, so a count it returns itself is proven); rows it cannot decide are
        handed to the numpy path (``special``). ``"numpy"``: the vectorised numpy path (companion eigenvalues,
        Newton, every mode checked by the legs' inverse kinematics). ``"auto"``: the kernel
        for batches of at least 2,000 rows when numba is installed and the design suits it
        (no PP dyad, Cramer denominator not identically zero), else numpy. The kernel is one
        generic compiled loop for every design: compiled once per installation and cached on
        disk; a new design costs only its small tables (:func:`imagespace.solve.kernel.design_tables`).

    Returns
    -------
    DKBatchResult
        ``solver`` says per row which path answered.

    Raises
    ------
    InputError
        ``Q`` is not of shape ``(3,)`` or ``(n, 3)``; ``method`` is not ``'auto'``, ``'kernel'``
        or ``'numpy'``; ``method='kernel'`` is not available for this design (no numba, a PP
        dyad, or a Cramer denominator vanishing identically).
    TypeError
        ``Q`` or ``certify`` has the wrong type.

    Examples
    --------
    >>> import imagespace as isp
    >>> import numpy as np
    >>> m = isp.examples.stigger_husty()
    >>> r = m.direct_kinematics_batch(np.array([m.q_example_float, [np.nan, 1, 1]]))
    >>> r.count.tolist(), r.row_ok.tolist(), r.solver.tolist()
    ([6, 0], [True, False], ['numpy', 'invalid'])
    """
    Q = as_float_array(Q, "Q", last=3, finite=False)
    certify = as_flag(certify, "certify")
    if Q.ndim == 1:
        Q = Q[None, :]
    warn_angle_units(Q, [leg.actuated_is_angle for leg in m.legs], "Q")
    if not isinstance(method, str) or method not in ("auto", "kernel", "numpy"):
        raise InputError(f"method must be 'auto', 'kernel' or 'numpy', got {method!r}")
    kernel = None
    if method == "kernel" or (method == "auto" and Q.shape[0] >= _KERNEL_MIN_ROWS):
        kernel = batch_kernel(m)
        if kernel is None and method == "kernel":
            raise InputError(
                f"method='kernel' is not available for {m.name}: "
                + ("numba is not installed" if not _have_numba() else
                   "the design has a PP dyad or a Cramer denominator vanishing identically")
                + "; use method='numpy' or 'auto'")
    per_row = (BATCH_PEAK_BYTES_PER_ROW["kernel" if kernel is not None else "numpy"]
               + (BATCH_PEAK_BYTES_PER_ROW["certify"] if certify else 0))
    check_memory(Q.shape[0] * per_row, f"direct_kinematics_batch of {Q.shape[0]:,} rows",
                 f"use direct_kinematics_chunks(Q, chunk_size=...) to solve it chunk by chunk "
                 f"(a chunk of 65,536 rows needs about {65536 * per_row / 1e9:.2g} GB)")
    far = far_rows(m, Q)
    Qf = Q
    if far.any():                          # the float solvers skip them (masked as non-finite)
        Qf = Q.copy()
        Qf[far] = np.nan
    res = _solve_kernel(m, Qf, kernel) if kernel is not None else solve_batch(m, Qf, raise_degenerate=False)
    if certify:
        certify_batch(m, Qf, res, kernel if kernel is not None else batch_kernel(m))
    if far.any():
        _solve_far_rows(m, Q, res, np.flatnonzero(far), certify)
    return res


def _solve_far_rows(m, Q, res, rows, certify):
    """Rows beyond the float paths' reach (:func:`far_rows`), answered one by one: no mode where
    a reach bound proves it, else the certified per-row path; a row beyond the float range that
    no bound decides is masked (``row_ok`` False, its message in ``errors``)."""
    got, modes = [], []
    counts = res.certified_roots.copy() if certify else None
    paths = res.certificate_path.astype(object) if certify else None
    for i in rows:
        i = int(i)
        try:
            ms = m.direct_kinematics(Q[i], certify=True)
        except (InputError, DegenerateDesignError) as exc:
            res.row_ok[i] = False
            res.errors[i] = str(exc)
            if certify:
                counts[i] = -1
                paths[i] = "continuum" if isinstance(exc, DegenerateDesignError) else "invalid"
            continue
        res.row_ok[i] = True
        res.errors.pop(i, None)
        res.near_singular[i] = not ms.certificate.certified
        got.append(i)
        modes.append(list(ms))
        if certify:
            cert = ms.certificate
            counts[i] = cert.count if cert.certified else -1
            paths[i] = ("reach" if cert.method.startswith("reach") else
                        "flint" if cert.certified and cert.exact else
                        "arb" if cert.certified else "uncertified")
            res.consistent[i] = bool(cert.certified)
    store_rows = [int(i) for i in rows]
    res.set_modes(store_rows, [modes[got.index(i)] if i in got else [] for i in store_rows])
    if res.solver is not None:
        res.set_solver(got, "certified")
        res.set_solver([i for i in store_rows if i not in got], "invalid")
    if certify:
        res.certified_roots, res.certificate_path = counts, np.asarray(paths).astype(str)


def certified_root_counts(m: Any, Q: npt.ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Proven numbers of real assembly modes (distinct real roots of the kinematic polynomial) for
    a batch of joint vectors, without computing the modes.

    Each row is decided at its exact input (floats taken as the binary rationals they are). With
    the compiled kernel the count is proven inside it: quadric coefficients, elimination and
    Bernstein root isolation run with a rigorous error bound on every value, so a count the
    kernel returns is a theorem, not an estimate (:meth:`BatchKernel.certified_counts`). Rows
    the bounds cannot decide (a double or nearly double root) are decided exactly per row
    (python-flint; arb for irrational coefficients). Designs the kernel does not take use the
    enclosed general-q polynomial and inclusion discs, with the same exact fallback.

    A root carries one mode except where the Cramer denominator vanishes at it (case (b):
    0, 1 or 2 modes); ``direct_kinematics_batch(Q, certify=True)`` reports both.

    A continuum of modes is reported as such (count -1, path ``"continuum"``): the kinematic
    polynomial vanishing identically, or the positions forming a curve at one orientation,
    decided exactly by :func:`imagespace.solve.continuum.continuum_at` on the rows with a
    multiple root (only those can hold one; in Cramer case (a) every row with a real root is
    tested).

    Parameters
    ----------
    Q : (n, 3) float
        Rows with NaN or out-of-domain values get -1 (not raised).

    Returns
    -------
    counts : (n,) int8
        -1 for invalid rows, continua (the polynomial vanishing identically, or a curve of
        positions at one orientation) and the rare rows nothing could certify (see ``path``).
    path : (n,) str
        ``"kernel"`` (proven in the kernel), ``"discs"``, ``"flint"``, ``"arb"``,
        ``"reach"`` (no real mode, proven by a reach bound: a row beyond
        ``tolerances.far_reach_ratio`` times the design's size whose legs cannot meet),
        ``"uncertified"``, ``"continuum"`` or ``"invalid"``.

    Raises
    ------
    InputError
        ``Q`` is not of shape ``(3,)`` or ``(n, 3)``.
    TypeError
        ``Q`` is not a real float or integer array.

    Examples
    --------
    >>> import imagespace as isp
    >>> import numpy as np
    >>> m = isp.examples.stigger_husty()
    >>> counts, path = m.certified_root_counts(np.array([m.q_example_float, [np.nan, 1, 1]]))
    >>> counts.tolist(), path.tolist()[1]
    ([6, -1], 'invalid')

    A platform congruent to its base, all legs of one length: it can translate on a circle.

    >>> m = isp.PlanarParallel([isp.RPR((0, 0), (0, 0)), isp.RPR((4, 0), (4, 0)), isp.RPR((1, 3), (1, 3))])
    >>> m.certified_root_counts(np.array([[2.0, 2.0, 2.0]]))[1].tolist()
    ['continuum']
    """
    from ..core.certify import certify_real_roots_batch

    Q = as_float_array(Q, "Q", last=3, finite=False)
    if Q.ndim == 1:
        Q = Q[None, :]
    n = Q.shape[0]
    row_ok, _ = check_rows(m, Q)
    counts = np.full(n, -1, dtype=np.int8)
    path = np.full(n, "invalid", dtype=object)
    far = np.flatnonzero(row_ok & far_rows(m, Q))
    for i in far:                           # beyond the float paths: a reach bound, else exact
        if reach_obstruction(m, Q[i]) is not None:
            counts[i], path[i] = 0, "reach"
            continue
        try:
            counts[i], path[i] = exact_root_count(m, Q[i])
        except DegenerateDesignError:
            counts[i], path[i] = -1, "continuum"
    row_ok[far] = False
    ok = np.flatnonzero(row_ok)
    kernel = batch_kernel(m) if ok.size else None
    if kernel is not None:
        c = kernel.certified_counts(Q[ok])[0]
        counts[ok] = c
        path[ok[c >= 0]] = "kernel"
        todo = ok[c < 0]
    elif ok.size:
        F, E = m.enclosure().evaluate(Q[ok])
        c, p = certify_real_roots_batch(F, E, lambda i: exact_certificate(m, Q[ok[i]]))
        counts[ok], path[ok] = c, p
        todo = ok[p == "zero"]
    else:
        todo = ok
    for i in todo:
        try:
            counts[i], path[i] = exact_root_count(m, Q[i])
        except DegenerateDesignError:
            counts[i], path[i] = -1, "continuum"
    if kernel is None and ok.size and m.exact_forms(None)[2]:
        # Cramer case (a): a simple orientation root may carry a continuum of positions
        for i in ok[counts[ok] > 0]:
            if continuum_at(m, Q[i])[0]:
                counts[i], path[i] = -1, "continuum"
    return counts, path.astype(str)


def direct_kinematics_chunks(m: Any, Q: npt.ArrayLike, chunk_size: int = 65536, certify: bool = False,
                             method: str = "auto") -> Iterator[tuple[int, DKBatchResult]]:
    """Direct kinematics of a large batch, chunk by chunk (memory bounded by the chunk).

    Parameters
    ----------
    Q : (n, 3) float array (a numpy memmap works)
    chunk_size : int
        Rows per chunk; the result of one chunk of 65,536 rows takes ~8 MB (ragged: ~0.12 kB a row
        at 3.3 modes a row, 0.21 kB with six).
    certify, method
        As in :meth:`direct_kinematics_batch`.

    Yields
    ------
    (start, DKBatchResult)
        The rows ``start : start + len(result.count)`` of ``Q``.

    Raises
    ------
    InputError
        ``Q`` is not of shape ``(n, 3)``, ``chunk_size`` is not a positive count, or ``method``
        is not one of ``'auto'``, ``'kernel'``, ``'numpy'``.
    TypeError
        ``Q`` is not a real float or integer array, or ``certify`` is not a bool.

    Examples
    --------
    >>> import imagespace as isp
    >>> import numpy as np
    >>> m = isp.examples.general_3rpr()
    >>> Q = np.tile(m.q_example_float, (5, 1))
    >>> [(s, r.count.tolist()) for s, r in m.direct_kinematics_chunks(Q, chunk_size=2)]
    [(0, [6, 6]), (2, [6, 6]), (4, [6])]
    """
    chunk_size = as_count(chunk_size, "chunk_size")
    certify = as_flag(certify, "certify")
    if not isinstance(method, str) or method not in ("auto", "kernel", "numpy"):
        raise InputError(f"method must be 'auto', 'kernel' or 'numpy', got {method!r}")
    if not isinstance(Q, np.ndarray):               # a memmap is validated chunk by chunk
        Q = as_float_array(Q, "Q", last=3, finite=False)
    elif Q.dtype.kind not in "iuf":
        raise TypeError(f"Q must be a real float or integer array, got dtype {Q.dtype}")
    if Q.ndim != 2 or Q.shape[-1] != 3:
        raise InputError(f"Q must have shape (n, 3), got {Q.shape}")
    return _chunks(m, Q, chunk_size, certify, method)    # validated now, solved lazily


def _chunks(m, Q, chunk_size, certify, method):
    """The generator behind :func:`direct_kinematics_chunks` (its arguments already checked)."""
    for start in range(0, Q.shape[0], chunk_size):
        yield start, direct_kinematics_batch(m, Q[start:start + chunk_size], certify, method)


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
        sub = solve_batch(m, Q[careful], raise_degenerate=False)
        res.replace_rows(careful, sub)      # modes, count, row_ok, near_singular, solver, errors
        res.special[careful] = True         # the kernel handed them on: special whatever sub says
    return res
