"""The derivative-cascade real-root finder of the batch kernel (:func:`real_roots_cascade`), and
the safeguarded Newton iteration (:func:`_monotone_root`) that refines each isolated root of the
kernel's rows."""

from __future__ import annotations

import math

import numpy as np

from ...core._numba import njit

# root-finder constants of real_roots_cascade (numerical-method knobs, not read from Tolerances: the
# cascade is called without a design, and its answers are checked by the row's later decisions)
_CRITICAL_STEP = 1e-9        # critical points (roots of a derivative) are polished to this step
_TOUCH_DUPLICATE = 1e-12     # a root touching the axis this close to a crossing root is that root
_UNIT_ROUNDOFF = 2.2e-16     # the double precision unit roundoff the rounding bounds below scale
_HORNER_ZERO = 4.5e-16       # |p(t)| below this * deg * sum|c_k||t|^k is zero within Horner's rounding
_BISECT_WIDTH = 4e-16        # a bracket narrower than this (relative) has converged: stopping width
_TOUCH_ZERO = 64 * _UNIT_ROUNDOFF  # a critical value below this * deg * scale touches the axis
_NEWTON_STEPS = 400          # most steps of the bracketed Newton iteration (bisection guarantees far fewer)


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
    return _bracketed_newton(c, deg, a, b, fa, fb, t, b - a, 0, coarse)


@njit(cache=True)
def _bracketed_newton(c, deg, a, b, fa, fb, t, width, it0, coarse):
    """The iteration of :func:`_monotone_root` from its step ``it0`` on, at the point ``t`` of the
    bracket ``[a, b]`` (``width``: the bracket's width at the last safeguard check): the lockstep
    kernel runs the first steps of every root of a block together and finishes the few slow ones
    here."""
    for it in range(it0, _NEWTON_STEPS):
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
