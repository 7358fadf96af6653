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

import warnings
from dataclasses import dataclass
from fractions import Fraction
from typing import Optional

import numpy as np
import sympy as sp

from ..core.certify import to_arb, flint_precision
from .._validate import as_exact, as_sympy, is_symbolic
from ..core.certify import certify_real_roots, certify_real_roots_batch, exact_is_zero
from ..core.kinematic_map import pose_of as _pose_of
from ..core.elimination import form_coefficients
from ..core.quadrics import dk_system as _system
from ..exceptions import DegenerateDesignError, InputError, NearSingularWarning
from .continuum import decide_continuum
from .numpy_path import finish_candidates, row_quadrics, scaled_quadrics, solve_batch, solve_orientation, store_modes
from .results import AssemblyMode, CertifiedModes, MAX_MODES

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
    """True when every value is an exact rational (the fmpq route applies)."""
    return all(as_sympy(v).is_Rational for v in values)


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


def _sympy_balls(D, X2, X3):
    """``balls(prec)`` of exact sympy coefficient lists (arb enclosures, see :func:`to_arb`)."""
    def balls(prec):
        return tuple([to_arb(as_sympy(c), prec) for c in f] for f in (D, X2, X3))
    return balls


def _arb_cramer(balls, root, t):
    """Irrational or transcendental coefficients: D's arb ball over the isolating interval must
    exclude zero. ``balls(prec)`` gives arb enclosures of the coefficients of ``(D, X2, X3)``."""
    import flint

    with flint_precision(ARB_BITS):
        Db, X2b, X3b = balls(ARB_BITS)

        def ev(form, x):
            acc = flint.arb(0)
            for c in reversed(form):
                acc = acc * x + c
            return acc

        if root is None:
            d = Db[-1]
            if d.contains(0):
                return None
            x2, x3 = X2b[-1] / d, X3b[-1] / d
            return float(x2.mid()), float(x3.mid())
        lo, hi = root
        mid = (lo + hi) / 2
        rad = (hi - lo) / 2
        tb = flint.arb(flint.fmpq(mid.numerator, mid.denominator)) \
            + flint.arb(0, float(rad) * 2 + 1e-300)
        if ev(Db, tb).contains(0):
            return None
        tm = flint.arb(flint.fmpq(t.numerator, t.denominator))
        d = ev(Db, tm)
        return float((ev(X2b, tm) / d).mid()), float((ev(X3b, tm) / d).mid())


def plan_roots(P, D, X2, X3, certificate, case_a, cramer_balls=None):
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
    cramer_balls : callable, optional
        ``cramer_balls(prec)`` returns arb enclosures of the coefficients of ``(D, X2, X3)``; for
        transcendental coefficients (:mod:`imagespace.core.transcendental`), where ``P, D, X2,
        X3`` are not sympy lists (they are then not read).

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
    if cramer_balls is None and not case_a:
        rational = _is_rational(list(P) + list(D) + list(X2) + list(X3))
        exact = _ExactCramer(D, X2, X3, P) if rational and cert.exact else None
        cramer_balls = None if exact is not None else _sympy_balls(D, X2, X3)
    else:
        exact = None
    plans = []
    for k, (iv, mult) in enumerate(roots):
        t = None if iv is None else (iv[0] + iv[1]) / 2
        x0, x1 = _orientation(t)
        pos = None
        if not case_a:
            if exact is not None:
                pos = exact.point(iv, t)
            else:
                pos = _arb_cramer(cramer_balls, iv, t)
        if pos is None:
            plans.append(RootPlan(k, "orientation", int(mult), x0, x1))
        else:
            plans.append(RootPlan(k, "cramer", int(mult), x0, x1, _normalised_point(t, *pos)))
    return plans


def _general_at(P, symbols, q_exact):
    """Exact coefficients of the general-q polynomial ``P`` at exact joint values."""
    sub = dict(zip(symbols, q_exact))
    return [sp.expand(c.subs(sub)) for c in form_coefficients(P)]


def _exact_evaluators(m):
    """The general-q forms ``P`` and ``(D, X2, X3)`` expanded for exact evaluation (None for a
    symbolic design or Cramer case (a))."""
    if not m.is_numeric:
        return None
    from ..core.codegen import CoefficientEnclosure

    _, el, case_a = m.exact_forms(None)
    if case_a:
        return None
    return (CoefficientEnclosure(m.kinematic_polynomial(), m.joint_symbols),
            CoefficientEnclosure(list(el.D) + list(el.X2) + list(el.X3), m.joint_symbols))


