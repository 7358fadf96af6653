from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.core.certify import certify_real_roots

x0, x1 = isp.image_symbols()[:2]


def sturm_count(coeffs):
    """Independent: sympy's Sturm-sequence count of distinct real roots, plus the root x0 = 0."""
    d = len(coeffs) - 1
    expr = sum(sp.sympify(c) * x0 ** (d - k) * x1**k for k, c in enumerate(coeffs))
    sqf = sp.Poly(sp.sqf_part(sp.expand(expr)), x0, x1)
    u = sp.Poly(sqf.as_expr().subs(x0, 1), x1)
    return u.count_roots() + (1 if u.degree() < sqf.total_degree() else 0)


@pytest.mark.slow
def test_random_rational_forms_against_sturm(rng):
    checked = 0
    for _ in range(150):
        d = int(rng.integers(2, 7))
        roots = [sp.Rational(int(v), int(rng.integers(1, 5))) for v in rng.integers(-6, 7, size=int(rng.integers(0, d + 1)))]
        poly = sp.Integer(1)
        for r in roots:
            poly *= (x1 - r * x0)
        # fill up with random quadratics (real or complex pairs) and maybe a power of x0
        while sp.Poly(poly, x0, x1).total_degree() + 2 <= d:
            a, b, c = (sp.Integer(int(v)) for v in rng.integers(-5, 6, size=3))
            q = a * x0**2 + b * x0 * x1 + (c if c != 0 else 1) * x1**2
            poly *= q
        while sp.Poly(poly, x0, x1).total_degree() < d:
            poly *= x0
        P = sp.Poly(sp.expand(poly), x0, x1)
        if P.is_zero:
            continue
        coeffs = [P.coeff_monomial(x0 ** (d - k) * x1**k) for k in range(d + 1)]
        cert = certify_real_roots(coeffs)
        assert cert.certified and cert.count == sturm_count(coeffs), (P, cert)
        # every constructed rational root lies in exactly one certified interval (exact ends)
        for r in set(roots):
            rf = Fraction(int(r.p), int(r.q))
            assert sum(lo <= rf <= hi for lo, hi in cert.exact_intervals) == 1, (P, r)
        checked += 1
    assert checked >= 140


def test_double_root_and_half_turn_exact():
    # (x1 - x0)^2 (x1 + 2 x0) x0: double root t = 1, simple t = -2, half-turn
    P = sp.Poly(sp.expand((x1 - x0) ** 2 * (x1 + 2 * x0) * x0), x0, x1)
    cert = certify_real_roots(P)
    assert cert.count == 3 and cert.at_infinity == 1 and sorted(cert.multiplicities) == [1, 2]
    assert cert.contains(1.0) and cert.contains(-2.0)


def test_float_coefficients_are_binary_rationals():
    # 0.1 is not 1/10: x0^2 - 0.1 x1^2 has the roots +-1/sqrt(0.1 as a binary rational)
    cert = certify_real_roots([1.0, 0.0, -0.1])
    assert cert.count == 2 and "exact" in cert.method


def test_algebraic_coefficients_and_mechanisms():
    m = isp.examples.stigger_husty()
    modes = m.direct_kinematics(m.q_example, certify=True)
    assert modes.certificate.certified and modes.certificate.count == 6
    assert modes.modes_per_root == (1,) * 6
    assert "arb" in modes.certificate.method
    c = isp.examples.collinear_3rpr(2, 1)
    cm = c.direct_kinematics(c.q_example, certify=True)
    assert cm.certificate.count == 2 and cm.modes_per_root == (2, 2) and len(cm) == 4


@pytest.mark.slow
def test_certified_counts_on_mechanisms_agree_with_sturm(rng):
    """Mixed designs with rational geometry and joint values: flint's count = sympy's Sturm count."""
    checked, with_modes = 0, 0
    while checked < 40:
        legs = []
        axes = [(1, 0), (0, 1), (3, 4), (-4, 3), (5, 12)]      # unit length after exact normalisation
        for k in rng.choice(["RPR", "PRR", "PPR"], size=3):
            A = tuple(int(v) for v in rng.integers(-6, 7, 2))
            a = tuple(int(v) for v in rng.integers(-3, 4, 2))
            if k == "RPR":
                legs.append(isp.RPR(base=A, platform=a))
            elif k == "PRR":
                legs.append(isp.PRR(base=A, axis=axes[int(rng.integers(5))], platform=a, length=int(rng.integers(2, 6))))
            else:
                legs.append(isp.PPR(base=A, axis=axes[int(rng.integers(5))], platform=a, angle=sp.pi / 2))
        try:
            m = isp.PlanarParallel(legs)
        except isp.DegenerateDesignError:
            continue
        q = [sp.Rational(int(v), 2) for v in rng.integers(2, 16, 3)]
        try:
            P = m.kinematic_polynomial(q)
        except isp.DegenerateDesignError:
            continue
        d = P.total_degree()
        coeffs = [P.coeff_monomial(x0 ** (d - k) * x1**k) for k in range(d + 1)]
        if not all(sp.sympify(c).is_Rational for c in coeffs):
            continue
        modes = m.direct_kinematics([float(v) for v in q], certify=True)
        assert modes.certificate.count == sturm_count(coeffs)
        assert sum(modes.modes_per_root) == len(modes)
        checked += 1
        with_modes += len(modes) > 0
    assert with_modes >= 8


