r"""The compiled batch direct-kinematics kernel: ONE generic kernel for every design, one pass per
joint vector, real roots only.

:meth:`PlanarParallel.direct_kinematics_batch` sends large batches here when numba is present.
Nothing is generated or compiled per design. A design enters as small tables
(:func:`design_tables`, derived once in a few milliseconds): each leg's eight quadric coefficients
and their derivatives in the joint value, as polynomials in the features ``q, cos q, sin q``
(``cos``/``sin`` for an actuated revolute), and the elimination plan. Per joint vector the
kernel then

1. evaluates the three dyad quadrics ``Q_i(x; q_i)`` (8 coefficients each) and their derivatives
   ``dQ_i/dq_i`` (the diagonal of ``Jq``, used for the joint-space residual) from the tables
   (:func:`design_row`),
2. eliminates ``x2, x3`` numerically, as binary-form arithmetic on these coefficients: the Cramer
   forms ``D, X2, X3`` and the form ``F`` of :mod:`imagespace.core.elimination`
   (:func:`imagespace.core.elimination.eliminate_row`, the compiled twin of ``eliminate``; ``F``
   keeps its factors ``x0**2 + x1**2``, which have no real roots),
3. finds the real roots of ``F`` on the projective line in two charts, ``t = x1/x0`` in
   ``[-1, 1]`` and ``s = x0/x1`` in ``(-1, 1)``, so half-turns are ordinary roots and no chart
   sees a root beyond 1. The roots are isolated by Descartes' rule in the Bernstein basis
   (:func:`imagespace.core.isolate.count_real_roots_row`) on the rigorous enclosure of ``F``
   that steps 1 and 2 compute alongside the values (``cos``/``sin`` enclosed, every rounding of
   the elimination bounded), so the number of isolated roots is the proven number of distinct
   real roots of the exact kinematic form at the binary-rational input, and a row whose bounds
   cannot separate its roots is flagged (``suspect``) rather than guessed; each root is then
   refined by Newton kept inside its isolating interval. No eigenvalues, no complex
   arithmetic (the derivative cascade of earlier versions stays as :func:`real_roots_cascade`),
4. back-substitutes ``x2 = X2/D, x3 = X3/D``, polishes ``(x0..x3)`` by Newton on
   ``[Q1, Q2, Q3, x0**2 + x1**2 - 1]`` (4x4 Gaussian elimination with partial pivoting) unless the
   residual is at rounding level already, and checks every mode: relative constraint residual
   below ``1e-9``, joint residual ``max_i |Q_i| / |dQ_i/dq_i|`` reported,
5. writes normalised image points, poses, aspects (sign of the 4x4 determinant) sorted by ``phi``.

A row is flagged instead of guessed when a float computation cannot decide it: roots the
isolation cannot separate (a double root, or a complex pair within rounding of the axis:
``suspect``), or the Cramer denominator vanishing at a root, a vanishing polynomial, a Newton
step that does not converge (``special``). The caller re-solves flagged rows with the numpy
path, which marks the rows whose count it cannot separate ``near_singular``.

The same tables drive the certified counts (:meth:`BatchKernel.certified_counts`): steps 1 and 2
with a rigorous error bound on every value (``cos``/``sin`` enclosed by
:func:`imagespace.core.bounded_trig.cos_sin_bounded`), then Descartes' rule in the Bernstein
basis (:func:`imagespace.core.isolate.count_real_roots_row`) with every sign decided despite the
bounds.

Designs the kernel does not take (the caller uses the numpy path): a PP dyad (its pair of planes
carries a spurious root that only the leg's inverse kinematics can discard) and designs whose
Cramer denominator vanishes identically (case (a), e.g. seed 003).

The compiled loops are cached on disk (``$IMAGESPACE_CACHE/kernels`` or
``~/.cache/imagespace/kernels``) only in a directory private to the user (created 0700; refused,
with a :class:`KernelCacheWarning`, when owned by someone else, writable by group or others, or a
symbolic link): one entry per installation, shared by every design. The cached ``k_<key>.py`` is
never executed: the source is compared with it (rewritten when it differs) and executed from
memory. A corrupted numba cache entry is deleted and rebuilt when the kernel is loaded; with no
writable place the loops are compiled in memory.
"""

from __future__ import annotations

import hashlib
import itertools
import math
import os

import numpy as np
import sympy as sp

from ..core._numba import HAVE_NUMBA, njit
from ..core.codegen import KernelCacheWarning, kernel_cache_dir, load_cached_module, warn_once  # noqa: F401
from ..core.bounded_trig import cos_sin_bounded
from ..core.elimination import (ELIMINATION_ROW_SIZE, ELIMINATION_WORK_SIZE, ROW_F,  # noqa: F401
                                eliminate_row as _eliminate_row_py)
from ..core.isolate import ISOLATE_WORK_SIZE, count_real_roots_row
from ..core.quadrics import dk_system_row
from ..tolerances import TOLERANCES

__all__ = ["BatchKernel", "DesignTables", "KernelCacheWarning", "build_kernel", "design_tables", "design_row",
           "real_roots_cascade", "HAVE_NUMBA", "MAX_MONOMIALS"]

_REACH = 1.0 + 1.0 / 64      # each chart searches a little beyond 1
_MAX = 6
# root-finder constants of real_roots_cascade (numerical-method knobs, not read from Tolerances: the
# cascade is called without a design, and its answers are checked by the row's later decisions)
_CRITICAL_STEP = 1e-9        # critical points (roots of a derivative) are polished to this step
_TOUCH_DUPLICATE = 1e-12     # a root touching the axis this close to a crossing root is that root
_UNIT_ROUNDOFF = 2.2e-16     # the double precision unit roundoff the rounding bounds below scale
_HORNER_ZERO = 4.5e-16       # |p(t)| below this * deg * sum|c_k||t|^k is zero within Horner's rounding
_BISECT_WIDTH = 4e-16        # a bracket narrower than this (relative) has converged: stopping width
_TOUCH_ZERO = 64 * _UNIT_ROUNDOFF  # a critical value below this * deg * scale touches the axis
_POLISHED = 1e-14            # a back-substituted mode with a relative residual below this and a
_CONDITIONED = 1e-2          # |det J| above this times Hadamard's bound is not polished by Newton
                             # (it is at rounding level already: a numerical-method knob, the
                             # residual check and the joint residual still decide)

