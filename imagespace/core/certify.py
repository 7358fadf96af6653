r"""Certified counts of the real roots of a binary form on the projective line (python-flint).

The answer to "how many real assembly modes" is a yes/no question per root, so it is decided here
with exact or rigorous interval arithmetic, never with floating point:

* **Rational coefficients** (integers, rationals, and floats taken as the exact binary rationals
  they are): the dehomogenised polynomial goes to python-flint as an ``fmpq_poly``;
  ``complex_roots()`` (FLINT's ``arb_fmpz_poly_complex_roots`` on the square-free factors) returns
  disjoint isolating balls with multiplicities, real roots with an imaginary part exactly zero.
  Exact, multiple roots included. A factor that Sturm's theorem proves free of real roots skips
  the isolation (on long coefficients a cluster of complex roots can make it slow), and an
  isolation on integers longer than :data:`INLINE_ROOT_BITS` runs in a child process that Ctrl-C
  stops (:mod:`imagespace.core.interruptible`).
* **Other exact coefficients** (algebraic numbers such as the seed-002 offset in
  :math:`\mathbb{Q}(\sqrt{181})`, or ``cos(7*pi/18)``): every coefficient is enclosed in an
  ``arb`` ball (sympy evaluates it to the working precision plus guard digits; the ball radius covers
  that error), ``acb_poly.roots()`` isolates the roots in disjoint discs, and a root is **real**
  when the hull of its disc and the conjugate disc (a disc centred on the real axis) meets no
  other disc (then the conjugate root must be itself), **non-real** when its disc misses the
  real axis. The precision doubles (64 -> 1024 bits) until every disc is decided; a multiple root
  with irrational coefficients cannot be isolated this way and is reported as not certified.

The point at infinity ``x0 = 0`` (the half-turn) is a root exactly when the coefficient of
``x1**d`` is zero, which is decided exactly (sympy ``equals``/rational zero test).
"""

from __future__ import annotations

import math
import threading
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import sympy as sp

from .._validate import as_float_array, as_sympy, as_sympy_entry
from ..exceptions import DegenerateDesignError, InputError, InputTypeError
from .elimination import form_coefficients
# the exact isolation on [0, 1] and the outward rounding live in core.exact_roots (issue [15]);
# their names stay importable here
from .exact_roots import (ISOLATION_WIDTH, as_fraction, float_down, float_up, fmpq_of,  # noqa: F401
                          roots_in_unit_interval, sturm_count, sturm_sequence)
# rigorous float enclosures of binary forms live in core.form_bounds; importable here as before
from .form_bounds import UNIT_ROUNDOFF as _U, form_signs_on, inclusion_discs, no_common_real_root  # noqa: F401

__all__ = ["RealRootCertificate", "certify_real_roots", "certify_real_roots_batch",
           "flint_precision", "arb_bounds", "outward_float_interval", "to_arb", "exact_is_zero",
           "refine_root_intervals", "reduced_angle"]

#: Relative width (in bits) to which every certified real root is refined: the isolating interval
#: of a root ``r`` ends narrower than ``2**-REFINE_BITS * max(1, |r|)``, far below double precision,
#: so two certified roots give two distinct float approximations whenever floats can tell them
#: apart, and the modes are back-substituted from a point that is exact to double precision.
REFINE_BITS = 200

_FLINT_LOCK = threading.RLock()


@contextmanager
def flint_precision(bits):
    """Run a block with python-flint's working precision set to ``bits``, thread-safely.

    python-flint keeps one process-global context (``flint.ctx.prec``). Every arb computation of
    imagespace runs inside this lock and restores the caller's setting afterwards, so two threads
    certifying at once do not change each other's precision, and a user's ``flint.ctx.dps`` does
    not reach a certificate. Correctness never depends on the precision anyway: arb balls enclose
    the exact value at any precision and every decision is taken on exact rational bounds read
    off them (:func:`arb_bounds`); the precision only decides how often a question can be settled.

    Examples
    --------
    >>> import flint
    >>> from imagespace.core.certify import flint_precision
    >>> with flint_precision(200):
    ...     flint.ctx.prec
    200
    """
    import flint

    with _FLINT_LOCK:
        old = flint.ctx.prec
        flint.ctx.prec = int(bits)
        try:
            yield
        finally:
            flint.ctx.prec = old


def _arf_fraction(x):
    """The exact value of an exact arb (radius zero, e.g. ``ball.mid()``) as a Fraction."""
    m, e = x.man_exp()
    m, e = int(m), int(e)
    return Fraction(m * 2**e) if e >= 0 else Fraction(m, 2**-e)