def _fast_exact_forms(m, q_exact):
    """``(P, D, X2, X3)`` exact coefficient lists (sympy numbers) at rational ``q`` from the
    general-q derivation (no sympy elimination per call), or None where that route does not
    apply (symbolic or irrational input, trigonometric features, or a Cramer case at this
    ``q`` that the general formulas do not see: then ``exact_forms`` decides)."""
    if not all(v.is_Rational for v in q_exact) or any(leg.actuated_is_angle for leg in m.legs):
        return None                 # cos/sin of an actuated angle: not rational, sympy decides
    ev = m.cached("exact_evaluators", lambda: _exact_evaluators(m))
    if ev is None:
        return None
    if ev[0].rational and ev[1].rational:
        from fractions import Fraction

        qq = [Fraction(int(v.p), int(v.q)) for v in q_exact]
        P, rest = ev[0].exact(qq), ev[1].exact(qq)
        P = [sp.Rational(v.numerator, v.denominator) for v in P]
        rest = [sp.Rational(v.numerator, v.denominator) for v in rest]
    else:
        P, rest = ev[0].exact_sympy(q_exact), ev[1].exact_sympy(q_exact)
    D, X2, X3 = rest[:3], rest[3:7], rest[7:11]
    if all(v == 0 for v in D) or all(exact_is_zero(v) for v in P):
        return None
    return P, D, X2, X3


def _exact_at(enc, q, q_exact):
    """Exact values (sympy numbers) of a :class:`CoefficientEnclosure` at rational joint values."""
    if enc.rational:
        from fractions import Fraction

        return [sp.Rational(v.numerator, v.denominator) for v in enc.exact([Fraction(float(v)) for v in q])]
    return enc.exact_sympy(q_exact)


def _has_angle_constants(m):
    """True when the design's exact geometry holds ``cos``/``sin`` of a rational angle (a fixed
    angle given as a float)."""
    for qd in m.quadrics(None):
        for c in qd.coefficients():
            c = as_sympy(c)
            if any(isinstance(a, (sp.cos, sp.sin)) and a.args[0].is_Rational for a in c.atoms(sp.cos, sp.sin)):
                return True
    return False


def transcendental_forms(m, q_exact):
    """The exact elimination at ``q_exact`` when ``cos``/``sin`` of a rational angle enter the
    quadrics (an actuated revolute, a fixed angle given as a float): a
    :class:`~imagespace.core.transcendental.TranscendentalElimination`, or None where every
    coefficient is rational or irrational only through radicals (the rational/sympy paths apply).
    Not public API.

    Raises
    ------
    DegenerateDesignError
        The kinematic polynomial vanishes identically at ``q_exact`` (a continuum)."""
    if not m.is_numeric or any(v.free_symbols for v in q_exact):
        return None
    if not (any(leg.actuated_is_angle for leg in m.legs)
            or m.cached("angle_constants", lambda: _has_angle_constants(m))):
        return None
    from ..core.transcendental import TranscendentalDesign, transcendental_elimination

    if all(v.is_Rational for v in q_exact):
        try:
            design = m.cached("transcendental_design", lambda: TranscendentalDesign(m))
        except ValueError:
            design = None
        if design is not None:
            return design.elimination(q_exact)
    return transcendental_elimination(m.quadrics(list(q_exact)), m.elimination_plan)


def exact_certificate(m, q):
    """The real-root certificate of the kinematic polynomial at the float joint vector ``q`` on
    its exact input (floats as binary rationals, ``cos``/``sin`` of angles enclosed, never
    rounded). Not public API.

    Raises
    ------
    DegenerateDesignError
        The kinematic polynomial vanishes identically at ``q`` (a continuum of modes)."""
    q_exact = [as_exact(float(v), f"q[{i}]") for i, v in enumerate(q)]
    tr = transcendental_forms(m, q_exact)
    if tr is not None:
        from ..core.transcendental import certify_transcendental

        return certify_transcendental(tr.P)
    return certify_real_roots(exact_coefficients(m, q))