# The per-row scratch buffer of _solve_row, one named slice per array (numba folds these globals
# into constants): the cascade's 7x7 table W, its points/values/new roots/roots, the scaled
# polynomial p, up to 12 chart candidates, the scaled quadrics Cs and Newton's val, dx, X, J.
_WORK_SIZES = (49, 8, 8, 7, 6, 7, 48, 24, 4, 4, 4, 16, ISOLATE_WORK_SIZE, 6, 6, 6)
(_W_W, _W_PTS, _W_VALS, _W_NEW, _W_RTS, _W_P, _W_CAND, _W_CS, _W_VAL, _W_DX, _W_X,
 _W_J, _W_ISO, _W_ILO, _W_IHI, _W_ICH) = (0, *itertools.accumulate(_WORK_SIZES[:-1]))
_WORK_SIZE = sum(_WORK_SIZES)

# The kernel's decision thresholds arrive as one float array (from the design's Tolerances, see
# kernel_tolerances); these name its entries.
(_T_CRAMER_SMALL, _T_PIVOT, _T_CHART_DUPLICATE, _T_NEWTON_STOP, _T_RESIDUAL, _T_DUPLICATE,
 _T_CHART_OVERLAP) = range(7)


def kernel_tolerances(tol):
    """The compiled kernel's thresholds as a float array (entries named ``_T_*``), read from a
    :class:`~imagespace.tolerances.Tolerances`.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import kernel_tolerances
    >>> kernel_tolerances(isp.TOLERANCES).tolist()
    [1e-07, 1e-14, 1e-10, 1e-09, 1e-09, 1e-09, 1e-12]
    """
    return np.array([tol.cramer_small, tol.newton_stop, tol.kernel_chart_duplicate,
                     tol.kernel_newton_stop, tol.kernel_residual, tol.kernel_duplicate,
                     tol.kernel_chart_overlap], dtype=float)


# --------------------------------------------------------------------------- scalar numerics

@njit(cache=True)
def _horner(c, deg, t):
    """``c[0] + c[1] t + ... + c[deg] t**deg`` by Horner's rule."""
    v = c[deg]
    for k in range(deg - 1, -1, -1):
        v = v * t + c[k]
    return v


@njit(cache=True)
def _abs_horner(c, deg, t):
    """``|c[0]| + |c[1]| |t| + ...``: the scale of a Horner evaluation, for its rounding bound."""
    v = abs(c[deg])
    at = abs(t)
    for k in range(deg - 1, -1, -1):
        v = v * at + abs(c[k])
    return v


@njit(cache=True)
def _monotone_root(c, deg, a, b, fa, fb, flat_a, flat_b, coarse):
    """The root of a polynomial monotone on [a, b] with fa * fb < 0: Newton kept inside the
    bracket (a step leaving it, or four steps that do not halve it, give way to bisection, so it
    always converges), stopped once ``|p(t)|`` is
    within the rounding error of its evaluation or the bracket is a few ulps wide; with
    ``coarse`` (a critical point for the next level of the cascade) once a step is below 1e-9.

    ``flat_a``/``flat_b``: the end is a critical point (p' = 0 there), so the first guess comes from
    the quadratic model p(a) + k (t - a)**2 through p(b) rather than from the secant.
    """
    if flat_a and (abs(fa) <= abs(fb) or not flat_b):
        t = a + (b - a) * math.sqrt(fa / (fa - fb))
    elif flat_b:
        t = b - (b - a) * math.sqrt(fb / (fb - fa))
    else:
        t = a - fa * (b - a) / (fb - fa)
    if not (a < t < b):
        t = 0.5 * (a + b)
    width = b - a
    for it in range(400):
        f = c[deg]
        d = 0.0
        e = abs(c[deg])
        at = abs(t)
        for k in range(deg - 1, -1, -1):
            d = d * t + f
            f = f * t + c[k]
            e = e * at + abs(c[k])
        if abs(f) <= _HORNER_ZERO * deg * e:
            return t
        if (f < 0.0) == (fa < 0.0):
            a, fa = t, f
        else:
            b, fb = t, f
        if b - a <= _BISECT_WIDTH * max(1.0, abs(a), abs(b)):
            return t
        tn = t - f / d if d != 0.0 else 0.5 * (a + b)
        if it % 4 == 3:
            # safeguard: a Newton run that has not halved the bracket in four steps is crawling
            # (far from the root, or a near-flat stretch): bisect
            if b - a > 0.5 * width:
                tn = 0.5 * (a + b)
            width = b - a
        if not (a < tn < b):
            tn = 0.5 * (a + b)
        elif coarse and abs(tn - t) <= _CRITICAL_STEP * max(1.0, abs(t)):
            return tn
        t = tn
    return t


@njit(cache=True)
def _interval_roots(p, deg, lo, hi, W, pts, vals, new, out):
    """Real roots of ``sum p[k] t**k`` (``p[deg] != 0``) in [lo, hi] by the derivative cascade.

    Work arrays for degree d: W (d+1, d+1), pts and vals (d+2,), new (d+1,); out (d,) receives the
    roots (ascending). Returns (count, suspect). A polynomial of degree ``dg`` has at most ``dg``
    roots; a root (touching or from a sign change) that would exceed that, which only rounding
    around a near-triple root can produce, is not stored but flags the row ``suspect`` (so no
    buffer is ever overrun).
    """
    for k in range(deg + 1):
        W[0, k] = p[k]
    for j in range(1, deg + 1):
        for k in range(deg + 1 - j):
            W[j, k] = W[j - 1, k + 1] * (k + 1)
    ncrit = 0
    suspect = False
    for j in range(deg - 1, -1, -1):
        dg = deg - j
        c = W[j]
        npts = ncrit + 2
        pts[0] = lo
        for i in range(ncrit):
            pts[i + 1] = out[i]
        pts[npts - 1] = hi
        for i in range(npts):
            vals[i] = _horner(c, dg, pts[i])
        nnew = 0
        for i in range(npts - 1):
            fa, fb = vals[i], vals[i + 1]
            if fa * fb < 0.0 and nnew >= dg:
                suspect = True        # see the docstring: never more than dg roots are stored
            elif fa * fb < 0.0:
                if dg == 1:
                    new[nnew] = -c[0] / c[1]
                elif dg == 2:
                    # the one root of a quadratic in a piece with a sign change, stably
                    disc = max(c[1] * c[1] - 4.0 * c[0] * c[2], 0.0)
                    qq = -0.5 * (c[1] + math.copysign(math.sqrt(disc), c[1]))
                    r1 = qq / c[2]
                    r2 = c[0] / qq if qq != 0.0 else r1
                    r = r1 if pts[i] <= r1 <= pts[i + 1] else r2
                    new[nnew] = min(max(r, pts[i]), pts[i + 1])
                else:
                    new[nnew] = _monotone_root(c, dg, pts[i], pts[i + 1], fa, fb,
                                               i > 0, i + 1 < npts - 1, j > 0)
                nnew += 1
            if i + 1 < npts - 1:
                # a root touching the axis at the critical point pts[i + 1]
                t = pts[i + 1]
                scale = _abs_horner(c, dg, max(abs(t), 1.0))
                if abs(vals[i + 1]) <= _TOUCH_ZERO * dg * scale:
                    dup = False
                    for m in range(nnew):
                        if abs(new[m] - t) <= _TOUCH_DUPLICATE * max(1.0, abs(t)):
                            dup = True
                    if not dup and nnew >= dg:
                        suspect = True    # see the docstring: never more than dg roots are stored
                    elif not dup:
                        new[nnew] = t
                        nnew += 1
                        if j == 0:
                            suspect = True
        # the pieces are visited in order, so new[] is sorted up to touching points
        for a in range(1, nnew):
            v = new[a]
            b = a - 1
            while b >= 0 and new[b] > v:
                new[b + 1] = new[b]
                b -= 1
            new[b + 1] = v
        ncrit = nnew
        for i in range(nnew):
            out[i] = new[i]
    return ncrit, suspect