def test_tangent_joint_values_double_root():
    """A 3-RPR at joint values on the singularity surface: the exact count sees the double root."""
    m = isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(0, 0)), isp.RPR(base=(10, 0), platform=(6, 0)),
                            isp.RPR(base=(3, 8), platform=(2, 5))])
    modes = m.direct_kinematics([3, 7, 5], certify=True)
    cert = modes.certificate
    assert cert.certified and cert.count == 3 and 2 in cert.multiplicities
    assert len(modes) == 3


def test_bad_input():
    with pytest.raises(isp.InputError, match="vanish"):
        certify_real_roots([0, 0, 0])


@pytest.mark.slow
def test_batch_certified_counts_agree_with_exact_isolation(rng):
    """2,000 rows: kinematic sextics of mixed designs, constructed double roots and half-turns."""
    from imagespace.core.certify import certify_real_roots_batch
    from imagespace.core.elimination import eliminate

    rows = []
    # kinematic polynomials of the seed-002 mechanism and a general 3-RPR at random joint values
    for m in (isp.examples.stigger_husty(), isp.examples.general_3rpr()):
        Q = rng.uniform(2, 16, (700, 3))
        el = eliminate(m.quadrics(Q))
        rows.append(np.stack(np.broadcast_arrays(*el.F), axis=1))
    # constructed: a double real root, or a root at x0 = 0 (half-turn), times random factors
    extra = []
    for i in range(600):
        r = rng.integers(-5, 6, 4) / 2.0
        f = np.array([1.0])
        if i % 3 == 0:
            f = np.convolve(f, [-r[0], 1.0])
            f = np.convolve(f, [-r[0], 1.0])           # double root t = r0
        elif i % 3 == 1:
            f = np.convolve(f, [1.0, 0.0])              # factor x0: the root x0 = 0 (half-turn)
            f = np.convolve(f, [-r[1], 1.0])
        while len(f) < 7:
            f = np.convolve(f, [rng.integers(-4, 5) or 1.0, rng.integers(-4, 5), rng.integers(1, 5)])
        assert len(f) == 7
        extra.append(f)
    rows.append(np.array(extra))
    F = np.concatenate(rows)
    assert F.shape[0] == 2000
    counts, path = certify_real_roots_batch(F)
    for i in range(F.shape[0]):
        exact = certify_real_roots([sp.Rational(float(v)) for v in F[i]])
        assert counts[i] == exact.count, (i, F[i], path[i])
    assert np.sum(F[:, 6] == 0) >= 150                 # half-turn rows present
    assert np.sum(path == "discs") > 1000 and np.sum(path == "flint") >= 200


def test_batch_odd_inputs():
    from imagespace.core.certify import certify_real_roots_batch

    counts, path = certify_real_roots_batch(np.array([[np.nan, 1.0, 1.0], [0.0, 0.0, 0.0], [1.0, 0.0, -1.0]]))
    assert counts.tolist() == [-1, -1, 2] and path.tolist() == ["invalid", "zero", "discs"]
    counts, path = certify_real_roots_batch(np.zeros((0, 7)))
    assert counts.shape == (0,)
    with pytest.raises(isp.InputError, match="shape"):
        certify_real_roots_batch(np.zeros(7))


@pytest.mark.slow
def test_batch_dk_with_certificates(rng):
    m = isp.examples.stigger_husty()
    poses = np.column_stack([rng.uniform(-6, 6, 300), rng.uniform(-6, 6, 300), rng.uniform(-np.pi, np.pi, 300)])
    Q = m.inverse_kinematics(poses)
    Q[7] = np.nan
    r = m.direct_kinematics_batch(Q, certify=True)
    assert r.certified_roots[7] == -1 and not r.consistent[7]
    ok = np.flatnonzero(r.row_ok)
    for i in ok[:60]:
        exact = m.kinematic_polynomial([sp.Rational(float(v)) for v in Q[i]])
        assert r.certified_roots[i] == certify_real_roots(exact).count
    # generic rows: one mode per certified root
    assert np.all(r.consistent[ok]) and np.all(r.count[ok] == r.certified_roots[ok])
    # a tangent row (double root) of a 3-RPR: three distinct real roots, three modes
    t = isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(0, 0)), isp.RPR(base=(10, 0), platform=(6, 0)),
                            isp.RPR(base=(3, 8), platform=(2, 5))])
    rt = t.direct_kinematics_batch(np.array([[3.0, 7.0, 5.0]]), certify=True)
    assert rt.certified_roots.tolist() == [3] and rt.count.tolist() == [3] and rt.consistent.tolist() == [True]
