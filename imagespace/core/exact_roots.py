"""Exact real roots of a univariate rational polynomial in ``[0, 1]``, and the outward rounding of
exact rationals to floats.

The exact side of the path and curve checks (:mod:`imagespace.paths.check`,
:mod:`imagespace.paths.curves`) and of the cuspidality proofs (:mod:`imagespace.atlas.cuspidal`):
:func:`roots_in_unit_interval` factors over Q and isolates by Sturm counts and exact bisection (no
arb ball, no float); :func:`float_down` / :func:`float_up` are the one outward-rounding rule of the
exact paths. Split from :mod:`imagespace.core.certify` (issue [15]), which still re-exports every
name.
"""

from __future__ import annotations

import math
from fractions import Fraction

import sympy as sp

__all__ = ["ISOLATION_WIDTH", "fmpq_of", "roots_in_unit_interval", "sturm_sequence", "sturm_count",
           "float_down", "float_up", "as_fraction"]

#: Roots isolated by :func:`roots_in_unit_interval` are refined to intervals narrower than this.
ISOLATION_WIDTH = 1e-12


def fmpq_of(x):
    """An exact rational (Fraction, int, sympy Rational, a float as its binary rational) as a
    python-flint ``fmpq``.

    Examples
    --------
    >>> from imagespace.core.exact_roots import fmpq_of
    >>> fmpq_of(0.5)
    1/2
    """
    from flint import fmpq

    if isinstance(x, Fraction):
        return fmpq(x.numerator, x.denominator)
    x = sp.Rational(x)
    return fmpq(int(x.p), int(x.q))


def roots_in_unit_interval(p, width=ISOLATION_WIDTH):
    """Real roots of a non-zero fmpq_poly in ``[0, 1]``: sorted list of ``(lo, hi, multiplicity)``.

    Exact rational arithmetic only (no arb ball, no float, nothing that reads
    ``flint.ctx.prec``): ``p`` is factored over Q into irreducible factors ``g**e``; a linear
    factor gives its rational root exactly; an irreducible ``g`` of degree >= 2 has no rational
    root, so it is non-zero at every bisection point and its roots in ``(0, 1)`` are isolated by
    Sturm counts (:func:`sturm_count`), then each is refined by exact sign bisection until the
    interval is narrower than ``width``. ``(lo, hi)`` are floats rounded outwards, so the float
    interval contains the root; roots of distinct factors are distinct, so each interval holds
    exactly one root of ``p``, of multiplicity ``e``.

    Examples
    --------
    >>> from flint import fmpq_poly
    >>> from imagespace.core.exact_roots import roots_in_unit_interval
    >>> p = fmpq_poly([-1, 2]) ** 2 * fmpq_poly([-1, 0, 2])      # (2t - 1)^2 (2t^2 - 1)
    >>> [(lo <= r <= hi, m) for (lo, hi, m), r in zip(roots_in_unit_interval(p), (0.5, 2**-0.5))]
    [(True, 2), (True, 1)]
    """
    from flint import fmpq

    w = fmpq_of(Fraction(width))
    zero, one = fmpq(0), fmpq(1)
    out = []
    for g, mult in p.factor()[1]:
        if g.degree() < 1:
            continue
        if g.degree() == 1:
            c0, c1 = g.coeffs()
            r = -c0 / c1
            if zero <= r <= one:
                out.append((float_down(r), float_up(r), mult))
            continue
        seq = sturm_sequence(g)
        stack = [(zero, one, sturm_count(seq, zero), sturm_count(seq, one))]
        while stack:
            lo, hi, v_lo, v_hi = stack.pop()
            n = v_lo - v_hi                    # roots of g in (lo, hi): g(lo), g(hi) != 0
            if n == 0:
                continue
            if n == 1:                         # one simple root: g changes sign on (lo, hi)
                g_lo = g(lo)
                while hi - lo >= w:
                    mid = (lo + hi) / 2
                    g_mid = g(mid)
                    if (g_mid > 0) == (g_lo > 0):
                        lo, g_lo = mid, g_mid
                    else:
                        hi = mid
                out.append((float_down(lo), float_up(hi), mult))
                continue
            mid = (lo + hi) / 2
            v_mid = sturm_count(seq, mid)
            stack += [(mid, hi, v_mid, v_hi), (lo, mid, v_lo, v_mid)]
    out.sort()
    return out


def sturm_sequence(g):
    """The Sturm sequence ``g, g', -rem(g, g'), ...`` of a square-free fmpq_poly (exact).

    Examples
    --------
    >>> from flint import fmpq_poly
    >>> from imagespace.core.exact_roots import sturm_count, sturm_sequence
    >>> seq = sturm_sequence(fmpq_poly([-2, 0, 1]))          # t^2 - 2: one root in (0, 2)
    >>> sturm_count(seq, 0) - sturm_count(seq, 2)
    1
    """
    seq = [g, g.derivative()]
    while seq[-1].degree() > 0:
        r = seq[-2] % seq[-1]
        if r.is_zero():
            break
        seq.append(-r)
    return seq


def sturm_count(seq, x):
    """Sign variations of a Sturm sequence at the rational ``x`` (zeros skipped); see
    :func:`sturm_sequence`."""
    changes, last = 0, 0
    for s in seq:
        v = s(x)
        sign = (v > 0) - (v < 0)
        if sign:
            changes += last * sign < 0
            last = sign
    return changes


def float_down(q):
    """The largest float ``<= q`` (``q`` an exact rational: fmpq, Fraction or sympy Rational):
    the one outward-rounding rule (with :func:`float_up`) of the exact paths.

    Examples
    --------
    >>> from fractions import Fraction
    >>> from imagespace.core.exact_roots import float_down
    >>> Fraction(float_down(Fraction(1, 3))) <= Fraction(1, 3)
    True
    """
    fr = as_fraction(q)
    f = float(fr)                              # correctly rounded
    return f if Fraction(f) <= fr else math.nextafter(f, -math.inf)


def float_up(q):
    """The smallest float ``>= q`` (see :func:`float_down`).

    Examples
    --------
    >>> from fractions import Fraction
    >>> from imagespace.core.exact_roots import float_up
    >>> Fraction(float_up(Fraction(1, 3))) >= Fraction(1, 3)
    True
    """
    fr = as_fraction(q)
    f = float(fr)
    return f if Fraction(f) >= fr else math.nextafter(f, math.inf)


def as_fraction(q):
    """An exact rational (Fraction, fmpq or sympy Rational: the last two have ``.p``, ``.q``)
    as a Fraction.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.exact_roots import as_fraction
    >>> as_fraction(sp.Rational(2, 6))
    Fraction(1, 3)
    """
    return q if isinstance(q, Fraction) else Fraction(int(q.p), int(q.q))