@njit(cache=True)
def _cascade_batch(C, roots, counts, suspect):
    """Real roots in [-1, 1] of each row of ``C`` by the derivative cascade, in parallel over
    rows (``suspect`` marks rows a float cascade cannot decide)."""
    n, d1 = C.shape
    d = d1 - 1
    W = np.empty((d1, d1))
    pts = np.empty(d + 2)
    vals = np.empty(d + 2)
    new = np.empty(d1)
    out = np.empty(d)
    for i in range(n):
        c = C[i]
        bound = 0.0
        for k in range(d):
            bound = max(bound, abs(c[k] / c[d]))
        bound = 1.0 + bound          # Cauchy: every root lies strictly inside
        k, sus = _interval_roots(c, d, -bound, bound, W, pts, vals, new, out)
        for m in range(d):
            roots[i, m] = out[m] if m < k else np.nan
        counts[i] = k
        suspect[i] = sus


def real_roots_cascade(C):
    """Real roots of a batch of polynomials ``sum_k C[:, k] t**k`` with non-zero leading coefficients.

    The derivative cascade of the batch kernel on the whole real line (inside the Cauchy bound):
    only real roots are computed, each by Newton kept inside a bracket on which the polynomial is
    monotone. A root met at a critical point without a sign change (a double root, or a complex
    pair within rounding of the axis) is reported there and the row flagged ``suspect``: a float
    computation cannot tell those apart, so callers send such rows to the certified path.

    Parameters
    ----------
    C : (n, d+1) float
        ``C[:, d]`` must be non-zero (rows where it is zero or that are not finite get count -1).

    Returns
    -------
    roots : (n, d) float
        Ascending real roots, NaN-padded.
    counts : (n,) int
    suspect : (n,) bool

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.solve.kernel import real_roots_cascade
    >>> r, n, s = real_roots_cascade(np.array([[-2.0, 0.0, 1.0], [1.0, -2.0, 1.0], [1.0, 0.0, 1.0]]))
    >>> n.tolist(), s.tolist()
    ([2, 1, 0], [False, True, False])
    >>> np.round(r[0], 12).tolist()
    [-1.414213562373, 1.414213562373]
    """
    C = np.ascontiguousarray(C, dtype=float)
    n, d1 = C.shape
    roots = np.full((n, d1 - 1), np.nan)
    counts = np.full(n, -1, dtype=np.int64)
    suspect = np.zeros(n, dtype=bool)
    good = np.all(np.isfinite(C), axis=1) & (C[:, -1] != 0)
    if np.any(good):
        r = np.empty((int(good.sum()), d1 - 1))
        k = np.empty(int(good.sum()), dtype=np.int64)
        s = np.empty(int(good.sum()), dtype=np.bool_)
        _cascade_batch(C[good], r, k, s)
        roots[good], counts[good], suspect[good] = r, k, s
    return roots, counts, suspect


@njit(cache=True)
def _bf(f, off, deg, x0, x1):
    """Binary form with coefficients f[off:off+deg+1] (x0**(deg-k) x1**k) at (x0, x1), |x0|, |x1| <= 1."""
    v = 0.0
    p1 = 1.0
    for k in range(deg + 1):
        v = v * x0 + f[off + k] * p1
        p1 *= x1
    return v


# the DK system and its Jacobian: compiled from its one home in core/quadrics.py
_system = njit(cache=True)(dk_system_row)
# the elimination of one row: compiled from its one home in core/elimination.py
eliminate_row = njit(cache=True)(_eliminate_row_py)


@njit(cache=True)
def _det4(J, x0, x1):
    """det of the 4x4 system Jacobian, expanded along its last row (2 x0, 2 x1, 0, 0)."""
    m30 = (J[0, 1] * (J[1, 2] * J[2, 3] - J[1, 3] * J[2, 2])
           - J[0, 2] * (J[1, 1] * J[2, 3] - J[1, 3] * J[2, 1])
           + J[0, 3] * (J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1]))
    m31 = (J[0, 0] * (J[1, 2] * J[2, 3] - J[1, 3] * J[2, 2])
           - J[0, 2] * (J[1, 0] * J[2, 3] - J[1, 3] * J[2, 0])
           + J[0, 3] * (J[1, 0] * J[2, 2] - J[1, 2] * J[2, 0]))
    return -2.0 * x0 * m30 + 2.0 * x1 * m31


@njit(cache=True)
def _solve4(J, r, dx, pivot):
    """Solve J dx = r in place (partial pivoting); returns the determinant (0 when singular: a
    pivot below ``pivot`` times the largest entry)."""
    det = 1.0
    scale = 0.0
    for i in range(4):
        for k in range(4):
            scale = max(scale, abs(J[i, k]))
    for k in range(4):
        p = k
        for i in range(k + 1, 4):
            if abs(J[i, k]) > abs(J[p, k]):
                p = i
        if abs(J[p, k]) <= pivot * scale:
            return 0.0
        if p != k:
            for m in range(4):
                tmp = J[k, m]
                J[k, m] = J[p, m]
                J[p, m] = tmp
            tmp = r[k]
            r[k] = r[p]
            r[p] = tmp
            det = -det
        det *= J[k, k]
        for i in range(k + 1, 4):
            f = J[i, k] / J[k, k]
            for m in range(k, 4):
                J[i, m] -= f * J[k, m]
            r[i] -= f * r[k]
    for k in range(3, -1, -1):
        s = r[k]
        for m in range(k + 1, 4):
            s -= J[k, m] * dx[m]
        dx[k] = s / J[k, k]
    return det