def exact_coefficients(m, q):
    """Exact coefficients (sympy numbers) of the kinematic polynomial at the joint vector ``q``
    (floats as the binary rationals they are): from the general-q forms where they are rational,
    else by the sympy elimination at ``q``. Not public API.

    Raises
    ------
    DegenerateDesignError
        The kinematic polynomial vanishes identically at ``q`` (a continuum of modes)."""
    q_exact = [as_exact(float(v), f"q[{i}]") for i, v in enumerate(q)]
    if not any(leg.actuated_is_angle for leg in m.legs):
        ev = m.cached("exact_evaluators", lambda: _exact_evaluators(m))
        if ev is not None:              # the polynomial and D alone (not X2, X3) from the general forms
            from ..core.codegen import CoefficientEnclosure

            D_ev = m.cached("exact_cramer_denominator", lambda: CoefficientEnclosure(
                list(m.exact_forms(None)[1].D), m.joint_symbols))
            P, D = (_exact_at(e, q, q_exact) for e in (ev[0], D_ev))
            if not all(v == 0 for v in D) and not all(exact_is_zero(v) for v in P):
                return P
    return form_coefficients(m.exact_forms(q_exact)[0])


def exact_mode_count(m, q):
    """The proven number of real assembly modes at the float joint vector ``q``, decided exactly:
    the fallback of the batch counts. In ``Q(sqrt d)`` arithmetic where the design's constants
    lie in one quadratic field and every root is a Cramer root; otherwise the certified per-row
    path (:func:`certified_modes`: the modes computed root by root from the exact certificate).
    ``(count, path)``, count -1 where that path cannot prove the number (path
    ``"uncertified"``). Not public API.

    Raises
    ------
    DegenerateDesignError
        A continuum of modes at ``q``."""
    from ..core.quadratic_field import quadratic_field_count

    fast = quadratic_field_count(m, q)     # constants in one Q(sqrt d): FLINT, no sympy per row
    if fast is not None:
        return fast, "arb"
    qf = np.asarray(q, dtype=float)
    if "PP" not in m.kinds:
        # simple roots, each proven a Cramer root (D != 0 there: exactly, or by an arb ball over
        # its refined interval): one mode each, nothing to solve
        q_exact = [as_exact(float(v), f"q[{i}]") for i, v in enumerate(qf)]
        stage = _exact_stage(m, q_exact)
        P, D, X2, X3, case_a, cert, balls, _ = stage
        if (cert.certified and not case_a and cert.at_infinity <= 1
                and all(k == 1 for k in cert.multiplicities)
                and all(p.kind == "cramer" for p in plan_roots(P, D, X2, X3, cert, False, cramer_balls=balls))):
            return cert.count, ("flint" if cert.exact else "arb")
    else:
        stage = None
    with np.errstate(over="ignore", invalid="ignore"):
        try:
            modes = certified_modes(m, qf, qf, warn=False, stage=stage)
        except (InputError, OverflowError):
            return -1, "uncertified"       # the poses leave the float range: not counted here
    cert = modes.certificate
    if not cert.certified or modes.doubts:
        return -1, "uncertified"
    return len(modes), ("flint" if cert.exact else "arb")


def _raise_if_continuum(m, q, cert, case_a):
    """Raise :class:`~imagespace.exceptions.DegenerateDesignError` when the positions form a
    continuum at one orientation, decided exactly (:func:`~imagespace.solve.continuum.continuum_at`).
    Only a multiple root of the kinematic polynomial, or any root in Cramer case (a), can carry
    one (see :mod:`imagespace.solve.continuum`), so certificates with simple roots only are not
    tested."""
    if not (case_a or cert.at_infinity > 1 or any(k > 1 for k in cert.multiplicities)):
        return
    verdict, phi = decide_continuum(m, q)
    if verdict:
        raise DegenerateDesignError(
            f"{m.name} at q = {np.asarray(q, dtype=float).tolist()}: a continuum of assembly modes "
            f"at phi = {phi:.6g} (the positions at that orientation form a curve: architecture "
            f"singularity or singular joint values)")


def _root_factor_rational(P, lo, hi):
    """The irreducible factor over Q of the rational form ``P`` (coefficients of ``t**k``) that
    vanishes in the isolating interval ``[lo, hi]`` (Fractions)."""
    import flint

    Pp = flint.fmpq_poly([flint.fmpq(int(sp.Rational(c).p), int(sp.Rational(c).q)) for c in P])
    num = flint.fmpz_poly([int(v) for v in (Pp * Pp.denom()).coeffs()])
    _, factors = num.factor()
    for fz, _ in factors:
        f = flint.fmpq_poly(fz.coeffs())
        a = f(flint.fmpq(lo.numerator, lo.denominator))
        if lo == hi:
            if a == 0:
                return f
            continue
        b = f(flint.fmpq(hi.numerator, hi.denominator))
        if a == 0 or b == 0 or (a > 0) != (b > 0):
            return f
    return None


