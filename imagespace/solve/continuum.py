r"""Exact detection of a continuum of assembly modes at given joint values.

At a fixed orientation ``(x0 : x1)`` the three dyad quadrics are, in the positions ``(x2, x3)``,
the rows ``(c_i, alpha_i, beta_i, kappa_i)`` of a 3x4 matrix ``M``: the circle or line
``c (x2**2 + x3**2) + alpha x2 + beta x3 + kappa = 0``, with ``alpha = a0 x0 + a1 x1``,
``beta = b0 x0 + b1 x1``, ``kappa = k0 x0**2 + k1 x0 x1 + k2 x1**2``. Two distinct circles or
lines meet in at most two points, so the positions at that orientation form a continuum exactly
when ``rank M <= 1`` (every non-zero row describes one curve) and that curve has infinitely many
real points: a line (``c = 0``, ``(alpha, beta) != 0``), a circle of positive squared radius
(``alpha**2 + beta**2 - 4 c kappa > 0``), or every row zero (the whole plane).

With ``t = x1/x0``, the entries of ``M`` are polynomials in ``t``; ``rank M <= 1`` at a real
``t`` exactly when ``t`` is a root of ``g``, the gcd of the eighteen 2x2 minors (the orientation
``x0 = 0`` is tested on its own). :func:`continuum_at` computes ``g`` exactly (python-flint,
rational coefficients: the joint values are the binary rationals of the floats), splits it into
irreducible factors, and decides the reality of the curve at each real root exactly (a rational
root directly; an irrational one by an isolating interval refined until the sign of
``alpha**2 + beta**2 - 4 c kappa`` is proven). Orientations where ``rank M <= 1`` are also roots
of the kinematic polynomial, at least double ones (its elimination forms ``D, X2, X3`` and the
final determinant vanish there to first and second order), so a row whose real roots are all
proven simple holds no continuum of positions: callers run this test only on rows whose proof
found a multiple (or undecided) root, or that fall in a Cramer case.

For designs whose constants lie in one quadratic field ``Q(sqrt d)`` (an axis normalised from
integers brings ``sqrt 181`` into seed 002), the same minors and their gcd are computed over the
field, in pairs of FLINT rationals (:mod:`imagespace.core.quadratic_field`): a constant gcd and a
rank-2 matrix at ``x0 = 0`` prove that no continuum exists (in ~0.1 ms; sympy's evaluation of
the same row took ~1.2 ms and could not decide); a common root is left undecided.

A continuum of orientations (the kinematic polynomial vanishing identically) is reported by
:meth:`~imagespace.core.mechanism.Mechanism.exact_forms` (a
:class:`~imagespace.exceptions.DegenerateDesignError`), not here.

The spurious orientation ``phi_c + pi`` of a PP dyad satisfies the quadric but is not a mode:
on designs with a PP dyad a continuum is confirmed by the legs' inverse kinematics at one of
its points (a floating-point check with ``Tolerances.joint_residual``).
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any, Optional

import numpy as np
import sympy as sp

from .._validate import as_exact, as_sympy, as_sympy_entry
from ..core.certify import certify_real_roots
from ..exceptions import InputError, InputTypeError
from ..core.kinematic_map import pose_of

__all__ = ["continuum_at"]

#: Bisections of an irrational root's isolating interval before the sign of the squared radius
#: is given up on (a numerical-method knob: giving up answers "undecided", never a wrong verdict).
_SIGN_REFINEMENTS = 200


def _fmpq(v):
    import flint

    v = sp.Rational(v)
    return flint.fmpq(int(v.p), int(v.q))


def _quadric_enclosure(m):
    """The 24 quadric coefficients general in the joint values, for exact evaluation at rational
    joint values (:class:`~imagespace.core.codegen.CoefficientEnclosure`), or None where they are
    not polynomial in the joint features."""
    from ..core.codegen import CoefficientEnclosure

    coeffs = [v for qd in m.quadrics(None) for v in qd.coefficients()]
    try:
        return CoefficientEnclosure(coeffs, m.joint_symbols)
    except ValueError:
        return None


def _exact_coefficients(m, q):
    """The 24 quadric coefficients at ``q`` as sympy rationals, or None where one is not rational
    (irrational geometry, the cosine of a non-zero actuated angle)."""
    rational_q = all(isinstance(v, (float, np.floating, int, np.integer)) or as_sympy(v).is_Rational for v in q)
    enc = m.cached("continuum_quadrics", lambda: _quadric_enclosure(m)) if rational_q else None
    if enc is not None and enc.rational:
        qq = [Fraction(float(v)) if isinstance(v, (float, np.floating)) else
              Fraction(int(sp.Rational(v).p), int(sp.Rational(v).q)) for v in q]
        return [sp.Rational(v.numerator, v.denominator) for v in enc.exact(qq)]
    q_exact = [sp.Rational(float(v)) if isinstance(v, (float, np.floating)) else as_sympy(v) for v in q]
    cf = [as_sympy(v) for qd in m.quadrics(q_exact) for v in qd.coefficients()]
    return cf if all(v.is_Rational for v in cf) else None


def _rows(cf):
    """The rows ``(c, alpha, beta, kappa)`` of the 24 rational coefficients ``cf`` as fmpq_poly in
    ``t = x1/x0`` (chart ``x0 = 1``), and the constant rows at ``x0 = 0, x1 = 1``."""
    import flint

    rows, top = [], []
    for i in range(3):
        c, a0, a1, b0, b1, k0, k1, k2 = (_fmpq(v) for v in cf[8 * i:8 * i + 8])
        P = flint.fmpq_poly
        rows.append((P([c]), P([a0, a1]), P([b0, b1]), P([k0, k1, k2])))
        top.append((c, a1, b1, k2))
    return rows, top


def _minors(rows):
    """The 2x2 minors of the 3x4 matrix of rows (any ring)."""
    out = []
    for i in range(3):
        for j in range(i + 1, 3):
            for a in range(4):
                for b in range(a + 1, 4):
                    out.append(rows[i][a] * rows[j][b] - rows[i][b] * rows[j][a])
    return out


def _squared_radius(row):
    """``alpha**2 + beta**2 - 4 c kappa`` of a row (any ring): positive iff the circle is real
    and not a point (for ``c != 0``)."""
    c, al, be, ka = row
    return al * al + be * be - 4 * c * ka


def _real_curve(row, is_zero, sign):
    """Whether one row, at one orientation, is a curve with infinitely many real points:
    ``is_zero(e)`` decides an entry, ``sign(e)`` the sign of the squared radius (None:
    undecided). Returns True, False or None."""
    c, al, be, ka = row
    if not is_zero(c):
        return None if sign(_squared_radius(row)) is None else sign(_squared_radius(row)) > 0
    if not (is_zero(al) and is_zero(be)):
        return True                 # a line
    return False                    # kappa = 0 alone: no solution (kappa != 0) -- callers skip zero rows


def _sign_at_root(h, f, interval):
    """The sign of the fmpq_poly ``h`` at the root of the irreducible ``f`` in ``interval``
    (Fractions), ``h`` not divisible by ``f`` (so non-zero there): refine the interval by
    bisection on the sign of ``f`` until ``h``'s enclosure over it excludes zero."""
    lo, hi = interval
    hc = [Fraction(int(v.p), int(v.q)) for v in (_sympy_rational(x) for x in h.coeffs())]
    fc = [Fraction(int(v.p), int(v.q)) for v in (_sympy_rational(x) for x in f.coeffs())]

    def ev(cs, x):
        acc = Fraction(0)
        for v in reversed(cs):
            acc = acc * x + v
        return acc

    def slope_bound(cs, r):
        return sum(abs(v) * k * r ** max(k - 1, 0) for k, v in enumerate(cs))

    flo = ev(fc, lo)
    for _ in range(_SIGN_REFINEMENTS):
        mid = (lo + hi) / 2
        r = max(abs(lo), abs(hi))
        val = ev(hc, mid)
        if abs(val) > slope_bound(hc, r) * (hi - lo) / 2:
            return 1 if val > 0 else -1
        fm = ev(fc, mid)
        if fm == 0:
            return 1 if ev(hc, mid) > 0 else -1
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return None


