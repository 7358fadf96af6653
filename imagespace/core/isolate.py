r"""Certified real-root counts of binary forms inside numba: Bernstein--Descartes isolation with a
rigorous error bound on every coefficient.

A binary form ``F(x0, x1) = sum_k F[k] x0**(d-k) x1**k`` (``d <= 6``) whose coefficients are known
only up to bounds (the exact form lies in ``F[k] +- E[k]``; ``E = 0`` means the floats are exact
binary rationals) has finitely many real roots on the projective line. :func:`count_real_roots_row`
proves their number and isolates each of them, or answers ``-1`` (undecided); it allocates nothing
and is meant to run per row inside another compiled kernel. :func:`certified_root_counts` is the
numpy-facing batch wrapper (parallel over rows).

Method
------
The projective line is covered by two charts:

* chart 0, ``t = x1/x0`` on the closed interval ``[-1, 1]``: ``p(t) = F(1, t)``;
* chart 1, ``s = x0/x1`` on the open interval ``(-1, 1)``: ``p(s) = F(s, 1)``
  (the points ``t = +-1`` and ``s = +-1`` coincide and belong to chart 0; ``x0 = 0`` is ``s = 0``).

On each chart the polynomial is written in the Bernstein basis of degree 6 on ``[-1, 1]`` (a form
of degree ``d < 6`` is elevated exactly: ``x0**(6-d) F`` on chart 0, ``x1**(6-d) F`` on chart 1,
which are the same polynomials there): with barycentric ``(y0, y1) = ((1-t)/2, (1+t)/2)``, so that
``1 = y0 + y1`` and ``t = y1 - y0``, the form ``G(y0, y1) = F(y0 + y1, y1 - y0)`` (chart 1:
``F(y1 - y0, y0 + y1)``) has integer coefficients in ``F`` (:data:`BERNSTEIN_MATRIX`), and its
coefficient of ``y0**(6-i) y1**i`` divided by ``binomial(6, i)`` is the Bernstein coefficient
``b_i``. This holds for every polynomial of degree ``<= 6``, so a vanishing leading coefficient (a
root at infinity of the chart) needs no special case. Isolation is the Bernstein form of the
Descartes / Collins--Akritas method: if ``p = sum b_i binomial(n, i) (t-a)**i (b-t)**(n-i) /
(b-a)**n`` on ``[a, b]``, then with ``x = (t-a)/(b-t)`` the roots of ``p`` in the open interval
``(a, b)`` are the positive roots of ``sum b_i binomial(n, i) x**i``, so by Descartes' rule of signs
their number (with multiplicity) is at most the number ``V`` of sign variations of ``b_0, ...,
b_n`` and has its parity. ``V = 0`` proves no root in ``(a, b)``; ``V = 1`` proves exactly one root
there, and that it is simple. Intervals with ``V >= 2`` are split by de Casteljau's algorithm at
``a + lam (b - a)`` (``lam = 1/2``, or ``7/16, 9/16, 3/8, 5/8`` when the sign of the value at the
midpoint cannot be certified); de Casteljau gives the Bernstein coefficients on both parts, and
the value at the split point is their common end coefficient.

Rigour
------
Each Bernstein coefficient is carried as a float ``c_i`` with a bound ``e_i`` such that the
coefficient of the exact form (any form in the box) is in ``[c_i - e_i, c_i + e_i]``:

* unless ``2**-300 <= max |F| <= 2**300``, the input is scaled by a power of two (exact; a scaled
  coefficient that becomes subnormal loses at most ``2**-1075``, covered by the floor below);
* the conversion ``b_i = (sum_k N_ik F_k) / binomial(6, i)`` has the inner-product bound
  ``gamma_{d+1} sum_k |N_ik| |F_k|`` (Higham, *Accuracy and Stability of Numerical Algorithms*,
  eq. 3.5) plus ``u |b_i|`` for the division, and the coefficient box contributes
  ``sum_k |N_ik| E_k / binomial(6, i)``;
* a de Casteljau step ``S = fl(fl(mu x) + fl(lam y))`` (``mu = 1 - lam``, exact for these dyadic
  ``lam``) is a convex combination, so the bound becomes ``mu e_x + lam e_y`` plus its rounding
  error, at most ``u (|fl(mu x)| + |fl(lam y)| + |S|)`` (each rounded result ``r`` of an exact ``z``
  satisfies ``|r - z| <= u |r|`` outside the subnormal range); for ``lam = 1/2``,
  ``S = fl(x + y) / 2`` and the rounding error is at most ``u |S|``;
* every bound is itself computed in floating point from non-negative terms by monotone
  operations, so its computed value is at least the exact one divided by ``(1 + u)**k`` after
  ``k`` operations (``k <= 36`` along the six levels of one split, ``k <= 20`` in the conversion);
  each bound is therefore multiplied by ``1 + 2**-46`` (more than ``(1 + u)**40``) once per split
  or conversion and increased by ``2**-1000``, which covers the absolute error of at most
  ``2**-1075`` per operation in the subnormal range (``u = 2**-53``, round to nearest). The floor
  is a normal number: arithmetic on subnormal operands is slow on common processors.

Signs are then decided with exact float comparisons: a coefficient is certainly positive when
``c > e``, certainly negative when ``c < -e``, and may be zero or either sign otherwise. Over every
form in the box, the sign sequence of the Bernstein coefficients ranges over the sequences allowed by
these intervals; a node is accepted only when **every** allowed sequence gives the same verdict:
both end coefficients (the values at the interval's ends) of certain, equal sign and no interior
coefficient able to take the other sign (``V_max = 0``: no root), or certain opposite end signs and
no interior pair that can realise a second and third variation (``V_max = 1``: exactly one simple
root). Since split points have certified non-zero values, no root sits on a split point, and the
open subintervals together with the certified ends partition each chart: the count is the number
of accepted one-root nodes. Split points are dyadic and exactly representable (the number of bits
of the interval ends is tracked, ``<= 52``), so the Bernstein coefficients describe exactly the
reported intervals.

Every reported interval holds exactly one root. Intervals of one chart are pairwise disjoint (a
one-root node touching the previous interval, or touching ``s = +-1`` in chart 1, is split further,
first at 7/8 of its width from the other end), and sorted by chart then ``lo``.

The answer is ``-1`` (undecided) for NaN or infinite input, a degree outside ``1..6``, a form whose
box contains zero at ``t = +-1`` (a root at, or too close to, the chart boundary), a split point
whose value keeps an uncertain sign for every ``lam``, more than :data:`MAX_SPLITS` splits, or
interval ends that would need more than 52 bits (roots closer than about ``1e-14``, double roots,
or a box that contains forms with double roots). ``-1`` is never a wrong answer; every other
answer is proven.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import as_float_array
from ..exceptions import InputError
from ._numba import njit, prange

__all__ = ["count_real_roots_row", "certified_root_counts", "ISOLATE_WORK_SIZE", "MAX_DEGREE", "GRID_FIELDS"]

#: Largest degree :func:`count_real_roots_row` handles (the scratch layout is sized for it).
MAX_DEGREE = 6

# -- numerical-method knobs (none decides an answer: exceeding one only gives up with -1) ---------
#: Most bits of the dyadic interval ends (the ends stay exactly representable, so the Bernstein
#: coefficients describe exactly the reported intervals); the narrowest interval is 2**-51 wide.
MAX_BITS = 52
#: Most de Casteljau splits per row before giving up (a box of uncertain coefficients could
#: otherwise make the subdivision tree grow exponentially).
MAX_SPLITS = 400

UNIT_ROUNDOFF = 2.0**-53                       # unit roundoff (round to nearest)
BOUND_INFLATE = 1.0 + 2.0**-46              # inflation of each computed bound: covers (1 + u)**40
BOUND_TINY = 2.0**-1000              # floor added to each bound, a normal number (subnormal operands are slow)
BOUND_GAMMA = 8 * UNIT_ROUNDOFF                     # >= gamma_{d+1} = (d+1)u / (1 - (d+1)u) for d <= 6

# split parameters lam = num / 2**r (num odd, < 16), tried in order until the split point's sign
# is certain; a one-root node that must be cut off an excluded end tries _EDGE_LAM (or
# 1 - _EDGE_LAM) first. With a, b in 2**-bits Z, |a|, |b| <= 1, the split point a + lam (b - a)
# is computed exactly when bits + 4 <= 52 (num (b - a) has at most bits + 5 significant bits)
_LAM = np.array([0.5, 0.4375, 0.5625, 0.375, 0.625])
_LAM_BITS = np.array([1, 4, 4, 3, 3], dtype=np.int64)
_EDGE_LAM = 0.875
_EDGE_BITS = 3
# |F| within these bounds: the floats are used unscaled (no over- or underflow can occur)
NO_SCALING_BELOW = 2.0**-300
NO_SCALING_ABOVE = 2.0**300

# layout of one node in the scratch array: a, b, bits, c_0..c_MAX, e_0..e_MAX
_C = 3
_E = 3 + MAX_DEGREE + 1
_STRIDE = 3 + 2 * (MAX_DEGREE + 1)
# a depth-first stack: one node per bit level plus the root and two scratch nodes for a split
_SLOTS = MAX_BITS + 4
_SCALED = _SLOTS * _STRIDE          # the scaled F and E (2 * (MAX_DEGREE + 1) floats)
SLOT_HEAP_INDEX = _SCALED + 2 * (MAX_DEGREE + 1)   # per stack slot: the node's heap index in a split grid (0: none)
#: Length of the float64 scratch array ``work`` that :func:`count_real_roots_row` needs.
ISOLATE_WORK_SIZE = SLOT_HEAP_INDEX + _SLOTS

# -- the split grid of the lockstep kernel (imagespace.solve.kernel.lockstep) ----------------------
# For a block of ``lanes`` rows side by side, the Bernstein coefficients of every node of the
# first levels of the subdivision tree, split at 1/2 from the chart's root node: node ``h`` of chart
# ``ch`` (heap order: root 1, children 2h and 2h + 1) is row ``ch * 2 * nleaf + h`` of the grid, and
# field ``f`` of the block's row ``lane`` its column ``f * lanes + lane``: c_0..c_6 in fields 0..6,
# their bounds in 7..13 and, for an inner node, the certain sign of its split point (the children's
# common end coefficient) in 14.
# The depth-first search of a row takes a node's children from there instead of splitting it
# (the same floats: the lockstep kernel's _half_split_block is _split at 1/2, lane by lane).
#: Rows of one node in the split grid.
GRID_FIELDS = 15


def _bernstein_matrix():
    """``N[i, k]``: the coefficient of ``y0**(6-i) y1**i`` in ``(y0 + y1)**(6-k) (y1 - y0)**k``
    (integers, exact in floats), and ``binomial(6, i)``."""
    n = MAX_DEGREE
    N = np.zeros((n + 1, n + 1))
    for k in range(n + 1):
        # polynomials in y1 with y0 = 1: (1 + y1)**(n-k) * (y1 - 1)**k, ascending powers of y1
        poly = np.array([1], dtype=np.int64)
        for _ in range(n - k):
            poly = np.convolve(poly, [1, 1])
        for _ in range(k):
            poly = np.convolve(poly, [-1, 1])
        N[:, k] = poly
    return N, np.array([math.comb(n, i) for i in range(n + 1)], dtype=float)


#: ``BERNSTEIN_MATRIX[i, k]``: integer weight of ``F[k]`` in ``binomial(6, i) b_i``, the
#: Bernstein coefficients of degree 6 on ``[-1, 1]`` of chart 0 (a form of degree ``d < 6`` is
#: elevated: ``F[k] = 0`` for ``k > d``; chart 1 uses the reversed coefficients ``F[d - k]``).
BERNSTEIN_MATRIX, BINOM = _bernstein_matrix()


@njit(cache=True)
def _bound(x):
    """A computed non-negative bound, inflated to cover its own rounding (module docstring)."""
    return x * BOUND_INFLATE + BOUND_TINY


@njit(cache=True)
def _certain_sign(c, e):
    """+1 / -1 when ``[c - e, c + e]`` excludes zero (exact comparisons), else 0."""
    if c > e:
        return 1
    if c < -e:
        return -1
    return 0


@njit(cache=True)
def _to_bernstein(work, d, reverse):
    """Bernstein coefficients (degree 6) and bounds on [-1, 1] of chart ``reverse`` into node 0,
    from the scaled coefficients and bounds in ``work``."""
    for i in range(MAX_DEGREE + 1):
        acc = 0.0
        mag = 0.0
        box = 0.0
        for k in range(d + 1):
            kk = d - k if reverse else k
            w = BERNSTEIN_MATRIX[i, k]
            g = work[_SCALED + kk]
            acc += w * g
            aw = abs(w)
            mag += aw * abs(g)
            box += aw * work[_SCALED + MAX_DEGREE + 1 + kk]
        binom = BINOM[i]
        b = acc / binom
        work[_C + i] = b
        work[_E + i] = _bound((box + BOUND_GAMMA * mag) / binom + UNIT_ROUNDOFF * abs(b))
    work[0] = -1.0
    work[1] = 1.0
    work[2] = 0.0


@njit(cache=True)
def _opposite(s0, c, e):
    """The coefficient ``c +- e`` may have the sign ``-s0``."""
    return s0 * c < e


@njit(cache=True)
def _same(s0, c, e):
    """The coefficient ``c +- e`` may have the sign ``s0``."""
    return s0 * c > -e


@njit(cache=True)
def _classify(c, e):
    """0: no root in the open interval; 1: exactly one (simple) root; 2: undecided (split).

    ``c``, ``e``: the 7 Bernstein coefficients and their bounds; the end coefficients have
    certain signs (checked when the node was made). With equal end signs ``s0``, ``V_max = 0``
    unless an interior coefficient may have the sign ``-s0``; with opposite end signs,
    ``V_max = 1`` unless an interior coefficient that may be ``-s0`` is followed by one that
    may be ``s0`` (then ``s0, ..., -s0, ..., s0, ..., -s0`` is possible: ``V_max >= 3``)."""
    s0 = 1.0 if c[0] > 0 else -1.0
    sd = 1.0 if c[6] > 0 else -1.0
    o1 = _opposite(s0, c[1], e[1])
    o2 = _opposite(s0, c[2], e[2])
    o3 = _opposite(s0, c[3], e[3])
    o4 = _opposite(s0, c[4], e[4])
    if s0 == sd:
        if o1 or o2 or o3 or o4 or _opposite(s0, c[5], e[5]):
            return 2
        return 0
    m5 = _same(s0, c[5], e[5])
    m4 = m5 or _same(s0, c[4], e[4])
    m3 = m4 or _same(s0, c[3], e[3])
    m2 = m3 or _same(s0, c[2], e[2])
    if (o1 and m2) or (o2 and m3) or (o3 and m4) or (o4 and m5):
        return 2
    return 1


@njit(cache=True)
def _lerp(x, y, ex, ey, lam, mu, half):
    """``mu x + lam y`` rounded, and its bound before inflation (module docstring)."""
    if half:
        s = (x + y) * 0.5                       # fl(x + y) / 2: error <= u |s|
        return s, (ex + ey) * 0.5 + UNIT_ROUNDOFF * abs(s)
    p1 = mu * x
    p2 = lam * y
    s = p1 + p2
    return s, mu * ex + lam * ey + UNIT_ROUNDOFF * (abs(p1) + abs(p2) + abs(s))


@njit(cache=True)
def _split(c, e, lam):
    """de Casteljau at ``lam`` on the degree-6 Bernstein coefficients ``c`` with bounds ``e``:
    ``(left c, left e, right c, right e)``; the bounds of the new coefficients are inflated once
    per split (each went through at most 6 levels of 4 rounded operations)."""
    mu = 1.0 - lam
    h = lam == 0.5
    c0, c1, c2, c3, c4, c5, c6 = c
    e0, e1, e2, e3, e4, e5, e6 = e
    p0, ep0 = _lerp(c0, c1, e0, e1, lam, mu, h)
    p1, ep1 = _lerp(c1, c2, e1, e2, lam, mu, h)
    p2, ep2 = _lerp(c2, c3, e2, e3, lam, mu, h)
    p3, ep3 = _lerp(c3, c4, e3, e4, lam, mu, h)
    p4, ep4 = _lerp(c4, c5, e4, e5, lam, mu, h)
    p5, ep5 = _lerp(c5, c6, e5, e6, lam, mu, h)
    q0, eq0 = _lerp(p0, p1, ep0, ep1, lam, mu, h)
    q1, eq1 = _lerp(p1, p2, ep1, ep2, lam, mu, h)
    q2, eq2 = _lerp(p2, p3, ep2, ep3, lam, mu, h)
    q3, eq3 = _lerp(p3, p4, ep3, ep4, lam, mu, h)
    q4, eq4 = _lerp(p4, p5, ep4, ep5, lam, mu, h)
    r0, er0 = _lerp(q0, q1, eq0, eq1, lam, mu, h)
    r1, er1 = _lerp(q1, q2, eq1, eq2, lam, mu, h)
    r2, er2 = _lerp(q2, q3, eq2, eq3, lam, mu, h)
    r3, er3 = _lerp(q3, q4, eq3, eq4, lam, mu, h)
    s0, es0 = _lerp(r0, r1, er0, er1, lam, mu, h)
    s1, es1 = _lerp(r1, r2, er1, er2, lam, mu, h)
    s2, es2 = _lerp(r2, r3, er2, er3, lam, mu, h)
    v0, ev0 = _lerp(s0, s1, es0, es1, lam, mu, h)
    v1, ev1 = _lerp(s1, s2, es1, es2, lam, mu, h)
    w0, ew0 = _lerp(v0, v1, ev0, ev1, lam, mu, h)
    ew0 = _bound(ew0)
    return ((c0, p0, q0, r0, s0, v0, w0),
            (e0, _bound(ep0), _bound(eq0), _bound(er0), _bound(es0), _bound(ev0), ew0),
            (w0, v1, s2, r3, q4, p5, c6),
            (ew0, _bound(ev1), _bound(es2), _bound(er3), _bound(eq4), _bound(ep5), e6))


@njit(cache=True)
def _load(work, o):
    c = (work[o + _C], work[o + _C + 1], work[o + _C + 2], work[o + _C + 3], work[o + _C + 4],
         work[o + _C + 5], work[o + _C + 6])
    e = (work[o + _E], work[o + _E + 1], work[o + _E + 2], work[o + _E + 3], work[o + _E + 4],
         work[o + _E + 5], work[o + _E + 6])
    return c, e


@njit(cache=True)
def _store(work, o, a, b, bits, c, e):
    work[o] = a
    work[o + 1] = b
    work[o + 2] = bits
    work[o + 3] = c[0]
    work[o + 4] = c[1]
    work[o + 5] = c[2]
    work[o + 6] = c[3]
    work[o + 7] = c[4]
    work[o + 8] = c[5]
    work[o + 9] = c[6]
    work[o + 10] = e[0]
    work[o + 11] = e[1]
    work[o + 12] = e[2]
    work[o + 13] = e[3]
    work[o + 14] = e[4]
    work[o + 15] = e[5]
    work[o + 16] = e[6]


@njit(cache=True)
def count_real_roots_row(F, E, d, lo, hi, chart, work):
    """Proven number of distinct real roots of one binary form with uncertain coefficients, and
    an isolating interval for each root.

    The form is ``sum_k F[k] x0**(d-k) x1**k``; its exact coefficients are only known to lie in
    ``[F[k] - E[k], F[k] + E[k]]``. The count is proven for **every** form in that box (the
    method and its rounding-error analysis are in the module docstring), or the answer is -1.
    Allocates nothing (compiled with numba; call it per row inside a ``prange`` loop).

    Parameters
    ----------
    F, E : float64 arrays, length >= d + 1
        Coefficients and their rigorous error bounds (``E >= 0``; ``E = 0`` takes the floats as
        the exact binary rationals they are). ``F[d]`` may be small or zero (roots at
        ``x0 = 0``).
    d : int
        Degree of the form, ``1 <= d <= 6``.
    lo, hi : float64 arrays, length >= d
        Output: the isolating interval ``[lo[j], hi[j]]`` of root ``j``.
    chart : integer array, length >= d
        Output: the chart of root ``j``: 0 for ``t = x1/x0`` with ``[lo, hi]`` inside ``[-1, 1]``,
        1 for ``s = x0/x1`` with ``[lo, hi]`` inside the open ``(-1, 1)`` (``t = +-1`` belong to
        chart 0, ``x0 = 0`` is ``s = 0``). Roots are sorted by chart, then by ``lo``; each
        interval holds exactly one root, simple, and the intervals of a chart are disjoint.
    work : float64 array, length >= ISOLATE_WORK_SIZE
        Scratch space (overwritten).

    Returns
    -------
    int
        The number of distinct real roots on the projective line, proven, with every real root
        simple; -1 if undecided (non-finite or negative input, ``d`` outside ``1..6``, a box
        that contains the zero form or a form vanishing at ``t = +-1``, a double or nearly
        double root, roots too close for the bounds, or the work budget :data:`MAX_SPLITS`
        exhausted). Entries ``j >= count`` of ``lo``, ``hi``, ``chart`` are left unspecified.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.isolate import count_real_roots_row, ISOLATE_WORK_SIZE
    >>> F = np.array([-2.0, 0.0, 1.0])        # x1^2 - 2 x0^2: t = +-sqrt(2), i.e. s = +-1/sqrt(2)
    >>> lo, hi = np.empty(2), np.empty(2)
    >>> chart = np.empty(2, dtype=np.int8)
    >>> work = np.empty(ISOLATE_WORK_SIZE)
    >>> count_real_roots_row(F, np.zeros(3), 2, lo, hi, chart, work)
    2
    >>> chart.tolist(), bool(lo[1] <= 2**-0.5 <= hi[1])
    ([1, 1], True)
    >>> count_real_roots_row(np.array([1.0, -2.0, 1.0]), np.zeros(3), 2, lo, hi, chart, work)
    -1
    """
    if d < 1 or d > MAX_DEGREE:
        return -1
    big = 0.0
    for k in range(d + 1):
        f = F[k]
        e = E[k]
        if not (math.isfinite(f) and math.isfinite(e)) or not e >= 0.0:
            return -1
        if abs(f) > big:
            big = abs(f)
    if big == 0.0:
        return -1
    # far from over- and underflow the floats are used as they are; otherwise they are scaled by
    # a power of two so that max |F| is in [1/2, 1) (the Bernstein coefficients are at most
    # 2**6 times larger than max |F|)
    s1 = 1.0
    s2 = 1.0
    if not NO_SCALING_BELOW <= big <= NO_SCALING_ABOVE:
        ex = math.frexp(big)[1]
        s1 = math.ldexp(1.0, -(ex // 2))
        s2 = math.ldexp(1.0, -ex - (-(ex // 2)))
    for k in range(d + 1):
        work[_SCALED + k] = (F[k] * s1) * s2
        eg = ((E[k] * s1) * s2) * (1.0 + 2.0 * UNIT_ROUNDOFF) + BOUND_TINY
        if not math.isfinite(eg):
            return -1
        work[_SCALED + MAX_DEGREE + 1 + k] = eg
    count = 0
    splits = 0
    for ch in range(2):
        _to_bernstein(work, d, ch == 1)
        if (_certain_sign(work[_C], work[_E]) == 0
                or _certain_sign(work[_C + MAX_DEGREE], work[_E + MAX_DEGREE]) == 0):
            return -1
        count, splits = _descend(work, ch, count, splits, d, lo, hi, chart, work[:GRID_FIELDS].reshape((1, GRID_FIELDS)),
                                 0, 1)
        if count < 0:
            return -1
    return count


@njit(cache=True)
def _descend(work, ch, count, splits, d, lo, hi, chart, grid, lane, nleaf):
    """The depth-first Bernstein--Descartes search of chart ``ch`` from the root node in ``work``
    (module docstring): appends the roots found to ``lo, hi, chart`` from ``count`` on and returns
    ``(count, splits)``, count -1 when undecided. A node of heap index ``h < nleaf`` split at 1/2
    takes its children from column ``lane`` of the split ``grid`` (see ``GRID_FIELDS``); the row
    kernel passes ``nleaf = 1`` (no grid)."""
    work[SLOT_HEAP_INDEX] = 1.0
    start = count
    count, splits, _ = search_chart(work, ch, count, splits, np.inf, d, lo, hi, chart, grid, lane, nleaf)
    if count < 0:
        return -1, splits
    # roots were found right to left: reverse this chart's entries
    i, j = start, count - 1
    while i < j:
        lo[i], lo[j] = lo[j], lo[i]
        hi[i], hi[j] = hi[j], hi[i]
        i += 1
        j -= 1
    return count, splits


@njit(cache=True)
def search_chart(work, ch, count, splits, last_lo, d, lo, hi, chart, grid, lane, nleaf):
    """The depth-first search of :func:`_descend` from the node in slot 0 of ``work`` (its heap
    index in the split grid at ``work[SLOT_HEAP_INDEX]``, 0 when it is not a grid node), the roots appended
    right to left from ``count`` on, ``last_lo`` the left end of the last root found (to its
    right). Returns ``(count, splits, last_lo)``, count -1 when undecided."""
    lanes = grid.shape[1] // GRID_FIELDS
    top = 0
    gbase = ch * 2 * nleaf
    while top >= 0:
        o = top * _STRIDE
        a = work[o]
        b = work[o + 1]
        bits = int(work[o + 2])
        c, e = _load(work, o)
        kind = _classify(c, e)
        if kind == 0:
            top -= 1
            continue
        if kind == 1 and b != last_lo and not (ch == 1 and (a == -1.0 or b == 1.0)):
            if count >= d:              # impossible for a degree-d form; never report it
                return -1, splits, last_lo
            lo[count] = a
            hi[count] = b
            chart[count] = ch
            count += 1
            last_lo = a
            top -= 1
            continue
        # split: the left part replaces the node, the right part goes on top of it. A
        # one-root node that touches an excluded end is cut close to that end first
        splits += 1
        if splits > MAX_SPLITS:
            return -1, splits, last_lo
        first = 0.5
        if kind == 1:
            touch_hi = b == last_lo or (ch == 1 and b == 1.0)
            touch_lo = ch == 1 and a == -1.0
            if touch_hi and not touch_lo:
                first = _EDGE_LAM
            elif touch_lo and not touch_hi:
                first = 1.0 - _EDGE_LAM
        h = int(work[SLOT_HEAP_INDEX + top])
        if first == 0.5 and 0 < h < nleaf and bits + 1 <= MAX_BITS:
            if grid[gbase + h, 14 * lanes + lane] != 0.0:   # the split point's sign is certain: children from the grid
                m = a + 0.5 * (b - a)
                store_grid(work, o, a, m, bits + 1, grid, gbase + 2 * h, lanes, lane)
                store_grid(work, o + _STRIDE, m, b, bits + 1, grid, gbase + 2 * h + 1, lanes, lane)
                work[SLOT_HEAP_INDEX + top] = 2.0 * h
                work[SLOT_HEAP_INDEX + top + 1] = 2.0 * h + 1.0
                top += 1
                continue
        done = False
        for j in range(_LAM.shape[0] + 1):
            if j == 0:
                lam = first
                r = 1 if first == 0.5 else _EDGE_BITS
            else:
                lam = _LAM[j - 1]
                r = _LAM_BITS[j - 1]
                if lam == first:
                    continue
            # exact split point a + lam (b - a): lam = num / 2**r with num < 16 needs
            # bits + 4 <= MAX_BITS, lam = 1/2 needs bits + 1 <= MAX_BITS (see _LAM)
            if bits + (1 if lam == 0.5 else 4) > MAX_BITS:
                continue
            lc, le, rc, re = _split(c, e, lam)
            if _certain_sign(rc[0], re[0]) != 0:
                m = a + lam * (b - a)
                _store(work, o, a, m, bits + r, lc, le)
                _store(work, o + _STRIDE, m, b, bits + r, rc, re)
                work[SLOT_HEAP_INDEX + top] = 0.0
                work[SLOT_HEAP_INDEX + top + 1] = 0.0
                done = True
                break
        if not done:
            return -1, splits, last_lo
        top += 1
    return count, splits, last_lo


@njit(cache=True)
def store_grid(work, o, a, b, bits, grid, node, lanes, lane):
    """Store node ``node`` of the block's row ``lane`` of the split grid in slot ``o``."""
    work[o] = a
    work[o + 1] = b
    work[o + 2] = bits
    for i in range(2 * (MAX_DEGREE + 1)):
        work[o + 3 + i] = grid[node, i * lanes + lane]