def _root_factor_transcendental(k, Pt, lo, hi):
    """The irreducible factor over Q of ``Pt`` (in ``k.t_ring()``) whose root at the actual angles
    lies in ``[lo, hi]`` (decided on arb enclosures), or None."""
    import flint

    _, factors = Pt.factor()
    for f, _ in factors:
        if f.degrees()[0] == 0:
            continue
        for prec in (256, 1024):
            vb = k.variable_balls(prec)
            with flint_precision(prec):
                def at(x):
                    vals = [flint.arb(flint.fmpq(x.numerator, x.denominator))] + list(vb)
                    acc = flint.arb(0)
                    for mono, c in f.terms():
                        term = flint.arb(c)
                        for v, e in zip(vals, mono):
                            if e:
                                term = term * v**int(e)
                        acc = acc + term
                    return acc
                a, b = at(lo), at(hi)
            if a.contains(0) or b.contains(0):
                continue
            if (a > 0) != (b > 0):
                return f
            break
    return None


def _orientation_positions(m, q_exact, P, tr, cert, plan):
    """The modes' positions at an orientation root, counted exactly
    (:func:`imagespace.solve.positions.positions_at_root`): a list of ``(x2, x3, multiplicity)``
    in the chart of the root (``x0 = 1``, or ``x1 = 1`` at the half-turn), or None where the exact
    count does not apply (irrational geometry) or could not be decided."""
    import flint

    from .positions import RationalRoot, TranscendentalRoot, positions_at_root

    finite = plan.index < len(cert.exact_intervals)
    lo, hi = cert.exact_intervals[plan.index] if finite else (Fraction(0), Fraction(0))
    if tr is None:
        if not cert.exact:
            return None
        cf = [as_sympy(v) for qd in m.quadrics(list(q_exact)) for v in qd.coefficients()]
        if not all(v.is_Rational for v in cf):
            return None
        Fp = flint.fmpq_poly

        def fq(v):
            return flint.fmpq(int(v.p), int(v.q))
        rows = []
        for i in range(3):
            c, a0, a1, b0, b1, k0, k1, k2 = (fq(v) for v in cf[8 * i:8 * i + 8])
            if finite:
                rows.append((Fp([c]), Fp([a0, a1]), Fp([b0, b1]), Fp([k0, k1, k2])))
            else:                                   # chart x1 = 1, s = x0 / x1 = 0
                rows.append((Fp([c]), Fp([a1, a0]), Fp([b1, b0]), Fp([k2, k1, k0])))
        if finite:
            f = _root_factor_rational(P, lo, hi)
            if f is None:
                return None
            root = RationalRoot(f, lo, hi)
        else:
            root = RationalRoot(Fp([0, 1]), Fraction(0), Fraction(0))
        return positions_at_root(rows, root)
    from ..core.transcendental import TranscendentalDesign

    if not all(v.is_Rational for v in q_exact):
        return None
    try:
        design = m.cached("transcendental_design", lambda: TranscendentalDesign(m))
    except ValueError:
        return None
    built = design.ring_quadrics([Fraction(int(v.p), int(v.q)) for v in q_exact])
    if built is None:
        return None
    k, quads = built
    if k.signature != tr.constants.signature:
        return None
    lift = k.lift
    rows = []
    for qd in quads:
        c, a0, a1, b0, b1, k0, k1, k2 = qd.coefficients()
        if finite:
            rows.append((lift(c), lift(a0) + lift(a1, 1), lift(b0) + lift(b1, 1),
                         lift(k0) + lift(k1, 1) + lift(k2, 2)))
        else:
            rows.append((lift(c), lift(a1) + lift(a0, 1), lift(b1) + lift(b0, 1),
                         lift(k2) + lift(k1, 1) + lift(k0, 2)))
    if finite:
        Pt = sum((lift(cj, j) for j, cj in enumerate(tr.P.coeffs)), k.t_ring().from_dict({}))
        f = _root_factor_transcendental(k, Pt, lo, hi)
        if f is None:
            return None
    else:
        f = k.t_ring().gens()[0]
    return positions_at_root(rows, TranscendentalRoot(f, k, lo, hi))


