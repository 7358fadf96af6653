"""Is a design cuspidal? Decided exactly, with a verified witness cusp when it is.

A manipulator is *cuspidal* when it can change assembly mode without crossing a singularity; for
3-DOF designs this happens exactly when the joint space holds a **cusp point**, where three
solutions of the direct kinematics merge (Wenger, *Cuspidal and noncuspidal robot manipulators*,
Robotica 25(6), 2007, hal-00454562; Zein, Wenger & Chablat, MMT 43 (2008) 480-490). With the kinematic polynomial ``p(t; q) = P(1, t; q)`` (``t = x1/x0 = tan(phi/2)``) a cusp
is a real solution of

    p = dp/dt = d2p/dt2 = 0           (three equations in t, q1, q2, q3: a curve),

or, at the half-turn orientation ``x0 = 0``, a common zero of the three leading coefficients.
:func:`is_cuspidal` decides whether this curve has a real point in a joint box:

1. **witness first** (fast): seeds from random joint vectors of the box whose roots cluster in
   threes (:func:`imagespace.atlas.curves.seeds_from_points`), Newton onto the curve, then a
   section ``q_k = c`` at an exact rational ``c`` across the curve, and the Krawczyk operator in
   arb ball arithmetic (python-flint) on the exact ``3 x 3`` system proves that the box it
   returns holds exactly one real cusp (Krawczyk, Computing 4 (1969) 187-201; Moore, *Interval
   Analysis*, 1966). The witness is checked to lie in the box with the same balls.
2. **otherwise an exact proof of absence** (msolve, ``imagespace[exact]``): a real point of the
   curve inside the closed box either lies on one of its six faces (six zero-dimensional systems,
   one joint fixed), or at ``x0 = 0``, or the curve has a compact component inside the open box,
   which then holds a critical point of a generic linear form ``l(q)`` restricted to the curve
   (Lagrange: ``grad l = lambda^T J``, zero-dimensional; computed once per design and cached).
   msolve isolates every real solution exactly; none in the box means no cusp in the box. A real
   solution found there is itself a witness (certificate ``"msolve"``).

Where a leg's actuated joint appears only squared (an RPR leg's length), ``u = q**2`` replaces
it, which divides the degrees. Irrational constants of the design (``sqrt(181)`` in seed 002)
become extra unknowns with their defining equation (``s**2 = 181``, ``s > 0``). Factors of the
kinematic polynomial free of ``q`` with no real root (``x0**2 + 9 x1**2`` for a 3-RPR with similar
base and platform) are divided out first: they carry no real mode.

What is not decided (``cuspidal=None``, with the reason): designs whose kinematic polynomial has
degree below 3 in the orientation (Cramer case (a), where one orientation carries two modes and
modes merge in position: not a triple root), designs with actuated revolute joints
(transcendental in ``q``) when no witness is found, and systems msolve reports as
positive-dimensional.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import sympy as sp

from .._html import dataclass_html, dataclass_repr
from .._validate import _short, as_count, as_sympy
from ..core.exact_roots import float_down, float_up
from ..core.mechanism import check_mechanism
from ..exceptions import InputError
from ..singular.cusps import cusp_system
from .curves import seeds_from_points
from .boxes import check_joint_box

__all__ = ["CuspWitness", "CuspidalityResult", "is_cuspidal", "default_joint_box", "verify_cusp",
           "cusp_polynomials"]

# numerical knobs (none decides an answer: every answer is proven or refused)
_WITNESS_SAMPLES = 4096       # random joint vectors of the box searched for a cluster of three roots
_WITNESS_SEEDS = 48           # best clusters followed by Newton
_WITNESS_TRIES = 6            # converged cusps handed to the interval proof, at most
_NEWTON_STEPS = 20
_KRAWCZYK_RADII = (1e-9, 1e-7, 1e-5)   # relative half-widths of the boxes tried
_PREC = 120                   # arb working precision (bits)
_NEWTON_STOP = 1e-15          # the float Newton on a section stops at steps below this (relative)
_SAME_SEED = 1e-6             # witness search: converged points this close (relative) are tried once
_NEAR = 0.05                  # verify_cusp: Newton may move the joints this far (relative), no further
_LAGRANGE_FORM = (3, -5, 7, 0)         # the linear form l: coefficients of (v1, v2, v3, t)


# -- results -------------------------------------------------------------------------------------------
@dataclass(frozen=True, repr=False)
class CuspWitness:
    """A proven cusp: a box of joint space holding exactly one real triple root.

    Attributes
    ----------
    q : (3,) float
        The cusp's joint vector (box centre).
    theta : float
        Half-angle of the triple root (``phi = 2 theta``).
    fixed : int
        The joint held at the exact rational ``value`` (the section the proof ran in).
    value : Fraction
    enclosure : (3, 2) float
        Outward-rounded intervals of ``q1, q2, q3`` holding the cusp, inside the joint box.
    t_enclosure : (2,) float
        Interval of the chart coordinate (``t = tan theta``, or ``cot theta`` in the chart
        ``x1 = 1``, see ``chart``).
    chart : str
        ``"t"`` (``x0 = 1``), ``"s"`` (``x1 = 1``) or ``"x0=0"``.
    certificate : str
        ``"krawczyk"`` (interval Newton in arb) or ``"msolve"`` (exact isolation).
    """

    q: np.ndarray
    theta: float
    fixed: int
    value: Fraction
    enclosure: np.ndarray
    t_enclosure: np.ndarray
    chart: str
    certificate: str

    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


@dataclass(frozen=True, repr=False)
class CuspidalityResult:
    """The answer of :func:`is_cuspidal`.

    Attributes
    ----------
    cuspidal : bool or None
        True: a cusp lies in the box (``witness`` proves it); False: proven that none does;
        None: not decided (``reason`` says why).
    joint_box : (3, 2) float
    witness : CuspWitness or None
    reason : str
    method : str
        ``"witness"``, ``"msolve"`` or ``"undecided"``.
    systems : int
        Polynomial systems handed to msolve.
    seconds : float
    """

    cuspidal: object
    joint_box: np.ndarray
    witness: object
    reason: str
    method: str
    systems: int
    seconds: float

    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


# -- the exact system ----------------------------------------------------------------------------------
@dataclass(frozen=True)
class CuspPolynomials:
    """The cusp system of a design in exact form (see :func:`cusp_polynomials`)."""

    t: sp.Symbol
    v: tuple                 # the joint unknowns (q_i, or u_i = q_i**2 where even)
    even: tuple              # per joint: True when v_i = q_i**2
    constants: tuple         # (symbol, defining polynomial, the constant's exact value)
    F: tuple                 # p, p_t, p_tt, p_ttt as sympy Poly in (t, v, constants) -- chart x0 = 1
    G: tuple                 # the same in the chart x1 = 1 (variable t standing for x0/x1)
    Finf: tuple              # the four leading coefficients (x0 = 0), Poly in (v, constants)
    degree: int
    removed: str             # q-free factors divided out
    exact: bool              # False when a coefficient is transcendental (no msolve path)
    why_not_exact: str


def cusp_polynomials(manipulator):
    """The exact cusp system of a numeric design (cached on the design).

    Parameters
    ----------
    manipulator : PlanarParallel

    Returns
    -------
    CuspPolynomials
        ``F = (p, p_t, p_tt)`` in ``(t, v1, v2, v3, constants...)`` with ``v_i = q_i**2`` where
        ``p`` is even in ``q_i``; ``Finf`` the system at ``x0 = 0``.

    Raises
    ------
    TypeError
        ``manipulator`` is not a design.
    InputError
        The design has free symbols, or an actuated revolute joint (its kinematic polynomial holds
        ``cos q``, ``sin q``: the cusp system is not polynomial in the joint values).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas.cuspidal import cusp_polynomials
    >>> cp = cusp_polynomials(isp.examples.general_3rpr())
    >>> cp.even, cp.degree
    ((True, True, True), 6)
    """
    check_mechanism(manipulator)
    if manipulator.design_symbols:
        raise InputError(f"is_cuspidal needs a numeric design; the design has the symbols "
                         f"{sorted(map(str, manipulator.design_symbols))}")
    why = _no_polynomial_system(manipulator)
    if why:
        raise InputError(f"the cusp system of {manipulator.name} is not polynomial: {why}")
    return manipulator.cached("atlas_cusp_polynomials", lambda: _build_cusp_polynomials(manipulator))


def _no_polynomial_system(m):
    """Why the cusp system of ``m`` is not polynomial in the joint values ('' when it is): an
    actuated revolute joint enters through its cosine and sine."""
    angles = [i for i, leg in enumerate(m.legs) if leg.actuated_is_angle]
    if not angles:
        return ""
    return (f"the actuated joint(s) {angles} are angles (the kinematic polynomial holds cos q, sin q), "
            "so neither the msolve proof of absence nor the interval proof of a witness applies")


def _build_cusp_polynomials(m):
    P = m.kinematic_polynomial()
    x0, x1 = P.gens
    qs = tuple(m.joint_symbols)
    full = sp.Poly(P.as_expr(), x0, x1, *qs)
    removed = ""
    # q-free factors without a real root carry no real mode: the gcd of the forms multiplying
    # each monomial in q is the q-free part; divide it out when it has no real root
    if full.domain.is_QQ or full.domain.is_ZZ:
        parts = {}
        for mon, c in full.terms():
            parts.setdefault(mon[2:], {})[mon[:2]] = c
        forms = [sp.Poly.from_dict(d, x0, x1, domain=full.domain) for d in parts.values()]
        g = forms[0]
        for f in forms[1:]:
            g = g.gcd(f)
            if g.total_degree() == 0:
                break
        if g.total_degree() > 0 and _no_real_root(g.as_expr(), x0, x1):
            quo = sp.Poly(P.as_expr(), x0, x1, *qs, domain=full.domain).exquo(
                sp.Poly(g.as_expr(), x0, x1, *qs, domain=full.domain))
            full = quo
            removed = f"({g.as_expr()})"
    coeffs = [c for _mon, c in full.terms()]
    consts = sorted({a for c in coeffs for a in as_sympy(c).atoms(sp.Pow)
                     if a.is_number and a.exp.is_Rational and a.exp.q == 2 and a.base.is_Rational
                     and a.base > 0}, key=str)
    exact = all(as_sympy(c).is_algebraic for c in coeffs[:50])
    exact = exact and not any(as_sympy(c).atoms(sp.Function, sp.NumberSymbol) for c in coeffs)
    why = "" if exact else "transcendental coefficients (an actuated revolute joint, or an angle of the design)"
    even = tuple(all(mon[2 + i] % 2 == 0 for mon in full.monoms()) for i in range(3))
    vs = tuple(sp.Symbol(f"u{i + 1}") if even[i] else sp.Symbol(f"q{i + 1}_") for i in range(3))
    t = sp.Symbol("t")
    cs = tuple(sp.Symbol(f"c{k}") for k in range(len(consts)))
    csub = {c: s_ for c, s_ in zip(consts, cs)}
    degree = max(a + b for a, b, *_ in full.monoms())
    gens = (t,) + vs + cs
    dp, dg, dinf = {}, {}, [{} for _ in range(4)]
    for mon, c in full.terms():
        a, b = mon[0], mon[1]
        vexp = tuple(mon[2 + i] // 2 if even[i] else mon[2 + i] for i in range(3))
        cpoly = sp.Poly(sp.expand(as_sympy(c).xreplace(csub)), *cs) if cs else None
        cterms = cpoly.terms() if cpoly is not None else [((), as_sympy(c))]
        for cm, cc in cterms:
            key_p = (b,) + vexp + tuple(cm)            # x0 = 1, x1 = t
            key_g = (a,) + vexp + tuple(cm)            # x1 = 1, x0 = t
            dp[key_p] = dp.get(key_p, 0) + cc
            dg[key_g] = dg.get(key_g, 0) + cc
            if a < 4 and a + b == degree:
                key_i = vexp + tuple(cm)
                dinf[a][key_i] = dinf[a].get(key_i, 0) + cc
    p = sp.Poly.from_dict(dp, *gens)
    g = sp.Poly.from_dict(dg, *gens)
    F = (p, p.diff(t), p.diff(t).diff(t), p.diff(t).diff(t).diff(t))
    G = (g, g.diff(t), g.diff(t).diff(t), g.diff(t).diff(t).diff(t))
    Finf = tuple(sp.Poly.from_dict(d, *(vs + cs)) if d else sp.Poly(0, *(vs + cs)) for d in dinf)
    cdef = tuple((s_, sp.Poly(s_ ** 2 - c.base ** (2 * c.exp), s_), c) for c, s_ in zip(consts, cs))
    return CuspPolynomials(t, vs, even, cdef, F, G, Finf, degree, removed, exact, why)


def _no_real_root(fac, x0, x1):
    f = sp.Poly(fac, x0, x1)
    if f.total_degree() == 0:
        return True
    if f.eval({x0: 0, x1: 1}) == 0:
        return False
    return len(sp.Poly(f.as_expr().subs({x0: 1}), x1).real_roots()) == 0


# -- the default box -----------------------------------------------------------------------------------
def default_joint_box(manipulator):
    """A joint box that holds the design's useful range, for ``is_cuspidal(m)`` without a box.

    Prismatic actuators: ``[L/1000, L]`` for legs whose length must be positive (RPR), else
    ``[-L, L]``, with ``L`` three times the largest of the design's anchor distances and of
    ``|q_example|``; revolute actuators: ``[-pi, pi]``.

    Parameters
    ----------
    manipulator : PlanarParallel

    Returns
    -------
    (3, 2) float

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import default_joint_box
    >>> default_joint_box(isp.examples.general_3rpr()).shape
    (3, 2)
    """
    check_mechanism(manipulator)
    size = 1.0
    for leg in manipulator.legs:
        for key, val in leg.geometry(exact=False).items():
            arr = np.asarray(val, dtype=float) if np.ndim(val) else np.asarray([val], dtype=float)
            if arr.size and np.all(np.isfinite(arr)):
                size = max(size, float(np.max(np.abs(arr))) * 2)
    qe = manipulator.q_example_float
    if qe is not None:
        size = max(size, float(np.max(np.abs(qe))))
    L = 3.0 * size
    box = np.empty((3, 2))
    for i, leg in enumerate(manipulator.legs):
        if leg.actuated_is_angle:
            box[i] = (-np.pi, np.pi)
        elif not bool(leg.joint_values_ok([-L])[0]):
            box[i] = (L / 1000, L)
        else:
            box[i] = (-L, L)
    return box


# -- arb evaluation and the Krawczyk proof -------------------------------------------------------------
class _ArbPoly:
    """A polynomial in (z0, z1, z2) with arb coefficients, from ``{exponents: arb}``."""

    def __init__(self, terms):
        self.terms = list(terms.items())
        self.deg = [max((mon[k] for mon, _ in self.terms), default=0) for k in range(3)]

    def __call__(self, z):
        import flint

        pw = []
        for k in range(3):
            row = [flint.arb(1)]
            for _ in range(self.deg[k]):
                row.append(row[-1] * z[k])
            pw.append(row)
        acc = flint.arb(0)
        for (a, b, c), coef in self.terms:
            acc += coef * pw[0][a] * pw[1][b] * pw[2][c]
        return acc


def _krawczyk(F, J, centre, radius):
    """True when the Krawczyk operator maps the box ``centre +- radius`` into its interior: the box
    then holds exactly one zero of F. ``F`` (3 callables), ``J`` (3x3 callables), floats in."""
    import flint

    c = [flint.arb(flint.fmpq(*float(x).as_integer_ratio())) for x in centre]
    X = [c[k] + flint.arb(0, flint.arb(flint.fmpq(*float(radius[k]).as_integer_ratio())))
         for k in range(3)]
    Fc = [f(c) for f in F]
    JX = [[J[i][j](X) for j in range(3)] for i in range(3)]
    Jm = np.array([[float(JX[i][j].mid()) for j in range(3)] for i in range(3)])
    try:
        Yf = np.linalg.inv(Jm)
    except np.linalg.LinAlgError:
        return False
    if not np.all(np.isfinite(Yf)):
        return False
    Y = [[flint.arb(flint.fmpq(*float(Yf[i][j]).as_integer_ratio())) for j in range(3)] for i in range(3)]
    K = []
    for i in range(3):
        acc = c[i]
        for j in range(3):
            acc -= Y[i][j] * Fc[j]
        for j in range(3):
            m_ij = (flint.arb(1) if i == j else flint.arb(0))
            for k in range(3):
                m_ij -= Y[i][k] * JX[k][j]
            acc += m_ij * (X[j] - c[j])
        K.append(acc)
    for k in range(3):
        lo_k, hi_k = c[k] - radius_arb(radius[k]), c[k] + radius_arb(radius[k])
        kl = K[k].mid() - K[k].rad()
        kh = K[k].mid() + K[k].rad()
        if not (kl > lo_k and kh < hi_k):
            return False
    return True


def radius_arb(r):
    import flint

    return flint.arb(flint.fmpq(*float(r).as_integer_ratio()))


def _section_system(cp, chart, fixed, value_v, prec):
    """Arb evaluators of the chart's cusp system with ``v[fixed] = value_v`` (exact) and the
    constants at their exact values: F (3) and J (3x3) in (chart variable, v_a, v_b)."""
    import flint

    from ..core.certify import to_arb

    polys = cp.F if chart == "t" else cp.G
    a, b = [k for k in range(3) if k != fixed]
    val = to_arb(as_sympy(value_v), prec)
    consts = [to_arb(c, prec) for _s, _d, c in cp.constants]
    F, J = [], []
    for p in polys:                       # p, p', p'' and p''' (the last is not differentiated)
        terms = {}
        for mon, c in p.terms():
            coef = flint.arb(flint.fmpq(int(sp.Rational(c).p), int(sp.Rational(c).q))) * val ** mon[1 + fixed]
            for k, e in enumerate(mon[4:]):
                coef *= consts[k] ** e
            key = (mon[0], mon[1 + a], mon[1 + b])
            terms[key] = terms.get(key, flint.arb(0)) + coef
        F.append(_ArbPoly(terms))
        if len(F) == 4:
            break
        row = []
        for k in range(3):
            d = {}
            for key, coef in terms.items():
                if key[k]:
                    nk = list(key)
                    nk[k] -= 1
                    d[tuple(nk)] = d.get(tuple(nk), flint.arb(0)) + coef * key[k]
            row.append(_ArbPoly(d))
        J.append(row)
    return F, J


def verify_cusp(manipulator, x, joint_box=None, fixed=None):
    """Prove a cusp near the float point ``x = (theta, q1, q2, q3)`` (interval Newton).

    The joint ``fixed`` (default: the one along which the cusp curve runs most steeply) is set
    to an exact rational near ``x``; Newton refines the other unknowns in float; the Krawczyk
    operator in arb ball arithmetic on the exact section system then proves that a small box
    holds exactly one real solution of ``p = p' = p'' = 0``.

    Parameters
    ----------
    manipulator : PlanarParallel
    x : (4,) float
        Approximate cusp ``(theta, q1, q2, q3)``.
    joint_box : (3, 2) float, optional
        If given, the proven enclosure must lie inside it.
    fixed : int, optional
        The joint (0, 1 or 2) held at an exact rational on the section.

    Returns
    -------
    CuspWitness or None
        None when the proof does not go through (no simple cusp within 5 % of ``x``'s joint
        values, or outside the box).

    Raises
    ------
    TypeError
        ``manipulator`` not a design; non-numeric ``x`` or box.
    InputError
        ``x`` not of shape ``(4,)``; a bad box; ``fixed`` not 0, 1 or 2; a design with free
        symbols, or with an actuated revolute joint (its cusp system is not polynomial).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import verify_cusp
    >>> w = verify_cusp(isp.examples.general_3rpr(), [0.659, 9.7776, 3.9609, 10.0])
    >>> w.certificate, bool(abs(w.q[2] - 10.0) < 1e-3)
    ('krawczyk', True)
    """
    from .._validate import as_float_array

    x = as_float_array(x, "x", last=4)
    if x.ndim != 1:
        raise InputError(f"x must be one point (theta, q1, q2, q3), got shape {x.shape}")
    box = None if joint_box is None else check_joint_box(manipulator, joint_box)
    if fixed is not None:
        fixed = as_count(fixed, "fixed", 0)
        if fixed > 2:
            raise InputError(f"fixed must be the joint held on the section, 0, 1 or 2, got {fixed}")
    cp = cusp_polynomials(manipulator)
    if cp.degree < 3:
        return None
    x0 = x.copy()
    x = _newton_curve(manipulator, x)
    if x is None or np.max(np.abs(x[1:] - x0[1:])) > _NEAR * (1 + np.max(np.abs(x0[1:]))):
        return None                       # no cusp near the point given
    G, J, _s = cusp_system(manipulator, x[None, :])
    _, _, vt = np.linalg.svd(J[0])
    tangent = vt[-1]
    if fixed is None:
        side = np.ones(3) if box is None else box[:, 1] - box[:, 0]
        fixed = int(np.argmax(np.abs(tangent[1:]) / side))
    a, b = [k for k in range(3) if k != fixed]
    value = Fraction(float(x[1 + fixed])).limit_denominator(2 ** 24)
    if box is not None and not (box[fixed, 0] <= value <= box[fixed, 1]):
        return None
    # Newton on the section (float), in the chart where |chart variable| <= 1
    chart = "t" if abs(np.tan(x[0])) <= 1 else "s"
    xs = x.copy()
    xs[1 + fixed] = float(value)
    for _ in range(_NEWTON_STEPS):
        G, J, s = cusp_system(manipulator, xs[None, :])
        A = J[0][:, [0, 1 + a, 1 + b]]
        try:
            d = np.linalg.solve(A, -G[0])
        except np.linalg.LinAlgError:
            return None
        xs[[0, 1 + a, 1 + b]] += d
        if np.max(np.abs(d)) <= _NEWTON_STOP * (1 + np.max(np.abs(xs))):
            break
    theta = float(xs[0])
    tval = np.tan(theta) if chart == "t" else 1.0 / np.tan(theta)
    q = xs[1:]
    vval = [q[k] ** 2 if cp.even[k] else q[k] for k in range(3)]
    value_v = sp.Rational(value.numerator, value.denominator)
    if cp.even[fixed]:
        value_v = value_v ** 2
    F, Jp = _section_system(cp, chart, fixed, value_v, _PREC)
    centre = np.array([tval, vval[a], vval[b]])
    import flint

    from ..core.certify import flint_precision

    with flint_precision(_PREC):
        for rel in _KRAWCZYK_RADII:
            radius = rel * (1 + np.abs(centre))
            if not _krawczyk(F[:3], Jp, centre, radius):
                continue
            # a genuine cusp: the third derivative is not 0 on the box (else maybe a quadruple root)
            X = [flint.arb(flint.fmpq(*float(centre[k]).as_integer_ratio()))
                 + flint.arb(0, radius_arb(radius[k])) for k in range(3)]
            if F[3](X).contains(0):
                continue
            # the enclosure in q (v = q**2 -> q = sqrt(v), the sign of the float point)
            enc = np.empty((3, 2))
            enc[fixed] = (float(value), float(value))
            for k, j in ((a, 1), (b, 2)):
                lo_v = centre[j] - radius[j]
                hi_v = centre[j] + radius[j]
                if cp.even[k]:
                    if lo_v <= 0:
                        break
                    lo_f, hi_f = _sqrt_interval(Fraction(float(lo_v)), Fraction(float(hi_v)))
                    enc[k] = (lo_f, hi_f) if q[k] >= 0 else (-hi_f, -lo_f)
                else:
                    enc[k] = (lo_v, hi_v)
            else:
                if box is not None and (np.any(enc[:, 0] < box[:, 0]) or np.any(enc[:, 1] > box[:, 1])):
                    return None
                tenc = np.array([centre[0] - radius[0], centre[0] + radius[0]])
                return CuspWitness(q.copy(), theta, fixed, value, enc, tenc, chart, "krawczyk")
    return None


def _newton_curve(m, x):
    """Minimum-norm Newton from x onto the cusp curve (float)."""
    x = np.asarray(x, dtype=float).copy()
    tol = m.tolerances.atlas_cusp_residual
    for _ in range(_NEWTON_STEPS):
        G, J, s = cusp_system(m, x[None, :])
        if not np.all(np.isfinite(G)):
            return None
        if np.max(np.abs(G[0])) <= tol * s[0]:
            return x
        x = x - np.linalg.lstsq(J[0], G[0], rcond=None)[0]
    G, J, s = cusp_system(m, x[None, :])
    return x if np.max(np.abs(G[0])) <= tol * s[0] else None


# -- the witness search -----------------------------------------------------------------------------
def _find_witness(m, box, rng):
    Q = box[:, 0] + rng.random((_WITNESS_SAMPLES, 3)) * (box[:, 1] - box[:, 0])
    seeds = seeds_from_points(m, Q, keep=_WITNESS_SEEDS)
    if not len(seeds):
        return None
    X = seeds.copy()
    tol = m.tolerances.atlas_cusp_residual
    with np.errstate(all="ignore"):
        for _ in range(_NEWTON_STEPS):
            G, J, s = cusp_system(m, X)
            step = np.einsum("nij,nj->ni", np.linalg.pinv(J), G)
            step[~np.all(np.isfinite(step), axis=1)] = 0
            X = X - step
        G, J, s = cusp_system(m, X)
    res = np.max(np.abs(G), axis=1) / np.where(s > 0, s, np.nan)
    inside = np.all((X[:, 1:] > box[:, 0]) & (X[:, 1:] < box[:, 1]), axis=1)
    good = np.flatnonzero(inside & (res < tol))
    good = good[np.argsort(res[good])]
    tried = []
    for i in good:
        if any(np.max(np.abs(X[i, 1:] - Y[1:])) < _SAME_SEED * (1 + np.max(np.abs(Y[1:]))) for Y in tried):
            continue
        tried.append(X[i])
        w = verify_cusp(m, X[i], box)
        if w is not None:
            return w
        if len(tried) >= _WITNESS_TRIES:
            break
    return None


# -- the exact decision -------------------------------------------------------------------------------
def _rat(x):
    return sp.Rational(*Fraction(float(x)).as_integer_ratio())


def _constants_ok(cp, boxes, offset):
    """Keep msolve boxes whose constant coordinates isolate the design's constants (s > 0 root)."""
    # each constant is sqrt(k) > 0, one of the two roots +-sqrt(k) of its defining equation
    return [bx for bx in boxes
            if all(bx[offset + k][0] > 0 for k in range(len(cp.constants)))]