@njit(cache=True)
def _solve_row(buf, Ef, layout, tol, out_X, out_P, out_res, out_asp, work):
    """Everything after the coefficients for one row. Returns (count, flag): flag 0 ok,
    1 special (careful path), 2 suspect (certified path). ``tol``: :func:`kernel_tolerances`;
    ``work``: ``_WORK_SIZE`` floats of scratch (named slices ``_W_*``)."""
    dD, dX, dF = layout[0], layout[1], layout[2]
    oD, oX2, oX3, oF = 48, 48 + dD + 1, 48 + dD + dX + 2, 48 + dD + 2 * dX + 3
    W = work[_W_W:_W_W + 49].reshape((7, 7))
    pts, vals = work[_W_PTS:_W_PTS + 8], work[_W_VALS:_W_VALS + 8]
    new, rts = work[_W_NEW:_W_NEW + 7], work[_W_RTS:_W_RTS + 6]
    p = work[_W_P:_W_P + 7]
    cand = work[_W_CAND:_W_CAND + 48].reshape((12, 4))
    Cs = work[_W_CS:_W_CS + 24]
    val, dx, X = work[_W_VAL:_W_VAL + 4], work[_W_DX:_W_DX + 4], work[_W_X:_W_X + 4]
    J = work[_W_J:_W_J + 16].reshape((4, 4))
    # scaled quadrics (zero set unchanged) and their q-derivatives with the same scale
    for i in range(3):
        s = 0.0
        for k in range(8):
            s = max(s, abs(buf[8 * i + k]))
        if not (s > 0.0) or not np.isfinite(s):
            return 0, 1
        for k in range(8):
            Cs[8 * i + k] = buf[8 * i + k] / s
            buf[24 + 8 * i + k] = buf[24 + 8 * i + k] / s
    fn = 0.0
    for k in range(dF + 1):
        if not np.isfinite(buf[oF + k]):
            return 0, 1
        fn = max(fn, abs(buf[oF + k]))
    if fn == 0.0:
        return 0, 1
    dn = 0.0
    for k in range(dD + 1):
        dn = max(dn, abs(buf[oD + k]))
    if dn == 0.0:
        return 0, 1
    # the real roots of F on the projective line, in two charts (t = x1/x0 on [-1, 1], s = x0/x1
    # on (-1, 1), so half-turns are ordinary roots and every root is found where its chart is
    # well conditioned): isolated by Descartes' rule in the Bernstein basis on the box F +- Ef
    # (core.isolate; Ef are rigorous bounds when the kernel runs with proof, so the count is
    # proven; a row it cannot decide, close or multiple roots, is flagged 2), then each refined
    # by Newton kept inside its isolating interval, on whose ends the polynomial has opposite signs
    ich = work[_W_ICH:_W_ICH + 6]
    nr = count_real_roots_row(buf[oF:oF + dF + 1], Ef, dF, work[_W_ILO:_W_ILO + 6],
                              work[_W_IHI:_W_IHI + 6], ich, work[_W_ISO:_W_ISO + ISOLATE_WORK_SIZE])
    if nr < 0:
        return 0, 2
    ncand = 0
    for m in range(nr):
        chart = 0 if ich[m] == 0.0 else 1
        for k in range(dF + 1):
            p[k] = buf[oF + k] / fn if chart == 0 else buf[oF + dF - k] / fn
        deg = dF
        while deg > 0 and p[deg] == 0.0:
            deg -= 1
        a = work[_W_ILO + m]
        b = work[_W_IHI + m]
        fa = _horner(p, deg, a)
        fb = _horner(p, deg, b)
        if deg == 0 or not (fa * fb < 0.0):
            return 0, 1          # rounding hid the sign change the isolation proved: careful path
        t = _monotone_root(p, deg, a, b, fa, fb, False, False, False)
        h = 1.0 / math.sqrt(1.0 + t * t)
        x0 = h if chart == 0 else t * h
        x1 = t * h if chart == 0 else h
        if x0 < 0.0 or (x0 == 0.0 and x1 < 0.0):
            x0, x1 = -x0, -x1
        cand[ncand, 0] = x0
        cand[ncand, 1] = x1
        ncand += 1
    count = 0
    for j in range(ncand):
        x0, x1 = cand[j, 0], cand[j, 1]
        Dv = _bf(buf, oD, dD, x0, x1)
        if abs(Dv) <= tol[_T_CRAMER_SMALL] * dn:
            return 0, 1
        X[0], X[1] = x0, x1
        X[2] = _bf(buf, oX2, dX, x0, x1) / Dv
        X[3] = _bf(buf, oX3, dX, x0, x1) / Dv
        # Newton on the 4x4 system: one step takes the back-substituted point (error ~1e-13)
        # to rounding; the error after a step is of the order of the step squared, so stop once
        # a step is below 1e-9 of the size. A point whose residual is already at rounding level
        # (about 90 % of them) is not stepped. The aspect is the sign of the determinant at the
        # last linearisation point (within a step of 1e-9 of the mode)
        _system(Cs, X, val, J)
        det = _det4(J, X[0], X[1])
        size = 1.0 + X[2] * X[2] + X[3] * X[3]
        # skipped only where that residual proves the point accurate: a small residual and a
        # well-conditioned Jacobian (|det J| against the product of its rows' norms, Hadamard's
        # bound); near a singularity (close roots) a small residual says little
        hadamard = 1.0
        for i in range(4):
            hadamard *= math.sqrt(J[i, 0] * J[i, 0] + J[i, 1] * J[i, 1] + J[i, 2] * J[i, 2] + J[i, 3] * J[i, 3])
        polished = (max(abs(val[0]), abs(val[1]), abs(val[2])) <= _POLISHED * size
                    and abs(det) >= _CONDITIONED * hadamard)
        if not polished:
            for it in range(8):
                if it > 0:
                    _system(Cs, X, val, J)
                    det = _det4(J, X[0], X[1])
                for i in range(4):
                    val[i] = -val[i]
                if _solve4(J, val, dx, tol[_T_PIVOT]) == 0.0:
                    break
                big = 1.0
                stp = 0.0
                for i in range(4):
                    X[i] += dx[i]
                    big = max(big, abs(X[i]))
                    stp = max(stp, abs(dx[i]))
                if stp <= tol[_T_NEWTON_STOP] * big:
                    break
        sg = -1.0 if (X[0] < 0.0 or (X[0] == 0.0 and X[1] < 0.0)) else 1.0
        nrm = sg / math.sqrt(X[0] * X[0] + X[1] * X[1])
        for i in range(4):
            X[i] = X[i] * nrm
        if polished:              # the quadrics are homogeneous of degree 2
            for i in range(3):
                val[i] = val[i] * (nrm * nrm)
        else:
            _system(Cs, X, val, J)
        size = 1.0 + X[2] * X[2] + X[3] * X[3]
        rel = max(abs(val[0]), abs(val[1]), abs(val[2])) / size
        if not (rel <= tol[_T_RESIDUAL]):
            return 0, 1
        jres = 0.0
        for i in range(3):
            g = buf[24 + 8 * i:32 + 8 * i]
            dq = (g[0] * (X[2] * X[2] + X[3] * X[3]) + X[2] * (g[1] * X[0] + g[2] * X[1])
                  + X[3] * (g[3] * X[0] + g[4] * X[1]) + g[5] * X[0] * X[0] + g[6] * X[0] * X[1]
                  + g[7] * X[1] * X[1])
            jres = max(jres, abs(val[i]) / abs(dq) if dq != 0.0 else math.inf)
        if count >= _MAX:
            return 0, 1
        phi = 2.0 * math.atan2(X[1], X[0])
        # insertion by phi
        pos = count
        while pos > 0 and out_P[pos - 1, 2] > phi:
            for i in range(4):
                out_X[pos, i] = out_X[pos - 1, i]
            for i in range(3):
                out_P[pos, i] = out_P[pos - 1, i]
            out_res[pos] = out_res[pos - 1]
            out_asp[pos] = out_asp[pos - 1]
            pos -= 1
        for i in range(4):
            out_X[pos, i] = X[i]
        out_P[pos, 0] = 2.0 * (X[3] * X[0] + X[2] * X[1])
        out_P[pos, 1] = 2.0 * (X[3] * X[1] - X[2] * X[0])
        out_P[pos, 2] = phi
        out_res[pos] = jres
        out_asp[pos] = 1 if det > 0 else (-1 if det < 0 else 0)
        count += 1
    # two roots may polish onto one mode only if the float roots were wrong: let the careful path decide
    for a in range(count):
        for b in range(a + 1, count):
            dd = 0.0
            for i in range(4):
                dd = max(dd, abs(out_X[a, i] - out_X[b, i]))
            if dd <= tol[_T_DUPLICATE] * (1.0 + abs(out_X[a, 2]) + abs(out_X[a, 3])):
                return 0, 1
    return count, 0


