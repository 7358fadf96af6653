r"""Exact forms over cos and sin of binary-rational angles, decided without rounding.

A joint angle given as a float is the exact binary rational ``r`` it stores. Its cosine and sine
are transcendental (Lindemann: ``e^{ir}`` is transcendental for algebraic ``r != 0``), so no
rational number is "the" value of ``cos r``, and a certificate computed from rounded ``cos r``,
``sin r`` answers a different question: near a discriminant it can give the wrong number of real
assembly modes. Here cosine and sine enter exactly.

**Angle groups.** Every distinct ``|r|`` among the ``cos(r)``, ``sin(r)`` atoms of the exact
coefficients (sympy keeps ``cos(-r) = cos(r)``, ``sin(-r) = -sin(r)``) is one group with the
tangent half-angle variable ``tau = tan(r/2)``, or ``tau = cot(r/2)`` when ``cos r < 0`` (so that
``|tau| <= 1``):

.. math::

    \cos r = \pm\frac{1 - \tau^2}{1 + \tau^2}, \qquad \sin r = \frac{2\tau}{1 + \tau^2}.

``tau`` is transcendental. A quadric's eight coefficients, polynomials in ``cos r, sin r`` of
total degree ``K``, multiplied by the positive ``(1 + tau^2)^K``, are polynomials over Q in
``tau`` (python-flint ``fmpq_mpoly``); the zero set of the quadric is unchanged. Any other
irrational constant of the design (``sqrt(181)``, ``cos(7*pi/18)``) is a free variable ``zeta``
with an arb enclosure (:func:`imagespace.core.certify.to_arb`). The elimination of
:mod:`imagespace.core.elimination` runs on these polynomials exactly.

**Decisions at the actual angles.** A coefficient that vanishes identically is zero. Otherwise an
arb ball of its value (``tau`` enclosed at the working precision) that excludes zero proves it
non-zero. With one angle group and no other constant, a non-zero polynomial over Q cannot vanish
at the transcendental ``tau``, so raising the precision always decides; with several groups (or
``zeta`` variables) an algebraic relation between them (``q2 = 2 q1`` ...) can make it vanish, and
the question is answered only when a ball decides it (otherwise the certificate says it is not
certified). The square-free decomposition of the kinematic polynomial over ``Q(tau)`` specialises
at a transcendental ``tau`` to the square-free decomposition of the actual polynomial (its
discriminants and resultants are non-zero polynomials in ``tau``); with several groups the
specialisation is verified by arb instead: every factor's roots isolated in disjoint discs,
factors' discs disjoint from each other. So multiple roots at an actuated angle (a design whose
modes are double for every angle, say) are certified with their multiplicity.

Nothing here rounds a transcendental number: every value is an arb ball of the exact one.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Callable, Optional, Sequence

import sympy as sp

from .._validate import as_sympy
from ..exceptions import DegenerateDesignError
from .certify import (REFINE_BITS, RealRootCertificate, arb_bounds, flint_precision,
                      outward_float_interval, refine_root_intervals, to_arb)
from .elimination import eliminate

__all__ = ["ExactConstants", "ExactForm", "TranscendentalElimination", "transcendental_elimination",
           "TranscendentalDesign",
           "certify_transcendental", "PRECISIONS", "MAX_BITS_ONE_GROUP", "MAX_BITS"]

#: Working precisions (bits) tried in turn for the direct isolation of the real roots.
PRECISIONS = (64, 128, 256, 512, 1024)
#: With several angle groups or other irrational constants a question no ball decides up to this
#: precision is reported as not certified (an algebraic relation may make the answer exact zero).
MAX_BITS = 4096
#: With one angle group and rational constants every question is decidable (the half-angle
#: tangent is transcendental); the precision climbs up to this bound (a safeguard only).
MAX_BITS_ONE_GROUP = 65536


# --------------------------------------------------------------------------- the constants


def _fmpq(v):
    import flint

    v = sp.Rational(v)
    return flint.fmpq(int(v.p), int(v.q))


def _is_angle_atom(a):
    return isinstance(a, (sp.cos, sp.sin)) and a.args[0].is_Rational and a.args[0] > 0


def _other_atoms(e):
    """Irrational constant atoms of an exact sympy number other than ``cos``/``sin`` of a
    rational: radicals, pi, E, other functions of numbers."""
    out = set()
    for a in sp.preorder_traversal(e):
        if a.is_Rational or a.is_Symbol:
            continue
        if _is_angle_atom(a):
            continue
        if isinstance(a, sp.Pow) and a.base.is_Rational and a.exp.is_Rational and not a.exp.is_Integer:
            out.add(a)
        elif isinstance(a, sp.NumberSymbol):
            out.add(a)
        elif isinstance(a, sp.Function) and not a.free_symbols:
            out.add(a)
    return out


class ExactConstants:
    """The irrational constants of a set of exact sympy numbers, as variables of a polynomial ring.

    ``cos(r)``, ``sin(r)`` with ``r`` rational form angle groups (one variable ``tau`` each, see
    the module docstring); every other irrational atom is a free variable ``zeta``.

    Parameters
    ----------
    exprs : sequence of sympy numbers
        Exact numbers (no free symbols).
    angles : sequence of Fraction, optional
        Further angles (joint values) whose groups the ring must have.

    Attributes
    ----------
    angles : tuple of Fraction
        The positive angle of each group.
    cot : tuple of bool
        Whether the group's variable is ``cot(r/2)`` (``cos r < 0``) rather than ``tan(r/2)``.
    others : tuple of sympy numbers
        The other irrational atoms.
    ctx : flint.fmpq_mpoly_ctx
        Variables ``T0, T1, ...`` (groups) then ``Z0, Z1, ...`` (others).

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.transcendental import ExactConstants
    >>> k = ExactConstants([3 * sp.cos(sp.Rational(1, 2)) + sp.sqrt(2), sp.sin(sp.Rational(1, 2))])
    >>> k.angles, k.others
    ((Fraction(1, 2),), (sqrt(2),))
    """

    def __init__(self, exprs, angles=()):
        import flint

        angles, others = {Fraction(a) for a in angles if a != 0}, set()
        angles = {abs(a) for a in angles}
        for e in exprs:
            e = as_sympy(e)
            if e.free_symbols:
                raise ValueError(f"exact constants must not hold symbols, got {e}")
            for a in e.atoms(sp.cos, sp.sin):
                if _is_angle_atom(a):
                    angles.add(Fraction(int(a.args[0].p), int(a.args[0].q)))
            others |= _other_atoms(e)
        self.angles = tuple(sorted(angles))
        self.others = tuple(sorted(others, key=sp.default_sort_key))
        cot = []
        with flint_precision(64):
            for r in self.angles:
                c = flint.arb(flint.fmpq(r.numerator, r.denominator)).cos()
                prec = 64
                while c.contains(0):            # cos of a rational is never zero
                    prec *= 2
                    with flint_precision(prec):
                        c = flint.arb(flint.fmpq(r.numerator, r.denominator)).cos()
                cot.append(bool(c < 0))
        self.cot = tuple(cot)
        names = tuple(f"T{i}" for i in range(len(self.angles))) + \
            tuple(f"Z{i}" for i in range(len(self.others)))
        self.ngroups = len(self.angles)
        self.ctx = flint.fmpq_mpoly_ctx.get(names or ("T0",), "lex")
        gens = self.ctx.gens()
        self._tau = gens[:self.ngroups]
        self._zeta = gens[self.ngroups:self.ngroups + len(self.others)]
        self._ball_cache = {}

    @property
    def trivial(self):
        """True when every number is rational (no group, no other constant)."""
        return not self.angles and not self.others

    @property
    def decidable(self):
        """True when every zero test is decidable by precision alone: at most one angle group
        and no other irrational constant."""
        return self.ngroups <= 1 and not self.others

    @property
    def signature(self):
        """A hashable key of the ring (its groups, their variables and the other atoms)."""
        return (self.angles, self.cot, self.others)

    def group(self, r):
        """``(g, sign)`` of the rational angle ``r != 0``: its group and the sign of ``sin``."""
        r = Fraction(r)
        return self.angles.index(abs(r)), (1 if r > 0 else -1)

    def trig_parts(self, g):
        """``(cn, sn, w)``: ``cos r = cn / w``, ``sin r = sn / w`` for group ``g`` (ring elements,
        ``w = 1 + tau**2 > 0``)."""
        return self._trig_parts(g)

    def _trig_parts(self, g):
        """Numerators of ``cos r``, ``sin r`` over ``1 + tau**2`` for group ``g``, and that
        denominator."""
        t = self._tau[g]
        w = 1 + t * t
        c = (t * t - 1) if self.cot[g] else (1 - t * t)
        return c, 2 * t, w

    def polys(self, exprs):
        """The numbers ``exprs`` as polynomials over Q, all multiplied by ONE positive factor
        ``prod_g (1 + tau_g**2)**K_g`` (so ratios, signs and zeros are those of the numbers).

        Returns
        -------
        list of flint.fmpq_mpoly, or None
            None when a number is not a polynomial in the atoms with rational coefficients.
        """
        cos_sym = {r: sp.Dummy(f"c{i}") for i, r in enumerate(self.angles)}
        sin_sym = {r: sp.Dummy(f"s{i}") for i, r in enumerate(self.angles)}
        zeta_sym = [sp.Dummy(f"z{i}") for i in range(len(self.others))]
        sub = {}
        for r in self.angles:
            rr = sp.Rational(r.numerator, r.denominator)
            sub[sp.cos(rr)] = cos_sym[r]
            sub[sp.sin(rr)] = sin_sym[r]
        sub.update(dict(zip(self.others, zeta_sym)))
        gens = [cos_sym[r] for r in self.angles] + [sin_sym[r] for r in self.angles] + zeta_sym
        G = self.ngroups
        polys = []
        for e in exprs:
            e = sp.expand(as_sympy(e).xreplace(sub)) if sub else sp.expand(as_sympy(e))
            if not gens:
                if not e.is_Rational:
                    return None
                polys.append([((), e)])
                continue
            try:
                p = sp.Poly(e, *gens)
            except sp.PolynomialError:
                return None
            terms = p.terms()
            if any(not c.is_Rational for _, c in terms):
                return None
            polys.append(terms)
        K = [0] * G
        for terms in polys:
            for mono, _ in terms:
                for g in range(G):
                    K[g] = max(K[g], mono[g] + mono[G + g])
        parts = [self._trig_parts(g) for g in range(G)]
        zero = self.ctx.from_dict({})
        out = []
        for terms in polys:
            acc = zero
            for mono, c in terms:
                t = zero + _fmpq(c)
                for g in range(G):
                    cn, sn, w = parts[g]
                    a, b = mono[g], mono[G + g]
                    t = t * cn**a * sn**b * w**(K[g] - a - b)
                for h in range(len(self.others)):
                    t = t * self._zeta[h]**mono[2 * G + h]
                acc = acc + t
            out.append(acc)
        return out

    def t_ring(self):
        """The ring ``Q[t, T0, ..., Z0, ...]``: this ring with a first variable ``t`` (the
        orientation ``x1/x0``), for polynomials in the orientation over these constants."""
        import flint

        return flint.fmpq_mpoly_ctx.get(("t",) + tuple(self.ctx.names()), "lex")

    def lift(self, p, power=0):
        """``p * t**power`` in :meth:`t_ring` (``p`` an element of this ring)."""
        return self.t_ring().from_dict({(power, *mono): c for mono, c in p.terms()})

    def variable_balls(self, prec):
        """arb balls of the ring's variables at working precision ``prec`` (cached)."""
        import flint

        if prec not in self._ball_cache:
            balls = []
            with flint_precision(prec + 16):
                for r, cot in zip(self.angles, self.cot):
                    half = flint.arb(flint.fmpq(r.numerator, r.denominator)) / 2
                    balls.append(1 / half.tan() if cot else half.tan())
                for a in self.others:
                    balls.append(to_arb(a, prec + 16))
            if not balls:
                balls = [flint.arb(0)]
            self._ball_cache[prec] = balls
        return self._ball_cache[prec]