def arb_bounds(ball):
    """Exact rational lower and upper bounds ``(lo, hi)`` of a python-flint ``arb`` ball.

    The midpoint and radius of an arb ball are exact binary numbers; they are read exactly, so
    ``lo <= x <= hi`` holds for every number ``x`` the ball encloses, whatever the working
    precision. (``float(ball.lower())`` is not such a bound: it rounds to nearest.)

    Raises
    ------
    InputError
        ``ball`` is not finite.

    Examples
    --------
    >>> import flint
    >>> from imagespace.core.certify import arb_bounds
    >>> lo, hi = arb_bounds(flint.arb(2).sqrt())
    >>> lo * lo <= 2 <= hi * hi
    True
    """
    if not ball.is_finite():
        raise InputError(f"ball must be finite, got {ball}")
    mid, rad = _arf_fraction(ball.mid()), _arf_fraction(ball.rad())
    return mid - rad, mid + rad


def outward_float_interval(lo, hi):
    """Floats ``(a, b)`` with ``a <= lo`` and ``b >= hi`` for exact rationals ``lo <= hi``.

    Examples
    --------
    >>> from fractions import Fraction
    >>> from imagespace.core.certify import outward_float_interval
    >>> a, b = outward_float_interval(Fraction(1, 3), Fraction(1, 3))
    >>> Fraction(a) < Fraction(1, 3) < Fraction(b)
    True
    """
    return float_down(lo), float_up(hi)


@dataclass(frozen=True)
class RealRootCertificate:
    """Proven number of distinct real roots of a binary form ``sum f_k x0^(d-k) x1^k``.

    Attributes
    ----------
    certified : bool
        True when every root was decided (the count is proven).
    count : int or None
        Number of distinct real roots on the projective line (``x0 = 0`` included); ``None``
        when not certified.
    intervals : tuple of (float, float)
        For each finite real root, an interval of ``t = x1/x0`` (i.e. ``tan(phi/2)``) that
        contains it and no other root, rounded outwards to floats.
    multiplicities : tuple of int
        Multiplicity of each finite real root (1 where only isolation, not the exact
        multiplicity, was computed: the arb path certifies simple roots only).
    at_infinity : int
        Multiplicity of the root ``x0 = 0`` (0 if none).
    method : str
        How the answer was obtained.
    exact_intervals : tuple of (Fraction, Fraction)
        The same isolating intervals with exact rational ends, refined so that each is narrower
        than ``2**-REFINE_BITS * max(1, |t|)``; ``intervals`` are these rounded outwards.
    exact : bool
        True when the coefficients were rational and every statement (count, multiplicities)
        was decided in exact arithmetic; False for the arb path (irrational coefficients).
    """

    certified: bool
    count: int | None
    intervals: tuple
    multiplicities: tuple
    at_infinity: int
    method: str
    exact_intervals: tuple = ()
    exact: bool = False

    def contains(self, t):
        """True if the finite real root intervals contain ``t = x1/x0`` (a float).

        Examples
        --------
        >>> from imagespace.core.certify import certify_real_roots
        >>> certify_real_roots([-1, 0, 1]).contains(1.0)      # x1^2 - x0^2
        True
        """
        return any(lo <= t <= hi for lo, hi in self.intervals)


def exact_is_zero(c):
    """Exact zero test of an exact sympy number: rationals directly; otherwise an arb ball
    that excludes zero proves ``c != 0`` (fast), and only a ball containing zero goes to sympy's
    symbolic test.

    Raises
    ------
    InputError
        sympy cannot decide whether the coefficient is zero.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.certify import exact_is_zero
    >>> exact_is_zero(sp.sqrt(2) * sp.sqrt(8) - 4), exact_is_zero(sp.sqrt(181) - 13)
    (True, False)
    """
    c = as_sympy(c)
    if c.is_Rational:
        return c == 0
    with flint_precision(128):
        ball = to_arb(c, 128)
    if ball.is_finite() and not ball.contains(0):
        return False
    z = c.equals(0)
    if z is None:
        raise InputError(f"cannot decide whether the coefficient {c} is zero")
    return bool(z)


def _fmpq(c):
    import flint

    c = sp.Rational(c)
    return flint.fmpq(int(c.p), int(c.q))


def _sign_at(poly, x):
    """Exact sign of a flint fmpq_poly at a Fraction."""
    import flint

    v = poly(flint.fmpq(x.numerator, x.denominator))
    return (v > 0) - (v < 0)