# --------------------------------------------------------------------------- the design tables

#: Monomials in ``(q, cos q, sin q)`` a leg's quadric coefficients may use (a leg needing more goes
#: to the numpy path).
MAX_MONOMIALS = 12
_U = 2.0**-53                    # unit roundoff
_GAMMA_SUM = (MAX_MONOMIALS + 4) * _U / (1 - (MAX_MONOMIALS + 4) * _U)  # a sum of rounded products
_INFLATE = 1.0 + 2.0**-40        # covers the rounding of the bound arithmetic itself
_TINY = 2.0**-500                # covers every underflow (each below 2**-1074 per operation); not
                                 # smaller: a product of two such floors must not underflow (slow)


class DesignTables:
    """The per-design input of the generic kernel: each leg's quadric coefficients (and their
    derivatives in the joint value) as polynomials in the features ``q, cos q, sin q``.

    Attributes
    ----------
    expo : (3, MAX_MONOMIALS, 3) int64
        Exponents of ``(q, cos q, sin q)`` of each leg's monomials.
    coef : (3, MAX_MONOMIALS, 16) float
        Constant factor of each monomial in the 8 quadric coefficients ``c, a0, a1, b0, b1, k0,
        k1, k2`` and their 8 derivatives in ``q``, each rounded once from its exact value.
    cerr : (3, MAX_MONOMIALS, 16) float
        Rigorous bounds on that rounding.
    nmono : (3,) int64
        Monomials per leg.
    trig : (3,) int64
        1 where the leg's coefficients use ``cos q``, ``sin q`` (an actuated revolute joint).
    plan : (7,) int64
        :func:`imagespace.core.elimination.plan_array` of the design's elimination plan.
    """

    def __init__(self, expo, coef, cerr, nmono, trig, plan):
        self.expo, self.coef, self.cerr, self.nmono, self.trig, self.plan = (
            expo, coef, cerr, nmono, trig, plan)

    @property
    def degree(self):
        """Degree of the eliminated form ``F`` (6, or 4 when no leg has an RR dyad).

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.solve.kernel import design_tables
        >>> design_tables(isp.examples.choi_3ppr()).degree
        4
        """
        return 4 if self.plan[6] == 1 else 6

    def arrays(self):
        """The arrays in the order the kernel takes them.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.solve.kernel import design_tables
        >>> len(design_tables(isp.examples.general_3rpr()).arrays())
        6
        """
        return self.expo, self.coef, self.cerr, self.nmono, self.trig, self.plan


def _rounded(v):
    """A float of the exact sympy number ``v`` and a rigorous bound on the rounding."""
    if v == 0:
        return 0.0, 0.0
    if v.is_Rational:
        f = float(v)                                   # correctly rounded
        return f, abs(f) * _U + 2.0**-1074
    f = float(sp.N(v, 40))                             # 40 digits, then rounded
    return f, abs(f) * 2 * _U + 2.0**-1000


