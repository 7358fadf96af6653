"""Rigorous cos/sin enclosures (imagespace.core.bounded_trig) against python-flint arb at 256
bits, an independent computation; the constants of the method against exact values."""

import math
import re
from fractions import Fraction

import flint
import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.core import bounded_trig as bt
from imagespace.core._numba import HAVE_NUMBA
from imagespace.core.bounded_trig import Q_MAX, cos_sin_bounded, cos_sin_enclosure
from imagespace.core.codegen import CoefficientEnclosure

ULP1 = 2.0**-52                 # one ulp of 1
PREC = 256


@pytest.fixture(autouse=True)
def high_precision():
    old = flint.ctx.prec
    flint.ctx.prec = PREC
    yield
    flint.ctx.prec = old


def assert_encloses(q, c, s, ec, es):
    """The arb balls of cos q and sin q (q exact) lie inside [c - ec, c + ec] and [s - es, s + es]."""
    q, c, s, ec, es = (np.ravel(a) for a in (q, c, s, ec, es))
    for i in range(q.size):
        b = flint.arb(float(q[i]))
        for exact, v, e, name in ((b.cos(), c[i], ec[i], "cos"), (b.sin(), s[i], es[i], "sin")):
            dist = exact - flint.arb(float(v))          # exact difference of two exact values
            assert dist.abs_upper() <= flint.arb(float(e)), (name, q[i].hex(), v, e, dist)


def assert_tight(q, c, s, ec, es, ulps=8):
    """Small bounds: at most `ulps` ulps of 1 absolute, and of max(|value|, 2**-60) relative."""
    assert np.all(ec <= ulps * ULP1) and np.all(es <= ulps * ULP1)
    assert np.all(ec <= ulps * ULP1 * np.maximum(np.abs(c), 2.0**-60)), q[np.argmax(ec)]
    assert np.all(es <= ulps * ULP1 * np.maximum(np.abs(s), 2.0**-60)), q[np.argmax(es)]


def sample(rng):
    """Joint values over many scales, both signs."""
    k = np.arange(1, 10**6 + 1, dtype=float)
    near = np.concatenate([k[rng.integers(0, k.size, 3000)] * (np.pi / 2),      # ~ k pi/2
                           np.arange(1, 201) * (np.pi / 2),
                           (2 * rng.integers(0, 10**6, 2000) + 1) * (np.pi / 4)])   # ~ odd k pi/4
    near = np.concatenate([near, np.nextafter(near, 0), np.nextafter(near, np.inf)])
    parts = [
        rng.uniform(-1e3, 1e3, 4000),
        rng.uniform(-1e-8, 1e-8, 500),
        rng.uniform(-4, 4, 4000),
        np.exp(rng.uniform(np.log(1e-8), np.log(1e3), 4000)),
        np.exp(rng.uniform(np.log(1e-300), np.log(1e-8), 1000)),
        np.exp(rng.uniform(np.log(1e3), np.log(Q_MAX), 1000)),
        near,
        [2.0**-26, np.nextafter(2.0**-26, 0), np.nextafter(2.0**-26, 1), 1e-300, 5e-324, 2.0**-1022,
         np.pi / 4, np.pi / 2, np.pi, 2 * np.pi, 0.78539816339744828, 0.8, Q_MAX,
         np.nextafter(Q_MAX, 0)],
    ]
    q = np.concatenate([np.asarray(p, dtype=float) for p in parts])
    return np.concatenate([q, -q])


def test_constants_against_arb():
    """pi/2 = P1 + P2 + P3 + P4 + delta with |delta| <= DELTA (arb, 300 bits); P1..P3 have at most
    30 significant bits, so k * P_i is exact for |k| < 2**23; and k stays below 2**22."""
    flint.ctx.prec = 300
    parts = [bt._P1, bt._P2, bt._P3, bt._P4]
    for p in parts[:3]:
        num, den = abs(p).as_integer_ratio()
        assert num.bit_length() <= 30 and den & (den - 1) == 0
    total = sum(Fraction(p) for p in parts)
    delta = flint.arb.pi() / 2 - flint.arb(flint.fmpq(total.numerator, total.denominator))
    assert delta.rad() < flint.arb(2) ** -290
    assert delta.abs_upper() <= flint.arb(bt._DELTA)
    assert bt._DELTA == 2.0**-144
    assert abs(bt._TWO_OVER_PI - 2 / math.pi) < 1e-16
    # |k| = round(|q| * 2/pi) < 2**22 for |q| <= Q_MAX
    assert Q_MAX == 2.0**22 and Q_MAX * bt._TWO_OVER_PI * (1 + 2.0**-50) + 1 < 2.0**22