def _refine(poly, lo, hi, bits):
    """Shrink ``[lo, hi]`` (exact, holding exactly one root of the square-free ``poly``, a simple
    root) by exact bisection until its width is below ``2**-bits * max(1, |lo|, |hi|)``."""
    slo, shi = _sign_at(poly, lo), _sign_at(poly, hi)
    if slo == 0:
        return lo, lo
    if shi == 0:
        return hi, hi
    if slo == shi:
        raise RuntimeError("isolating interval without a sign change of its square-free factor")
    scale = max(Fraction(1), abs(lo), abs(hi))
    target = scale / 2**bits
    # bisect on dyadic points: their denominators grow by one bit per step
    while hi - lo > target:
        mid = (lo + hi) / 2
        s = _sign_at(poly, mid)
        if s == 0:
            return mid, mid
        if s == slo:
            lo = mid
        else:
            hi = mid
    return lo, hi


#: Root isolations of integer polynomials with a coefficient longer than this many bits run in a
#: child process that Ctrl-C can stop (:func:`imagespace.core.interruptible.call_interruptibly`);
#: shorter ones run inline (measured on (t - 1)((t^2 + 1)^k 2^1000 + 1), whose complex roots
#: cluster: 0.35 s at degree 5, 0.8 s at degree 11; a row of a float input has 50-300 bits). A
#: responsiveness knob: both give the same answer.
INLINE_ROOT_BITS = 1024


def _sturm_real_root_count(f):
    """Number of distinct real roots of the integer polynomial ``f`` (a python-flint
    ``fmpz_poly`` of degree >= 1): Sturm's theorem, sign changes of the exact remainder sequence
    at ``-inf`` and ``+inf``."""
    import flint

    seq = [flint.fmpq_poly(f.coeffs())]
    seq.append(seq[0].derivative())
    while seq[-1].degree() > 0:
        r = seq[-2] % seq[-1]
        if r.degree() < 0:
            break
        seq.append(-r)

    def changes(values):
        v = [x for x in values if x != 0]
        return sum(1 for a, b in zip(v, v[1:]) if (a > 0) != (b > 0))

    lead = [p.coeffs()[-1] for p in seq]
    at_minus = [c if p.degree() % 2 == 0 else -c for c, p in zip(lead, seq)]
    return changes(at_minus) - changes(lead)


def _real_root_balls(ints, prec, in_child=False):
    """The isolation step of :func:`_exact_path`, in plain data (it may run in a child process):
    for the integer polynomial with coefficients ``ints`` (ascending), each real root of each
    square-free factor as ``(factor coefficients, lo, hi, multiplicity)``, ``[lo, hi]`` exact
    rational bounds of FLINT's isolating ball. Factors Sturm's theorem proves free of real roots
    skip the complex isolation (on long coefficients, clusters of complex roots can make it slow).
    Sets python-flint's precision to ``prec`` under the lock inline, directly in a (single
    threaded) child: there the lock may be a copy held by another thread of the parent."""
    import flint

    num = flint.fmpz_poly(ints)
    _, factors = num.factor_squarefree()
    found = []
    if in_child:
        flint.ctx.prec = int(prec)
    with nullcontext() if in_child else flint_precision(prec):
        for fac, mult in factors:
            if fac.degree() < 1 or _sturm_real_root_count(fac) == 0:
                continue
            coeffs = [int(v) for v in fac.coeffs()]
            for root, _m in fac.complex_roots():
                if not root.imag.is_zero():
                    continue
                lo, hi = arb_bounds(root.real)
                found.append((coeffs, lo, hi, int(mult)))
    return found


def _exact_path(coeffs, bits=None):
    """Real roots of a rational polynomial ``sum coeffs[k] t**k``: exact isolating intervals
    (Fractions), refined; multiplicities from the square-free factorisation.

    FLINT's ``complex_roots`` isolates the roots of each square-free factor in disjoint balls
    whose real roots have an imaginary part exactly zero; the balls are valid at any working
    precision. Their ends are read exactly (:func:`arb_bounds`), and each interval is refined by
    exact bisection on the sign of its square-free factor, so nothing here depends on the
    working precision or on rounding.
    """
    import flint

    from .interruptible import call_interruptibly

    bits = REFINE_BITS if bits is None else bits
    poly = flint.fmpq_poly([_fmpq(c) for c in coeffs])
    ints = [int(v) for v in (poly * poly.denom()).coeffs()]
    # a root isolation on long integers can take minutes inside FLINT, where Ctrl-C does not
    # reach Python: such calls run in a child process that Ctrl-C stops
    heavy = max(abs(v).bit_length() for v in ints) > INLINE_ROOT_BITS
    found = call_interruptibly(_real_root_balls, (ints, bits + 32, heavy), in_child=heavy)
    out = []
    for g, lo, hi, mult in found:
        g = flint.fmpq_poly([int(v) for v in g])
        lo, hi = _refine(g, lo, hi, bits)
        out.append((lo, hi, mult))
    out.sort(key=lambda r: r[0])
    return out


