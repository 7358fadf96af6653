r"""The lockstep twin of the one-path tracker (:mod:`imagespace.spatial.tracker`): ``LANES``
paths of the parameter homotopy advanced together (issue [18], target 5).

The same tracker -- predictor, corrector, step control, polishing, every knob of
:mod:`imagespace.spatial.tracker` -- on ``LANES`` paths at once. The lanes' numbers live in one
float buffer per block, ``B[row, lane]`` (real and imaginary parts in separate rows), so the
evaluation, the LU and the solves are loops over lanes that LLVM vectorises (the lane count is read
from the buffer's shape: a loop of a constant short length would be unrolled instead, and numba
leaves the straight-line (SLP) vectoriser off). Each lane keeps its own ``s``, step size and stage,
and a lane whose path ends takes the next (row, path) job of its block. The real quadrics are read
as sparse rows (a leg's quadric has 52 non-zero entries of 64, Study's quadric 8).

Each lane takes the decisions of the one-path tracker; the floating-point operations differ in
order (sparse products, the LU's row swaps, reassociation), so endpoints agree to rounding, not bit
for bit. ``tests/spatial/test_lanes.py`` holds the two equal: same path status, same endpoints, same
real-mode counts on general and near-singular designs. Nothing here is a proof: the endpoints go to
the same classification and certificate as the one-path tracker's.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from ..core._numba import njit, prange
from .tracker import (CORRECT_TOL, DIM, DIVERGED, FINAL_NEWTON, FINAL_TOL, FIRST_CORRECTION, MAX_STEPS,
                      NEWTON_STEPS, PATH_FAILED, PATH_OK, STEP_CUT, STEP_FIRST, STEP_GROW, STEP_KEEP,
                      STEP_MAX, STEP_MIN, STEP_SHRINK)

__all__: list[str] = []     # internal: the default kernel of imagespace.spatial.homotopy.track_parameters

#: paths advanced together (a multiple of the SIMD width: 4 doubles with AVX2, 8 with AVX-512)
LANES = 32
#: the lane buffer holds the target parameters of up to this many parameters (the Gough-Stewart
#: platform has 6, the 3-RPS 3)
MAX_PARAMETERS = 8
#: jobs are cut into at most this many blocks per thread (numba's prange hands each thread a
#: contiguous share of the blocks; several per thread even out paths of different lengths) ...
BLOCKS_PER_THREAD = 4
#: ... and into blocks of at least this many jobs per lane (a lane idles only in its block's last
#: jobs: short blocks would leave most lanes idle most of the time)
JOBS_PER_LANE = 4
#: fastmath for the lanes: reassociation and contraction, but NaN and infinity stay defined (a
#: singular lane must not poison its neighbours' comparisons)
_LANE_MATH = {"reassoc", "contract", "arcp", "nsz"}
# lane stages
_IDLE = 0
_INIT = 1                # evaluate at the start point: the first tangent
_CORRECT = 2             # Newton iterations of a step
_FINAL = 3               # polishing at s = 0
# rows of the lane buffer
_WR, _WI = 0, 8          # the point evaluated (predictor, corrector iterates)
_ZR, _ZI = 16, 24        # the last accepted point
_ZPR, _ZPI = 32, 40      # the one before
_DZR, _DZI = 48, 56      # tangents at them
_DZPR, _DZPI = 64, 72
_HR, _HI = 80, 88        # H at w
_HSR, _HSI = 96, 104     # dH/ds at w
_XR, _XI = 112, 120      # J^-1 H
_YR, _YI = 128, 136      # J^-1 dH/ds
_EZR, _EZI = 144, 152    # E w
_AZR, _AZI = 160, 168    # A_k w
_JR, _JI = 176, 240      # J (8 x 8, row i at 8 i), then its LU factors
_DR, _DI = 304, 312      # 1 / pivots
_PIV = 320               # pivot rows (as floats)
_ACC = 328               # 6 rows of per-lane sums
_BIG = 334
_OK = 335                # 1.0: the LU has no zero pivot
_T = 336                 # s at which w is evaluated
_P0R, _P0I = 337, 345    # the lanes' target parameters (up to 8)
_ROWS = 353


def _sparse_rows(A):
    """The non-zero entries of the real quadrics, row by row: ``(ptr, col, val)`` with the
    entries of row ``i`` of quadric ``k`` at ``ptr[k, i] .. ptr[k, i + 1] - 1`` (a leg's quadric
    has 52 of 64, Study's 8)."""
    m = A.shape[0]
    nz = A != 0.0
    flat = np.concatenate([[0], np.cumsum(nz.sum(axis=2).ravel())])
    ptr = np.ascontiguousarray(np.stack([flat[k * DIM:(k + 1) * DIM + 1] for k in range(m)]), dtype=np.int64)
    return ptr, np.ascontiguousarray(np.nonzero(nz)[2], dtype=np.int64), np.ascontiguousarray(A[nz], dtype=float)


@njit(cache=True, fastmath=_LANE_MATH)
def _lanes_evaluate(B, Ed, pidx, ptr, col, val, p1r, p1i, cr, ci):
    """The one-path tracker's evaluation (mode 0) on every lane: ``H``, ``dH/ds`` and ``J`` at ``(w, t)`` with the
    lanes' own target parameters ``p0``."""
    m = pidx.shape[0]
    L = B.shape[1]
    a0 = _ACC
    for l in range(L):
        B[a0, l] = 0.0
        B[a0 + 1, l] = 0.0
        B[a0 + 2, l] = 0.0
        B[a0 + 3, l] = 0.0
    for i in range(DIM):
        e = Ed[i]
        a = cr[i]
        b = ci[i]
        for l in range(L):
            xr = B[_WR + i, l]
            xi = B[_WI + i, l]
            er = e * xr
            ei = e * xi
            B[_EZR + i, l] = er
            B[_EZI + i, l] = ei
            B[a0, l] += xr * er - xi * ei
            B[a0 + 1, l] += xr * ei + xi * er
            B[a0 + 2, l] += a * xr - b * xi
            B[a0 + 3, l] += a * xi + b * xr
    for k in range(m):
        for i in range(DIM):
            for l in range(L):
                B[_AZR + i, l] = 0.0
                B[_AZI + i, l] = 0.0
            for e in range(ptr[k, i], ptr[k, i + 1]):
                j = col[e]
                a = val[e]
                for l in range(L):
                    B[_AZR + i, l] += a * B[_WR + j, l]
                    B[_AZI + i, l] += a * B[_WI + j, l]
        for l in range(L):
            B[a0 + 4, l] = 0.0
            B[a0 + 5, l] = 0.0
        for i in range(DIM):
            for l in range(L):
                xr = B[_WR + i, l]
                xi = B[_WI + i, l]
                ar = B[_AZR + i, l]
                ai = B[_AZI + i, l]
                B[a0 + 4, l] += xr * ar - xi * ai
                B[a0 + 5, l] += xr * ai + xi * ar
        q = pidx[k]
        if q >= 0:
            ar = p1r[q]
            ai = p1i[q]
            for l in range(L):
                tl = B[_T, l]
                dpr = ar - B[_P0R + q, l]
                dpi = ai - B[_P0I + q, l]
                pkr = B[_P0R + q, l] + tl * dpr
                pki = B[_P0I + q, l] + tl * dpi
                zr = B[a0, l]
                zi = B[a0 + 1, l]
                B[_HR + k, l] = B[a0 + 4, l] - (pkr * zr - pki * zi)
                B[_HI + k, l] = B[a0 + 5, l] - (pkr * zi + pki * zr)
                B[_HSR + k, l] = -(dpr * zr - dpi * zi)
                B[_HSI + k, l] = -(dpr * zi + dpi * zr)
                B[a0 + 4, l] = pkr           # from here on: p_k(t) of the lane
                B[a0 + 5, l] = pki
            for i in range(DIM):
                for l in range(L):
                    pkr = B[a0 + 4, l]
                    pki = B[a0 + 5, l]
                    B[_JR + k * DIM + i, l] = 2.0 * (B[_AZR + i, l] - (pkr * B[_EZR + i, l] - pki * B[_EZI + i, l]))
                    B[_JI + k * DIM + i, l] = 2.0 * (B[_AZI + i, l] - (pkr * B[_EZI + i, l] + pki * B[_EZR + i, l]))
        else:
            for l in range(L):
                B[_HR + k, l] = B[a0 + 4, l]
                B[_HI + k, l] = B[a0 + 5, l]
                B[_HSR + k, l] = 0.0
                B[_HSI + k, l] = 0.0
            for i in range(DIM):
                for l in range(L):
                    B[_JR + k * DIM + i, l] = 2.0 * B[_AZR + i, l]
                    B[_JI + k * DIM + i, l] = 2.0 * B[_AZI + i, l]
    for l in range(L):
        B[_HR + m, l] = B[a0 + 2, l] - 1.0
        B[_HI + m, l] = B[a0 + 3, l]
        B[_HSR + m, l] = 0.0
        B[_HSI + m, l] = 0.0
    for i in range(DIM):
        a = cr[i]
        b = ci[i]
        for l in range(L):
            B[_JR + m * DIM + i, l] = a
            B[_JI + m * DIM + i, l] = b


@njit(cache=True, fastmath=_LANE_MATH)
def _lanes_lu(B):
    """The one-path tracker's LU on every lane (partial pivoting on ``|re| + |im|``). A row swap moves the
    columns from the pivot's on (the multipliers stay where they were computed, and
    :func:`_lanes_solve` replays the swaps in order); the pivots' inverses go to rows ``_DR``,
    ``_DI``; row ``_OK`` is 0 on a zero pivot."""
    L = B.shape[1]
    for l in range(L):
        B[_OK, l] = 1.0
    for k in range(DIM):
        rkk = _JR + k * DIM + k
        ikk = _JI + k * DIM + k
        for l in range(L):
            B[_BIG, l] = abs(B[rkk, l]) + abs(B[ikk, l])
            B[_PIV + k, l] = k
        for i in range(k + 1, DIM):
            ri = _JR + i * DIM + k
            ii = _JI + i * DIM + k
            fi = float(i)
            for l in range(L):
                a = abs(B[ri, l]) + abs(B[ii, l])
                better = a > B[_BIG, l]
                B[_BIG, l] = a if better else B[_BIG, l]
                B[_PIV + k, l] = fi if better else B[_PIV + k, l]
        for i in range(k + 1, DIM):        # the swap as selects over lanes (vectorised)
            fi = float(i)
            for j in range(k, DIM):
                for part in range(2):
                    a = _JR + part * (_JI - _JR) + k * DIM + j
                    b = _JR + part * (_JI - _JR) + i * DIM + j
                    for l in range(L):
                        swap = B[_PIV + k, l] == fi
                        u = B[a, l]
                        v = B[b, l]
                        B[a, l] = v if swap else u
                        B[b, l] = u if swap else v
        for l in range(L):
            a = B[rkk, l]
            b = B[ikk, l]
            n2 = a * a + b * b
            good = n2 > 0.0
            inv = 1.0 / n2 if good else 0.0
            B[_DR + k, l] = a * inv
            B[_DI + k, l] = -b * inv
            B[_OK, l] = B[_OK, l] if good else 0.0
        for i in range(k + 1, DIM):
            ri = _JR + i * DIM + k
            ii = _JI + i * DIM + k
            for l in range(L):
                a = B[ri, l]
                b = B[ii, l]
                B[ri, l] = a * B[_DR + k, l] - b * B[_DI + k, l]
                B[ii, l] = a * B[_DI + k, l] + b * B[_DR + k, l]
            for j in range(k + 1, DIM):
                rt = _JR + i * DIM + j
                it = _JI + i * DIM + j
                ru = _JR + k * DIM + j
                iu = _JI + k * DIM + j
                for l in range(L):
                    fr = B[ri, l]
                    fi = B[ii, l]
                    ur = B[ru, l]
                    ui = B[iu, l]
                    B[rt, l] -= fr * ur - fi * ui
                    B[it, l] -= fr * ui + fi * ur


@njit(cache=True, fastmath=_LANE_MATH)
def _lanes_solve(B, br, bi, xr, xi):
    """``x = J^-1 b`` on every lane from the factors of :func:`_lanes_lu` (``br, bi, xr, xi``:
    first rows of ``b`` and ``x`` in the buffer)."""
    L = B.shape[1]
    for i in range(DIM):
        for l in range(L):
            B[xr + i, l] = B[br + i, l]
            B[xi + i, l] = B[bi + i, l]
    for k in range(DIM):
        for i in range(k + 1, DIM):        # the swap as selects over lanes (vectorised)
            fi = float(i)
            for part in range(2):
                a = (xr if part == 0 else xi) + k
                b = (xr if part == 0 else xi) + i
                for l in range(L):
                    swap = B[_PIV + k, l] == fi
                    u = B[a, l]
                    v = B[b, l]
                    B[a, l] = v if swap else u
                    B[b, l] = u if swap else v
        for i in range(k + 1, DIM):
            rf = _JR + i * DIM + k
            jf = _JI + i * DIM + k
            for l in range(L):
                fr = B[rf, l]
                fi = B[jf, l]
                a = B[xr + k, l]
                b = B[xi + k, l]
                B[xr + i, l] -= fr * a - fi * b
                B[xi + i, l] -= fr * b + fi * a
    for i in range(DIM - 1, -1, -1):
        for j in range(i + 1, DIM):
            ru = _JR + i * DIM + j
            iu = _JI + i * DIM + j
            for l in range(L):
                ur = B[ru, l]
                ui = B[iu, l]
                a = B[xr + j, l]
                b = B[xi + j, l]
                B[xr + i, l] -= ur * a - ui * b
                B[xi + i, l] -= ur * b + ui * a
        for l in range(L):
            a = B[xr + i, l]
            b = B[xi + i, l]
            B[xr + i, l] = a * B[_DR + i, l] - b * B[_DI + i, l]
            B[xi + i, l] = a * B[_DI + i, l] + b * B[_DR + i, l]


@njit(cache=True)
def _lane_norm(B, re, l):
    """The 2-norm of the complex 8-vector of lane ``l`` with real rows ``re``, imaginary rows
    ``re + 8``."""
    acc = 0.0
    for i in range(2 * DIM):
        a = B[re + i, l]
        acc += a * a
    return np.sqrt(acc)


@njit(cache=True)
def _lane_copy(B, src, dst, l, sign):
    for i in range(2 * DIM):
        B[dst + i, l] = sign * B[src + i, l]


@njit(cache=True)
def _lane_load(B, l, jb, k, starts, P0):
    r = jb // k
    j = jb - r * k
    for i in range(DIM):
        v = starts[j, i]
        B[_WR + i, l] = v.real
        B[_WI + i, l] = v.imag
        B[_ZR + i, l] = v.real
        B[_ZI + i, l] = v.imag
    for q in range(P0.shape[1]):
        B[_P0R + q, l] = P0[r, q].real
        B[_P0I + q, l] = P0[r, q].imag
    B[_T, l] = 1.0


@njit(cache=True)
def _lane_begin_step(B, l, s, sp, h, have_prev, nsteps):
    """Start a step of lane ``l`` from its accepted point: the predictor (cubic Hermite through
    the last two accepted points, Euler for the first step) into ``w``; False when the step
    budget is spent."""
    nsteps[l] += 1
    if nsteps[l] > MAX_STEPS:
        return False
    if h[l] > s[l]:
        h[l] = s[l]
    tt = s[l] - h[l]
    B[_T, l] = tt
    if have_prev[l]:
        d = s[l] - sp[l]
        tau = (tt - sp[l]) / d
        t2 = tau * tau
        t3 = t2 * tau
        h00 = 2.0 * t3 - 3.0 * t2 + 1.0
        h10 = (t3 - 2.0 * t2 + tau) * d
        h01 = -2.0 * t3 + 3.0 * t2
        h11 = (t3 - t2) * d
        for i in range(2 * DIM):         # real rows, then imaginary rows
            B[_WR + i, l] = (h00 * B[_ZPR + i, l] + h10 * B[_DZPR + i, l]
                             + h01 * B[_ZR + i, l] + h11 * B[_DZR + i, l])
    else:
        hl = h[l]
        for i in range(2 * DIM):
            B[_WR + i, l] = B[_ZR + i, l] - hl * B[_DZR + i, l]
    return True


@njit(cache=True)
def _lanes_block(starts, Ed, pidx, ptr, col, val, P0, p1r, p1i, cr, ci, lo, hi, Z, status, steps):
    """Track the jobs ``lo .. hi - 1`` (job ``r * k + j``: start point ``j`` to the parameters of
    row ``r``) on ``LANES`` lanes; each lane takes the decisions of the one-path tracker
    (:mod:`imagespace.spatial.tracker`)."""
    L = LANES
    k = starts.shape[0]
    B = np.zeros((_ROWS, L))
    s = np.ones(L)
    sp = np.ones(L)
    h = np.zeros(L)
    stage = np.zeros(L, dtype=np.int64)
    job = np.full(L, -1, dtype=np.int64)
    it = np.zeros(L, dtype=np.int64)
    nsteps = np.zeros(L, dtype=np.int64)
    evals = np.zeros(L, dtype=np.int64)
    have_prev = np.zeros(L, dtype=np.bool_)
    nxt = lo
    active = 0
    for l in range(L):
        if nxt < hi:
            _lane_load(B, l, nxt, k, starts, P0)
            stage[l] = _INIT
            job[l] = nxt
            nxt += 1
            active += 1
    while active > 0:
        _lanes_evaluate(B, Ed, pidx, ptr, col, val, p1r, p1i, cr, ci)
        _lanes_lu(B)
        _lanes_solve(B, _HR, _HI, _XR, _XI)
        _lanes_solve(B, _HSR, _HSI, _YR, _YI)
        for l in range(L):
            st = stage[l]
            if st == _IDLE:
                continue
            ok = B[_OK, l] == 1.0
            done = False
            result = PATH_FAILED
            count = 0
            if st == _INIT:
                if not ok:
                    done = True
                else:
                    _lane_copy(B, _YR, _DZR, l, -1.0)
                    s[l] = 1.0
                    sp[l] = 1.0
                    have_prev[l] = False
                    h[l] = STEP_FIRST
                    nsteps[l] = 0
                    evals[l] = 1
                    stage[l] = _CORRECT
                    it[l] = 0
                    if not _lane_begin_step(B, l, s, sp, h, have_prev, nsteps):
                        done = True
                        count = nsteps[l]
            elif st == _CORRECT:
                evals[l] += 1
                step_failed = False
                converged = False
                if not ok:
                    step_failed = True
                else:
                    for i in range(2 * DIM):
                        B[_WR + i, l] -= B[_XR + i, l]
                    nd = _lane_norm(B, _XR, l)
                    nw = _lane_norm(B, _WR, l)
                    if it[l] == 0 and nd > FIRST_CORRECTION * (1.0 + nw):
                        step_failed = True
                    elif nd <= CORRECT_TOL * (1.0 + nw):
                        converged = True
                    else:
                        it[l] += 1
                        if it[l] >= NEWTON_STEPS:
                            step_failed = True
                if converged:
                    if _lane_norm(B, _WR, l) > DIVERGED:
                        done = True
                        count = nsteps[l]
                    else:
                        _lane_copy(B, _ZR, _ZPR, l, 1.0)
                        _lane_copy(B, _DZR, _DZPR, l, 1.0)
                        _lane_copy(B, _WR, _ZR, l, 1.0)
                        _lane_copy(B, _YR, _DZR, l, -1.0)
                        sp[l] = s[l]
                        s[l] = B[_T, l]
                        have_prev[l] = True
                        used = it[l] + 1
                        if used == 1:
                            h[l] = min(h[l] * STEP_GROW, STEP_MAX)
                        elif used == 2:
                            h[l] = min(h[l] * STEP_KEEP, STEP_MAX)
                        else:
                            h[l] *= STEP_SHRINK
                        it[l] = 0
                        if s[l] > 0.0:
                            if not _lane_begin_step(B, l, s, sp, h, have_prev, nsteps):
                                done = True
                                count = nsteps[l]
                        else:
                            stage[l] = _FINAL
                            B[_T, l] = 0.0
                elif step_failed:
                    h[l] *= STEP_CUT
                    it[l] = 0
                    if h[l] < STEP_MIN:
                        done = True
                        count = nsteps[l]
                    elif not _lane_begin_step(B, l, s, sp, h, have_prev, nsteps):
                        done = True
                        count = nsteps[l]
            else:   # _FINAL: w is the accepted point
                if not ok:
                    done = True
                else:
                    for i in range(2 * DIM):
                        B[_WR + i, l] -= B[_XR + i, l]
                    it[l] += 1
                    if _lane_norm(B, _XR, l) <= FINAL_TOL * (1.0 + _lane_norm(B, _WR, l)) or it[l] >= FINAL_NEWTON:
                        done = True
                if done:
                    _lane_copy(B, _WR, _ZR, l, 1.0)
                result = PATH_OK
                count = evals[l]
            if done:
                jb = job[l]
                r = jb // k
                j = jb - r * k
                for i in range(DIM):
                    Z[r, j, i] = complex(B[_ZR + i, l], B[_ZI + i, l])
                status[r, j] = result
                steps[r, j] = count
                if nxt < hi:
                    _lane_load(B, l, nxt, k, starts, P0)
                    stage[l] = _INIT
                    job[l] = nxt
                    nxt += 1
                else:
                    stage[l] = _IDLE
                    job[l] = -1
                    active -= 1


@njit(cache=True, parallel=True)
def _track_lanes(starts, Ed, pidx, ptr, col, val, P0, p1, c, Z, status, steps, blocks):
    """Every (row, path) job in ``blocks`` contiguous blocks, each on its own lanes."""
    n = P0.shape[0]
    k = starts.shape[0]
    jobs = n * k
    p1r = np.ascontiguousarray(p1.real)
    p1i = np.ascontiguousarray(p1.imag)
    cr = np.ascontiguousarray(c.real)
    ci = np.ascontiguousarray(c.imag)
    for b in prange(blocks):
        _lanes_block(starts, Ed, pidx, ptr, col, val, P0, p1r, p1i, cr, ci, b * jobs // blocks,
                     (b + 1) * jobs // blocks, Z, status, steps)


def _threads() -> int:
    """numba's thread count (1 without numba: the kernels then run as Python)."""
    try:
        from numba import get_num_threads
    except ImportError:  # pragma: no cover - without numba the kernels run as Python
        return 1
    return int(get_num_threads())


def track_lanes(starts: npt.ArrayLike, A: npt.ArrayLike, E: npt.ArrayLike, pidx: npt.ArrayLike,
                P0: npt.ArrayLike, p1: npt.ArrayLike, c: npt.ArrayLike, Z: npt.NDArray[np.complex128],
                status: npt.NDArray[np.integer], steps: npt.NDArray[np.integer]) -> None:
    """Track every (row, path) pair of the parameter homotopy on ``LANES`` lanes at a time.

    The lockstep twin of :func:`imagespace.spatial.tracker.track_many` in mode 0: row ``r``
    takes the start points to the parameters ``P0[r]`` along ``p(s) = (1 - s) P0[r] + s p1``,
    each path with the one-path tracker's decisions.

    Parameters
    ----------
    starts : (k, 8) complex
        Start points on the patch (the solutions at ``p1``).
    A : (m, 8, 8) float
        The parameter-free parts of the quadrics (``m = 7``: with the patch a square system).
    E : (8, 8) float
        Diagonal; only its diagonal is read.
    pidx : (m,) int
        The parameter of quadric ``k`` (``-1``: none), below ``MAX_PARAMETERS``.
    P0 : (n, p) complex
        Target parameters, ``p <= MAX_PARAMETERS``.
    p1 : (p,) complex
        The start parameters.
    c : (8,) complex
        The patch ``c . z = 1``.
    Z : (n, k, 8) complex
        Receives the endpoints.
    status : (n, k) int
        Receives :data:`~imagespace.spatial.tracker.PATH_OK` or ``PATH_FAILED``.
    steps : (n, k) int
        Receives the Jacobian evaluations of an arrived path, the steps of a failed one.

    Raises
    ------
    InputError
        More than ``MAX_PARAMETERS`` parameters, or not a square system (``m + 1 != 8``).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.homotopy import solve_start_system
    >>> from imagespace.spatial.quadrics import sphere_quadric, study_quadric_matrix
    >>> rng = np.random.default_rng(1)
    >>> A = np.concatenate([sphere_quadric(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)), 0.0),
    ...                     study_quadric_matrix()[None]])
    >>> st = solve_start_system(A, np.diag([1.0, 1, 1, 1, 0, 0, 0, 0]), np.r_[np.arange(6), -1], 6,
    ...                         expected=40)
    >>> Z = np.zeros((1, 40, 8), complex)
    >>> status, steps = np.zeros((1, 40), np.int64), np.zeros((1, 40), np.int64)
    >>> track_lanes(st.solutions, st.A, st.E, st.pidx, np.full((1, 6), 4.0 + 0j), st.p_star,
    ...             st.patch, Z, status, steps)
    >>> bool(np.all(status == PATH_OK))
    True
    """
    A = np.ascontiguousarray(A, dtype=float)
    P0 = np.ascontiguousarray(np.atleast_2d(P0), dtype=complex)
    pidx = np.ascontiguousarray(pidx, dtype=np.int64)
    starts = np.ascontiguousarray(starts, dtype=complex)
    if A.ndim != 3 or A.shape[0] + 1 != DIM or A.shape[1:] != (DIM, DIM):
        from ..exceptions import InputError
        raise InputError(f"A must hold {DIM - 1} quadrics of shape ({DIM}, {DIM}) (a square system with "
                         f"the patch), got shape {A.shape}")
    if P0.shape[1] > MAX_PARAMETERS or pidx.max(initial=-1) >= P0.shape[1]:
        from ..exceptions import InputError
        raise InputError(f"P0 must have at most {MAX_PARAMETERS} parameters, one for every index in "
                         f"pidx, got {P0.shape[1]} parameters and pidx {pidx.tolist()}")
    n, k = P0.shape[0], starts.shape[0]
    jobs = n * k
    if not jobs:
        return
    ptr, col, val = _sparse_rows(A)
    blocks = int(min(BLOCKS_PER_THREAD * _threads(), max(1, jobs // (JOBS_PER_LANE * LANES))))
    _track_lanes(starts, np.ascontiguousarray(np.diag(np.asarray(E, dtype=float))), pidx, ptr, col, val,
                 P0, np.ascontiguousarray(p1, dtype=complex), np.ascontiguousarray(c, dtype=complex),
                 Z, status, steps, blocks)