def pp_genuine_forms(m, q=None):
    """For each PP dyad of ``m``, the coefficients ``(a0, a1, a2)`` of ``x0**2, x0*x1, x1**2`` in
    the binary form ``(x0**2 - x1**2) cos(phi_c) + 2 x0 x1 sin(phi_c)`` (sympy, up to one positive
    factor): ``cos(phi - phi_c)`` times ``x0**2 + x1**2``, positive at the orientation ``phi_c``
    the dyad's pair of planes fixes, negative at its spurious ``phi_c + pi``. At the exact joint
    values ``q``, or general in the joint symbols (``q`` None). The one home of this form: the
    per-call test :func:`_spurious_root` and the batch counts' enclosure
    (:func:`imagespace.solve.planar.counts`) both read it. Not public API."""
    out = []
    for qd in m.quadrics(None if q is None else list(q)):
        if qd.kind == "PP":
            c = qd.coefficients()
            cos, sin = as_sympy(c[6]) / 2, as_sympy(c[7])
            out.append((cos, 2 * sin, -cos))
    return out


#: Working precisions (bits) of the exact decision whether a certified root is the spurious
#: ``phi_c + pi`` root of a PP dyad (the sign of ``cos(phi - phi_c)``, which is +-1 there).
SPURIOUS_BITS = (64, 256, 1024)


def _spurious_root(pp, iv):
    """True when the certified root (isolating interval ``iv`` of ``t = x1/x0``, None for
    ``x0 = 0``) lies on the spurious plane ``phi = phi_c + pi`` of a PP dyad of ``pp``
    (:func:`pp_genuine_forms` at the exact joint values): the sign of ``cos(phi - phi_c)``, i.e.
    of ``a0 + a1 t + a2 t**2`` (``a2`` at ``x0 = 0``), decided on arb balls over the interval. None where no ball decides it (it is ``+-(1 + t**2)`` times a positive
    factor at a root of the dyad, so this does not happen at a root the dyad carries)."""
    import flint

    for prec in SPURIOUS_BITS:
        verdict = False
        with flint_precision(prec):
            if iv is not None:
                t = flint.arb(flint.fmpq(iv[0].numerator, iv[0].denominator)).union(
                    flint.arb(flint.fmpq(iv[1].numerator, iv[1].denominator)))
            for a0, a1, a2 in pp:
                b0, b1, b2 = (to_arb(a, prec) for a in (a0, a1, a2))
                g = b2 if iv is None else b0 + t * (b1 + t * b2)
                if g.contains(0):
                    verdict = None
                    break
                if g < 0:
                    verdict = True
        if verdict is not None:
            return verdict
    return None


def _exact_stage(m, q_exact):
    """The exact elimination at ``q_exact`` and the certificate of its kinematic polynomial:
    ``(P, D, X2, X3, case_a, cert, cramer_balls, tr)`` (``P .. X3`` None and ``cramer_balls``
    set where ``cos``/``sin`` of an angle enter, ``tr`` that elimination)."""
    tr = transcendental_forms(m, q_exact)
    if tr is not None:          # cos/sin of an angle: exact in Q(tan(r/2)), decided on arb enclosures
        from ..core.transcendental import certify_transcendental

        return (None, None, None, None, tr.case_a, certify_transcendental(tr.P),
                None if tr.case_a else tr.cramer_balls, tr)
    fast = _fast_exact_forms(m, q_exact)
    if fast is not None:
        P, D, X2, X3 = fast
        return P, D, X2, X3, False, certify_real_roots(P), None, None
    Pp, el, case_a = m.exact_forms(q_exact)
    return (form_coefficients(Pp), list(el.D), list(el.X2), list(el.X3), case_a,
            certify_real_roots(Pp), None, None)