def _in_range(lo, hi, a, b):
    """1 inside [a, b], 0 outside, -1 ambiguous (the isolating interval straddles an end)."""
    if lo >= a and hi <= b:
        return 1
    if hi < a or lo > b:
        return 0
    return -1


def _v_range(cp, k, box):
    a, b = Fraction(float(box[k, 0])), Fraction(float(box[k, 1]))
    if cp.even[k]:
        if a >= 0:
            return a * a, b * b
        if b <= 0:
            return b * b, a * a
        return Fraction(0), max(a * a, b * b)
    return a, b


def _lagrange(m, cp, timeout):
    """Critical points of l = sum a_k v_k + a_3 t on the cusp curve (msolve, cached per design)."""
    key = ("atlas_cusp_lagrange", timeout)

    def build():
        from ..core.msolve import solve_real

        lam = sp.symbols("lam0:3")
        gens = (cp.t,) + cp.v
        a = _LAGRANGE_FORM
        grad = [a[3]] + list(a[:3])
        eqs = [p.as_expr() for p in cp.F[:3]]
        for j, g in enumerate(gens):
            eqs.append(sum(lam[i] * sp.diff(cp.F[i].as_expr(), g) for i in range(3)) - grad[j])
        cdefs = [d.as_expr() for _s, d, _c in cp.constants]
        variables = list(gens) + [s for s, _d, _c in cp.constants] + list(lam)
        return solve_real(eqs + cdefs, variables, timeout=timeout)

    return m.cached(key, build)


