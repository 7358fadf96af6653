r"""Exact real-root counts of kinematic polynomials with coefficients in a quadratic field
:math:`\mathbb{Q}(\sqrt d)`, in FLINT arithmetic (no sympy per row).

A design whose constants are rational except for one square root (the seed-002 offset
``sqrt(181)``, from normalising an integer direction) has a kinematic polynomial, general in the
joint values, whose coefficients are polynomials in ``q1, q2, q3`` over ``Q(sqrt d)``. Each
coefficient is stored once per design as a pair of ``fmpq_mpoly`` (its rational part and the part
multiplying ``zeta = sqrt d``: ``zeta**2 = d`` is reduced away, so the pair is unique and a number
is zero exactly when both parts are). At a joint vector (floats are the binary rationals they
are) the pairs are evaluated exactly, in ``fmpq``.

The number of distinct real roots of the binary form is then decided as follows: the roots at
``x0 = 0`` by exact zero tests of the trailing coefficients; the square-free part of the
the real roots by ``acb_poly.roots`` on arb enclosures of the exact coefficients (``sqrt d``
enclosed, never rounded): a root is real when its box meets the real axis and its mirror image
meets no other box, non-real when its box misses the axis; the precision climbs until every box
is decided, which it does for a square-free polynomial. Where the first precisions do not
decide, the square-free part is computed by Euclid's algorithm over ``Q(sqrt d)`` (exact: the
field's inverse is ``(a - b zeta) / (a**2 - d b**2)``; costly, as the rationals grow), so an
exactly repeated root is seen as such instead of being chased to ever higher precision.

:func:`quadratic_field_count` is the per-row fallback of the batch counts for such designs; a row
with a repeated root (where a continuum must be ruled out) is left to the general certified path.
"""

from __future__ import annotations

import math
import numbers
from fractions import Fraction

import sympy as sp

from .._validate import as_sympy, as_sympy_entry
from ..exceptions import InputError, InputTypeError

__all__ = ["QuadraticFieldForms", "quadratic_field_count", "count_distinct_real_roots", "poly_mul", "poly_sub",
           "poly_gcd", "check_radicand", "PRECISIONS"]

#: Working precisions (bits) of the arb isolation, tried in turn.
PRECISIONS = (64, 128, 256, 512, 1024, 2048, 4096)


def check_radicand(d, name="d"):
    """``d`` as a python int when it is an integer greater than 1 that is not a perfect square
    (so ``Q(sqrt d)`` is a field of degree 2 and ``a**2 - d b**2`` vanishes only at 0), else an
    :class:`~imagespace.exceptions.InputError` naming ``name``.

    Examples
    --------
    >>> from imagespace.core.quadratic_field import check_radicand
    >>> check_radicand(181)
    181
    >>> check_radicand(4)
    Traceback (most recent call last):
    ...
    imagespace.exceptions.InputError: d must be an integer > 1 that is not a perfect square (Q(sqrt d) a quadratic field), got 4
    """
    if isinstance(d, (bool, str, bytes)) or not isinstance(d, (numbers.Integral, sp.Integer)):
        raise InputTypeError(f"{name} must be an integer > 1 that is not a perfect square, got "
                             f"{type(d).__name__} {d!r}")
    d = int(d)
    if d <= 1 or math.isqrt(d) ** 2 == d:
        raise InputError(f"{name} must be an integer > 1 that is not a perfect square (Q(sqrt d) a "
                         f"quadratic field), got {d}")
    return d