def design_tables(manipulator):
    """Derive the :class:`DesignTables` of a numeric design, or None where the generic kernel does
    not apply (a PP dyad, a Cramer denominator vanishing identically, coefficients that are not
    polynomial in ``q, cos q, sin q``, too many monomials).

    The derivation is small and done once per design: each leg's dyad quadric with a symbolic
    joint value (eight coefficients and their derivatives), expanded on the monomials of the
    features. Nothing is eliminated symbolically: the kernel eliminates per row.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import design_tables
    >>> t = design_tables(isp.examples.stigger_husty())
    >>> t.nmono.tolist(), t.trig.tolist(), t.degree
    ([3, 3, 2], [0, 0, 0], 6)
    """
    from ..core.elimination import combine_rows, plan_array

    if "PP" in manipulator.kinds:
        return None
    plan = manipulator.elimination_plan
    # case (a): the Cramer denominator vanishes identically (a property of the design)
    rows = combine_rows(manipulator.quadrics(None), plan)
    E1, E2 = rows[0], rows[1]
    D = [sp.expand(E1.A[0] * E2.B[0] - E2.A[0] * E1.B[0]),
         sp.expand(E1.A[0] * E2.B[1] + E1.A[1] * E2.B[0] - E2.A[0] * E1.B[1] - E2.A[1] * E1.B[0]),
         sp.expand(E1.A[1] * E2.B[1] - E2.A[1] * E1.B[1])]
    if all(v == 0 for v in D):
        return None
    expo = np.zeros((3, MAX_MONOMIALS, 3), dtype=np.int64)
    coef = np.zeros((3, MAX_MONOMIALS, 16))
    cerr = np.zeros((3, MAX_MONOMIALS, 16))
    nmono = np.zeros(3, dtype=np.int64)
    trig = np.zeros(3, dtype=np.int64)
    for i, leg in enumerate(manipulator.legs):
        q = sp.Symbol("q", real=True)
        cs = [sp.expand(sp.sympify(c)) for c in leg.dyad(q).coefficients()]
        exprs = cs + [sp.expand(sp.diff(c, q)) for c in cs]
        gens = (q, sp.cos(q), sp.sin(q))
        terms = {}
        for k, e in enumerate(exprs):
            try:
                poly = sp.Poly(e, *gens)
            except sp.PolynomialError:
                return None
            for mono, val in poly.terms():
                if val.free_symbols:
                    return None
                terms.setdefault(mono, {})[k] = val
        if len(terms) > MAX_MONOMIALS:
            return None
        for j, mono in enumerate(sorted(terms)):
            expo[i, j] = mono
            for k, val in terms[mono].items():
                coef[i, j, k], cerr[i, j, k] = _rounded(sp.sympify(val))
        nmono[i] = len(terms)
        trig[i] = int(any(mono[1] or mono[2] for mono in terms))
    return DesignTables(expo, coef, cerr, nmono, trig, plan_array(plan))


@njit(cache=True)
def design_row(qr, expo, coef, cerr, nmono, trig, bounded, buf, Ce, acc):
    """The quadric coefficients of one joint vector ``qr`` (3,) from the design tables: ``buf[0:24]``
    the three quadrics, ``buf[24:48]`` their derivatives in the joint values; with ``bounded``
    also rigorous bounds ``Ce`` (24,) on the error of ``buf[0:24]`` (``acc``: 8 floats of scratch).

    The joint values are exact binary rationals; ``cos q``, ``sin q`` come with rigorous bounds
    from :func:`imagespace.core.bounded_trig.cos_sin_bounded` when ``bounded``, else from libm.

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import design_row, design_tables
    >>> m = isp.examples.general_3rpr()
    >>> t = design_tables(m)
    >>> buf, Ce, acc = np.zeros(48), np.zeros(24), np.zeros(8)
    >>> design_row(np.array(m.q_example_float), t.expo, t.coef, t.cerr, t.nmono, t.trig, True, buf, Ce, acc)
    >>> quads = m.quadrics(m.q_example_float)
    >>> bool(np.allclose(buf[:24], [float(v) for qd in quads for v in qd.coefficients()]))
    True
    """
    for i in range(3):
        q = qr[i]
        cq = 0.0
        sq = 0.0
        ec = 0.0
        es = 0.0
        if trig[i] != 0:
            if bounded:
                cq, sq, ec, es = cos_sin_bounded(q)
            else:
                cq = math.cos(q)
                sq = math.sin(q)
        for k in range(8):
            buf[8 * i + k] = 0.0
            buf[24 + 8 * i + k] = 0.0
            Ce[8 * i + k] = 0.0
            acc[k] = 0.0
        for j in range(nmono[i]):
            mv = 1.0
            me = 0.0
            for _ in range(expo[i, j, 0]):
                nv = mv * q
                me = me * abs(q) + _U * abs(nv)
                mv = nv
            for _ in range(expo[i, j, 1]):
                nv = mv * cq
                me = abs(mv) * ec + me * abs(cq) + me * ec + _U * abs(nv)
                mv = nv
            for _ in range(expo[i, j, 2]):
                nv = mv * sq
                me = abs(mv) * es + me * abs(sq) + me * es + _U * abs(nv)
                mv = nv
            for k in range(8):
                v = coef[i, j, k]
                p = mv * v
                buf[8 * i + k] += p
                buf[24 + 8 * i + k] += mv * coef[i, j, 8 + k]
                if bounded:
                    Ce[8 * i + k] += abs(mv) * cerr[i, j, k] + me * abs(v) + me * cerr[i, j, k]
                    acc[k] += abs(p)
        if bounded:
            for k in range(8):
                Ce[8 * i + k] = (Ce[8 * i + k] + _GAMMA_SUM * acc[k]) * _INFLATE + _TINY


_LOOP_SOURCE = """

@njit(parallel=True, cache=CACHE)
def run(Q, expo, coef, cerr, nmono, trig, plan, tol, proof, X, P, R, A, cnt, flag):
    n = Q.shape[0]
    nblocks = min(n, 64)
    dF = 4 if plan[6] == 1 else 6
    for b in prange(nblocks):
        lo = b * n // nblocks
        hi = (b + 1) * n // nblocks
        buf = np.empty(48 + ROW_SIZE)
        Ce = np.zeros(24)
        eout = np.zeros(ROW_SIZE)
        ework = np.empty(ELIM_WORK + 8)
        work = np.empty(WORK_SIZE)
        layout = np.empty(3, dtype=np.int64)
        layout[0] = 2
        layout[1] = 3
        layout[2] = dF
        for r in range(lo, hi):
            design_row(Q[r], expo, coef, cerr, nmono, trig, proof, buf, Ce, ework)
            eliminate_row(buf, Ce, plan, buf[48:], eout, ework, proof)
            k, f = _solve_row(buf, eout[ROW_F:], layout, tol, X[r], P[r], R[r], A[r], work)
            if f != 0:
                k = 0
            for j in range(k, X.shape[1]):
                for i in range(4):
                    X[r, j, i] = np.nan
                for i in range(3):
                    P[r, j, i] = np.nan
                R[r, j] = np.nan
                A[r, j] = 0
            cnt[r] = k
            flag[r] = f
"""

_COUNTS_SOURCE = """

@njit(parallel=True, cache=CACHE)
def run_counts(Q, expo, coef, cerr, nmono, trig, plan, counts, lo, hi, chart):
    n = Q.shape[0]
    nblocks = min(n, 64)
    for b in prange(nblocks):
        r0 = b * n // nblocks
        r1 = (b + 1) * n // nblocks
        buf = np.empty(48 + ROW_SIZE)
        Ce = np.zeros(24)
        eout = np.zeros(ROW_SIZE)
        ework = np.empty(ELIM_WORK + 8)
        iwork = np.empty(ISOLATE_WORK)
        for r in range(r0, r1):
            design_row(Q[r], expo, coef, cerr, nmono, trig, True, buf, Ce, ework)
            d = eliminate_row(buf, Ce, plan, buf[48:], eout, ework, True)
            counts[r] = count_real_roots_row(buf[48 + ROW_F:], eout[ROW_F:], d, lo[r], hi[r], chart[r], iwork)
"""

