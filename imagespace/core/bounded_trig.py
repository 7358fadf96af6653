"""Rigorous enclosures of ``cos q`` and ``sin q`` for float64 ``q``, compiled with numba.

:func:`cos_sin_bounded` returns, for one float ``q`` (an exact binary rational), floats ``c, s``
and bounds ``ec, es`` with ``|cos q - c| <= ec`` and ``|sin q - s| <= es`` as a mathematical
guarantee, in a few dozen floating-point operations and without allocation, so other numba
kernels can call it per row. :func:`cos_sin_enclosure` applies it to an array and hands the few
elements beyond the kernel's range (``|q| > Q_MAX``) to python-flint's arb.

Method and why the bounds are rigorous
--------------------------------------
Everything runs in IEEE binary64 with round-to-nearest. For a real ``x`` whose rounded value
``fl(x)`` is normal, ``|fl(x) - x| <= u |fl(x)|`` with ``u = 2**-53``; additions whose result is
subnormal are exact; a product that underflows errs by at most ``2**-1075`` in absolute value.
numba compiles without fast-math, so LLVM neither reassociates nor fuses a product and a sum
into an FMA (``tests/core/test_bounded_trig.py`` checks the machine code for FMA instructions).

1. **Tiny arguments** (``|q| < TINY = 2**-26``): ``c = 1``, ``s = q``;
   ``|sin q - q| <= |q|**3 / 6 < |q| 2**-54`` and ``|cos q - 1| <= q**2 / 2 < |q| 2**-27``. The
   bounds are these products (exact powers-of-two scalings, or subnormal with the error covered
   by adding ``2**-1074``). ``q = ±0`` is exact (bounds 0).
2. **Argument reduction** (Cody–Waite with three short parts): ``pi/2 = P1 + P2 + P3 + P4 +
   delta`` where ``P1, P2, P3`` are integers of at most 30 bits times powers of two (lsb
   ``2**-29``, ``2**-59``, ``2**-89``), ``P4`` is the double nearest the rest, and
   ``|delta| <= DELTA = 2**-144`` (the hard-coded constants are verified against a 300-bit arb
   value of ``pi`` by the tests). With ``k`` the integer nearest ``q * 2/pi`` (any integer would
   do for rigour; this one keeps ``|r| <= pi/4 + 2**-29``) and ``|q| <= Q_MAX = 2**22``, so
   ``|k| < 2**22``, the products ``k*P1, k*P2, k*P3`` have at most 52 significant bits and are
   exact; ``t4 = fl(k*P4)`` errs by at most ``u |t4|``. The main part ``H`` is
   ``((q - k P1) - k P2) - k P3`` in three rounded subtractions whose errors ``e1, e2, e3`` are
   recovered exactly by Knuth's TwoSum; the low part ``L = ((e1 + e2) + e3) - t4`` is rounded
   three times, each time by at most ``u`` times the computed partial sum. So, with
   ``r = q - k pi/2``, ``|r - (H + L)| <= Er = u (|e1 + e2| + |e1 + e2 + e3| + |L| + |t4|) +
   |k| DELTA`` (partial sums as computed). As ``|e_i| <= u |H_i|`` for the intermediate ``H_i``,
   ``Er`` is about ``2**-104 |r|`` plus ``2**-120``, also next to multiples of ``pi/2`` (there
   ``H_2`` and ``H_3`` are small too). No products other than the exact ones are needed, so
   Dekker's TwoProduct (Veltkamp splitting) is not used.
3. **Polynomials** on ``|H| <= RHO = 0.8``: ``sin H = H + H z p_s(z)`` and
   ``cos H = 1 + z p_c(z)`` with ``z = H*H`` and the Taylor coefficients ``(-1)**j / n!`` up to
   ``H**17`` and ``H**18``, each rounded once (error ``<= u`` relative), evaluated by Horner with a
   running bound: every computed quantity ``a`` carries ``ea >= |a - A|`` for its exact
   counterpart ``A``, with ``|ab - AB| <= |a| eb + (|b| + eb) ea`` plus ``u |fl(ab)|`` and
   ``|fl(a + b) - (A + B)| <= ea + eb + u |fl(a + b)|``. Lagrange's remainders add
   ``|H|**19 / 19! <= |H| RHO**18 / 19! = |H| K_SIN`` and ``|H|**20 / 20! <= K_COS``.
4. **The low part and the reduction error**: ``sin(H + d) = sin H + d cos H + R`` with
   ``|R| <= d**2 / 2`` (likewise for ``cos``); ``s_r = fl(S_H + fl(L C_H))`` and
   ``c_r = fl(C_H - fl(L S_H))``, their bounds adding ``|L|`` times the other function's bound,
   the two roundings, ``Er`` (``|d cos/dr| <= 1``) and ``(|L| + Er)**2 / 2``.
5. **Quadrant**: ``cos q`` and ``sin q`` are ``(c_r, s_r)``, ``(-s_r, c_r)``, ``(-c_r, -s_r)`` or
   ``(s_r, -c_r)`` for ``k mod 4 = 0, 1, 2, 3`` (exact sign changes and swaps).
6. **Rounding of the bounds themselves**: every bound is a sum of products of non-negative
   quantities built from fewer than 200 rounded operations, so its computed value is at least
   ``(1 - u)**200 > 1 - 2**-44`` times the exact expression, less underflow losses below
   ``2**-1067``; the final bounds are multiplied by ``SLACK = 1 + 2**-30`` and ``FLOOR = 2**-1000``
   is added, which covers both.

The resulting bounds are about ``3u`` relative to ``|c|`` and ``|s|`` (a few ulps), and absolute
``~2**-110`` where one of them is tiny (``q`` next to a multiple of ``pi/2``).

Beyond ``Q_MAX`` (and, as a safety net that cannot trigger, if ``|H| > RHO``) the kernel returns
libm's ``cos``/``sin`` clamped to ``[-1, 1]`` with the trivially rigorous bound ``2``; NaN and
infinite ``q`` give NaN values and infinite bounds. A bound of ``1`` or more therefore marks an
element the kernel did not enclose tightly; :func:`cos_sin_enclosure` recomputes those with arb.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import as_float_array
from ._numba import njit, prange

__all__ = ["cos_sin_bounded", "cos_sin_enclosure", "Q_MAX"]

#: Largest ``|q|`` the compiled reduction encloses tightly (``2**22``): ``|k| < 2**22`` keeps the
#: products with the 30-bit parts of ``pi/2`` exact. Larger finite ``q`` get the bound 2 from
#: :func:`cos_sin_bounded` and arb in :func:`cos_sin_enclosure`.
Q_MAX = 4194304.0

# Below TINY the Taylor terms after the first are below the bounds q * 2**-54 and q * 2**-27
# (numerical-method constant, not a decision).
_TINY = 2.0 ** -26
_U = 2.0 ** -53                       # unit roundoff of binary64
_SLACK = 1.0 + 2.0 ** -30             # covers the rounding of the bound computations (step 6)
_FLOOR = 2.0 ** -1000                 # covers underflow in any product (step 6)
_SUB = 2.0 ** -1074                   # smallest subnormal

# pi/2 = P1 + P2 + P3 + P4 + delta, |delta| <= DELTA; P1..P3 have <= 30 significant bits
# (P1 = 843314857 * 2**-29, P2 = -501838813 * 2**-59, P3 = 320018826 * 2**-89); checked against arb
_P1 = 1.5707963276654482
_P2 = -8.705515700674349e-10
_P3 = 5.17018297889025e-19
_P4 = 2.9038559739793605e-28
_DELTA = 2.0 ** -144
_TWO_OVER_PI = 0.6366197723675814     # only chooses k; its accuracy does not affect rigour

_RHO = 0.8                            # the polynomials' domain |H| <= RHO (pi/4 + 2**-29 needed)
# Taylor coefficients, each the double nearest the rational (checked exactly by the tests):
# sin H = H + H z (S1 + z (S2 + ... + z S8)), S_j = (-1)**j / (2j+1)!
_SIN_COEFFS = (-1.0 / 6.0, 1.0 / 120.0, -1.0 / 5040.0, 1.0 / 362880.0, -1.0 / 39916800.0,
               1.0 / 6227020800.0, -1.0 / 1307674368000.0, 1.0 / 355687428096000.0)
# cos H = 1 + z (C1 + z (C2 + ... + z C9)), C_j = (-1)**j / (2j)!
_COS_COEFFS = (-1.0 / 2.0, 1.0 / 24.0, -1.0 / 720.0, 1.0 / 40320.0, -1.0 / 3628800.0,
               1.0 / 479001600.0, -1.0 / 87178291200.0, 1.0 / 20922789888000.0,
               -1.0 / 6402373705728000.0)
# Lagrange remainder factors, rounded up (checked by the tests): RHO**18 / 19!, RHO**20 / 20!
_K_SIN = 1.5e-19
_K_COS = 4.8e-21


@njit(cache=True, inline="always")
def _two_sum(a, b):
    """Knuth's TwoSum: ``s + e == a + b`` exactly, ``s = fl(a + b)``."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