def _eval_ball(p, balls):
    """arb value of an fmpq_mpoly at arb values of its variables (current working precision)."""
    import flint

    acc = flint.arb(0)
    for mono, c in p.terms():
        t = flint.arb(c)
        for v, e in zip(balls, mono):
            if e:
                t = t * v**int(e)
        acc = acc + t
    return acc


# --------------------------------------------------------------------------- forms


class ExactForm:
    """A binary form ``sum f_k x0**(d-k) x1**k`` whose coefficients are polynomials over Q in the
    variables of an :class:`ExactConstants` (one common positive factor aside).

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.transcendental import ExactConstants, ExactForm
    >>> r = sp.Rational(1, 3)
    >>> k = ExactConstants([sp.cos(r)])
    >>> f = ExactForm(k, k.polys([sp.cos(r), 0, -1]))          # cos(1/3) x0^2 - x1^2
    >>> f.degree, f.is_zero(1), f.is_zero(0)
    (2, True, False)
    """

    def __init__(self, constants, coeffs):
        self.constants = constants
        self.coeffs = list(coeffs)
        self.degree = len(self.coeffs) - 1

    def identically_zero(self):
        """True when every coefficient vanishes identically (zero whatever the constants)."""
        return all(c.is_zero() for c in self.coeffs)

    def balls(self, prec):
        """arb balls of the coefficients at working precision ``prec``."""
        vb = self.constants.variable_balls(prec)
        with flint_precision(prec):
            return [_eval_ball(c, vb) for c in self.coeffs]

    def is_zero(self, k, max_bits=None):
        """Exact zero test of coefficient ``k`` at the actual constants: True, False, or None
        where no ball up to ``max_bits`` decides (possible only with several angle groups or
        other irrational constants)."""
        c = self.coeffs[k]
        if c.is_zero():
            return True
        if c.is_constant():
            return False
        prec = 64
        top = max_bits or (MAX_BITS_ONE_GROUP if self.constants.decidable else MAX_BITS)
        while prec <= top:
            vb = self.constants.variable_balls(prec)
            with flint_precision(prec):
                b = _eval_ball(c, vb)
            if not b.contains(0):
                return False
            prec *= 2
        return None