def certified_modes(m, q, qf, warn=True, stage=None):
    """The certified per-call path: modes computed root by root from the exact certificate.

    The certified stage of :func:`imagespace.solve.front.direct_kinematics` (``certify=True``):
    ``q`` is the joint vector as given (exact where it is), ``qf`` its float copy; ``stage`` the
    exact stage at ``q`` (:func:`_exact_stage`) where the caller already computed it. What is not
    proven is said in ``doubts`` of the result (and, with ``warn``, in a
    :class:`NearSingularWarning` each; the batches read ``doubts`` instead). Not public API (out
    of ``__all__``)."""
    items = list(q) if is_symbolic(q) else list(np.ravel(np.asarray(q, dtype=object)))
    q_exact = [as_exact(v, f"q[{i}]") for i, v in enumerate(items)]
    P, D, X2, X3, case_a, cert, balls, tr = _exact_stage(m, q_exact) if stage is None else stage
    if not cert.certified:
        res = solve_batch(m, qf[None, :], raise_degenerate=True)
        doubt = (f"{m.name} at q = {qf.tolist()}: the real roots could not be "
                 f"certified ({cert.method}); the floating-point modes are returned")
        _say([doubt], warn)
        return CertifiedModes(res.modes(0), cert, (), (), doubts=(doubt,))
    _raise_if_continuum(m, q_exact, cert, case_a)
    plans = plan_roots(P, D, X2, X3, cert, case_a, cramer_balls=balls)
    if not plans:                       # no real root: nothing for the float stages to compute
        return CertifiedModes([], cert, (), ())
    C, _, L = scaled_quadrics(m, qf[None, :])
    quads = row_quadrics(m, C[0])
    tol = m.tolerances
    per_root = [[] for _ in plans]
    pp = pp_genuine_forms(m, q_exact) if "PP" in m.kinds else []
    iv_of = list(cert.exact_intervals) + ([None] if cert.at_infinity else [])
    # which roots are the spurious phi_c + pi root of a PP dyad: decided exactly; a root that is
    # not carries its modes whatever their float residual (a residual above the tolerance there
    # is a double-precision limit of the pose, said in a warning, never a reason to drop a mode)
    spurious = [bool(pp) and _spurious_root(pp, iv_of[p.index]) for p in plans]
    inaccurate, unsure = [], []

    def keep(plan, resid):
        """Whether a mode of ``plan`` with joint residual ``resid`` is reported."""
        if resid <= tol.joint_residual:
            return not spurious[plan.index] or spurious[plan.index] is None
        if spurious[plan.index]:
            return False                       # the legs reject it, and so does the exact test
        if spurious[plan.index] is None:
            unsure.append(plan.index)          # undecided: the legs' check decides, said below
            return False
        inaccurate.append(plan.index)
        return True

    def modes_at(X):
        poses = _pose_of(X)
        resid = np.atleast_1d(m.joint_residual(poses, np.tile(qf, (len(X), 1)), length=L[0]))
        Xs = X.copy()
        Xs[:, 2:] /= L[0]
        _, J = _system(np.repeat(C, len(X), axis=0), Xs[:, None, :])
        return poses, resid, np.linalg.det(J[:, 0])

    cramer = [p for p in plans if p.kind == "cramer"]
    if cramer:
        X = np.array([p.image_point for p in cramer])
        poses, resid, det = modes_at(X)
        for j, plan in enumerate(cramer):
            if not keep(plan, resid[j]):
                continue
            aspect = 0 if plan.multiplicity > 1 else int(np.sign(det[j]))
            per_root[plan.index] = [AssemblyMode(X[j], poses[j], float(resid[j]), aspect, True,
                                                 plan.multiplicity)]
    undecided = []
    for plan in plans:
        if plan.kind == "cramer" or spurious[plan.index]:
            continue
        exact = _orientation_positions(m, q_exact, P, tr, cert, plan)
        if exact is not None:
            iv = iv_of[plan.index]
            t = None if iv is None else (iv[0] + iv[1]) / 2
            if not exact:
                continue
            X = np.array([_normalised_point(t, x2, x3) for x2, x3, _ in exact])
            poses, resid, det = modes_at(X)
            # case (b): the root's multiplicity is accounted for by the positions (two simple
            # ones, or a tangency) unless it exceeds them: then a mode there is singular and which
            # one is not decided here, so all are reported singular. Case (a): the root is one of
            # the orientation form's, a multiple one fixes a fold of the orientation: its modes
            # are singular
            total = sum(mult for _, _, mult in exact)
            found = []
            for j, (_, _, mult) in enumerate(exact):
                if not keep(plan, resid[j]):
                    continue
                if case_a:
                    mlt = plan.multiplicity if plan.multiplicity > 1 else mult
                else:
                    mlt = plan.multiplicity if plan.multiplicity > total else mult
                aspect = 0 if mlt > 1 else int(np.sign(det[j]))
                found.append(AssemblyMode(X[j], poses[j], float(resid[j]), aspect, True, mlt))
            per_root[plan.index] = found
            continue
        undecided.append(plan.index)
        cand = solve_orientation(m, qf, quads, plan.x0, plan.x1, L[0])
        if not cand:
            continue
        arr = np.full((1, max(len(cand), MAX_MODES), 4), np.nan)
        arr[0, :len(cand)] = cand
        sub = finish_candidates(m, qf[None, :], C, arr, np.array([True]), {}, np.array([True]), L)
        found = sub.modes(0)
        if plan.multiplicity > 1:       # a multiple orientation root: its modes are singular
            found = [AssemblyMode(mm.image_point, mm.pose, mm.residual, 0, True, plan.multiplicity)
                     for mm in found]
        per_root[plan.index] = found
    doubts = []
    if undecided:
        doubts.append(f"{m.name} at q = {qf.tolist()}: the positions at {len(undecided)} orientation "
                      "root(s) (where the Cramer denominator vanishes) could not be counted exactly "
                      "(irrational geometry, or several actuated angles in an exact relation); they "
                      "are solved in floating point and their number is not proven")
    if unsure:
        doubts.append(f"{m.name} at q = {qf.tolist()}: {len(unsure)} certified root(s) could not be told "
                      "apart from a PP dyad's spurious root phi_c + pi and their modes fail the legs' "
                      "check; they are left out and the number of modes is not proven")
    _say(doubts, warn)
    if inaccurate:          # the count is proven; only the poses' accuracy is in doubt
        _say([f"{m.name} at q = {qf.tolist()}: {len(inaccurate)} certified mode(s) miss the legs' "
              f"inverse-kinematics check (joint residual above {tol.joint_residual:g}): each "
              "exists (its root is certified and not a PP dyad's spurious root), but its pose "
              "is not as accurate as the tolerance asks (double precision at this scale), or a "
              "leg's actuated joint is free at that pose (a leg singularity: its inverse "
              "kinematics does not determine the joint value)"], warn)
    tagged = [(mm, k) for k, lst in enumerate(per_root) for mm in lst]
    tagged.sort(key=lambda item: item[0].pose[2])
    return CertifiedModes([mm for mm, _ in tagged], cert, [len(lst) for lst in per_root],
                          [k for _, k in tagged], doubts=tuple(doubts))