@njit(cache=True, inline="always")
def _sin_poly(z, ez):
    """``p_s(Z) = sum_j S_(j+1) Z**j`` by Horner at the computed ``z`` (``|z - Z| <= ez``), with a
    bound on the distance to the exact polynomial (exact rational coefficients) at ``Z``. (The
    tuple is read as a global: passed as an argument, numba would index it through memory.)"""
    n = len(_SIN_COEFFS)
    za = z + ez
    y = _SIN_COEFFS[n - 1]
    ey = _U * abs(y)
    for j in range(n - 2, -1, -1):
        t = y * z
        y2 = t + _SIN_COEFFS[j]
        # the bound's own chain is one product and one sum per step, like the value's
        ey = za * ey + (abs(y) * ez + _U * (abs(t) + abs(_SIN_COEFFS[j]) + abs(y2)))
        y = y2
    return y, ey


@njit(cache=True, inline="always")
def _cos_poly(z, ez):
    """``p_c(Z) = sum_j C_(j+1) Z**j`` with its bound, as :func:`_sin_poly`."""
    n = len(_COS_COEFFS)
    za = z + ez
    y = _COS_COEFFS[n - 1]
    ey = _U * abs(y)
    for j in range(n - 2, -1, -1):
        t = y * z
        y2 = t + _COS_COEFFS[j]
        # the bound's own chain is one product and one sum per step, like the value's
        ey = za * ey + (abs(y) * ez + _U * (abs(t) + abs(_COS_COEFFS[j]) + abs(y2)))
        y = y2
    return y, ey


