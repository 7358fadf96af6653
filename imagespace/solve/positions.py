r"""The positions at a certified orientation root, counted exactly.

Where the Cramer denominator vanishes at a root of the kinematic polynomial (case (b)) or
identically (case (a), a PP dyad among the linear rows, parallel lines), the root fixes only an
orientation ``t* = x1/x0`` and the positions ``(x2, x3)`` are solved at it: the three quadrics are
then, in ``(x2, x3)``, the rows ``(c_i, alpha_i, beta_i, kappa_i)`` of circles or lines

.. math::

    c (x_2^2 + x_3^2) + \alpha x_2 + \beta x_3 + \kappa = 0,\qquad
    \alpha = a_0 + a_1 t,\ \beta = b_0 + b_1 t,\ \kappa = k_0 + k_1 t + k_2 t^2 .

Near a tangency the number of real positions (0, 1 or 2) is a sign at ``t*``, which floating
point cannot decide. Here every decision is exact: the entries are polynomials in ``t`` (over Q,
or over ``Q[tan(r/2)]`` for an actuated angle, :mod:`imagespace.core.transcendental`), ``t*`` is a
root of an irreducible factor ``f`` of the kinematic polynomial, an entry is zero at ``t*``
exactly when ``f`` divides it, and a non-zero entry's sign is read off an arb enclosure over the
root's isolating interval (refined until it excludes zero). No division is needed:

* the lines and the differences ``c_j E_i - c_i E_j`` of circles form a linear system whose rank
  (2, 1 or 0) and consistency are decided by exact zero tests of its minors;
* rank 2: one point, Cramer's rule; it is a position when it also lies on the circle (an exact
  zero test);
* rank 1 and a circle: the line meets the circle in 2, 1 (tangent: a double solution) or 0
  points as ``(a^2 + b^2)(A^2 + B^2 - 4 c C) - (2 c k - a A - b B)^2`` is positive, zero or
  negative (the squared radius minus the squared distance of the centre, times ``4 c^2 (a^2 + b^2)``);
* rank 1 without a circle, or rank 0 with a real circle: a continuum (raised).

The positions themselves are then evaluated in arb at the refined root and rounded once.
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any, Optional

from ..core.certify import flint_precision
from ..exceptions import DegenerateDesignError

__all__ = ["RationalRoot", "TranscendentalRoot", "positions_at_root"]

#: Working precisions (bits) for the signs of non-zero entries at an orientation root.
SIGN_PRECISIONS = (128, 256, 512, 1024, 2048)


class RationalRoot:
    """A real root ``t*`` of an irreducible ``f`` (python-flint ``fmpq_poly``) in ``[lo, hi]``
    (Fractions, ``f`` changing sign there, or ``lo == hi == t*``); entries are ``fmpq_poly`` in
    ``t``.

    Examples
    --------
    >>> import flint
    >>> from fractions import Fraction
    >>> from imagespace.solve.positions import RationalRoot
    >>> r = RationalRoot(flint.fmpq_poly([-2, 0, 1]), Fraction(1), Fraction(2))    # sqrt 2
    >>> r.sign(flint.fmpq_poly([-3, 2])), r.is_zero(flint.fmpq_poly([-4, 0, 2]))   # 2 sqrt 2 < 3
    (-1, True)
    """

    def __init__(self, f, lo, hi):
        self.f = f
        self.lo, self.hi = Fraction(lo), Fraction(hi)

    def is_zero(self, h):
        if h.is_zero():
            return True
        return (h % self.f).is_zero()

    def _refine(self):
        import flint

        lo, hi = self.lo, self.hi
        if lo == hi:
            return
        mid = (lo + hi) / 2
        flo = self.f(flint.fmpq(lo.numerator, lo.denominator))
        fm = self.f(flint.fmpq(mid.numerator, mid.denominator))
        if fm == 0:
            self.lo = self.hi = mid
        elif (fm > 0) == (flo > 0):
            self.lo = mid
        else:
            self.hi = mid

    def ball(self, h, prec):
        """arb enclosure of ``h(t*)`` at working precision ``prec``."""
        import flint

        with flint_precision(prec):
            mid = (self.lo + self.hi) / 2
            t = flint.arb(flint.fmpq(mid.numerator, mid.denominator))
            if self.hi != self.lo:
                rad = (self.hi - self.lo) / 2
                t = t + flint.arb(0, flint.arb(flint.fmpq(rad.numerator, rad.denominator)).upper())
            acc = flint.arb(0)
            for c in reversed(h.coeffs()):
                acc = acc * t + flint.arb(c)
            return acc

    def sign(self, h):
        """The exact sign of ``h(t*)``: 0 when ``f`` divides ``h``, else read off an enclosure
        that excludes zero (the interval is bisected on the sign of ``f`` until it does)."""
        if self.is_zero(h):
            return 0
        for _ in range(4000):
            b = self.ball(h, 256)
            if not b.contains(0):
                return 1 if b > 0 else -1
            self._refine()
        return None                                     # not reached for a non-zero h


class TranscendentalRoot:
    """A real root ``t*`` of an irreducible ``f`` in ``Q[t, tau, ...]`` (an ``fmpq_mpoly`` with
    ``t`` first, the other variables those of ``constants``), isolated in ``[lo, hi]`` at the
    actual angles; entries are ``fmpq_mpoly`` in the same ring.

    Zero tests are exact when ``constants.decidable`` (one angle group, no other irrational
    constant: ``f`` divides ``h`` in ``Q(tau)[t]`` exactly when ``h`` vanishes at ``t*``); with
    several groups a zero that no enclosure excludes is undecided (``None``).
    """

    def __init__(self, f, constants, lo, hi):
        self.f = f
        self.k = constants
        self.lo, self.hi = Fraction(lo), Fraction(hi)
        self._fdeg = f.degrees()[0]

    def _divides(self, h):
        g = self.f.gcd(h)
        return g.degrees()[0] == self._fdeg

    def ball(self, h, prec):
        import flint

        vb = self.k.variable_balls(prec)
        with flint_precision(prec):
            mid = (self.lo + self.hi) / 2
            t = flint.arb(flint.fmpq(mid.numerator, mid.denominator))
            if self.hi != self.lo:
                rad = (self.hi - self.lo) / 2
                t = t + flint.arb(0, flint.arb(flint.fmpq(rad.numerator, rad.denominator)).upper())
            vals = [t] + list(vb)
            acc = flint.arb(0)
            for mono, c in h.terms():
                term = flint.arb(c)
                for v, e in zip(vals, mono):
                    if e:
                        term = term * v**int(e)
                acc = acc + term
            return acc

    def is_zero(self, h):
        if h.is_zero():
            return True
        for prec in SIGN_PRECISIONS[:2]:
            if not self.ball(h, prec).contains(0):
                return False
        if self._divides(h):
            return True
        if self.k.decidable:
            return False
        for prec in SIGN_PRECISIONS[2:]:
            if not self.ball(h, prec).contains(0):
                return False
        return None

    def sign(self, h):
        z = self.is_zero(h)
        if z is None:
            return None
        if z:
            return 0
        for prec in SIGN_PRECISIONS:
            b = self.ball(h, prec)
            if not b.contains(0):
                return 1 if b > 0 else -1
        return None


def _minor(p, q, a, b):
    return p[a] * q[b] - p[b] * q[a]


def positions_at_root(rows, root):
    """The real positions ``(x2, x3)`` of three circle/line rows at an orientation root, counted
    exactly (see the module docstring).

    Parameters
    ----------
    rows : three tuples ``(c, alpha, beta, kappa)``
        Ring elements (polynomials in ``t``) as read by ``root``.
    root : RationalRoot or TranscendentalRoot
        The orientation: ``t*`` in the chart ``x0 = 1``, or ``s* = 0`` in the chart ``x1 = 1``
        for the half-turn root ``x0 = 0`` (the rows then written in ``s = x0/x1``).

    Returns
    -------
    list of ``(x2, x3, multiplicity)`` floats, or None
        The positions (in the chart of the rows), multiplicity 2 for a tangency;
        None where a zero test could not be decided (several angles in an exact relation).

    Raises
    ------
    DegenerateDesignError
        The positions at this orientation form a continuum.

    Examples
    --------
    Two circles of radius 1 centred at ``(-d, 0)`` and ``(d, 0)`` and the line ``x3 = 0``, where
    ``d = t*`` is the root of ``t**2 - 2`` in ``[1, 2]``: two circles at distance ``2 sqrt 2 > 2``
    do not meet.

    >>> import flint
    >>> from fractions import Fraction
    >>> from imagespace.solve.positions import RationalRoot, positions_at_root
    >>> P = flint.fmpq_poly
    >>> r = RationalRoot(P([-2, 0, 1]), Fraction(1), Fraction(2))
    >>> t = P([0, 1])
    >>> rows = [(P([1]), 2 * t, P([0]), t * t - 1), (P([1]), -2 * t, P([0]), t * t - 1), (P([0]), P([0]), P([1]), P([0]))]
    >>> positions_at_root(rows, r)
    []
    """
    zc = [root.is_zero(r[0]) for r in rows]
    if any(z is None for z in zc):
        return None
    circles = [r for r, z in zip(rows, zc) if not z]
    lines = [r[1:] for r, z in zip(rows, zc) if z]
    if circles:
        c0 = circles[0]
        lines += [tuple(r[0] * c0[j] - c0[0] * r[j] for j in (1, 2, 3)) for r in circles[1:]]
    # rank of the (alpha, beta) part and consistency, by exact zero tests of minors
    nz = []
    for ln in lines:
        z = [root.is_zero(v) for v in ln]
        if any(v is None for v in z):
            return None
        if not (z[0] and z[1]):
            nz.append(ln)
        elif not z[2]:
            return []                                 # 0 x2 + 0 x3 + kappa, kappa != 0
    pair = None
    for i in range(len(nz)):
        for j in range(i + 1, len(nz)):
            z = root.is_zero(_minor(nz[i], nz[j], 0, 1))
            if z is None:
                return None
            if not z:
                pair = (nz[i], nz[j])
                break
        if pair:
            break
    if pair is not None:                              # rank 2: one point by Cramer's rule
        (a1, b1, k1), (a2, b2, k2) = pair
        det = a1 * b2 - a2 * b1
        n2 = -(k1 * b2 - k2 * b1)
        n3 = -(a1 * k2 - a2 * k1)
        for ln in nz:                                 # every other line through the point
            z = root.is_zero(ln[0] * n2 + ln[1] * n3 + ln[2] * det)
            if z is None:
                return None
            if not z:
                return []
        if circles:
            c, A, B, C = circles[0]
            z = root.is_zero(c * (n2 * n2 + n3 * n3) + (A * n2 + B * n3) * det + C * det * det)
            if z is None:
                return None
            if not z:
                return []
        d = root.ball(det, 256)
        return [(float((root.ball(n2, 256) / d).mid()), float((root.ball(n3, 256) / d).mid()), 1)]
    if nz:                                            # rank 1: one line (the others are multiples)
        a, b, k = nz[0]
        for ln in nz[1:]:                             # consistency: proportional including kappa
            for (p, q) in ((0, 2), (1, 2)):
                z = root.is_zero(_minor(nz[0], ln, p, q))
                if z is None:
                    return None
                if not z:
                    return []
        if not circles:
            raise DegenerateDesignError("the positions at this orientation form a line: a continuum "
                                        "of assembly modes")
        c, A, B, C = circles[0]
        n2 = a * a + b * b
        disc = n2 * (A * A + B * B - 4 * c * C) - (2 * c * k - a * A - b * B) ** 2
        s = root.sign(disc)
        if s is None:
            return None
        if s < 0:
            return []
        import flint
        prec = 256
        with flint_precision(prec):
            av, bv, kv = (root.ball(v, prec) for v in (a, b, k))
            cv, Av, Bv, Cv = (root.ball(v, prec) for v in (c, A, B, C))
            cx, cy = -Av / (2 * cv), -Bv / (2 * cv)
            nn = av * av + bv * bv
            dist = (av * cx + bv * cy + kv) / nn
            fx, fy = cx - dist * av, cy - dist * bv
            if s == 0:
                return [(float(fx.mid()), float(fy.mid()), 2)]
            half = (root.ball(disc, prec)).sqrt() / (2 * abs(cv) * nn)
            return [(float((fx - half * bv).mid()), float((fy + half * av).mid()), 1),
                    (float((fx + half * bv).mid()), float((fy - half * av).mid()), 1)]
    # rank 0: no line constrains the positions
    if not circles:
        raise DegenerateDesignError("no constraint on the positions at this orientation: a continuum "
                                    "of assembly modes")
    c, A, B, C = circles[0]
    s = root.sign(A * A + B * B - 4 * c * C)
    if s is None:
        return None
    if s > 0:
        raise DegenerateDesignError("the positions at this orientation form a circle: a continuum of "
                                    "assembly modes")
    if s < 0:
        return []
    prec = 256
    cv, Av, Bv = (root.ball(v, prec) for v in (c, A, B))
    return [(float((-Av / (2 * cv)).mid()), float((-Bv / (2 * cv)).mid()), 2)]
