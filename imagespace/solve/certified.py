r"""Certified direct kinematics: assembly modes computed root by root from the exact certificate.

The floating-point paths find roots of the kinematic polynomial, polish them and then *match*
them to a certificate; near a singularity (two modes closer than the float resolution, a double
root, a continuum) matching cannot be right. Here the direction is reversed: every certified real
root of the exact kinematic polynomial ``P`` (exact joint values, floats taken as the binary
rationals they are) is refined to an interval narrower than ``2**-200`` relative
(:data:`imagespace.core.certify.REFINE_BITS`), and its modes are computed *from that root*:

* **Cramer roots** - the Cramer denominator ``D`` of the elimination is proven non-zero at the
  root (rational coefficients: exactly, through ``gcd(D, P)``; irrational ones: an arb ball of
  ``D`` over the isolating interval that excludes zero). The root then carries exactly one
  mode, ``x2 = X2/D``, ``x3 = X3/D``, evaluated exactly (rational case) or in arb at the refined
  point, and rounded once to floats. A root of multiplicity ``k > 1`` is one singular mode with
  ``multiplicity == k``. Two roots ``1e-20`` apart give two modes.
* **Orientation roots** - ``D`` vanishes identically (case (a), e.g. the collinear 3-RPR of
  seed 003, where ``P`` is the orientation quadratic) or at the root (case (b)): the orientation is
  fixed by the certified root and the positions (none, one, two, or a continuum) are solved on
  their own at that orientation in floating point and polished. These are the documented
  exceptions to "one mode per root": such a root carries 0, 1 or 2 modes.

A mode must also pass each leg's inverse-kinematics check; the spurious root ``phi_c + pi`` of a
PP dyad (its pair of planes) fails it and carries no mode.

This module holds the exact arithmetic; :class:`imagespace.PlanarParallel` orchestrates.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
import sympy as sp

from ..core.certify import to_arb, flint_precision

__all__ = ["RootPlan", "plan_roots"]

#: Working precision (bits) of the arb evaluation of ``D``, ``X2``, ``X3`` at a refined root with
#: irrational coefficients; results are rounded once to double precision.
ARB_BITS = 256


@dataclass(frozen=True)
class RootPlan:
    """How one certified real root of the kinematic polynomial turns into modes.

    Attributes
    ----------
    index : int
        Position of the root in the certificate (finite roots ascending in ``t = x1/x0``, then
        the root ``x0 = 0``).
    kind : str
        ``"cramer"`` (exactly one mode, ``image_point`` given) or ``"orientation"`` (positions to
        be solved at the orientation ``(x0, x1)``).
    multiplicity : int
        Multiplicity of the root (1 on the arb path, which isolates simple roots only).
    x0, x1 : float
        The orientation, normalised ``x0**2 + x1**2 = 1``, rounded from the refined root.
    image_point : (4,) float or None
        For ``"cramer"``: the normalised image point (not yet checked by the legs).
    """

    index: int
    kind: str
    multiplicity: int
    x0: float
    x1: float
    image_point: Optional[np.ndarray] = None


def _is_rational(values):
    return all(sp.sympify(v).is_Rational for v in values)


def _orientation(t):
    """Normalised ``(x0, x1)`` floats for ``t = x1/x0`` (a Fraction) or ``None`` (``x0 = 0``)."""
    if t is None:
        return 0.0, 1.0
    tf = float(t)
    h = float(np.hypot(1.0, tf))
    return 1.0 / h, tf / h


def _normalised_point(t, x2, x3):
    """Normalised image point from the chart ``x0 = 1`` (or ``x1 = 1`` when ``t`` is None)."""
    if t is None:
        return np.array([0.0, 1.0, float(x2), float(x3)])
    tf = float(t)
    h = float(np.hypot(1.0, tf))
    return np.array([1.0 / h, tf / h, float(x2) / h, float(x3) / h])


class _ExactCramer:
    """Exact Cramer data of one row (rational coefficients), prepared once for all roots."""

    def __init__(self, D, X2, X3, P):
        import flint

        def q(c):
            c = sp.Rational(c)
            return flint.fmpq(int(c.p), int(c.q))

        self.D, self.X2, self.X3 = (flint.fmpq_poly([q(c) for c in f]) for f in (D, X2, X3))
        self.Dtop, self.X2top, self.X3top = q(D[-1]), q(X2[-1]), q(X3[-1])
        Pp = flint.fmpq_poly([q(c) for c in P])
        self.sqf = None
        if self.D.degree() >= 0:
            g = self.D.gcd(Pp)
            if g.degree() >= 1:
                num = flint.fmpz_poly([int(v) for v in (g * g.denom()).coeffs()])
                _, facs = num.factor_squarefree()
                sqf = flint.fmpq_poly([1])
                for f, _m in facs:
                    sqf = sqf * flint.fmpq_poly(f.coeffs())
                self.sqf = sqf

    def point(self, root, t):
        """``(x2, x3)`` in the chart at the root, or None where ``D`` vanishes there. ``root`` is
        the isolating interval ``(lo, hi)`` (Fractions), None for ``x0 = 0``."""
        import flint

        if self.D.degree() < 0:
            return None
        if root is None:                                # x0 = 0: evaluate at (0, 1)
            if self.Dtop == 0:
                return None
            return self.X2top / self.Dtop, self.X3top / self.Dtop
        lo, hi = root
        if self.sqf is not None:
            # the root of P in [lo, hi] is a root of gcd(D, P) iff the square-free part of the
            # gcd changes sign (or vanishes) on [lo, hi]: [lo, hi] holds one distinct root of P
            a = self.sqf(flint.fmpq(lo.numerator, lo.denominator))
            b = self.sqf(flint.fmpq(hi.numerator, hi.denominator))
            if a * b <= 0:
                return None
        tq = flint.fmpq(t.numerator, t.denominator)
        d = self.D(tq)
        if d == 0:
            return None
        return self.X2(tq) / d, self.X3(tq) / d


def _arb_cramer(D, X2, X3, root, t):
    """Irrational coefficients: D's arb ball over the isolating interval must exclude zero."""
    import flint

    with flint_precision(ARB_BITS):
        def ev(form, x):
            acc = flint.arb(0)
            for c in reversed(form):
                acc = acc * x + to_arb(sp.sympify(c), ARB_BITS)
            return acc

        if root is None:
            d = to_arb(sp.sympify(D[-1]), ARB_BITS)
            if d.contains(0):
                return None
            x2, x3 = to_arb(sp.sympify(X2[-1]), ARB_BITS) / d, to_arb(sp.sympify(X3[-1]), ARB_BITS) / d
            return float(x2.mid()), float(x3.mid())
        lo, hi = root
        mid = (lo + hi) / 2
        rad = (hi - lo) / 2
        tb = flint.arb(flint.fmpq(mid.numerator, mid.denominator)) \
            + flint.arb(0, float(rad) * 2 + 1e-300)
        if ev(D, tb).contains(0):
            return None
        tm = flint.arb(flint.fmpq(t.numerator, t.denominator))
        d = ev(D, tm)
        return float((ev(X2, tm) / d).mid()), float((ev(X3, tm) / d).mid())