def to_arb(c, prec):
    """A rigorous arb ball of an exact sympy number at the current working precision: built by
    arb arithmetic on the expression tree (rationals, sums, products, integer and half-integer
    powers, sqrt, pi, cos, sin); anything else through sympy's evaluation (:func:`_ball`).

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.certify import flint_precision, to_arb
    >>> with flint_precision(100):
    ...     b = to_arb(3 * sp.sqrt(181) / 2 + sp.cos(sp.Rational(1, 3)), 100)
    >>> round(float(b.mid()), 12) == round(float(sp.N(3 * sp.sqrt(181) / 2 + sp.cos(sp.Rational(1, 3)), 30)), 12)
    True
    >>> float(b.rad()) < 1e-25
    True
    """
    import flint

    if c.is_Rational:
        return flint.arb(flint.fmpq(int(c.p), int(c.q)))
    if c.is_Add:
        acc = flint.arb(0)
        for a in c.args:
            acc = acc + to_arb(a, prec)
        return acc
    if c.is_Mul:
        acc = flint.arb(1)
        for a in c.args:
            acc = acc * to_arb(a, prec)
        return acc
    if c.is_Pow and c.exp.is_Rational:
        b = to_arb(c.base, prec)
        e = c.exp
        if e.is_Integer:
            return b ** int(e)
        if e.q == 2 and c.base.is_positive:
            return b.sqrt() ** int(e.p)
    if c is sp.pi:
        return flint.arb.pi()
    if isinstance(c, (sp.cos, sp.sin)) and c.args[0].is_real:
        x = to_arb(c.args[0], prec)
        return x.cos() if isinstance(c, sp.cos) else x.sin()
    return _ball(c, prec)


def reduced_angle(c):
    """The float nearest ``c mod 2 pi`` in ``(-pi, pi]`` (within an ulp) for an exact sympy angle
    ``c`` (``20000000000*pi``, ``1/2 + 7*pi``, a rational), computed on arb balls with ``pi``
    enclosed: the precision grows with ``|c|`` until the remainder is known to far below an ulp.

    Raises
    ------
    InputError
        ``c`` is not a finite real number (NaN, infinite, an expression with symbols).
    InputTypeError
        ``c`` is a string (never parsed), a bool, None or a complex number.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.certify import reduced_angle
    >>> reduced_angle(2 * 10**10 * sp.pi), round(reduced_angle(sp.Rational(1, 2) + 7 * sp.pi), 12)
    (0.0, -2.641592653590)
    """
    import flint

    c = as_sympy_entry(c, "angle")          # strings are refused, never parsed
    if c.free_symbols:
        raise InputError(f"angle must be a number, got the expression {c}")
    prec = 128
    while prec <= 1 << 16:
        with flint_precision(prec):
            x = to_arb(c, prec)
            if not x.is_finite():
                raise InputError(f"angle must be a finite real number, got {c}")
            turn = 2 * flint.arb.pi()
            k = math.floor(_arf_fraction((x / turn).mid()) + Fraction(1, 2))
            r = x - turn * k               # any integer k is exact; this one puts r near [-pi, pi]
            if r.rad() < flint.arb(2) ** -80 and abs(float(r.mid())) < 4:
                v = float(r.mid())
                if v > math.pi:
                    v -= 2 * math.pi
                return math.pi if v <= -math.pi else v
        prec *= 2
    raise InputError(f"angle {c} could not be reduced modulo 2 pi")


def _ball(c, prec):
    import flint

    digits = int(prec * 0.30103) + 20
    v = sp.N(c, digits)
    if not v.is_real:
        raise InputError(f"coefficient {c} is not real")
    s = sp.Float(v, digits)
    # the decimal string has |error| < 10^(exponent - digits + 2); enclose it generously
    mag = abs(s)
    rad = sp.Float(10) ** (int(sp.floor(sp.log(mag, 10))) - digits + 5) if mag != 0 else sp.Float(10) ** (-digits)
    return flint.arb(str(s)) + flint.arb(0, str(sp.Float(rad, 5)))


def _arb_discs(coeffs, prec):
    import flint

    poly = flint.acb_poly([flint.acb(to_arb(as_sympy(c), prec)) for c in coeffs])
    try:
        roots = poly.roots()
    except ValueError:
        return None
    discs = []
    for r in roots:
        rlo, rhi = arb_bounds(r.real)
        ilo, ihi = arb_bounds(r.imag)
        discs.append((rlo, rhi, ilo, ihi))
    return discs