def _divide_circle(form):
    """Divide a binary form (list of ring elements) by ``x0**2 + x1**2`` as often as it divides
    exactly (those factors have no real roots)."""
    while len(form) > 3:
        d = len(form) - 1
        quo = [None] * (d - 1)
        for k in range(d - 1):
            quo[k] = form[k] - (quo[k - 2] if k >= 2 else 0)
        # the last two coefficients must match: f_{d-1} = q_{d-3}, f_d = q_{d-2}
        if not ((form[d - 1] - quo[d - 3]).is_zero() and (form[d] - quo[d - 2]).is_zero()):
            break
        if all(q.is_zero() for q in quo):
            break
        form = quo
    return form


@dataclass
class _RingQuadric:
    """A dyad quadric whose coefficients are ring elements (the duck type :func:`eliminate` reads)."""

    kind: str
    coeffs: tuple

    def coefficients(self):
        return self.coeffs


def _orientation_form(rows):
    """Case (a) of the elimination on ring elements (the analogue of
    :func:`imagespace.core.elimination.orientation_form`)."""
    from .elimination import bf_add, bf_scale

    E1, E2 = rows[0], rows[1]
    v1 = [*E1.A, *E1.B]
    v2 = [*E2.A, *E2.B]
    if all(v.is_zero() for v in v1):
        G = list(E1.K)
    else:
        j = next(k for k, v in enumerate(v1) if not v.is_zero())
        G = bf_add(bf_scale(E1.K, v2[j]), bf_scale(E2.K, -v1[j]))
    if all(g.is_zero() for g in G):
        if all(v.is_zero() for v in v1) and any(not k.is_zero() for k in E2.K):
            return list(E2.K)
        raise DegenerateDesignError(
            "the constraint equations leave a continuum of assembly modes (the x2, x3-free "
            "combination of the linear constraints vanishes identically)")
    return G