def _exact_decision(m, cp, box, timeout):
    from ..core.msolve import MsolveError, solve_real

    y = sp.Symbol("y_")
    csyms = [s for s, _d, _c in cp.constants]
    cdefs = [d.as_expr() for _s, d, _c in cp.constants]
    ranges = [_v_range(cp, k, box) for k in range(3)]
    systems = 0
    ambiguous = []
    # 0. is every triple root a quadruple root (p''' = 0 on the whole cusp set)? Then no cusp at all
    allvars = [cp.t] + list(cp.v) + csyms + [y]
    res = solve_real([p.as_expr() for p in cp.F[:3]] + [y * cp.F[3].as_expr() - 1] + cdefs, allvars,
                     timeout=timeout)
    systems += 1
    if res.dimension == -1:
        return False, ("every common root of p, p', p'' is a root of the third derivative too (msolve: "
                       "p = p' = p'' = 0 with p''' != 0 has no complex solution): roots merge in pairs "
                       "or fours, never three at a time"), systems, None
    # 1. the six faces
    for k in range(3):
        a, b = [j for j in range(3) if j != k]
        for end in (0, 1):
            bound = ranges[k][end]
            val = sp.Rational(bound.numerator, bound.denominator)
            e = [sp.expand(p.as_expr().subs(cp.v[k], val)) for p in cp.F]
            eqs = e[:3] + [y * e[3] - 1] + cdefs       # third derivative != 0: a triple root
            try:
                res = solve_real(eqs, [cp.t, cp.v[a], cp.v[b]] + csyms + [y], timeout=timeout)
            except MsolveError as exc:
                return None, f"msolve failed on the face v{k + 1} = {bound}: {exc}", systems, None
            systems += 1
            if res.positive_dimensional:
                return None, (f"the cusp system on the face q{k + 1} = {float(box[k, end]):g} is "
                              "positive-dimensional"), systems, None
            for bx in _constants_ok(cp, res.boxes, 3):
                ia = _in_range(*bx[1], *ranges[a])
                ib = _in_range(*bx[2], *ranges[b])
                if ia == 1 and ib == 1:
                    return True, f"a real cusp on the face q{k + 1} = {float(box[k, end]):g} (msolve)", \
                        systems, _msolve_witness(cp, bx, k, bound, [a, b])
                if ia != 0 and ib != 0:
                    ambiguous.append(f"face q{k + 1}")
    # 2. the half-turn orientation x0 = 0 (x0**3 divides the form, x0**4 does not)
    if not cp.Finf[3].is_zero:
        eqs = [p.as_expr() for p in cp.Finf[:3]] + [y * cp.Finf[3].as_expr() - 1] + cdefs
        res = solve_real(eqs, list(cp.v) + csyms + [y], timeout=timeout)
        systems += 1
        if res.positive_dimensional:
            return None, "the cusp system at x0 = 0 is positive-dimensional", systems, None
        for bx in _constants_ok(cp, res.boxes, 3):
            flags = [_in_range(*bx[k], *ranges[k]) for k in range(3)]
            if all(f == 1 for f in flags):
                return True, "a real cusp at the half-turn orientation x0 = 0 (msolve)", systems, None
            if all(f != 0 for f in flags):
                ambiguous.append("x0 = 0")
    # 3. compact components inside the box: critical points of a generic linear form
    res = _lagrange(m, cp, timeout)
    systems += 1
    if res.positive_dimensional:
        return None, "the critical-point system of the cusp curve is positive-dimensional", systems, None
    for bx in _constants_ok(cp, res.boxes, 4):
        flags = [_in_range(*bx[1 + k], *ranges[k]) for k in range(3)]
        if all(f == 1 for f in flags):
            if _third_derivative_nonzero(cp, bx):
                return True, "a real cusp inside the box (a critical point of the curve, msolve)", \
                    systems, _msolve_witness(cp, bx[:4], None, None, None)
            ambiguous.append("a critical point where the third derivative may vanish")
        elif all(f != 0 for f in flags):
            ambiguous.append("a critical point")
    if ambiguous:
        return None, f"isolating boxes straddle the joint box's boundary ({', '.join(ambiguous)})", \
            systems, None
    return False, (f"no real solution of the cusp system on the six faces of the box, at x0 = 0, "
                   f"nor among the {res.count} real critical points of the curve (all isolated "
                   f"exactly by msolve)"), systems, None


