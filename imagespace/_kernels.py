"""Compiled kernels (numba, cached) with pure-numpy fallbacks.

``real_roots_cascade`` finds the real roots of a batch of real polynomials by the derivative
cascade: the real roots of ``p^(k)`` split the real line into intervals on which ``p^(k-1)`` is
monotone, so each interval holds at most one root, found by safeguarded Newton-bisection inside
the Cauchy bound. Only real roots are ever computed (no eigenvalues). A root that touches the axis
without a sign change (a double root, or a complex pair within rounding of the real axis) is
reported at the critical point and flagged ``suspect``: a float computation cannot tell those
apart, so callers send such rows to the certified path.
"""

from __future__ import annotations

import numpy as np

try:  # numba is optional: the kernels fall back to plain Python/numpy loops without it
    from numba import njit, prange
    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised only where numba is missing
    HAVE_NUMBA = False
    prange = range

    def njit(*args, **kwargs):
        def wrap(f):
            return f
        return wrap(args[0]) if args and callable(args[0]) else wrap

__all__ = ["real_roots_cascade", "HAVE_NUMBA"]


@njit(cache=True)
def _horner(c, deg, t):
    v = c[deg]
    for k in range(deg - 1, -1, -1):
        v = v * t + c[k]
    return v


@njit(cache=True)
def _abs_horner(c, deg, t):
    v = abs(c[deg])
    at = abs(t)
    for k in range(deg - 1, -1, -1):
        v = v * at + abs(c[k])
    return v


@njit(cache=True)
def _solve_monotone(c, deg, a, b, fa, fb):
    """Root of a polynomial monotone on [a, b] with fa * fb < 0: Newton kept inside a bracket."""
    t = 0.5 * (a + b)
    for _ in range(200):
        f = _horner(c, deg, t)
        if f == 0.0:
            return t
        if (f < 0.0) == (fa < 0.0):
            a, fa = t, f
        else:
            b, fb = t, f
        # derivative
        d = deg * c[deg]
        for k in range(deg - 1, 0, -1):
            d = d * t + k * c[k]
        tn = t - f / d if d != 0.0 else 0.5 * (a + b)
        if not (a < tn < b):
            tn = 0.5 * (a + b)
        if abs(tn - t) <= 4e-16 * max(1.0, abs(t)) or b - a <= 4e-16 * max(1.0, abs(a), abs(b)):
            return tn
        t = tn
    return t


@njit(cache=True)
def _cascade_row(coef, roots, suspect_out):
    """coef: (d+1,) with coef[d] != 0. Writes real roots into roots (NaN-padded); returns count."""
    d = coef.shape[0] - 1
    # derivative coefficient table: D[j, k] = coefficient of t^k in p^(j)
    D = np.zeros((d + 1, d + 1))
    for k in range(d + 1):
        D[0, k] = coef[k]
    for j in range(1, d + 1):
        for k in range(d + 1 - j):
            D[j, k] = D[j - 1, k + 1] * (k + 1)
    bound = 0.0
    for k in range(d):
        bound = max(bound, abs(coef[k] / coef[d]))
    bound = 1.0 + bound
    crit = np.empty(d + 2)
    ncrit = 0
    suspect = False
    # level d-1: linear
    for j in range(d - 1, -1, -1):
        deg = d - j
        c = D[j]
        pts = np.empty(ncrit + 2)
        pts[0] = -bound
        for i in range(ncrit):
            pts[i + 1] = crit[i]
        pts[ncrit + 1] = bound
        new = np.empty(deg)
        nnew = 0
        vals = np.empty(ncrit + 2)
        for i in range(ncrit + 2):
            vals[i] = _horner(c, deg, pts[i])
        for i in range(ncrit + 1):
            a, b = pts[i], pts[i + 1]
            fa, fb = vals[i], vals[i + 1]
            if b <= a:
                continue
            if fa == 0.0:
                continue
            if fa * fb < 0.0:
                new[nnew] = _solve_monotone(c, deg, a, b, fa, fb)
                nnew += 1
        # roots at critical points (touching or exactly zero)
        for i in range(1, ncrit + 1):
            # the size of the terms at max(|t|, 1): near t = 0 a double root's critical point is
            # off by ~eps absolutely, and the terms at t itself would be as small as p there
            scale = _abs_horner(c, deg, max(abs(pts[i]), 1.0))
            if abs(vals[i]) <= 64 * 2.2e-16 * deg * scale:
                dup = False
                for m in range(nnew):
                    if abs(new[m] - pts[i]) <= 1e-12 * max(1.0, abs(pts[i])):
                        dup = True
                if not dup:
                    new[nnew] = pts[i]
                    nnew += 1
                    if j == 0:
                        suspect = True
        # sort new roots -> next level's critical points
        for a_ in range(nnew):
            for b_ in range(a_ + 1, nnew):
                if new[b_] < new[a_]:
                    tmp = new[a_]
                    new[a_] = new[b_]
                    new[b_] = tmp
        ncrit = nnew
        for i in range(nnew):
            crit[i] = new[i]
    for i in range(roots.shape[0]):
        roots[i] = np.nan
    for i in range(ncrit):
        roots[i] = crit[i]
    suspect_out[0] = suspect
    return ncrit


@njit(cache=True)
def _cascade_batch(C, roots, counts, suspect):
    n = C.shape[0]
    flag = np.zeros(1, dtype=np.bool_)
    for i in range(n):
        counts[i] = _cascade_row(C[i], roots[i], flag)
        suspect[i] = flag[0]


def real_roots_cascade(C):
    """Real roots of a batch of polynomials ``sum_k C[:, k] t**k`` with non-zero leading coefficients.

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
        A root was taken at a critical point without a sign change (double root or a complex
        pair within rounding of the axis): decide such rows with the certified path.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace._kernels import real_roots_cascade
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