@dataclass
class TranscendentalElimination:
    """The elimination of three exact quadrics with transcendental constants.

    Attributes
    ----------
    constants : ExactConstants
    P : ExactForm
        The kinematic polynomial (factors ``x0**2 + x1**2`` divided out).
    D, X2, X3 : ExactForm or None
        The Cramer forms (None in case (a)).
    case_a : bool
        The Cramer denominator vanishes identically (``P`` is the orientation form).
    """

    constants: ExactConstants
    P: ExactForm
    D: Optional[ExactForm]
    X2: Optional[ExactForm]
    X3: Optional[ExactForm]
    case_a: bool

    def cramer_balls(self, prec):
        """arb balls of ``(D, X2, X3)`` at working precision ``prec`` (for back-substitution)."""
        return self.D.balls(prec), self.X2.balls(prec), self.X3.balls(prec)


def _finish_elimination(k, ring, plan):
    """Eliminate ring quadrics and divide out the circle factors (see
    :func:`transcendental_elimination`)."""
    el = eliminate(ring, plan)
    D = list(el.D)
    if all(v.is_zero() for v in D):
        P = _orientation_form(el.rows)
        return TranscendentalElimination(k, ExactForm(k, P), None, None, None, True)
    F = list(el.F)
    if all(v.is_zero() for v in F):
        raise DegenerateDesignError("the kinematic polynomial vanishes identically at these joint "
                                    "values: infinitely many assembly modes (a continuum)")
    P = _divide_circle(F)
    return TranscendentalElimination(k, ExactForm(k, P), ExactForm(k, D), ExactForm(k, el.X2),
                                     ExactForm(k, el.X3), False)