def _arb_decide(discs):
    """Real roots among disjoint boxes: a box off the real axis holds a non-real root; a box that
    meets the axis holds a real root when its mirror image meets no other box (the conjugate of
    its root is then itself). Returns the real intervals, or None if some box is undecided."""
    intervals = []
    for i, (rlo, rhi, ilo, ihi) in enumerate(discs):
        if ilo > 0 or ihi < 0:
            continue
        m = max(abs(ilo), abs(ihi))
        for j, (slo, shi, jlo, jhi) in enumerate(discs):
            if j != i and not (shi < rlo or slo > rhi or jlo > m or jhi < -m):
                return None
        intervals.append((rlo, rhi))
    return intervals


#: The refinement of a real root on arb coefficients (:func:`refine_root_intervals`) starts at
#: ``bits + REFINE_GUARD_BITS`` of working precision and doubles it while a sign or a Newton step
#: is limited by the balls, up to this many bits (a root that still cannot be refined is reported
#: as such; with one angle group every simple root refines long before).
REFINE_MAX_PREC = 1 << 16
#: Guard bits above the target relative width at which the refinement starts.
REFINE_GUARD_BITS = 64


def _interval_ball(flint, lo, hi):
    """An arb ball enclosing the exact interval ``[lo, hi]`` (Fractions)."""
    return flint.arb(fmpq_of(lo)).union(flint.arb(fmpq_of(hi)))


def _ball_sign(ball):
    """+1, -1, or 0 where the ball contains zero (undecided)."""
    if ball.contains(0):
        return 0
    return 1 if ball > 0 else -1


def refine_root_intervals(balls_at, intervals, bits=None):
    """Shrink isolating intervals of simple real roots on arb coefficients below ``2**-bits``
    relative: each ``[lo, hi]`` ends narrower than ``2**-bits * max(1, |lo|, |hi|)``.

    ``balls_at(prec)`` returns arb balls (python-flint, computed at working precision ``prec``)
    enclosing the exact coefficients of a real polynomial ``sum c_k t**k``; each interval of
    ``intervals`` (exact Fractions) must hold exactly one real root of it, a simple one. Each
    step is the interval Newton operator ``N(X) = m - p(m) / p'(X)`` (every root in ``X`` lies in
    ``N(X)``, so ``X & N(X)`` still holds the root) where ``p'(X)`` excludes zero, else a
    bisection on the proven sign of ``p`` at the midpoint; the precision doubles where the balls
    limit either. The width is relative, so a root near the half-turn (``|t|`` of ``1e17``)
    refines like one near 0. Nothing is rounded: the ends are exact rationals read off arb
    balls (:func:`arb_bounds`).

    Parameters
    ----------
    balls_at : callable
        ``balls_at(prec) -> sequence of flint.arb``, ascending powers of ``t``.
    intervals : sequence of (Fraction, Fraction)
    bits : int, optional
        Default :data:`REFINE_BITS`.

    Returns
    -------
    list of (Fraction, Fraction), or None
        None where an interval could not be refined up to :data:`REFINE_MAX_PREC` bits (or holds
        no sign change: not an isolating interval of a simple root).

    Examples
    --------
    >>> import flint
    >>> from fractions import Fraction
    >>> from imagespace.core.certify import refine_root_intervals
    >>> balls = lambda prec: [flint.arb(-2), flint.arb(0), flint.arb(1)]       # t^2 - 2
    >>> (lo, hi), = refine_root_intervals(balls, [(Fraction(1), Fraction(2))])
    >>> lo * lo < 2 < hi * hi, float(hi - lo) < 2.0 ** -200
    (True, True)
    """
    import flint

    bits = REFINE_BITS if bits is None else int(bits)
    cache = {}

    def polys(prec):
        if prec not in cache:
            with flint_precision(prec):
                p = flint.arb_poly(list(balls_at(prec)))
                cache[prec] = (p, p.derivative())
        return cache[prec]

    out = []
    for lo, hi in intervals:
        got = _refine_one(flint, polys, Fraction(lo), Fraction(hi), bits)
        if got is None:
            return None
        out.append(got)
    return out