_HEADER = """# generated by imagespace.solve.kernel: the generic batch loop (one per installation); safe to delete
import math
import numpy as np
from imagespace.core._numba import njit, prange
from imagespace.solve.kernel import (_solve_row, _WORK_SIZE as WORK_SIZE, design_row,
    eliminate_row, ELIMINATION_ROW_SIZE as ROW_SIZE, ELIMINATION_WORK_SIZE as ELIM_WORK, ROW_F,
    count_real_roots_row, ISOLATE_WORK_SIZE as ISOLATE_WORK)
"""

_DISK_ATTEMPTS = 3         # loads from the disk cache before compiling in memory (see _compile)
_SERIAL_ROWS = 16          # certified counts of at most this many rows run serially (a speed knob)


def _numba_files(dispatchers):
    """numba's index and data files of the given dispatchers (those with an on-disk cache)."""
    files = []
    for disp in dispatchers:
        cache_file = getattr(getattr(disp, "_cache", None), "_cache_file", None)
        if cache_file is None:
            continue
        try:
            folder, index = cache_file._cache_path, cache_file._index_name
        except AttributeError:     # another numba layout: its stale entry is merely not deleted
            continue
        files.append(os.path.join(folder, index))
        stem = index[:-len(".nbi")] + "."
        try:
            names = os.listdir(folder)
        except OSError:
            continue
        files += [os.path.join(folder, f) for f in names if f.startswith(stem) and f.endswith(".nbc")]
    return files


def _discard(files):
    """Delete the given cache files, ignoring those already gone."""
    for f in files:
        try:
            os.unlink(f)          # removes a symbolic link itself, never its target
        except OSError:
            pass


def _helpers_without_code():
    """This module's cached numba helpers not compiled in this process: after a kernel entry was
    discarded and loading still fails, their own cache entries are the suspects."""
    return [v for v in globals().values()
            if hasattr(v, "_cache") and hasattr(v, "overloads") and not v.overloads]


def _warm(mod, name):
    """Compile (or load from numba's cache) the loop ``name`` (``"run"`` or ``"run_counts"``) of
    the generated module ``mod`` for exactly the types :class:`BatchKernel` passes, on an empty
    batch: a corrupted cache entry fails here, not in a user's batch. Each loop is loaded only
    when first needed (loading one takes about half a second)."""
    i64 = np.int64
    tables = (np.zeros((3, MAX_MONOMIALS, 3), dtype=i64), np.zeros((3, MAX_MONOMIALS, 16)),
              np.zeros((3, MAX_MONOMIALS, 16)), np.zeros(3, dtype=i64), np.zeros(3, dtype=i64),
              np.zeros(7, dtype=i64))
    if name == "run":
        mod.run(np.empty((0, 3)), *tables, np.zeros(len(kernel_tolerances(TOLERANCES))), True,
                np.empty((0, _MAX, 4)), np.empty((0, _MAX, 3)), np.empty((0, _MAX)),
                np.empty((0, _MAX), dtype=np.int8), np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int8))
    else:
        mod.run_counts(np.empty((0, 3)), *tables, np.empty(0, dtype=np.int8), np.empty((0, _MAX)),
                       np.empty((0, _MAX)), np.empty((0, _MAX), dtype=np.int8))
    return getattr(mod, name)


_INLINED_MODULES = ("imagespace.solve.kernel", "imagespace.core.elimination", "imagespace.core.quadrics",
                    "imagespace.core.isolate", "imagespace.core.bounded_trig")


def _module_source(name):
    """The bytes of an imported module's source file."""
    import sys

    with open(sys.modules[name].__file__, "rb") as fh:
        return fh.read()


def _compile(source, name):
    """The compiled ``run`` of generated ``source``: from the disk cache where there is a private
    one, else compiled in memory.

    A cache entry that does not load (numba's ``.nbi``/``.nbc`` are pickles: a truncated or
    garbage one raises ``EOFError``, ``UnpicklingError``, ``AttributeError``, ...) is deleted and
    rebuilt; if that fails too, the helpers' entries are deleted as well, and at last the kernel
    is compiled in memory. One :class:`KernelCacheWarning` per broken entry.
    """
    # the key covers the source of every module whose functions the loops compile in (this one,
    # the elimination, the quadrics' system, the isolation, the trig enclosure): numba's cache of
    # the generated loops does not notice a change in the helpers they call, so a new imagespace
    # must mean a new file
    own = b"".join(_module_source(name) for name in _INLINED_MODULES)
    key = hashlib.sha256(source.encode() + own).hexdigest()[:20]
    folder = kernel_cache_dir()
    if folder is not None:
        path = os.path.join(folder, f"k_{key}.py")
        errors = []
        for attempt in range(_DISK_ATTEMPTS):
            try:
                mod = load_cached_module(folder, key, source.replace("CACHE", "True"))
            except OSError:            # the directory is not writable: compile in memory
                break
            try:
                run = _warm(mod, name)
            except Exception as exc:   # noqa: BLE001 - anything numba's cache loader raises
                errors.append(f"{type(exc).__name__}: {exc}"[:200])
                stale = [getattr(mod, name, None)]
                if attempt >= 1:
                    stale += _helpers_without_code()
                _discard(_numba_files(stale) + [path])
                continue
            if errors:
                warn_once("corrupted", path, f"kernel cache entry {path} was corrupted "
                           f"({errors[0]}): deleted and rebuilt")
            return run
        if errors:
            warn_once("corrupted", path, f"kernel cache entry {path} was corrupted ({errors[0]}) "
                       "and could not be rebuilt: deleted, the kernel is compiled in memory")
    import types

    mod = types.ModuleType(f"imagespace_kernel_{key}")
    exec(compile(source.replace("CACHE", "False"), f"<imagespace kernel {key}>", "exec"), mod.__dict__)
    return _warm(mod, name)