def test_taylor_constants_are_exact_roundings():
    s = [Fraction((-1) ** j, math.factorial(2 * j + 1)) for j in range(1, 9)]
    c = [Fraction((-1) ** j, math.factorial(2 * j)) for j in range(1, 10)]
    assert list(bt._SIN_COEFFS) == [float(v) for v in s]         # float(Fraction): correctly rounded
    assert list(bt._COS_COEFFS) == [float(v) for v in c]
    rho = Fraction(bt._RHO)
    assert Fraction(bt._K_SIN) >= rho**18 / math.factorial(19)
    assert Fraction(bt._K_COS) >= rho**20 / math.factorial(20)
    # the polynomials' domain contains every reduced argument: |r| <= pi/4 + 2**-29, plus the
    # reduction error
    assert bt._RHO > math.pi / 4 + 2.0**-28


@pytest.mark.slow
def test_encloses_arb_over_many_scales(rng):
    q = sample(rng)
    c, s, ec, es = cos_sin_enclosure(q)
    assert_encloses(q, c, s, ec, es)
    assert_tight(q, c, s, ec, es)


@pytest.mark.slow
def test_kernel_and_enclosure_agree_elementwise(rng):
    q = sample(rng)[::7]
    got = np.array([cos_sin_bounded(float(v)) for v in q])
    assert np.array_equal(np.column_stack(cos_sin_enclosure(q)), got)


def test_zero_and_tiny_arguments():
    for z in (0.0, -0.0):
        c, s, ec, es = cos_sin_bounded(z)
        assert (c, s, ec, es) == (1.0, 0.0, 0.0, 0.0)
        assert math.copysign(1.0, s) == math.copysign(1.0, z)
    q = np.array([5e-324, -5e-324, 1e-310, 1e-300, 1e-200, 2.0**-60, 1e-9, -1e-9])
    c, s, ec, es = cos_sin_enclosure(q)
    assert np.all(s == q) and np.all(c == 1.0)
    assert_encloses(q, c, s, ec, es)
    assert np.all(es <= np.abs(q) * 2.0**-53 + 2.0**-1073)      # relative, even for subnormals


def test_large_arguments_fall_back_to_arb(rng):
    """Beyond Q_MAX the kernel returns the trivially rigorous bound 2; the array wrapper
    recomputes those elements with arb, so the bounds stay small."""
    q = np.concatenate([np.exp(rng.uniform(np.log(1e6), np.log(1e15), 300)),
                        2.0 ** np.arange(-1074, 1024), [np.nextafter(Q_MAX, np.inf), 1.7e308]])
    q = np.concatenate([q, -q])
    big = np.abs(q) > Q_MAX
    kern = np.array([cos_sin_bounded(float(v)) for v in q[big]])
    assert np.all(kern[:, 2:] == 2.0) and np.all(np.abs(kern[:, :2]) <= 1.0)
    assert_encloses(q[big], *kern.T)
    c, s, ec, es = cos_sin_enclosure(q)
    assert_encloses(q, c, s, ec, es)
    assert np.all(ec <= 8 * ULP1) and np.all(es <= 8 * ULP1)


def test_nan_and_infinity():
    for v in (math.nan, math.inf, -math.inf):
        c, s, ec, es = cos_sin_bounded(v)
        assert math.isnan(c) and math.isnan(s) and ec == math.inf and es == math.inf
    c, s, ec, es = cos_sin_enclosure([[np.nan, 1.0], [np.inf, -np.inf]])
    assert c.shape == (2, 2)
    assert np.isnan(c[[0, 1, 1], [0, 0, 1]]).all() and np.isinf(es[[0, 1, 1], [0, 0, 1]]).all()
    assert np.isfinite(c[0, 1]) and ec[0, 1] < ULP1