def _refine_one(flint, polys, lo, hi, bits):
    """One interval of :func:`refine_root_intervals`, or None."""
    target = max(Fraction(1), abs(lo), abs(hi)) / 2**bits
    prec = bits + REFINE_GUARD_BITS
    s_lo = 0                          # sign of p left of the root (decided lazily)
    while hi - lo > target:
        if prec > REFINE_MAX_PREC:
            return None
        p, dp = polys(prec)
        width = hi - lo
        mid = (lo + hi) / 2
        with flint_precision(prec):
            d = dp(_interval_ball(flint, lo, hi))
            if not d.contains(0):
                n = flint.arb(fmpq_of(mid)) - p(flint.arb(fmpq_of(mid))) / d
                nlo, nhi = arb_bounds(n)
                nlo, nhi = max(lo, nlo), min(hi, nhi)
                if nlo > nhi:
                    return None       # no root in [lo, hi]: not an isolating interval
                if nhi - nlo <= width / 2:
                    lo, hi = nlo, nhi
                    continue
            if s_lo == 0:
                s_lo = _ball_sign(p(flint.arb(fmpq_of(lo))))
                if s_lo == 0:
                    s_hi = _ball_sign(p(flint.arb(fmpq_of(hi))))
                    s_lo = -s_hi
                if s_lo == 0:
                    prec *= 2
                    continue
            s_mid = 0
            for frac in (Fraction(1, 2), Fraction(3, 8), Fraction(5, 8)):
                x = lo + frac * width
                s_mid = _ball_sign(p(flint.arb(fmpq_of(x))))
                if s_mid:
                    break
        if s_mid == 0:
            prec *= 2
            continue
        if s_mid == s_lo:
            lo = x
        else:
            hi = x
    return lo, hi


def _arb_path(coeffs, bits=None):
    """Isolation of the real roots of a polynomial with irrational exact coefficients (arb).

    The working precision climbs 64 -> 1024 bits until every root is decided; the real roots
    are then refined by :func:`refine_root_intervals` (None where that fails: the roots are then
    not returned as certified)."""
    bits = REFINE_BITS if bits is None else bits
    for prec in (64, 128, 256, 512, 1024):
        with flint_precision(prec):
            discs = _arb_discs(coeffs, prec)
        intervals = None if discs is None else _arb_decide(discs)
        if intervals is None:
            continue
        intervals.sort()
        refined = refine_root_intervals(
            lambda p: [to_arb(as_sympy(c), p) for c in coeffs], intervals, bits)
        if refined is None:
            return None, None, prec
        return refined, [1] * len(refined), prec
    return None, None, prec


def certify_real_roots(form):
    """Certified count of the distinct real roots of a binary form on the projective line.

    Parameters
    ----------
    form : sympy.Poly in (x0, x1), or sequence of exact numbers ``[f_0, ..., f_d]``
        ``f_k`` multiplies ``x0**(d-k) x1**k``. Floats are taken as exact binary rationals.

    Returns
    -------
    RealRootCertificate

    Raises
    ------
    TypeError
        ``form`` is not a sympy Poly or a sequence of numbers (a string, a non-iterable), or a
        coefficient is a boolean, a string or another non-numeric object.
    InputError
        ``form`` is a 2-d array, a coefficient is not finite or holds symbols, or every
        coefficient is zero.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.certify import certify_real_roots
    >>> c = certify_real_roots([0, -2, 0, 1, 0])   # x0 x1 (x1^2 - 2 x0^2): roots 0, +-sqrt 2, infinity
    >>> c.count, c.at_infinity, c.certified
    (4, 1, True)
    >>> certify_real_roots([1, 0, -sp.sqrt(2)]).count   # x0^2 - sqrt(2) x1^2
    2
    """
    if isinstance(form, sp.Poly):
        gens = form.gens
        d = form.total_degree()
        coeffs = form_coefficients(form) if len(gens) == 2 else \
            [form.coeff_monomial(gens[0] ** (d - k) * gens[1] ** k) for k in range(d + 1)]
    else:
        if isinstance(form, (str, bytes)):
            raise InputTypeError(f"form must be a sympy Poly or a sequence of numbers, got {form!r}")
        if isinstance(form, np.ndarray) and form.ndim != 1:
            raise InputError(f"form must be one binary form, a 1-d sequence of coefficients, got an "
                             f"array of shape {form.shape}; use certify_real_roots_batch for rows")
        try:
            entries = list(form)
        except TypeError:
            raise InputTypeError(f"form must be a sympy Poly or a sequence of numbers, got "
                                 f"{type(form).__name__} {form!r}") from None
        coeffs = []
        for k, c in enumerate(entries):
            if isinstance(c, (bool, np.bool_, sp.logic.boolalg.Boolean)):
                raise InputTypeError(f"form[{k}] must be a number or a sympy expression, got the boolean {c!r}")
            if isinstance(c, (str, bytes)):
                raise InputTypeError(f"form[{k}] must be a number or a sympy expression, got the string {c!r}")
            if isinstance(c, (float, np.floating)):
                if not math.isfinite(float(c)):
                    raise InputError(f"form[{k}] must be finite, got {float(c)}")
                coeffs.append(sp.Rational(float(c)))
            elif isinstance(c, (int, np.integer)):
                coeffs.append(sp.Integer(int(c)))
            elif isinstance(c, Fraction):
                coeffs.append(sp.Rational(c.numerator, c.denominator))
            elif isinstance(c, sp.Basic):
                coeffs.append(c)
            else:
                raise InputTypeError(f"form[{k}] must be a number or a sympy expression, got "
                                     f"{type(c).__name__} {c!r}")
    for k, c in enumerate(coeffs):
        if c.has(sp.nan, sp.zoo, sp.oo, -sp.oo) or c.free_symbols:
            raise InputError(f"coefficient {k} of the form must be a finite number, got {c}")
    if len(coeffs) == 0 or all(exact_is_zero(c) for c in coeffs):
        raise InputError("form must not vanish identically (every coefficient is zero)")
    at_inf = 0
    while exact_is_zero(coeffs[-1]):
        coeffs = coeffs[:-1]
        at_inf += 1
    rational = all(as_sympy(c).is_Rational for c in coeffs)
    if len(coeffs) == 1:
        return RealRootCertificate(True, int(at_inf > 0), (), (), at_inf,
                                   "exact: the form is a constant times a power of x0", (), rational)
    if rational:
        roots = _exact_path(coeffs)
        exact_iv = tuple((lo, hi) for lo, hi, _ in roots)
        return RealRootCertificate(True, len(roots) + int(at_inf > 0),
                                   tuple(outward_float_interval(lo, hi) for lo, hi in exact_iv),
                                   tuple(m for _, _, m in roots), at_inf,
                                   "exact: python-flint complex_roots on the square-free factors "
                                   "(arb_fmpz_poly_complex_roots; factors without a real root by "
                                   "Sturm's theorem), intervals refined by exact bisection",
                                   exact_iv, True)
    intervals, mults, prec = _arb_path(coeffs)
    if intervals is None:
        return RealRootCertificate(False, None, (), (), at_inf,
                                   f"not certified: acb_poly.roots could not isolate every root up to "
                                   f"{prec} bits (a multiple root with irrational coefficients?)", (), False)
    return RealRootCertificate(True, len(intervals) + int(at_inf > 0),
                               tuple(outward_float_interval(lo, hi) for lo, hi in intervals),
                               tuple(mults), at_inf,
                               f"arb balls: python-flint acb_poly.roots isolation at {prec} bits, real "
                               "roots by conjugate-symmetric discs", tuple(intervals), False)