def _say(messages, warn):
    """Each message as a :class:`NearSingularWarning` (at the public caller) when ``warn``."""
    if warn:
        for msg in messages:
            warnings.warn(msg, NearSingularWarning, stacklevel=4)


def _disc_certificate(m, Q, res):
    """Certified counts from the enclosed general-q kinematic polynomial (inclusion discs, exact
    fallback) and which rows' float modes they account for: ``(counts, path, consistent)``."""
    n = Q.shape[0]
    enc = m.enclosure()
    Qs = np.where(res.row_ok[:, None], Q, 0.0)
    F, E = enc.evaluate(Qs)
    F = np.where(res.row_ok[:, None], F, np.nan)

    trig = any(leg.actuated_is_angle for leg in m.legs) or m.cached(
        "angle_constants", lambda: _has_angle_constants(m))

    def exact(i):
        if trig:
            return exact_certificate(m, Q[i])
        vals = enc.exact(Q[i])
        if vals is not None:
            return [sp.Rational(v.numerator, v.denominator) for v in vals]
        return _general_at(m.kinematic_polynomial(), m.joint_symbols,
                           [as_exact(float(v), "q") for v in Q[i]])

    if n:
        counts, path, ivals = certify_real_roots_batch(F, E, exact, return_intervals=True)
    else:
        counts, path, ivals = np.zeros(0, int), np.zeros(0, str), np.zeros((0, enc.degree, 2))
    path = path.astype(object)        # later entries ("continuum", "uncertified") are longer
    consistent = np.zeros(n, dtype=bool)
    # disc-certified rows: every real root simple; each must hold exactly one float mode, and
    # no float mode may lie outside them (t = x1/x0 of the normalised image point)
    disc = np.flatnonzero(res.row_ok & (path == "discs"))
    if disc.size:
        X = res.image_points[disc]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = X[..., 1] / X[..., 0]
        lo, hi = ivals[disc, :, 0], ivals[disc, :, 1]            # (m, d)
        inside = (t[:, :, None] >= lo[:, None, :]) & (t[:, :, None] <= hi[:, None, :])
        inside &= res.valid[disc][:, :, None]
        per_root = inside.sum(axis=1)                              # (m, d)
        per_mode = inside.sum(axis=2)                              # (m, 6)
        real_slot = np.isfinite(lo)
        ok_rows = (np.all(np.where(real_slot, per_root == 1, per_root == 0), axis=1)
                   & np.all(np.where(res.valid[disc], per_mode == 1, True), axis=1)
                   & (res.count[disc] == counts[disc]))
        consistent[disc[ok_rows]] = True
    return counts, path, consistent