def test_shapes():
    c, s, ec, es = cos_sin_enclosure(0.5)
    assert c.shape == () and float(s) == cos_sin_bounded(0.5)[1]
    assert cos_sin_enclosure(np.zeros((0, 3)))[0].shape == (0, 3)
    q = np.arange(24.0).reshape(2, 3, 4)[:, ::2]                       # not contiguous
    c, s, ec, es = cos_sin_enclosure(q)
    assert c.shape == (2, 2, 4) and c[1, 1, 3] == cos_sin_bounded(float(q[1, 1, 3]))[0]


def test_invalid_input_names_the_parameter():
    with pytest.raises(TypeError, match="q must be numeric"):
        cos_sin_enclosure("1.0")
    with pytest.raises(TypeError, match="q must be real"):
        cos_sin_enclosure(np.array([1j]))


def test_two_sum_is_error_free(rng):
    a = rng.standard_normal(2000) * 2.0 ** rng.integers(-60, 60, 2000)
    b = rng.standard_normal(2000) * 2.0 ** rng.integers(-60, 60, 2000)
    for x, y in zip(a, b):
        s, e = bt._two_sum(float(x), float(y))
        assert Fraction(s) + Fraction(e) == Fraction(float(x)) + Fraction(float(y))
        assert s == x + y


def test_compiled_equals_plain_python(rng):
    """numba's code rounds exactly like Python's IEEE arithmetic (no contraction, no reordering)."""
    if not HAVE_NUMBA:
        pytest.skip("numba missing: the functions are plain Python already")
    q = sample(rng)[::5]
    q = q[np.abs(q) <= Q_MAX]
    plain = bt.cos_sin_bounded.py_func
    assert all(cos_sin_bounded(float(v)) == plain(float(v)) for v in q)


@pytest.mark.slow                                   # compiles four functions afresh (~3 s)
@pytest.mark.skipif(not HAVE_NUMBA, reason="inspects numba's machine code")
def test_no_fused_multiply_add_in_machine_code():
    """The error analysis assumes every product and sum is rounded separately."""
    import numba

    fresh = {name: numba.njit(getattr(bt, name).py_func) for name in
             ("_two_sum", "_sin_poly", "_cos_poly", "cos_sin_bounded")}
    fresh["_two_sum"](1.0, 2.0)
    fresh["_sin_poly"](0.1, 1e-18)
    fresh["_cos_poly"](0.1, 1e-18)
    fresh["cos_sin_bounded"](1.0)
    for name, f in fresh.items():
        asm = "\n".join(f.inspect_asm(sig) for sig in f.signatures)
        assert re.search(r"\badd[sp]d|\bvadd[sp]d", asm), name           # real code inspected
        assert not re.search(r"\bv?f[n]?m(add|sub)", asm), name


def arb_value(expr, q):
    """An arb ball of a sympy expression polynomial in q_i, cos q_i, sin q_i with constants in a
    radical extension of the rationals, at exact float joint values (evaluated from the expression tree, not expanded)."""
    if expr.is_Rational:
        return flint.arb(flint.fmpq(int(expr.p), int(expr.q)))
    if expr.is_Symbol:
        return flint.arb(q[expr])
    if isinstance(expr, sp.cos):
        return arb_value(expr.args[0], q).cos()
    if isinstance(expr, sp.sin):
        return arb_value(expr.args[0], q).sin()
    if expr.is_Add:
        out = flint.arb(0)
        for a in expr.args:
            out += arb_value(a, q)
        return out
    if expr.is_Mul:
        out = flint.arb(1)
        for a in expr.args:
            out *= arb_value(a, q)
        return out
    if expr.is_Pow and expr.exp.is_Integer:
        return arb_value(expr.base, q) ** int(expr.exp)
    if expr.is_Pow and expr.exp.is_Rational:                # sqrt(109) from a unit direction
        return arb_value(expr.base, q) ** arb_value(expr.exp, q)
    raise NotImplementedError(expr)