def plan_roots(P, D, X2, X3, certificate, case_a):
    """Turn each certified real root into a :class:`RootPlan`.

    Parameters
    ----------
    P : list
        Exact coefficients of the kinematic polynomial, ``P[k]`` multiplying ``x0**(d-k) x1**k``.
    D, X2, X3 : lists
        Exact Cramer forms of the elimination (degrees 2, 3, 3), same convention.
    certificate : RealRootCertificate
        Of ``P``; must be certified.
    case_a : bool
        ``D`` vanishes identically (``P`` is then the orientation form).

    Returns
    -------
    list of RootPlan

    Examples
    --------
    >>> from imagespace.core.certify import certify_real_roots
    >>> from imagespace.solve.certified import plan_roots
    >>> P = [-1, 0, 1]                         # x1^2 - x0^2: t = -1, 1
    >>> D, X2, X3 = [1, 0, 0], [0, 0, 0, 0], [2, 0, 0, 0]
    >>> [(r.kind, r.multiplicity) for r in plan_roots(P, D, X2, X3, certify_real_roots(P), False)]
    [('cramer', 1), ('cramer', 1)]
    """
    cert = certificate
    roots = [(iv, m) for iv, m in zip(cert.exact_intervals, cert.multiplicities)]
    if cert.at_infinity:
        roots.append((None, cert.at_infinity))
    rational = _is_rational(list(P) + list(D) + list(X2) + list(X3))
    exact = _ExactCramer(D, X2, X3, P) if rational and cert.exact and not case_a else None
    plans = []
    for k, (iv, mult) in enumerate(roots):
        t = None if iv is None else (iv[0] + iv[1]) / 2
        x0, x1 = _orientation(t)
        pos = None
        if not case_a:
            if exact is not None:
                pos = exact.point(iv, t)
            else:
                pos = _arb_cramer(D, X2, X3, iv, t)
        if pos is None:
            plans.append(RootPlan(k, "orientation", int(mult), x0, x1))
        else:
            plans.append(RootPlan(k, "cramer", int(mult), x0, x1, _normalised_point(t, *pos)))
    return plans