def certify_real_roots_batch(F, err=None, exact=None, return_intervals=False):
    """Certified real-root counts for a batch of binary forms, vectorised, with an exact fallback.

    Each row is a binary form known either exactly (``err`` None: the floats are taken as the
    exact binary rationals they are) or up to a rigorous bound per coefficient (the exact form
    lies in ``F +- err``, e.g. coefficients evaluated in floating point with a rounding bound).
    For every row the roots are approximated (companion eigenvalues) and enclosed in the discs of
    the Gerschgorin-type theorem for polynomials (Braess-Hadeler, Carstensen): with ``z_1..z_d``
    distinct approximations of the roots of ``p`` (degree ``d``, leading coefficient ``a_d``), the
    discs ``D(z_i, d |p(z_i)| / |a_d prod_{j != i} (z_i - z_j)|)`` cover all roots and a union of
    ``m`` discs disjoint from the others holds exactly ``m`` roots. Rounding is bounded rigorously:
    ``|p(z_i)|`` is enlarged by the Horner error bound ``gamma_{2d+1} sum |a_k| |z_i|^k`` plus the
    coefficient uncertainty ``sum err_k |z_i|^k``, ``|a_d|`` is decreased by ``err_d`` and the
    denominator by a relative ``(4d + 4) u``; the bound then holds for every form in the box, the
    exact one included. A row is decided by the discs when they are pairwise disjoint and each
    is either off the real axis (non-real root) or such that the disc centred on the real axis
    that covers it and its mirror image meets no other disc (the root is its own conjugate:
    real; it is then also simple). Every other row (multiple or nearly multiple roots, a root at
    ``x0 = 0``, coefficients too uncertain) is decided exactly by :func:`certify_real_roots` on
    the exact coefficients.

    Parameters
    ----------
    F : (n, d+1) float
        ``F[:, k]`` multiplies ``x0**(d-k) x1**k``.
    err : (n, d+1) float, optional
        Rigorous bounds ``|exact - F| <= err`` per coefficient. Requires ``exact``.
    exact : callable, optional
        ``exact(i)`` returns the exact coefficients of row ``i`` (sympy numbers or Fractions),
        or directly its :class:`RealRootCertificate` (e.g. one decided on enclosures of
        transcendental coefficients), for the rows the discs cannot decide. Default: the floats
        of ``F`` themselves.
    return_intervals : bool
        Also return the real-root intervals.

    Returns
    -------
    counts : (n,) int
        Distinct real roots on the projective line; ``-1`` for rows that are not finite, that
        vanish identically (``path == "zero"``) or could not be certified.
    path : (n,) str array
        ``"discs"`` (vectorised inclusion discs), ``"flint"`` (exact fallback, rational
        coefficients), ``"arb"`` (fallback on arb enclosures of irrational or transcendental
        coefficients), ``"zero"`` (the exact form vanishes identically), ``"uncertified"`` (the
        fallback could not decide, irrational coefficients with a multiple root) or ``"invalid"``.
    intervals : (n, d, 2) float, only with ``return_intervals``
        For each certified real root, an interval of ``t = x1/x0`` that contains it and no other
        root, rounded outwards, in ascending order; ``(inf, inf)`` for the root ``x0 = 0``; NaN
        in unused slots. On the disc path the roots are simple.

    Raises
    ------
    InputError
        ``F`` is not of shape ``(n, d+1)`` with ``d >= 1``; ``err`` has a negative entry or
        another shape than ``F``; ``err`` is non-zero but ``exact`` is not given.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.core.certify import certify_real_roots_batch
    >>> counts, path = certify_real_roots_batch(np.array([[-2.0, 0.0, 1.0], [1.0, -2.0, 1.0]]))
    >>> counts.tolist(), path.tolist()     # x1^2 - 2 x0^2 (two roots); (x1 - x0)^2 (one double)
    ([2, 1], ['discs', 'flint'])
    """
    F = as_float_array(F, "F", finite=False)       # non-finite rows are reported "invalid"
    if F.ndim != 2 or F.shape[1] < 2:
        raise InputError(f"F must have shape (n, d+1) with d >= 1, got {F.shape}")
    n, d1 = F.shape
    d = d1 - 1
    if err is None:
        E = np.zeros_like(F)
    else:
        E = as_float_array(err, "err", finite=False)
        if np.any(E < 0):
            raise InputError("err must hold non-negative error bounds, got a negative entry")
        if E.shape != F.shape:
            raise InputError(f"err must have the shape of F {F.shape}, got {E.shape}")
        if exact is None and np.any(E != 0):
            raise InputError("err needs exact: the rows the discs cannot decide are decided on "
                             "their exact coefficients")
    if exact is None:
        def exact(i):
            return [sp.Rational(float(v)) for v in F[i]]
    counts = np.full(n, -1, dtype=int)
    path = np.full(n, "invalid", dtype=object)
    ivals = np.full((n, d, 2), np.nan)
    finite = np.all(np.isfinite(F), axis=1) & np.all(np.isfinite(E), axis=1)
    nonzero = finite & np.any(np.abs(F) > E, axis=1)
    regular = nonzero & (np.abs(F[:, d]) > E[:, d])
    idx = np.flatnonzero(regular)
    decided = np.zeros(n, dtype=bool)
    if idx.size:
        good, real, z, hull_r = inclusion_discs(F[idx], E[idx])
        counts[idx[good]] = np.sum(real[good], axis=1)
        path[idx[good]] = "discs"
        decided[idx[good]] = True
        if return_intervals:
            grow = 1 + 8 * _U                           # outward rounding of centre +- radius
            lo = (z.real - hull_r * grow) - np.abs(z.real) * 4 * _U
            hi = (z.real + hull_r * grow) + np.abs(z.real) * 4 * _U
            lo = np.where(real, lo, np.inf)
            order = np.argsort(lo, axis=1)
            lo = np.take_along_axis(lo, order, axis=1)
            hi = np.take_along_axis(np.where(real, hi, np.nan), order, axis=1)
            gi = np.flatnonzero(good)
            sub = np.stack([lo[gi], hi[gi]], axis=-1)
            sub[~np.isfinite(sub[..., 0])] = np.nan
            ivals[idx[gi]] = sub
    for i in np.flatnonzero(finite & ~decided):
        try:
            val = exact(int(i))
            cert = val if isinstance(val, RealRootCertificate) else certify_real_roots(val)
        except (InputError, DegenerateDesignError):
            path[i] = "zero"
            continue
        if not cert.certified:
            path[i] = "uncertified"
            continue
        counts[i] = cert.count
        path[i] = "flint" if cert.exact else "arb"
        if return_intervals:
            rows = list(cert.intervals) + ([(np.inf, np.inf)] if cert.at_infinity else [])
            for j, (a, b) in enumerate(rows[:d]):
                ivals[i, j] = (a, b)
    if return_intervals:
        return counts, path.astype(str), ivals
    return counts, path.astype(str)