def _sympy_rational(x):
    return sp.Rational(int(x.p), int(x.q))


def _orientations(rows):
    """The real orientations ``t`` (as ``(factor, interval or rational)``) where every 2x2 minor
    vanishes; ``"all"`` when they vanish identically."""
    import flint

    g = None
    for mnr in _minors(rows):
        if mnr.degree() < 0:
            continue
        g = mnr if g is None else g.gcd(mnr)
        if g.degree() < 1:
            return []               # a constant gcd: rank 2 at every orientation (the usual case)
    if g is None:
        return "all"
    if g.degree() < 1:
        return []
    num = flint.fmpz_poly([int(v) for v in (g * g.denom()).coeffs()])
    _, factors = num.factor()
    out = []
    for fz, _mult in factors:
        f = flint.fmpq_poly(fz.coeffs())
        if f.degree() == 1:
            a, b = f.coeffs()                           # a + b t
            out.append((f, Fraction(int(-a.p * b.q), int(a.q * b.p))))
            continue
        cert = certify_real_roots([_sympy_rational(v) for v in f.coeffs()])
        for iv in cert.exact_intervals:
            out.append((f, tuple(iv)))
    return out


def _check_pose(m, q, row, t):
    """Float confirmation by the legs' inverse kinematics (designs with a PP dyad): one point
    of the real curve ``row`` at the orientation ``t`` (a float, None for ``x0 = 0``)."""
    x0, x1 = (1.0, t) if t is not None else (0.0, 1.0)
    c, al, be, ka = (float(v) for v in row)
    if c != 0:
        x2, x3 = -al / (2 * c) + np.sqrt(max(al * al + be * be - 4 * c * ka, 0.0)) / (2 * abs(c)), -be / (2 * c)
    elif al != 0 or be != 0:
        s = -ka / (al * al + be * be)
        x2, x3 = al * s, be * s
    else:
        x2, x3 = 0.0, 0.0
    h = np.hypot(x0, x1)
    pose = pose_of(np.array([x0, x1, x2, x3]) / h)
    return bool(m.joint_residual(pose, np.asarray(q, float)) <= m.tolerances.joint_residual)