def _kernel_certificate(kernel, Q, res):
    """Certified counts from the generic kernel (rigorous bounds, Bernstein isolation) and which
    rows' float modes they account for: ``(counts, path, consistent)``."""
    n = Q.shape[0]
    ok = res.row_ok
    counts, lo, hi, chart = kernel.certified_counts(np.where(ok[:, None], Q, 0.0))
    counts = np.where(ok, counts.astype(int), -1)
    path = np.where(ok, np.where(counts >= 0, "kernel", "uncertified"), "invalid").astype(object)
    consistent = np.zeros(n, dtype=bool)
    rows = np.flatnonzero(ok & (counts >= 0))
    if rows.size:
        X = res.image_points[rows]
        valid = res.valid[rows]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (X[..., 1] / X[..., 0])[:, :, None]            # chart 0: t = x1 / x0
            s = (X[..., 0] / X[..., 1])[:, :, None]            # chart 1: s = x0 / x1
        L, H, c = lo[rows][:, None, :], hi[rows][:, None, :], chart[rows][:, None, :]
        inside = (((c == 0) & (t >= L) & (t <= H)) | ((c == 1) & (s >= L) & (s <= H)))
        inside &= valid[:, :, None]
        per_root = inside.sum(axis=1)
        per_mode = inside.sum(axis=2)
        real_slot = chart[rows] >= 0
        good = (np.all(np.where(real_slot, per_root == 1, per_root == 0), axis=1)
                & np.all(np.where(valid, per_mode == 1, True), axis=1)
                & (res.count[rows] == counts[rows]))
        consistent[rows[good]] = True
    return counts, path, consistent


def certify_batch(m, Q, res, kernel=None):
    """Certified counts per row on the exact input, and modes held to them (see DKBatchResult).

    The certification stage of :func:`imagespace.solve.front.direct_kinematics_batch`
    (``certify=True``): runs after the float batch solve and updates ``res`` in place. With the
    design's generic ``kernel`` the counts are proven inside it (:meth:`BatchKernel.certified_counts`:
    no symbolic derivation, no eigenvalues); without it (designs the kernel does not take) the
    general-q kinematic polynomial is enclosed and decided by inclusion discs. Rows neither
    decides, and rows whose float modes the certificate does not account for, are solved again
    by the certified per-row path. Not public API (out of ``__all__``)."""
    n = Q.shape[0]
    if kernel is not None:
        counts, path, consistent = _kernel_certificate(kernel, Q, res)
    else:
        counts, path, consistent = _disc_certificate(m, Q, res)
    redo = {}                     # row -> (modes, solver name), stored in one rebuild after the loop
    for i in np.flatnonzero(res.row_ok & ~consistent):
        try:
            modes = certified_modes(m, Q[i], Q[i], warn=False)
        except DegenerateDesignError as e:
            res.row_ok[i] = False
            res.errors[int(i)] = str(e)
            counts[i] = -1
            path[i] = "continuum"
            redo[int(i)] = ([], "invalid")
            continue
        redo[int(i)] = (modes, "certified")
        cert = modes.certificate
        counts[i] = cert.count if cert.certified else -1
        if path[i] != "flint":
            path[i] = "flint" if cert.certified and cert.exact else (
                "arb" if cert.certified else "uncertified")
        consistent[i] = bool(cert.certified) and not modes.doubts
        res.near_singular[i] = not consistent[i]
    if redo:
        store_modes(res, list(redo), [ms for ms, _ in redo.values()])
        if res.solver is not None:
            for name in ("invalid", "certified"):
                res.set_solver([i for i, (_, s) in redo.items() if s == name], name)
    res.near_singular = res.near_singular & ~consistent      # proven rows are not in doubt
    res.certified_roots, res.certificate_path, res.consistent = counts, np.asarray(path).astype(str), consistent
    res.release_padded()          # the padded image points and masks read above are not kept