class TranscendentalDesign:
    """A design's legs as exact templates in the features ``q, cos q, sin q`` of their joint
    values, for the exact elimination at any exact joint vector without sympy per call.

    Each leg's quadric with a symbolic joint value is expanded once on the monomials
    ``q**a cos(q)**b sin(q)**c`` with exact constant coefficients (the design's own irrational
    constants, a fixed angle given as a float included). At a joint vector the quadrics are built
    directly in the polynomial ring of :class:`ExactConstants` (rational constants never touch
    sympy) and eliminated there.

    Parameters
    ----------
    mechanism : PlanarParallel
        A numeric design.

    Raises
    ------
    ValueError
        A leg's quadric is not polynomial in ``q, cos q, sin q`` with constant coefficients.

    Examples
    --------
    >>> import sympy as sp
    >>> import imagespace as isp
    >>> from imagespace.core.transcendental import TranscendentalDesign
    >>> m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(1, 2)),
    ...                         isp.RPR(base=(4, 0), platform=(1, 0)),
    ...                         isp.RPR(base=(0, 4), platform=(0, 1))])
    >>> el = TranscendentalDesign(m).elimination([0.5, 3.0, 3.0])
    >>> el.constants.angles, el.P.degree
    ((Fraction(1, 2),), 6)
    """

    def __init__(self, mechanism):
        self.plan = mechanism.elimination_plan
        self.kinds = tuple(mechanism.kinds)
        self.legs = []
        consts = []
        for i, leg in enumerate(mechanism.legs):
            q = sp.Dummy(f"q{i}", real=True)
            gens = (q, sp.cos(q), sp.sin(q))
            coeffs = [sp.expand(as_sympy(c)) for c in leg.dyad(q).coefficients()]
            terms = {}
            for k, c in enumerate(coeffs):
                try:
                    poly = sp.Poly(c, *gens)
                except sp.PolynomialError:
                    raise ValueError(f"leg {i}'s quadric is not polynomial in q, cos q, sin q") from None
                for mono, val in poly.terms():
                    if val.free_symbols:
                        raise ValueError(f"leg {i}'s quadric has symbolic constants: {val}")
                    terms.setdefault(mono, [sp.Integer(0)] * 8)[k] = val
            monos = sorted(terms)
            self.legs.append((monos, [terms[mo] for mo in monos],
                              any(mo[1] or mo[2] for mo in monos)))
            consts += [v for mo in monos for v in terms[mo]]
        self.rational = all(v.is_Rational for v in consts)
        self._design_constants = [v for v in consts if not v.is_Rational]
        self._const_cache = {}

    def _constants(self, k, i):
        """Leg ``i``'s constant coefficients as ring elements (one common positive factor)."""
        key = (k.signature, i)
        if key not in self._const_cache:
            monos, rows, _ = self.legs[i]
            flat = [v for row in rows for v in row]
            if all(v.is_Rational for v in flat):
                zero = k.ctx.from_dict({})
                polys = [zero + _fmpq(v) for v in flat]
            else:
                polys = k.polys(flat)
                if polys is None:
                    raise ValueError(f"leg {i}'s constants are not polynomial in their atoms")
            self._const_cache[key] = [polys[8 * j:8 * j + 8] for j in range(len(monos))]
            if len(self._const_cache) > 256:
                self._const_cache.pop(next(iter(self._const_cache)))
        return self._const_cache[key]

    def elimination(self, q):
        """The exact elimination at the joint vector ``q`` (floats as binary rationals, or exact
        rationals): a :class:`TranscendentalElimination`, or None when every number is rational
        (the rational paths apply).

        Raises
        ------
        DegenerateDesignError
            The kinematic polynomial vanishes identically at ``q`` (a continuum of modes).
        """
        built = self.ring_quadrics(q)
        if built is None:
            return None
        k, ring = built
        return _finish_elimination(k, ring, self.plan)

    def ring_quadrics(self, q):
        """``(constants, quadrics)``: the three quadrics at ``q`` with coefficients in the ring of
        :class:`ExactConstants` (each quadric times a positive factor), or None when every
        number is rational.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.core.transcendental import TranscendentalDesign
        >>> m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(1, 2)),
        ...                         isp.RPR(base=(4, 0), platform=(1, 0)),
        ...                         isp.RPR(base=(0, 4), platform=(0, 1))])
        >>> k, quads = TranscendentalDesign(m).ring_quadrics([0.5, 3.0, 3.0])
        >>> [qd.kind for qd in quads], k.ngroups
        (['RR', 'RR', 'RR'], 1)
        """
        import flint

        r = [Fraction(v) if not isinstance(v, sp.Basic) else Fraction(int(v.p), int(v.q)) for v in q]
        angles = [ri for ri, (_, _, trig) in zip(r, self.legs) if trig and ri != 0]
        if not angles and self.rational:
            return None
        k = ExactConstants(self._design_constants, angles=angles)
        zero = k.ctx.from_dict({})
        ring = []
        for i, ((monos, _, trig), ri, kind) in enumerate(zip(self.legs, r, self.kinds)):
            consts = self._constants(k, i)
            rq = flint.fmpq(ri.numerator, ri.denominator)
            if trig and ri != 0:
                g, sign = k.group(ri)
                cn, sn, w = k.trig_parts(g)
                sn = sn * sign
                K = max(mo[1] + mo[2] for mo in monos)
            coeffs = [zero] * 8
            for mo, row in zip(monos, consts):
                a, b, c = mo
                f = zero + rq**a
                if b or c:
                    if ri == 0:              # cos 0 = 1, sin 0 = 0 exactly
                        if c:
                            continue
                    else:
                        f = f * cn**b * sn**c * w**(K - b - c)
                elif trig and ri != 0:
                    f = f * w**K
                coeffs = [acc + f * v for acc, v in zip(coeffs, row)]
            ring.append(_RingQuadric(kind, tuple(coeffs)))
        return k, ring