def _check_poly(p, name):
    """A polynomial over ``Q(sqrt d)`` given as ascending ``(a, b)`` pairs of exact rationals
    (fmpq, int, Fraction; a float is its binary rational), as a list of fmpq pairs."""
    import flint

    if isinstance(p, (str, bytes)) or not isinstance(p, (list, tuple)):
        raise InputTypeError(f"{name} must be a list of (a, b) pairs (the coefficient a + b sqrt d), got "
                             f"{type(p).__name__}")
    out = []
    for k, pair in enumerate(p):
        if not isinstance(pair, (list, tuple)) or len(pair) != 2:
            raise InputError(f"{name}[{k}] must be a pair (a, b) of rationals, got {pair!r}")
        vals = []
        for v in pair:
            if isinstance(v, flint.fmpq):
                vals.append(v)
            elif isinstance(v, (bool, str, bytes)) or not isinstance(v, (numbers.Rational, float, flint.fmpz)):
                raise InputTypeError(f"{name}[{k}] must hold exact rationals (fmpq, int, Fraction), got "
                                     f"{type(v).__name__} {v!r}")
            else:
                if isinstance(v, float) and not math.isfinite(v):
                    raise InputError(f"{name}[{k}] must be finite, got {v}")
                f = Fraction(int(v)) if isinstance(v, flint.fmpz) else Fraction(v)
                vals.append(flint.fmpq(f.numerator, f.denominator))
        out.append(tuple(vals))
    return out


def _radicand(exprs):
    """The square-free integer ``d > 1`` when the only irrational atoms of ``exprs`` are square
    roots of the one integer ``d`` (whether every number really is ``a + b sqrt d`` is checked by
    :func:`_split`), else None (rational numbers only, functions, pi, several radicands)."""
    roots = set()
    for e in exprs:
        e = as_sympy(e)
        if e.free_symbols or e.atoms(sp.Function) or e.atoms(sp.NumberSymbol):
            return None
        for a in e.atoms(sp.Pow):
            if abs(a.exp) == sp.Rational(1, 2) and a.base.is_Integer and a.base > 1:
                roots.add(int(a.base))
            elif not (a.exp.is_Integer and a.base.is_Rational):
                return None
    if len(roots) != 1:
        return None
    d = roots.pop()
    return None if sp.sqrt(d).is_Rational else d