class BatchKernel:
    """The generic compiled direct-kinematics kernel, bound to one design's tables (see the
    module docstring).

    Built by :func:`build_kernel`; called by :meth:`PlanarParallel.direct_kinematics_batch`. The
    compiled loop is the same for every design (compiled once per installation, then loaded
    from the cache); only the small :class:`DesignTables` differ.

    Attributes
    ----------
    source : str
        The generic loop's module (readable Python), the same for every design.
    layout : (3,) int
        Degrees of ``D``, ``X2``/``X3`` and ``F``.
    tables : DesignTables
    """

    def __init__(self, tables, tolerances=None):
        self.source = _SOURCE
        self.tables = tables
        self.layout = np.array([2, 3, tables.degree], dtype=np.int64)
        self.tolerances = kernel_tolerances(TOLERANCES if tolerances is None else tolerances)

    def __call__(self, Q, proof=True):
        """Solve joint vectors ``Q`` (n, 3) (finite, in the joints' domains).

        Parameters
        ----------
        Q : (n, 3) float
        proof : bool
            Isolate the real roots with rigorous bounds on the coefficients of ``F`` (quadric
            coefficients with ``cos``/``sin`` enclosed, bounded elimination): the count of an
            unflagged row is then the proven number of distinct real roots of the exact
            kinematic form, and a row the bounds cannot decide is flagged 2. ``False`` takes
            the float coefficients as exact (an unflagged count may then be wrong near a
            double root; kept as the baseline of ``benchmarks/dk_throughput.py``).

        Returns
        -------
        X (n, 6, 4), poses (n, 6, 3), residual (n, 6), aspect (n, 6) int8, count (n,) int64,
        flag (n,) int8 (0 solved, 1 careful path needed, 2 certified path needed)

        Examples
        --------
        >>> import numpy as np
        >>> import imagespace as isp
        >>> from imagespace.solve.proof import batch_kernel
        >>> m = isp.examples.general_3rpr()
        >>> X, P, R, A, count, flag = batch_kernel(m)(np.array([m.q_example_float]))
        >>> count.tolist(), flag.tolist()
        ([6], [0])
        """
        Q = np.ascontiguousarray(Q, dtype=float)
        n = Q.shape[0]
        # every slot is written by the kernel (in parallel: the pages are first touched there)
        X = np.empty((n, _MAX, 4))
        P = np.empty((n, _MAX, 3))
        R = np.empty((n, _MAX))
        A = np.empty((n, _MAX), dtype=np.int8)
        cnt = np.empty(n, dtype=np.int64)
        flag = np.empty(n, dtype=np.int8)
        if n:
            _generic_loop("run")(Q, *self.tables.arrays(), self.tolerances, bool(proof), X, P, R, A, cnt, flag)
        return X, P, R, A, cnt, flag

    def certified_counts(self, Q):
        """Proven numbers of distinct real roots of the kinematic form for joint vectors ``Q`` (n, 3)
        (finite, in the joints' domains; floats taken as the exact binary rationals they are).

        Per row: the quadric coefficients with rigorous error bounds (``cos``/``sin`` enclosed),
        the elimination with a rigorous bound on every coefficient of ``F``, then
        :func:`imagespace.core.isolate.count_real_roots_row` (Descartes' rule in the Bernstein
        basis, every sign decided despite the bounds). No eigenvalues, no flint.

        Returns
        -------
        counts : (n,) int8
            The count, or -1 where the bounds could not decide it (a multiple or nearly multiple
            root, a root on a chart boundary): the caller decides those rows exactly.
        lo, hi : (n, 6) float
            Isolating interval of each root (NaN padded), in ``t = x1/x0`` where ``chart`` is 0
            and in ``s = x0/x1`` where it is 1.
        chart : (n, 6) int8
            -1 in unused slots.

        Examples
        --------
        >>> import numpy as np
        >>> import imagespace as isp
        >>> from imagespace.solve.proof import batch_kernel
        >>> m = isp.examples.general_3rpr()
        >>> counts, lo, hi, chart = batch_kernel(m).certified_counts(np.array([m.q_example_float]))
        >>> counts.tolist(), int((chart[0] >= 0).sum())
        ([6], 6)
        """
        Q = np.ascontiguousarray(Q, dtype=float)
        n = Q.shape[0]
        counts = np.empty(n, dtype=np.int8)
        lo = np.full((n, _MAX), np.nan)
        hi = np.full((n, _MAX), np.nan)
        chart = np.full((n, _MAX), -1, dtype=np.int8)
        if n > _SERIAL_ROWS:
            _generic_loop("run_counts")(Q, *self.tables.arrays(), counts, lo, hi, chart)
        elif n:
            self._counts_serial(Q, counts, lo, hi, chart)
        return counts, lo, hi, chart

    def _counts_serial(self, Q, counts, lo, hi, chart):
        """The rows of ``run_counts`` one by one from Python, through the same compiled steps
        (``design_row``, ``eliminate_row``, ``count_real_roots_row``): a few rows (the per-call
        float path's proof) cost microseconds here, where starting the parallel loop's threads
        can cost milliseconds on a loaded machine."""
        expo, coef, cerr, nmono, trig, plan = self.tables.arrays()
        buf = np.empty(48 + ELIMINATION_ROW_SIZE)
        Ce = np.zeros(24)
        eout = np.zeros(ELIMINATION_ROW_SIZE)
        ework = np.empty(ELIMINATION_WORK_SIZE + 8)
        iwork = np.empty(ISOLATE_WORK_SIZE)
        for r in range(Q.shape[0]):
            design_row(Q[r], expo, coef, cerr, nmono, trig, True, buf, Ce, ework)
            d = eliminate_row(buf, Ce, plan, buf[48:], eout, ework, True)
            counts[r] = count_real_roots_row(buf[48 + ROW_F:], eout[ROW_F:], d, lo[r], hi[r], chart[r], iwork)


_SOURCE = _HEADER + _LOOP_SOURCE + _COUNTS_SOURCE
_RUN = {}                  # the compiled generic loops per cache directory in effect, per process


def _generic_loop(name):
    """The compiled generic loop ``name``, loaded from the private cache (compiled once per
    installation) and then kept for the process; a change of ``$IMAGESPACE_CACHE`` loads it from
    there."""
    key = (kernel_cache_dir(), name)
    if key not in _RUN:
        _RUN[key] = _compile(_SOURCE, name)
    return _RUN[key]


def build_kernel(manipulator):
    """The batch kernel of a numeric design, or None where the kernel does not apply (no numba,
    a PP dyad, a Cramer denominator vanishing identically): the generic compiled loop bound to
    the design's :func:`design_tables`. No per-design code is generated or compiled.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import build_kernel, HAVE_NUMBA
    >>> k = build_kernel(isp.examples.general_3rpr())
    >>> (k is not None) == HAVE_NUMBA
    True
    """
    if not HAVE_NUMBA:
        return None
    tables = design_tables(manipulator)
    if tables is None:
        return None
    return BatchKernel(tables, manipulator.tolerances)