@njit(cache=True, parallel=True)
def _batch(F, E, d, counts, intervals, charts):
    n = F.shape[0]
    nblocks = min(n, 64)
    for blk in prange(nblocks):
        first = blk * n // nblocks
        last = (blk + 1) * n // nblocks
        work = np.empty(ISOLATE_WORK_SIZE)
        lo = np.empty(d)
        hi = np.empty(d)
        ch = np.empty(d, dtype=np.int8)
        for r in range(first, last):
            k = count_real_roots_row(F[r], E[r], d, lo, hi, ch, work)
            counts[r] = k
            for j in range(max(k, 0)):
                intervals[r, j, 0] = lo[j]
                intervals[r, j, 1] = hi[j]
                charts[r, j] = ch[j]


def certified_root_counts(F, E=None):
    """Proven real-root counts and isolating intervals for a batch of binary forms (compiled,
    parallel over rows).

    Row ``r`` is the form ``sum_k F[r, k] x0**(d-k) x1**k``, its exact coefficients known to lie
    in ``F +- E``. Each row goes through :func:`count_real_roots_row` (Bernstein--Descartes
    isolation with rigorous error bounds); rows it cannot decide get -1, to be decided some other
    way (e.g. exactly, :func:`imagespace.core.certify.certify_real_roots_batch`).

    Parameters
    ----------
    F : (n, d+1) array_like of float
        ``F[:, k]`` multiplies ``x0**(d-k) x1**k``; ``1 <= d <= 6``. Rows with NaN or infinite
        entries are undecided.
    E : (n, d+1) array_like of float, optional
        Rigorous bounds ``|exact - F| <= E``, non-negative. Default 0: the floats are the exact
        coefficients.

    Returns
    -------
    counts : (n,) int8
        Distinct real roots on the projective line (every one of them proven simple); -1 where
        undecided.
    intervals : (n, d, 2) float
        ``intervals[r, j]`` isolates root ``j`` of row ``r`` in the chart ``chart[r, j]``; NaN in
        unused slots.
    chart : (n, d) int8
        0: the interval is of ``t = x1/x0``, inside ``[-1, 1]``; 1: of ``s = x0/x1``, inside the
        open ``(-1, 1)``; -1 in unused slots. Roots are sorted by chart, then by interval.

    Raises
    ------
    InputError
        ``F`` is not of shape ``(n, d+1)`` with ``1 <= d <= 6``; ``E`` has another shape than
        ``F`` or a negative entry.
    TypeError
        ``F`` or ``E`` is not a numeric array.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.isolate import certified_root_counts
    >>> F = np.array([[-2.0, 0.0, 1.0],      # x1^2 - 2 x0^2: two roots
    ...               [1.0, 0.0, 1.0],       # x0^2 + x1^2: none
    ...               [1.0, -2.0, 1.0]])     # (x1 - x0)^2: a double root, undecided
    >>> counts, intervals, chart = certified_root_counts(F)
    >>> counts.tolist(), chart[0].tolist()
    ([2, 0, -1], [1, 1])
    >>> bool(np.all(np.isnan(intervals[1])))
    True
    """
    F = as_float_array(F, "F", finite=False)          # non-finite rows are undecided
    if F.ndim != 2 or not 2 <= F.shape[1] <= MAX_DEGREE + 1:
        raise InputError(f"F must have shape (n, d+1) with 1 <= d <= {MAX_DEGREE}, got shape {F.shape}")
    if E is None:
        E = np.zeros_like(F)
    else:
        E = as_float_array(E, "E", finite=False)
        if E.shape != F.shape:
            raise InputError(f"E must have the shape of F {F.shape}, got shape {E.shape}")
        if np.any(E < 0):
            raise InputError("E must hold non-negative error bounds, got a negative entry")
    n, d1 = F.shape
    d = d1 - 1
    counts = np.full(n, -1, dtype=np.int8)
    intervals = np.full((n, d, 2), np.nan)
    chart = np.full((n, d), -1, dtype=np.int8)
    if n:
        _batch(np.ascontiguousarray(F), np.ascontiguousarray(E), d, counts, intervals, chart)
    return counts, intervals, chart