def _transcendental_verdict(m, q):
    """Quadric coefficients holding ``cos``/``sin`` of a joint angle (exact in
    ``Q[tan(r/2)]``, :mod:`imagespace.core.transcendental`): with one angle group and no other
    irrational constant, "no orientation of rank <= 1" is decided exactly. The minors are
    polynomials in ``(t, tau)``; when they share no factor involving ``t`` their common zeros are
    finitely many points with algebraic coordinates, and ``tau = tan(r/2)`` is transcendental, so
    no common zero has this ``tau``. The same at ``x0 = 0`` for the constant rows: a minor that
    is a non-zero polynomial in ``tau`` is non-zero at ``tau``. Anything else is left undecided
    (``(None, None)``)."""
    from ..core.transcendental import TranscendentalDesign

    try:
        q_exact = [Fraction(float(v)) if isinstance(v, (float, np.floating, int, np.integer))
                   else Fraction(int(sp.Rational(v).p), int(sp.Rational(v).q)) for v in q]
    except (TypeError, ValueError):
        return None, None
    try:
        design = m.cached("transcendental_design", lambda: TranscendentalDesign(m))
    except ValueError:
        return None, None
    built = design.ring_quadrics(q_exact)
    if built is None:
        return None, None
    k, quads = built
    if not k.decidable:
        return None, None
    top = [(qd.coefficients()[0], qd.coefficients()[2], qd.coefficients()[4], qd.coefficients()[7])
           for qd in quads]
    if all(mn.is_zero() for mn in _minors(top)):
        return None, None                     # rank <= 1 at the half-turn for every angle: undecided
    lift = k.lift
    rows = []
    for qd in quads:
        c, a0, a1, b0, b1, k0, k1, k2 = qd.coefficients()
        rows.append((lift(c), lift(a0) + lift(a1, 1), lift(b0) + lift(b1, 1),
                     lift(k0) + lift(k1, 1) + lift(k2, 2)))
    g = None
    for mn in _minors(rows):
        if mn.is_zero():
            continue
        g = mn if g is None else g.gcd(mn)
        if g.degrees()[0] == 0:
            return False, None
    return None, None


def _quadratic_field_quadrics(m):
    """The 24 quadric coefficients general in the joint values as pairs over ``Q(sqrt d)``
    (:class:`~imagespace.core.quadratic_field.QuadraticFieldForms`), or None where the design's
    constants do not lie in one quadratic field (rational designs, angles, other radicals)."""
    from ..core.quadratic_field import QuadraticFieldForms

    if not m.is_numeric:
        return None
    coeffs = [v for qd in m.quadrics(None) for v in qd.coefficients()]
    try:
        return QuadraticFieldForms([coeffs], m.joint_symbols)
    except ValueError:
        return None