@njit(cache=True)
def cos_sin_bounded(q):
    """Enclose ``cos q`` and ``sin q`` for one float ``q``, rigorously.

    ``q`` is taken as the exact binary rational it stores. The module docstring gives the method
    and the argument for rigour. Cheap and allocation-free, so it can be called inside other
    numba kernels.

    Parameters
    ----------
    q : float

    Returns
    -------
    c, s, ec, es : float
        ``|cos q - c| <= ec`` and ``|sin q - s| <= es``, guaranteed. For finite
        ``|q| <= Q_MAX`` the bounds are a few ulps of ``|c|`` and ``|s|`` (absolute ``~2**-110``
        next to a multiple of ``pi/2``; 0 for ``q = ±0``). For larger finite ``|q|``: libm's values
        with the bound 2 (a bound ``>= 1`` marks such elements). NaN or infinite ``q``: NaN values
        and infinite bounds.

    Examples
    --------
    >>> from imagespace.core.bounded_trig import cos_sin_bounded
    >>> c, s, ec, es = cos_sin_bounded(1.0)
    >>> round(c, 12), round(s, 12), bool(ec < 1e-15), bool(es < 1e-15)
    (0.540302305868, 0.841470984808, True, True)
    >>> cos_sin_bounded(1e7)[2]
    2.0
    """
    if not math.isfinite(q):
        return math.nan, math.nan, math.inf, math.inf
    aq = abs(q)
    if aq < _TINY:
        if q == 0.0:
            return 1.0, q, 0.0, 0.0
        return 1.0, q, aq * 2.0 ** -27 + _SUB, aq * 2.0 ** -54 + _SUB
    if aq > Q_MAX:
        return _beyond(q)
    k = math.floor(q * _TWO_OVER_PI + 0.5)
    t4 = k * _P4
    # k*P1, k*P2, k*P3 are exact (step 2); the main chain is three additions, their rounding
    # errors e1..e3 exact (TwoSum), the low part l = e1 + e2 + e3 - t4 rounded three times
    h, e1 = _two_sum(q, -(k * _P1))
    h, e2 = _two_sum(h, -(k * _P2))
    h, e3 = _two_sum(h, -(k * _P3))
    l12 = e1 + e2
    l123 = l12 + e3
    l = l123 - t4
    er = _U * (abs(l12) + abs(l123) + abs(l) + abs(t4)) + abs(k) * _DELTA
    ah = abs(h)
    if ah > _RHO:                           # cannot happen (|r| <= pi/4 + 2**-29): safety net
        return _beyond(q)
    z = h * h
    ez = _U * z
    # sin H = H + (H z) p_s(z)
    ys, eys = _sin_poly(z, ez)
    w = h * z
    ew = ah * ez + _U * abs(w)
    v = w * ys
    ev = abs(w) * eys + (abs(ys) + eys) * ew + _U * abs(v)
    sh = h + v
    esh = ev + _U * abs(sh) + _K_SIN * ah
    # cos H = 1 + z p_c(z)
    yc, eyc = _cos_poly(z, ez)
    v = z * yc
    ev = z * eyc + (abs(yc) + eyc) * ez + _U * abs(v)
    ch = 1.0 + v
    ech = ev + _U * abs(ch) + _K_COS
    # r = H + L + eps, |eps| <= er: first order in d = L + eps, Lagrange remainder d**2 / 2
    al = abs(l)
    d2 = 0.5 * (al + er) * (al + er)
    lc = l * ch
    sr = sh + lc
    esr = esh + al * ech + _U * abs(lc) + er + d2 + _U * abs(sr)
    ls = l * sh
    cr = ch - ls
    ecr = ech + al * esh + _U * abs(ls) + er + d2 + _U * abs(cr)
    esr = esr * _SLACK + _FLOOR
    ecr = ecr * _SLACK + _FLOOR
    # quadrant without branches (a random quadrant would mispredict): k mod 4 = 0, 1, 2, 3 gives
    # (cos q, sin q) = (c_r, s_r), (-s_r, c_r), (-c_r, -s_r), (s_r, -c_r)
    n = int(k) & 3
    odd = n & 1
    a = sr if odd else cr
    b = cr if odd else sr
    ea = esr if odd else ecr
    eb = ecr if odd else esr
    sign_c = 1.0 - 2.0 * (((n + 1) >> 1) & 1)
    sign_s = 1.0 - 2.0 * ((n >> 1) & 1)
    return sign_c * a, sign_s * b, ea, eb