def transcendental_elimination(quadrics, plan):
    """Eliminate ``(x2, x3)`` from three exact quadrics whose coefficients hold ``cos``/``sin`` of
    rational angles (or other irrational constants), exactly (see the module docstring).

    Parameters
    ----------
    quadrics : sequence of three Quadric
        Exact sympy coefficients, no free symbols.
    plan : EliminationPlan

    Returns
    -------
    TranscendentalElimination, or None
        None when every coefficient is rational (use the rational path) or a coefficient is not a
        polynomial in its irrational atoms with rational coefficients.

    Raises
    ------
    DegenerateDesignError
        The kinematic polynomial vanishes identically (a continuum of assembly modes).

    Examples
    --------
    >>> import sympy as sp
    >>> import imagespace as isp
    >>> from imagespace.core.transcendental import transcendental_elimination
    >>> m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(1, 2)),
    ...                         isp.RPR(base=(4, 0), platform=(1, 0)),
    ...                         isp.RPR(base=(0, 4), platform=(0, 1))])
    >>> el = transcendental_elimination(m.quadrics([sp.Rational(1, 2), 3, 3]), m.elimination_plan)
    >>> el.constants.angles, el.P.degree
    ((Fraction(1, 2),), 6)
    """
    coeff_lists = [tuple(as_sympy(c) for c in q.coefficients()) for q in quadrics]
    k = ExactConstants([c for cl in coeff_lists for c in cl])
    if k.trivial:
        return None
    ring = []
    for q, cl in zip(quadrics, coeff_lists):
        polys = k.polys(cl)
        if polys is None:
            return None
        ring.append(_RingQuadric(q.kind, tuple(polys)))
    return _finish_elimination(k, ring, plan)