def _quadratic_field_verdict(m, q):
    """"No continuum" decided in ``Q(sqrt d)`` arithmetic (FLINT, no sympy per row) for designs
    whose constants lie in one quadratic field: the same minors as the rational route, their gcd
    over ``Q(sqrt d)[t]`` by Euclid's algorithm (exact). A constant gcd and a rank-2 matrix at
    ``x0 = 0`` prove that no orientation has ``rank M <= 1``: ``(False, None)``; otherwise
    ``(None, None)`` (undecided: a common root would need its reality and the curve's decided in
    the field). Returns None where this route does not apply."""
    from ..core.quadratic_field import poly_gcd, poly_mul, poly_sub

    if not all(isinstance(v, (float, np.floating, int, np.integer)) or as_sympy(v).is_Rational for v in q):
        return None
    forms = m.cached("continuum_quadratic_field", lambda: _quadratic_field_quadrics(m))
    if forms is None:
        return None
    d = forms.d
    cf = forms.at([float(v) if isinstance(v, (float, np.floating)) else Fraction(int(sp.Rational(v).p),
                                                                                  int(sp.Rational(v).q))
                   for v in q])[0]

    # x0 = 0: the constant rows (c, a1, b1, k2); every minor zero leaves the row undecided
    top = [([cf[8 * i]], [cf[8 * i + 2]], [cf[8 * i + 4]], [cf[8 * i + 7]]) for i in range(3)]
    if all(not poly_sub(poly_mul(r[a], s[b], d), poly_mul(r[b], s[a], d))
           for r, s in _row_pairs(top) for a, b in _column_pairs()):
        return None, None
    rows = []
    for i in range(3):
        c, a0, a1, b0, b1, k0, k1, k2 = cf[8 * i:8 * i + 8]
        rows.append(([c], [a0, a1], [b0, b1], [k0, k1, k2]))
    g = None
    for r, s in _row_pairs(rows):
        for a, b in _column_pairs():
            mnr = poly_sub(poly_mul(r[a], s[b], d), poly_mul(r[b], s[a], d))
            if not mnr:
                continue
            g = mnr if g is None else poly_gcd(g, mnr, d)
            if len(g) == 1:
                return False, None      # a constant gcd: rank 2 at every orientation
    return None, None


def _row_pairs(rows):
    return [(rows[i], rows[j]) for i in range(3) for j in range(i + 1, 3)]


def _column_pairs():
    return [(a, b) for a in range(4) for b in range(a + 1, 4)]


def _checked_joint_values(m, q):
    """``q`` as three numbers continuum_at can take exactly: python/numpy floats (binary
    rationals) and integers as they are, every other entry through
    :func:`~imagespace._validate.as_sympy_entry` (strings are refused, never parsed; sympy floats
    become their binary rationals), the values inside the joints' domains."""
    from ..core.planar import PlanarMechanism

    if not isinstance(m, PlanarMechanism):
        raise InputTypeError(f"m must be a planar design (PlanarParallel), got {type(m).__name__}")
    if isinstance(q, np.ndarray):
        if q.ndim != 1:
            raise InputError(f"q must be 3 joint values (shape (3,)), got an array of shape {q.shape}")
        q = list(q)
    elif not isinstance(q, (list, tuple)):
        raise InputTypeError(f"q must be a sequence of 3 joint values, got {type(q).__name__}")
    if len(q) != 3:
        raise InputError(f"q must have 3 joint values, got {len(q)}")
    out = []
    for i, v in enumerate(q):
        name = f"q[{i}]"
        if isinstance(v, (bool, np.bool_)):
            raise InputTypeError(f"{name} must be a real number, got the boolean {v}")
        if isinstance(v, (float, np.floating)):
            if not np.isfinite(v):
                raise InputError(f"{name} must be finite, got {float(v)}")
            out.append(float(v))
        elif isinstance(v, (int, np.integer)):
            out.append(int(v))
        else:
            e = as_sympy_entry(v, name)
            if e.free_symbols:
                raise InputError(f"{name} must be a number (continuum_at decides numeric joint values), "
                                 f"got the expression {e}")
            out.append(as_exact(e, name))
    m.check_q(out)
    return out