@njit(cache=True)
def _beyond(q):
    """libm's values clamped to [-1, 1] with the trivially rigorous bound 2."""
    c = min(1.0, max(-1.0, math.cos(q)))
    s = min(1.0, max(-1.0, math.sin(q)))
    return c, s, 2.0, 2.0


@njit(cache=True, parallel=True)
def _enclose_flat(q, c, s, ec, es):
    for i in prange(q.shape[0]):
        c[i], s[i], ec[i], es[i] = cos_sin_bounded(q[i])


def _arb_cos_sin(x):
    """``(c, s, ec, es)`` for one float from python-flint's arb (64 bits; any finite size)."""
    import flint

    from .certify import flint_precision

    with flint_precision(64):
        b = flint.arb(float(x))
        out = []
        for ball in (b.cos(), b.sin()):
            v = float(ball.mid())
            out.append((v, float(ball.rad()) * (1 + 4 * _U) + abs(v) * _U + _SUB))
    return out[0][0], out[1][0], out[0][1], out[1][1]


def cos_sin_enclosure(q):
    """Rigorous enclosures of ``cos q`` and ``sin q`` for an array of floats.

    Each element (an exact binary rational) goes through the compiled :func:`cos_sin_bounded`
    in parallel; the finite elements beyond its range (``|q| > Q_MAX``) are recomputed with
    python-flint's arb, so every bound returned for a finite element is small (a few ulps) and
    rigorous.

    Parameters
    ----------
    q : array_like of float
        Any shape. NaN and infinite elements are allowed.

    Returns
    -------
    c, s, ec, es : numpy.ndarray
        Arrays of ``q``'s shape with ``|cos q - c| <= ec`` and ``|sin q - s| <= es`` element by
        element. NaN or infinite elements give NaN values and infinite bounds.

    Raises
    ------
    TypeError
        ``q`` is not numeric (strings, booleans, complex numbers, symbolic values).
    InputError
        ``q`` holds a number beyond the float range.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.bounded_trig import cos_sin_enclosure
    >>> c, s, ec, es = cos_sin_enclosure(np.array([[0.0, 1.0], [1e9, np.nan]]))
    >>> c.shape, bool(np.all(ec[:, 0] < 1e-15)), bool(np.all(es[:, 0] < 1e-15))
    ((2, 2), True, True)
    >>> bool(ec[1, 0] < 1e-15), float(ec[1, 1])
    (True, inf)
    """
    arr = as_float_array(q, "q", finite=False)
    flat = np.ascontiguousarray(arr, dtype=np.float64).ravel()
    n = flat.shape[0]
    c, s, ec, es = (np.empty(n) for _ in range(4))
    _enclose_flat(flat, c, s, ec, es)
    redo = np.flatnonzero(np.isfinite(flat) & ((ec >= 1.0) | (es >= 1.0)))
    for i in redo:
        c[i], s[i], ec[i], es[i] = _arb_cos_sin(flat[i])
    shape = arr.shape
    return c.reshape(shape), s.reshape(shape), ec.reshape(shape), es.reshape(shape)