@pytest.mark.slow
def test_coefficient_enclosure_with_actuated_angles(rng):
    """CoefficientEnclosure on coefficients in cos/sin of actuated angles (two RRR legs with
    actuated base angles and an RRP leg, also actuated by an angle; products of the legs' quadric
    coefficients mix the angles) encloses the exact coefficients, evaluated in arb from the
    unexpanded expressions."""
    legs = [isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, sp.Rational(5, 2)), actuated=0),
            isp.RRP(base=(2, 5), length=2, platform=(0, sp.Rational(6, 5)), direction=(3, 4)),
            isp.RRR(base=(6, 0), platform=(sp.Rational(3, 2), 0), lengths=(sp.Rational(7, 2), 3), actuated=0)]
    m = isp.PlanarParallel(legs)
    eqs = [sp.expand(e) for e in m.constraint_equations()]
    x = sorted(set().union(*(e.free_symbols for e in eqs)) - set(m.joint_symbols), key=str)
    assert [str(v) for v in x] == ["x0", "x1", "x2", "x3"]
    cs = [sp.Poly(e, *x).coeffs() for e in eqs]
    exprs = ([c for cc in cs for c in cc] + [a * b for a in cs[0] for b in cs[2]]
             + [a * b * c for a in cs[0][:3] for b in cs[1][:3] for c in cs[2][:3]])
    enc = CoefficientEnclosure(exprs, m.joint_symbols)
    assert len(enc._trig) == 6                      # cos, sin of q1, q2 (RRP: an angle), q3
    Q = np.column_stack([rng.uniform(-4, 4, 24), rng.uniform(-4, 4, 24), rng.uniform(-4, 4, 24)])
    Q[:5, 0] = [0.0, np.pi / 2, -np.pi, 1e-12, 2e7]         # near multiples of pi/2, tiny, beyond Q_MAX
    Q[5:8, 1] = [-3 * np.pi / 2, 1e-300, -1e9]
    F, E = enc.evaluate(Q)
    assert F.shape == (24, len(exprs))
    scale = np.abs(F).max(axis=1, keepdims=True)
    assert np.all(E <= 1e-12 * scale)    # small (the expanded monomials cancel: ~1e3 ulps at most)
    for r in range(len(Q)):
        qv = dict(zip(m.joint_symbols, (float(v) for v in Q[r])))
        for k, expr in enumerate(exprs):
            dist = arb_value(expr, qv) - flint.arb(float(F[r, k]))
            assert dist.abs_upper() <= flint.arb(float(E[r, k])), (r, k)


@pytest.mark.slow                                   # the general-q kinematic polynomial: ~45 s
def test_kinematic_polynomial_enclosure_with_an_rrr_leg(rng):
    """The certified batch path's enclosure (Mechanism.enclosure) of the sextic general in q,
    on the design of tests/solve/test_fastdk.py (RRR with its base angle actuated, PRR, RRP),
    against arb evaluation of the sympy coefficients."""
    legs = [isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3.0, 2.5), actuated=0),
            isp.PRR(base=(6, 0), axis=(0.4, 1.0), platform=(1.5, 0), length=2.8),
            isp.RRP(base=(2, 5), length=2.0, platform=(0, 1.2), direction=(1.0, 0.3))]
    m = isp.PlanarParallel(legs)
    poses = np.column_stack([rng.uniform(1, 3, 40), rng.uniform(0.5, 2.5, 40), rng.uniform(-0.6, 0.6, 40)])
    Q = m.inverse_kinematics(poses, working_modes=[1, 0, 0])
    Q = Q[np.all(np.isfinite(Q), axis=1)][:6]
    assert len(Q) >= 3
    P = m.kinematic_polynomial()
    d = P.total_degree()
    x0, x1 = P.gens
    coeffs = [P.coeff_monomial(x0 ** (d - k) * x1**k) for k in range(d + 1)]
    F, E = m.enclosure().evaluate(Q)
    assert np.all(E <= 1e-12 * np.abs(F).max(axis=1, keepdims=True))
    for r in range(len(Q)):
        qv = dict(zip(m.joint_symbols, (float(v) for v in Q[r])))
        for k, expr in enumerate(coeffs):
            dist = arb_value(expr, qv) - flint.arb(float(F[r, k]))
            assert dist.abs_upper() <= flint.arb(float(E[r, k])), (r, k)