def _third_derivative_nonzero(cp, bx):
    """The third derivative on an msolve isolating box (t, v1, v2, v3, constants...) excludes 0."""
    import flint

    from ..core.certify import flint_precision

    with flint_precision(_PREC):
        vals = []
        for lo, hi in bx[: 4 + len(cp.constants)]:
            a = flint.arb(flint.fmpq(lo.numerator, lo.denominator))
            b = flint.arb(flint.fmpq(hi.numerator, hi.denominator))
            vals.append(a.union(b))
        acc = flint.arb(0)
        for mon, c in cp.F[3].terms():
            term = flint.arb(flint.fmpq(int(sp.Rational(c).p), int(sp.Rational(c).q)))
            for v, e in zip(vals, mon):
                term *= v ** e
            acc += term
        return not acc.contains(0)


def _sqrt_interval(lo, hi):
    """Floats ``a <= sqrt(lo)`` and ``b >= sqrt(hi)`` (exact rationals in, outward rounding)."""
    import flint

    from ..core.certify import arb_bounds, flint_precision

    with flint_precision(_PREC):
        a = arb_bounds(flint.arb(flint.fmpq(lo.numerator, lo.denominator)).sqrt())[0]
        b = arb_bounds(flint.arb(flint.fmpq(hi.numerator, hi.denominator)).sqrt())[1]
    return float_down(max(a, Fraction(0))), float_up(b)