def _split(c, zeta, d):
    """``(a, b)`` rationals with ``c = a + b sqrt(d)``, or None."""
    e = sp.expand(as_sympy(c).xreplace({sp.sqrt(d): zeta, 1 / sp.sqrt(d): zeta / d}))
    try:
        p = sp.Poly(e, zeta)
    except sp.PolynomialError:
        return None
    a, b = sp.Integer(0), sp.Integer(0)
    for (k,), v in p.terms():
        if not v.is_Rational:
            return None
        a, b = (a + v * d ** (k // 2), b) if k % 2 == 0 else (a, b + v * d ** (k // 2))
    return a, b


class QuadraticFieldForms:
    """Forms general in the joint values with coefficients in ``Q(sqrt d)``, for exact evaluation.

    Parameters
    ----------
    forms : sequence of sequences of sympy expressions
        Coefficient lists (polynomials in ``symbols`` with constants in ``Q(sqrt d)``).
    symbols : sequence of three sympy symbols

    Raises
    ------
    InputError
        A string or other non-number among the coefficients (never parsed); the constants are not in one ``Q(sqrt d)`` with ``d > 1`` square-free (rational only,
        trigonometric features, other radicals), or a coefficient is not polynomial in ``symbols``.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.quadratic_field import QuadraticFieldForms
    >>> q = sp.symbols("q1:4")
    >>> f = QuadraticFieldForms([[q[0] - sp.sqrt(2), 1]], q)
    >>> f.d, f.at([3, 0, 0])[0][0]
    (2, (3, -1))
    """

    def __init__(self, forms, symbols):
        import flint

        if isinstance(forms, (str, bytes)) or not isinstance(forms, (list, tuple)):
            raise InputTypeError(f"forms must be a list of coefficient lists, got {type(forms).__name__}")
        for k, form in enumerate(forms):
            if isinstance(form, (str, bytes)) or not isinstance(form, (list, tuple)):
                raise InputTypeError(f"forms[{k}] must be a list of coefficients, got {type(form).__name__}")
        if isinstance(symbols, (str, bytes)) or not isinstance(symbols, (list, tuple)) or \
                not all(isinstance(v, sp.Symbol) for v in symbols):
            raise InputTypeError(f"symbols must be a sequence of sympy Symbols, got {symbols!r}")
        exprs = [sp.expand(as_sympy_entry(c, f"forms[{k}][{j}]")) for k, form in enumerate(forms)
                 for j, c in enumerate(form)]
        forms = [list(form) for form in forms]
        self.symbols = tuple(symbols)
        consts = []
        polys = []
        for e in exprs:
            try:
                p = sp.Poly(e, *self.symbols)
            except sp.PolynomialError:
                raise InputError(f"forms: a coefficient is not polynomial in {self.symbols}: {e}") from None
            if any(v.free_symbols for _, v in p.terms()):
                raise InputError(f"forms: a coefficient is not polynomial in {self.symbols}: {e}")
            polys.append(p)
            consts += [v for _, v in p.terms()]
        d = _radicand(consts)
        if d is None:
            raise InputError("forms: the constants do not lie in one quadratic field Q(sqrt d)")
        self.d = d
        zeta = sp.Dummy("zeta")
        self._ctx = flint.fmpq_mpoly_ctx.get(tuple(str(s) for s in self.symbols), "lex")
        parts = []
        for p in polys:
            ra, rb = {}, {}
            for mono, v in p.terms():
                ab = _split(v, zeta, d)
                if ab is None:
                    raise InputError(f"forms: the constant {v} is not in Q(sqrt {d})")
                for part, x in zip((ra, rb), ab):
                    if x != 0:
                        part[tuple(mono)] = flint.fmpq(int(x.p), int(x.q))
            parts.append((self._ctx.from_dict(ra), self._ctx.from_dict(rb)))
        self._parts = []
        i = 0
        for form in forms:
            self._parts.append(parts[i:i + len(form)])
            i += len(form)

    def at(self, q):
        """The forms' coefficients at exact joint values ``q`` (floats as binary rationals,
        Fractions, fmpq): per form a list of ``(a, b)`` fmpq pairs, the value ``a + b sqrt d``.

        Examples
        --------
        >>> import sympy as sp
        >>> from imagespace.core.quadratic_field import QuadraticFieldForms
        >>> q = sp.symbols("q1:4")
        >>> QuadraticFieldForms([[q[1] * sp.sqrt(3), q[2] / 2]], q).at([0, 0.5, 3])
        [[(0, 1/2), (3/2, 0)]]
        """
        import flint

        qq = []
        for v in q:
            if isinstance(v, flint.fmpq):
                qq.append(v)
            else:
                f = Fraction(v)
                qq.append(flint.fmpq(f.numerator, f.denominator))
        return [[(a(*qq), b(*qq)) for a, b in form] for form in self._parts]


# --------------------------------------------------------------------------- arithmetic in Q(sqrt d)

def _mul(x, y, d):
    return (x[0] * y[0] + d * x[1] * y[1], x[0] * y[1] + x[1] * y[0])


def _sub(x, y):
    return (x[0] - y[0], x[1] - y[1])


def _is_zero(x):
    return x[0] == 0 and x[1] == 0


def _inv(x, d):
    n = x[0] * x[0] - d * x[1] * x[1]         # non-zero for x != 0: d is not a square
    return (x[0] / n, -x[1] / n)


def _trimmed(p):
    while p and _is_zero(p[-1]):
        p = p[:-1]
    return p


def _rem(p, g, d):
    """Remainder of ``p`` by ``g`` (ascending coefficient lists over Q(sqrt d), ``g`` trimmed)."""
    p = list(p)
    inv = _inv(g[-1], d)
    while len(p) >= len(g):
        f = _mul(p[-1], inv, d)
        s = len(p) - len(g)
        for i in range(len(g)):
            p[s + i] = _sub(p[s + i], _mul(f, g[i], d))
        p = _trimmed(p[:-1])
    return p


def _gcd_degree(p, d):
    """Degree of ``gcd(p, p')`` over Q(sqrt d) (``p`` trimmed, degree >= 1)."""
    a, b = p, _trimmed([(k * x, k * y) for k, (x, y) in enumerate(p)][1:])
    while b:
        a, b = b, _rem(a, b, d)
    return len(a) - 1


def poly_mul(p, q, d):
    """The product of two polynomials over ``Q(sqrt d)``, as ascending lists of ``(a, b)`` pairs
    (the coefficient ``a + b sqrt d``), trimmed (``[]`` is the zero polynomial).

    Examples
    --------
    >>> import flint
    >>> from imagespace.core.quadratic_field import poly_mul
    >>> z, one, r = flint.fmpq(0), flint.fmpq(1), flint.fmpq(1)
    >>> poly_mul([(z, -r), (one, z)], [(z, r), (one, z)], 2)     # (t - sqrt 2)(t + sqrt 2)
    [(-2, 0), (0, 0), (1, 0)]
    """
    p, q, d = _check_poly(p, "p"), _check_poly(q, "q"), check_radicand(d)
    if not p or not q:
        return []
    out = [(0, 0)] * (len(p) + len(q) - 1)
    for i, x in enumerate(p):
        for j, y in enumerate(q):
            m = _mul(x, y, d)
            out[i + j] = (out[i + j][0] + m[0], out[i + j][1] + m[1])
    return _trimmed(out)


def poly_sub(p, q):
    """``p - q`` for polynomials over ``Q(sqrt d)`` (ascending lists of pairs), trimmed.

    Examples
    --------
    >>> import flint
    >>> from imagespace.core.quadratic_field import poly_sub
    >>> one, z = flint.fmpq(1), flint.fmpq(0)
    >>> poly_sub([(one, z), (one, one)], [(z, z), (one, one)])
    [(1, 0)]
    """
    p, q = _check_poly(p, "p"), _check_poly(q, "q")
    n = max(len(p), len(q))
    p = list(p) + [(0, 0)] * (n - len(p))
    q = list(q) + [(0, 0)] * (n - len(q))
    return _trimmed([_sub(x, y) for x, y in zip(p, q)])


def poly_gcd(p, q, d):
    """A greatest common divisor of two polynomials over ``Q(sqrt d)`` (ascending lists of
    ``(a, b)`` pairs, exact: Euclid's algorithm with the field's inverse
    ``(a - b sqrt d) / (a**2 - d b**2)``), up to a unit; ``[]`` when both are zero. Its length
    minus one is the degree of the gcd: 0 when the polynomials have no common root in ``C``.

    Examples
    --------
    >>> import flint
    >>> from imagespace.core.quadratic_field import poly_gcd, poly_mul
    >>> z, one = flint.fmpq(0), flint.fmpq(1)
    >>> a = [(z, -one), (one, z)]                    # t - sqrt 2
    >>> len(poly_gcd(poly_mul(a, [(one, z), (one, z)], 2), poly_mul(a, [(z, one), (one, z)], 2), 2)) - 1
    1
    >>> len(poly_gcd(a, [(z, one), (one, z)], 2)) - 1   # t - sqrt 2 and t + sqrt 2
    0
    """
    d = check_radicand(d)
    a, b = _trimmed(_check_poly(p, "p")), _trimmed(_check_poly(q, "q"))
    while b:
        a, b = b, _rem(a, b, d)
    return a


def count_distinct_real_roots(coeffs, d):
    """Distinct real roots on the projective line of the binary form ``sum_k c_k x0**(n-k) x1**k``
    with ``c_k = a_k + b_k sqrt d`` exact (``coeffs``: fmpq pairs), and whether every root is simple.

    Returns
    -------
    (count, simple) or None
        ``simple`` False when a root is repeated (the count is then not computed: None for it);
        None when the form vanishes identically.

    Examples
    --------
    >>> import flint
    >>> from imagespace.core.quadratic_field import count_distinct_real_roots
    >>> q = flint.fmpq
    >>> count_distinct_real_roots([(q(-1), q(0)), (q(0), q(0)), (q(0), q(1))], 2)   # sqrt2 t^2 - 1
    (2, True)
    >>> count_distinct_real_roots([(q(2), q(0)), (q(0), q(-2)), (q(1), q(0))], 2)   # (t - sqrt 2)^2
    (None, False)
    """
    import flint

    from .certify import flint_precision
    from .transcendental import real_root_intervals, isolating_boxes

    d = check_radicand(d)
    coeffs = _check_poly(coeffs, "coeffs")
    p = _trimmed(list(coeffs))
    if not p:
        return None
    at_inf = len(coeffs) - len(p)
    if at_inf > 1:
        return None, False
    if len(p) == 1:
        return int(at_inf > 0), True
    for prec in PRECISIONS:
        with flint_precision(prec):
            root = flint.arb(d).sqrt()
            balls = [flint.arb(a) + flint.arb(b) * root for a, b in p]
            discs = isolating_boxes(balls)
        intervals = None if discs is None else real_root_intervals(discs)
        if intervals is not None:
            return len(intervals) + int(at_inf > 0), True
        if prec == PRECISIONS[1] and len(p) > 2 and _gcd_degree(p, d) > 0:
            return None, False      # exactly repeated: no precision separates it (Euclid's numbers grow: tried late)
    return None, True


def quadratic_field_count(m, q):
    """The proven number of real assembly modes of ``m`` at the float joint vector ``q``, decided
    in ``Q(sqrt d)`` arithmetic (FLINT), for designs whose constants lie in one quadratic field;
    None where this route does not apply (other designs, a PP dyad, a repeated root, a vanishing
    polynomial, or a root shared with the Cramer denominator at ``q``: the general certified path
    decides).

    Every root of the kinematic polynomial is one mode where the Cramer denominator ``D`` does not
    vanish there (``x2 = X2/D``, ``x3 = X3/D`` are then real): proven by ``gcd(P, D) = 1`` over the
    field (and ``P``, ``D`` not both vanishing at ``x0 = 0``).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.core.quadratic_field import quadratic_field_count
    >>> m = isp.examples.stigger_husty()                  # sqrt(181) among its constants
    >>> quadratic_field_count(m, m.q_example_float)
    6
    """
    if "PP" in m.kinds:
        return None
    forms = m.cached("quadratic_field_forms", lambda: _design_forms(m))
    if forms is None:
        return None
    P, D = forms.at([float(v) for v in q])
    if all(_is_zero(c) for c in D):
        return None
    if _is_zero(P[-1]) and _is_zero(D[-1]):
        return None                         # a common root at x0 = 0
    if len(poly_gcd(P, D, forms.d)) > 1:
        return None                         # a root where the Cramer denominator vanishes
    out = count_distinct_real_roots(P, forms.d)
    if out is None or not out[1] or out[0] is None:
        return None
    return out[0]


def _design_forms(m):
    """:class:`QuadraticFieldForms` of the kinematic polynomial and the Cramer denominator of
    ``m`` (general in q), or None where they do not apply."""
    if not m.is_numeric or any(leg.actuated_is_angle for leg in m.legs):
        return None
    _, el, case_a = m.exact_forms(None)
    if case_a:
        return None
    P = m.kinematic_polynomial()
    dP = P.total_degree()
    coeffs = [P.coeff_monomial(P.gens[0] ** (dP - k) * P.gens[1] ** k) for k in range(dP + 1)]
    try:
        return QuadraticFieldForms([coeffs, list(el.D)], m.joint_symbols)
    except ValueError:
        return None