# --------------------------------------------------------------------------- root isolation


def isolating_boxes(balls, shrink=False):
    """Disjoint isolating boxes of the roots of the polynomial with arb coefficients ``balls``
    (``balls[k]`` multiplies ``t**k``; current working precision), or None.

    With ``shrink`` each box is refined to a radius of about ``2**(-prec/2)`` times the size of
    the roots (``acb_poly.roots`` otherwise stops as soon as the roots are isolated from each
    other, and a box can stay ``1e-10`` wide: too wide to be told apart from the roots of another
    factor next to it)."""
    import flint

    poly = flint.acb_poly([flint.acb(b) for b in balls])
    try:
        if shrink:
            lead = abs(float(balls[-1].mid())) or 1.0
            size = 1.0 + max(abs(float(b.mid())) for b in balls[:-1]) / lead     # Cauchy's bound
            prec = flint.ctx.prec
            roots = poly.roots(tol=size * 2.0 ** -(prec // 2), maxprec=4 * prec)
        else:
            roots = poly.roots()
    except (ValueError, OverflowError):
        return None
    out = []
    for r in roots:
        rlo, rhi = arb_bounds(r.real)
        ilo, ihi = arb_bounds(r.imag)
        out.append((rlo, rhi, ilo, ihi))
    return out


def real_root_intervals(discs, others=()):
    """Real roots among disjoint boxes (see :func:`imagespace.core.certify._arb_path`); ``others``
    are boxes of other factors that must be disjoint from these. Returns the real intervals, or
    None when a box is undecided."""
    for i, (rlo, rhi, ilo, ihi) in enumerate(discs):
        for (slo, shi, jlo, jhi) in others:
            if not (shi < rlo or slo > rhi or jhi < ilo or jlo > ihi):
                return None
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


def _trim(form, at_inf, top):
    """Drop leading coefficients that vanish at the actual constants: ``(coeffs, at_infinity)``
    or None where a zero test is undecided."""
    n = len(form.coeffs)
    while n > 0:
        z = form.is_zero(n - 1, max_bits=top)
        if z is None:
            return None
        if not z:
            break
        n -= 1
        at_inf += 1
    return n, at_inf


def _certificate(intervals, mults, at_inf, method):
    intervals = sorted(zip(intervals, mults))
    iv = tuple(i for i, _ in intervals)
    return RealRootCertificate(True, len(iv) + int(at_inf > 0),
                               tuple(outward_float_interval(lo, hi) for lo, hi in iv),
                               tuple(m for _, m in intervals), at_inf, method, iv, False)


_NOT_REFINED = ("a real root could not be refined to the promised width (the coefficients' balls "
                "did not shrink enough up to the precision cap)")


def _uncertified(at_inf, why):
    return RealRootCertificate(False, None, (), (), at_inf, "not certified: " + why, (), False)


def _squarefree_factors(form, n):
    """The square-free factors over ``Q(tau, zeta)`` of the dehomogenised form (first ``n``
    coefficients): list of ``(coefficient polys in t, multiplicity)`` for factors of positive
    degree in ``t``."""
    import flint

    k = form.constants
    names = ("t",) + tuple(k.ctx.names())
    ctx = flint.fmpq_mpoly_ctx.get(names, "lex")
    terms = {}
    for j in range(n):
        for mono, c in form.coeffs[j].terms():
            terms[(j, *mono)] = c
    P = ctx.from_dict(terms)
    _, facs = P.factor_squarefree()
    out = []
    for f, e in facs:
        d = f.degrees()[0]
        if d == 0:
            continue
        parts = [k.ctx.from_dict({}) for _ in range(d + 1)]
        for mono, c in f.terms():
            parts[mono[0]] = parts[mono[0]] + k.ctx.from_dict({tuple(mono[1:]): c})
        out.append((parts, int(e)))
    return out


def certify_transcendental(form, refine_bits=None):
    """Certified count of the distinct real roots of an :class:`ExactForm` on the projective line.

    Every statement is decided on arb enclosures of the exact coefficients (see the module
    docstring): first a direct isolation (simple roots) at 64 ... 1024 bits, then, where a root may
    be multiple, the square-free factors over ``Q(tau)`` each isolated and checked disjoint from
    the others, with their multiplicities. Real roots are refined below ``2**-refine_bits``
    relative.

    Parameters
    ----------
    form : ExactForm
    refine_bits : int, optional
        Default :data:`imagespace.core.certify.REFINE_BITS`.

    Returns
    -------
    RealRootCertificate
        ``exact`` is False (the coefficients are transcendental); ``certified`` False where the
        structure could not be decided (several angle groups or other irrational constants in an
        exactly degenerate relation).

    Raises
    ------
    DegenerateDesignError
        Every coefficient vanishes identically.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.transcendental import ExactConstants, ExactForm, certify_transcendental
    >>> r = sp.Rational(1, 3)
    >>> k = ExactConstants([sp.cos(r)])
    >>> cert = certify_transcendental(ExactForm(k, k.polys([-sp.cos(r)**2, 0, 1])))  # (t - c)(t + c)
    >>> cert.count, cert.multiplicities, cert.certified
    (2, (1, 1), True)
    >>> cert = certify_transcendental(ExactForm(k, k.polys([sp.cos(r)**2, -2 * sp.cos(r), 1])))  # (t - c)^2
    >>> cert.count, cert.multiplicities
    (1, (2,))
    """
    bits = REFINE_BITS if refine_bits is None else refine_bits
    if form.identically_zero():
        raise DegenerateDesignError("the form vanishes identically: infinitely many roots (a continuum)")
    k = form.constants
    top = MAX_BITS_ONE_GROUP if k.decidable else MAX_BITS
    trimmed = _trim(form, 0, top)
    if trimmed is None:
        return _uncertified(0, "the leading coefficient cannot be decided at these angles (several "
                               "angle groups in an exact relation?)")
    n, at_inf = trimmed
    if n <= 1:
        return _certificate([], [], at_inf, "exact: the form is a constant times a power of x0")
    where = (f"{k.ngroups} angle group(s)" + (f" and {len(k.others)} other constant(s)" if k.others else ""))

    def balls_at(prec):
        return form.balls(prec)[:n]

    for prec in PRECISIONS:
        with flint_precision(prec):
            discs = isolating_boxes(balls_at(prec))
        intervals = None if discs is None else real_root_intervals(discs)
        if intervals is not None:
            intervals = refine_root_intervals(balls_at, intervals, bits)
            if intervals is None:
                return _uncertified(at_inf, _NOT_REFINED)
            return _certificate(intervals, [1] * len(intervals), at_inf,
                                f"arb enclosures of cos/sin of the exact angles ({where}): "
                                f"acb_poly.roots isolation at {prec} bits")
    if k.others:
        return _uncertified(at_inf, "a root may be multiple and the constants include irrational "
                                    "numbers other than cos/sin of the angles")
    factors = _squarefree_factors(form, n)
    prec = PRECISIONS[-1]
    while prec <= top:
        vb = k.variable_balls(prec)
        all_discs, result = [], []
        ok = True
        with flint_precision(prec):
            for parts, mult in factors:
                fb = [_eval_ball(c, vb) for c in parts]
                discs = isolating_boxes(fb, shrink=True)
                iv = None if discs is None else real_root_intervals(discs, all_discs)
                if iv is None:
                    ok = False
                    break
                all_discs.extend(discs)
                result.append((parts, mult, iv))
        if ok:
            intervals, mults = [], []
            for parts, mult, iv in result:
                def fb_at(p, parts=parts):
                    v = k.variable_balls(p)
                    with flint_precision(p):
                        return [_eval_ball(c, v) for c in parts]
                iv = refine_root_intervals(fb_at, iv, bits)
                if iv is None:
                    return _uncertified(at_inf, _NOT_REFINED)
                intervals += iv
                mults += [mult] * len(iv)
            return _certificate(intervals, mults, at_inf,
                                f"arb enclosures of cos/sin of the exact angles ({where}): square-free "
                                f"factors over Q(tan(r/2)) isolated at {prec} bits")
        prec *= 2
    return _uncertified(at_inf, f"the square-free factors could not be isolated up to {top} bits "
                                f"({where}: an exact relation between the angles?)")