def continuum_at(m: Any, q: Any) -> tuple[Optional[bool], Optional[float]]:
    """Decide exactly whether the design ``m`` has a continuum of assembly modes at one
    orientation for the joint values ``q`` (floats taken as the binary rationals they are).

    Parameters
    ----------
    m : PlanarParallel
        A numeric design.
    q : (3,) float or exact numbers

    Returns
    -------
    verdict : bool or None
        True: a continuum of positions at the orientation ``phi``; False: none at any
        orientation (proven); None: undecided (irrational geometry, several actuated angles
        in a relation, a structural rank drop at a transcendental angle, or a sign that could
        not be refined).
    phi : float or None
        The orientation of the continuum (radians), when ``verdict`` is True.

    Examples
    --------
    A triangle platform congruent to the base, rotated by ``phi = 2 atan(1/3)``, all legs of
    length 2: the platform can translate along a circle at that orientation.

    >>> import imagespace as isp
    >>> import sympy as sp
    >>> from imagespace.solve.continuum import continuum_at
    >>> R = sp.Rational
    >>> m = isp.PlanarParallel([isp.RPR((0, 0), (0, 0)), isp.RPR((4, 0), (R(16, 5), R(-12, 5))),
    ...                         isp.RPR((1, 3), (R(13, 5), R(9, 5)))])
    >>> verdict, phi = continuum_at(m, [2, 2, 2])
    >>> verdict, round(phi, 6)
    (True, 0.643501)
    >>> continuum_at(m, [2, 2, 2.5])
    (False, None)
    """
    return decide_continuum(m, _checked_joint_values(m, q))


def decide_continuum(m: Any, q: Any) -> tuple[Optional[bool], Optional[float]]:
    """:func:`continuum_at` on joint values the caller has already validated (the direct
    kinematics' own stages: a float array or exact numbers inside the joints' domains); the public
    boundary validates once, this does not again. Not public API."""
    field = _quadratic_field_verdict(m, q)
    if field is not None:
        return field
    cf = _exact_coefficients(m, q)
    if cf is None:
        return _transcendental_verdict(m, q)
    rows, top = _rows(cf)
    pp = "PP" in m.kinds
    undecided = False
    # x0 = 0: constant rows
    if all(top[i][a] * top[j][b] == top[i][b] * top[j][a] for i in range(3) for j in range(i + 1, 3)
           for a in range(4) for b in range(a + 1, 4)):
        nz = [r for r in top if any(v != 0 for v in r)]
        if not nz:
            return True, float(np.pi)
        verdict = _real_curve(nz[0], lambda e: e == 0, lambda e: (e > 0) - (e < 0))
        if verdict and (not pp or _check_pose(m, q, nz[0], None)):
            return True, float(np.pi)
    found = _orientations(rows)
    if found == "all":
        # rank <= 1 at every orientation: the positions are a continuum wherever the curve of a
        # non-zero row is real; such a design also has a vanishing kinematic polynomial
        samples = [Fraction(k, 7) for k in range(-21, 22)]
        for t in samples:
            tq = _fmpq(sp.Rational(t.numerator, t.denominator))
            vals = [tuple(e(tq) for e in r) for r in rows]
            nz = [r for r in vals if any(v != 0 for v in r)]
            if not nz:
                return True, float(2 * np.arctan(float(t)))
            v = _real_curve(nz[0], lambda e: e == 0, lambda e: (e > 0) - (e < 0))
            if v and (not pp or _check_pose(m, q, nz[0], float(t))):
                return True, float(2 * np.arctan(float(t)))
        return None, None
    for f, root in found:
        if isinstance(root, Fraction):
            tq = _fmpq(sp.Rational(root.numerator, root.denominator))
            vals = [tuple(e(tq) for e in r) for r in rows]
            nz = [r for r in vals if any(v != 0 for v in r)]
            tf = float(root)
            verdict = True if not nz else _real_curve(nz[0], lambda e: e == 0, lambda e: (e > 0) - (e < 0))
            row_f = nz[0] if nz else (0, 0, 0, 0)
        else:
            nz = [r for r in rows if any((e % f).degree() >= 0 for e in r)]
            tf = float((root[0] + root[1]) / 2)
            if not nz:
                verdict, row_f = True, (0, 0, 0, 0)
            else:
                r0 = nz[0]
                verdict = _real_curve(r0, lambda e: (e % f).degree() < 0,
                                      lambda e: 0 if (e % f).degree() < 0 else _sign_at_root(e % f, f, root))
                row_f = tuple(float(e(_fmpq(sp.Rational(tf)))) for e in r0)
        if verdict is None:
            undecided = True
            continue
        if verdict and (not pp or _check_pose(m, q, row_f, tf)):
            return True, float(2 * np.arctan(tf))
    return (None, None) if undecided else (False, None)