def _msolve_witness(cp, bx, fixed, bound, free):
    """A CuspWitness from an msolve isolating box (coordinates t, v...)."""
    lo_t, hi_t = bx[0]
    tmid = float((lo_t + hi_t) / 2)
    enc = np.empty((3, 2))
    q = np.empty(3)
    for k in range(3):
        if fixed is not None and k == fixed:
            lo = hi = bound
        else:
            lo, hi = bx[1 + (free.index(k) if free is not None else k)]
        if cp.even[k]:
            lo_f, hi_f = _sqrt_interval(max(Fraction(lo), Fraction(0)), Fraction(hi))
        else:
            lo_f, hi_f = float_down(Fraction(lo)), float_up(Fraction(hi))
        enc[k] = (lo_f, hi_f)
        q[k] = 0.5 * (lo_f + hi_f)
    return CuspWitness(q, float(np.arctan(tmid)), -1 if fixed is None else fixed,
                       Fraction(bound) if bound is not None else Fraction(0), enc,
                       np.array([float(lo_t), float(hi_t)]), "t", "msolve")


def is_cuspidal(manipulator, joint_box=None, exact=True, timeout=120.0, seed=0):
    """Decide whether the design has a cusp (three merging assembly modes) in a joint box.

    See the module notes for the method (a verified witness, else an exact proof of absence).

    Parameters
    ----------
    manipulator : PlanarParallel
        A numeric design.
    joint_box : (3, 2) float, optional
        The joint box (default :func:`default_joint_box`).
    exact : bool
        Run the exact proof of absence when no witness is found (needs msolve,
        ``imagespace[exact]``); False returns ``cuspidal=None`` instead.
    timeout : float
        Seconds each msolve run may take.
    seed : int
        Seed of the witness search's random samples.

    Returns
    -------
    CuspidalityResult

    Raises
    ------
    TypeError
        ``manipulator`` not a design; non-numeric box; ``exact`` not a boolean; ``seed`` not a
        whole number.
    InputError
        A box of the wrong shape or outside the joints' domains; a design with free symbols; a
        non-positive timeout.
    MsolveUnavailableError
        The exact path is needed and msolve is not installed.

    References
    ----------
    P. Wenger, *Cuspidal and noncuspidal robot manipulators*, Robotica 25(6), 2007
    (hal-00454562); P. Wenger, D. Chablat, M. Zein, *Degeneracy study of the forward kinematics
    of planar 3-RPR parallel manipulators*, J. Mech. Des. 129, 2007 (similar base and platform:
    no cusp; cited from memory, the text was not reachable here).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import is_cuspidal
    >>> r = is_cuspidal(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)])
    >>> r.cuspidal, r.witness.certificate
    (True, 'krawczyk')
    """
    from .._validate import as_flag, as_scalar

    t0 = time.perf_counter()
    check_mechanism(manipulator)
    if manipulator.design_symbols:
        raise InputError(f"is_cuspidal needs a numeric design; the design has the symbols "
                         f"{sorted(map(str, manipulator.design_symbols))}")
    box = default_joint_box(manipulator) if joint_box is None else check_joint_box(manipulator, joint_box)
    exact = as_flag(exact, "exact")
    timeout = as_scalar(timeout, "timeout")
    if not timeout > 0:
        raise InputError(f"timeout must be a positive number of seconds, got {timeout!r}")
    seed = as_count(seed, "seed", 0)

    def done(c, w, reason, method, systems=0):
        return CuspidalityResult(c, box, w, reason, method, systems, time.perf_counter() - t0)

    why = _no_polynomial_system(manipulator)
    if why:
        return done(None, None, f"not decided: {why}", "undecided")
    cp = cusp_polynomials(manipulator)

    if cp.degree < 3:
        return done(None, None, (f"the kinematic polynomial has degree {cp.degree} < 3 in the orientation "
                                 "(Cramer case (a): one orientation carries two modes, which merge in "
                                 "position, not as a triple root); not decided here"), "undecided")
    try:
        with np.errstate(over="raise"):
            w = _find_witness(manipulator, box, np.random.default_rng(seed))
        skipped = ""
    except (OverflowError, FloatingPointError):     # beyond the float range (a design in 1e100 units)
        w = None
        skipped = " (the float search was skipped: the design's coefficients exceed the float range)"
    if w is not None:
        return done(True, w, "a cusp proven by interval Newton (Krawczyk) in the box", "witness")
    if not cp.exact:
        return done(None, None, f"no witness found{skipped}, and no exact path: {cp.why_not_exact}", "undecided")
    if not exact:
        return done(None, None, f"no witness found{skipped}; the exact proof of absence was not asked for",
                    "undecided")
    c, reason, systems, w = _exact_decision(manipulator, cp, box, timeout)
    reason += skipped
    if cp.removed and c is False:
        reason += f"; q-free factors without real roots divided out first: {cp.removed}"
    return done(c, w, reason, "msolve" if c is not None else "undecided", systems)
