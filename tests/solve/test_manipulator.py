import mpmath
import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import imagespace as isp
from bruteforce import brute_force_dk

x0s, x1s, x2s, x3s = isp.image_symbols()

PAPER_X1 = [-1.0878919, -0.79150760, -0.49099818, -0.45561388, 0.49313162, 1.7635434]
SEEDS_POSES = [(-7.7528, 6.3162, -1.6549), (1.8441, -9.8285, -1.3391), (-9.4219, -3.3509, -0.9128),
               (-5.5018, -8.3505, -0.8550), (-9.4569, 3.2508, 0.9163), (3.1096, 9.5042, 2.1099)]


def same_pose(a, b, tol):
    return (np.max(np.abs(np.asarray(a[:2]) - np.asarray(b[:2]))) < tol
            and abs(np.angle(np.exp(1j * (a[2] - b[2])))) < tol)


def match(modes, poses, tol=1e-6):
    """Every pose matched by exactly one mode and vice versa."""
    if len(modes) != len(poses):
        return False
    used = set()
    for p in poses:
        hits = [i for i, mm in enumerate(modes) if i not in used and same_pose(mm.pose, p, tol)]
        if not hits:
            return False
        used.add(hits[0])
    return True


# ----------------------------------------------------------------------------- seed 002

def test_seed_002_six_modes_as_printed():
    m = isp.examples.stigger_husty()
    modes = m.direct_kinematics(m.q_example)
    assert len(modes) == 6
    x1 = sorted(mm.image_point[1] / mm.image_point[0] for mm in modes)
    assert np.allclose(x1, PAPER_X1, atol=5e-8)
    first = min(modes, key=lambda mm: mm.image_point[1] / mm.image_point[0])
    X = first.image_point / first.image_point[0]
    # printed to 10 digits; they agree with the exact roots to 8 significant digits
    assert X[2] == pytest.approx(1.059032801, abs=5e-8)
    assert X[3] == pytest.approx(-7.312056755, abs=5e-8)
    assert match(modes, SEEDS_POSES, tol=1e-4)


def test_seed_002_modes_satisfy_constraints_and_ik():
    m = isp.examples.stigger_husty()
    eqs = m.constraint_equations(m.q_example)
    q = m.q_example_float
    checked = 0
    for mm in m.direct_kinematics(m.q_example):
        sub = dict(zip((x0s, x1s, x2s, x3s), mm.image_point))
        for e in eqs:
            assert abs(float(e.subs(sub))) < 1e-9
        assert np.allclose(m.inverse_kinematics(mm.pose), q, atol=1e-10)
        checked += 1
    assert checked == 6


def test_seed_002_exact_polynomial_has_six_real_roots():
    m = isp.examples.stigger_husty()
    P = m.kinematic_polynomial(m.q_example)
    assert P.total_degree() == 6 and P.is_homogeneous
    u = sp.Poly(P.as_expr().subs(x0s, 1), x1s)
    roots = sorted(float(r) for r in sp.Poly(u.as_expr().evalf(40), x1s).nroots(n=20) if abs(sp.im(r)) < 1e-20)
    assert np.allclose(roots, PAPER_X1, atol=5e-8)


@pytest.mark.slow
def test_seed_002_matches_brute_force():
    m = isp.examples.stigger_husty()
    q = m.q_example_float
    assert match(m.direct_kinematics(q), brute_force_dk(m, q))


# ----------------------------------------------------------------------------- brute force

def random_design(rng):
    kinds = rng.choice(["RPR", "RRR", "PRR", "PPR"], size=3)
    legs = []
    for k in kinds:
        A = rng.uniform(-6, 6, 2)
        a = rng.uniform(-3, 3, 2)
        if k == "RPR":
            legs.append(isp.RPR(base=A, platform=a))
        elif k == "RRR":
            legs.append(isp.RRR(base=A, platform=a, lengths=rng.uniform(2, 5, 2)))
        elif k == "PRR":
            legs.append(isp.PRR(base=A, axis=rng.normal(size=2), platform=a, length=rng.uniform(2, 5)))
        else:
            legs.append(isp.PPR(base=A, axis=rng.normal(size=2), platform=a, angle=rng.uniform(0.5, 2.6)))
    return isp.PlanarParallel(legs)


@pytest.mark.slow
def test_against_brute_force_on_random_mixed_designs(rng):
    compared, total_modes = 0, 0
    while compared < 30:
        m = random_design(rng)
        pose = np.array([rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-np.pi, np.pi)])
        branches = [rng.integers(leg.n_branches) for leg in m.legs]
        try:
            q = m.inverse_kinematics(pose, working_modes=branches)
        except isp.InputError:
            continue
        if any(leg.joints == "RPR" and q[i] < 0 for i, leg in enumerate(m.legs)):
            continue
        modes = m.direct_kinematics(q)
        ref = brute_force_dk(m, q)
        assert any(same_pose(mm.pose, pose, 1e-7) for mm in modes)
        assert match(modes, ref), (m, q, [mm.pose for mm in modes], ref)
        compared += 1
        total_modes += len(modes)
    assert total_modes > 60


# ----------------------------------------------------------------------------- half-turns

@pytest.mark.parametrize("phi", [np.pi, np.pi - 1e-9, -np.pi + 1e-9])
def test_half_turn_modes_are_found(phi):
    m = isp.examples.general_3rpr()
    pose = np.array([0.4, -0.3, phi])
    q = m.inverse_kinematics(pose)
    modes = m.direct_kinematics(q)
    assert any(same_pose(mm.pose, pose, 1e-8) for mm in modes)
    hit = [mm for mm in modes if same_pose(mm.pose, pose, 1e-8)][0]
    assert abs(hit.image_point[0]) < 1e-8


# ----------------------------------------------------------------------------- seed 003 and 004

def closed_form_003(R, r, d1, d2, d3):
    """The course notes' closed form (seed 003), written here."""
    c = (2 * (d2**2 + R**2 + r**2) - d1**2 - d3**2) / (4 * r * R)
    out = []
    if abs(c) > 1:
        return out
    for s in (np.sqrt(1 - c * c), -np.sqrt(1 - c * c)):
        a = (R - r * c) / (r * s)
        b = (d3**2 - d1**2) / (4 * r * s)
        disc = a * a * d2**2 + d2**2 - b * b
        if disc < 0:
            continue
        for sign in (1, -1):
            x = (-a * b + sign * np.sqrt(disc)) / (1 + a * a)
            out.append((x, a * x + b, np.arctan2(s, c)))
    return out


def test_seed_003_closed_form_equals_elimination():
    checked = 0
    for R, r in [(2, 1), (3, 1.2), (1.5, 0.8)]:
        m = isp.examples.collinear_3rpr(R, r)
        for pose in ([0.3 * R, 1.2 * R, 0.7], [0.1, 0.9 * R, -0.4], [-0.2, 0.5 * R, 2.0]):
            q = m.inverse_kinematics(pose)
            modes = m.direct_kinematics(q)
            ref = closed_form_003(R, r, *q)
            assert len(ref) == 4
            assert match(modes, ref, 1e-8)
            checked += 1
    assert checked == 9


def test_seed_003_sin_theta_zero_no_division_by_zero():
    m = isp.examples.collinear_3rpr(2, 1)
    # theta = 0: all legs meet... poses with sin(theta) = 0 are singular: the float path finds
    # the pose but must say that its count is not to be trusted
    for phi in (0.0, np.pi):
        q = m.inverse_kinematics([0.5, 1.5, phi])
        with pytest.warns(isp.NearSingularWarning):
            modes = m.direct_kinematics(q)
        assert any(same_pose(mm.pose, [0.5, 1.5, phi], 1e-6) for mm in modes)
    # the exact singular input (squared leg lengths 9/2, 5/2, 5/2 from |P_i - A_i|^2 at the pose
    # (1/2, 3/2, 0) with base (-2, 0), (0, 0), (2, 0)... computed here by hand): the orientation
    # phi = 0 is a double root of the orientation quadratic; it carries the two mirror positions,
    # both singular (multiplicity 2, aspect 0)
    A = [(-2, 0), (0, 0), (2, 0)]
    a = [(-1, 0), (0, 0), (1, 0)]
    P = (sp.Rational(1, 2), sp.Rational(3, 2))
    legs = [m.legs[i].geometry() for i in range(3)]
    assert [tuple(g["base"]) for g in legs] == [tuple(map(sp.Integer, p)) for p in A]
    assert [tuple(g["platform"]) for g in legs] == [tuple(map(sp.Integer, p)) for p in a]
    q2 = [(P[0] + a[i][0] - A[i][0])**2 + (P[1] + a[i][1] - A[i][1])**2 for i in range(3)]
    cm = m.direct_kinematics([sp.sqrt(v) for v in q2], certify=True)
    assert cm.certificate.count == 1 and cm.certificate.multiplicities == (2,)
    assert len(cm) == 2 and cm.modes_per_root == (2,)
    assert all(mm.multiplicity == 2 and mm.aspect == 0 for mm in cm)
    assert sorted(round(float(mm.pose[1]), 12) for mm in cm) == [-1.5, 1.5]


def test_seed_004_two_modes_share_position():
    checked = 0
    for alpha in (7 * np.pi / 18, 11 * np.pi / 18, 1.0):
        m = isp.examples.choi_3ppr(1.0, 0.5, alpha)
        pose = np.array([0.1, -0.05, 0.2])
        modes = m.direct_kinematics(m.inverse_kinematics(pose))
        assert len(modes) == 2
        assert np.allclose(modes[0].pose[:2], modes[1].pose[:2], atol=1e-9)
        phis = sorted(mm.pose[2] for mm in modes)
        other = np.angle(np.exp(1j * (2 * alpha - 0.2)))
        assert np.allclose(sorted([0.2, other]), phis, atol=1e-9)
        checked += 1
    assert checked == 3


# ----------------------------------------------------------------------------- properties

def smallest_singular_value_of_ik(m, pose, h=1e-6):
    """Independent distance-to-singularity measure: sigma_min of d(IK)/d(pose), central differences."""
    J = np.empty((3, 3))
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        J[:, k] = (m.inverse_kinematics(pose + e) - m.inverse_kinematics(pose - e)) / (2 * h)
    s = np.linalg.svd(J, compute_uv=False)
    return s[-1] / s[0]


def _ik_of_dk_is_q(x, y, phi):
    m = isp.examples.stigger_husty()
    # at a pose on (or within 1e-4 of) the singularity surface two modes merge and the float path
    # cannot separate them to 1e-7; that case belongs to the certified tests
    assume(smallest_singular_value_of_ik(m, np.array([x, y, phi])) > 1e-4)
    q = m.inverse_kinematics([x, y, phi])
    # a (nearly) zero-length RPR leg is singular too (det Jq = 2 rho = 0): two modes ~2 rho apart
    assume(min(q[0], q[1]) > 1e-3)
    modes = m.direct_kinematics(q)
    assert any(same_pose(mm.pose, [x, y, phi], 1e-7) for mm in modes)
    for mm in modes:
        assert np.allclose(m.inverse_kinematics(mm.pose), q, rtol=1e-8, atol=1e-8)


# the property in the fast lane with 10 examples, the full 40-example sweep with the slow checks
_IK_POSES = (st.floats(-3, 3), st.floats(-3, 3), st.floats(-np.pi, np.pi))
test_ik_of_dk_is_q = settings(max_examples=10, deadline=None)(given(*_IK_POSES)(_ik_of_dk_is_q))
test_ik_of_dk_is_q_sweep = pytest.mark.slow(settings(max_examples=40, deadline=None)(given(*_IK_POSES)(_ik_of_dk_is_q)))


@pytest.mark.slow
def test_symbolic_polynomial_at_q_equals_numeric(rng):
    m = isp.examples.general_3rpr()
    P = m.kinematic_polynomial()
    qs = m.joint_symbols
    roots_checked = 0
    for _ in range(5):
        q = rng.uniform(4, 12, 3)
        numeric = m.kinematic_polynomial(q)
        sub = P.as_expr().subs(dict(zip(qs, [sp.Rational(v) for v in q])))
        for pt in rng.normal(size=(3, 2)):
            a = float(sub.subs({x0s: pt[0], x1s: pt[1]}))
            b = float(numeric.as_expr().subs({x0s: pt[0], x1s: pt[1]}))
            assert np.isclose(a, b, rtol=1e-9)
        # and its real roots are the modes' orientations
        modes = m.direct_kinematics(q)
        for mm in modes:
            val = float(numeric.as_expr().subs({x0s: mm.image_point[0], x1s: mm.image_point[1]}))
            scale = float(sum(abs(c) for c in numeric.coeffs()))
            assert abs(val) < 1e-9 * scale
            roots_checked += 1
    assert roots_checked >= 5


@pytest.mark.slow
def test_polynomial_is_general_in_design_parameters():
    px, qx = sp.symbols("p_x q_x", real=True)
    m = isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(0, 0)), isp.RPR(base=(px, 0), platform=(qx, 0)),
                            isp.PPR(base=(10, 9), axis=(-10, -9), platform=(7, 10), angle=sp.pi / 2)])
    P = m.kinematic_polynomial()
    assert {px, qx} <= P.as_expr().free_symbols
    ref = isp.examples.stigger_husty()
    sub = P.as_expr().subs({px: 7, qx: 5}).subs(dict(zip(m.joint_symbols, ref.q_example)))
    exact = ref.kinematic_polynomial(ref.q_example).as_expr()
    ratio = sp.Poly(sp.expand(sub), x0s, x1s).coeffs()[0] / sp.Poly(exact, x0s, x1s).coeffs()[0]
    assert sp.expand(sp.expand(sub) - sp.expand(ratio * exact)) == 0


def test_batch_equals_single(rng):
    m = isp.examples.stigger_husty()
    poses = np.column_stack([rng.uniform(-4, 4, 50), rng.uniform(-4, 4, 50), rng.uniform(-np.pi, np.pi, 50)])
    Q = m.inverse_kinematics(poses)
    Q[3] = np.nan
    Q[7, 0] = -1.0
    r = m.direct_kinematics_batch(Q)
    assert r.poses.shape == (50, 6, 3) and r.valid.shape == (50, 6)
    assert not r.row_ok[3] and not r.row_ok[7] and 3 in r.errors and "rho" in r.errors[7]
    for i in range(50):
        if i in (3, 7):
            assert r.count[i] == 0
            continue
        single = m.direct_kinematics(Q[i])
        assert r.count[i] == len(single)
        for a, b in zip(r.modes(i), single):
            assert np.allclose(a.image_point, b.image_point, atol=1e-12)


# ----------------------------------------------------------------------------- errors

def test_no_real_mode_is_empty():
    m = isp.examples.stigger_husty()
    assert m.direct_kinematics([1.0, 1.0, 100.0]) == []
    assert m.direct_kinematics_batch(np.array([[1.0, 1.0, 100.0]])).count.tolist() == [0]


def test_complex_modes_on_request():
    m = isp.examples.collinear_3rpr(2, 1)
    m2 = isp.examples.general_3rpr()
    q = m2.inverse_kinematics([0.5, 0.2, 0.3])
    modes = m2.direct_kinematics(q, include_complex=True)
    real = [mm for mm in modes if mm.is_real]
    cplx = [mm for mm in modes if not mm.is_real]
    assert len(real) + len(cplx) == 6
    for mm in cplx:
        eqs = m2.quadrics(q)
        X = mm.image_point
        for e in eqs:
            c, a0, a1, b0, b1, k0, k1, k2 = (float(v) for v in e.coefficients())
            val = (c * (X[2]**2 + X[3]**2) + X[2] * (a0 * X[0] + a1 * X[1]) + X[3] * (b0 * X[0] + b1 * X[1])
                   + k0 * X[0]**2 + k1 * X[0] * X[1] + k2 * X[1]**2)
            assert abs(val) < 1e-6 * (1 + np.abs(X).max() ** 2)
    assert m.direct_kinematics(m.q_example, include_complex=False)


def test_bad_input():
    m = isp.examples.stigger_husty()
    with pytest.raises(isp.InputError, match="shape"):
        m.direct_kinematics([1.0, 2.0])
    with pytest.raises(isp.InputError, match="finite"):
        m.direct_kinematics([np.nan, 2.0, 3.0])
    with pytest.raises(isp.InputError, match="finite"):
        m.direct_kinematics([np.inf, 2.0, 3.0])
    with pytest.raises(isp.InputError, match="rho"):
        m.direct_kinematics([-1.0, 2.0, 3.0])
    with pytest.raises(isp.InputError, match="Q"):
        m.direct_kinematics_batch(np.zeros((4, 2)))
    with pytest.raises(isp.InputError, match="legs"):
        isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(0, 0))])
    with pytest.raises(TypeError, match="legs"):
        isp.PlanarParallel([1, 2, 3])
    with pytest.raises(isp.InputError, match="out of reach"):
        isp.PlanarParallel([isp.RRR(base=(i, 0), platform=(0, i), lengths=(1, 1)) for i in range(3)]
                           ).inverse_kinematics([9.0, 0, 0])


def test_coincident_anchors_are_degenerate():
    with pytest.raises(isp.DegenerateDesignError, match="same base anchor"):
        isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(1, 0)), isp.RPR(base=(0, 0), platform=(1, 0)),
                            isp.RPR(base=(3, 0), platform=(2, 1))])
    with pytest.raises(isp.DegenerateDesignError, match="platform anchor"):
        isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(1, 0)), isp.RPR(base=(4, 0), platform=(1, 0)),
                            isp.RPR(base=(3, 5), platform=(1, 0))])


def test_architecture_singularity_is_reported():
    # congruent base and platform, equal legs: the platform translates on a circle at phi = 0
    tri = [(0, 0), (4, 0), (1, 3)]
    m = isp.PlanarParallel([isp.RPR(base=p, platform=p) for p in tri])
    with pytest.raises(isp.DegenerateDesignError, match="continuum"):
        m.direct_kinematics([2.0, 2.0, 2.0])
    r = m.direct_kinematics_batch(np.array([[2.0, 2.0, 2.0], [1.0, 1.5, 2.0]]))
    assert r.row_ok.tolist() == [False, True] and "continuum" in r.errors[0]


# ----------------------------------------------------------------------------- all leg variants

def any_leg(rng, kind, act):
    A = rng.uniform(-5, 5, 2)
    a = rng.uniform(-2, 2, 2)
    d = rng.normal(size=2)
    if kind == "RPR":
        return isp.RPR(base=A, platform=a, actuated=act)
    if kind == "RRR":
        return isp.RRR(base=A, platform=a, lengths=rng.uniform(2, 5, 2), actuated=act)
    if kind == "PRR":
        return isp.PRR(base=A, axis=d, platform=a, length=rng.uniform(2, 5), actuated=act)
    if kind == "RRP":
        return isp.RRP(base=A, length=rng.uniform(2, 5), platform=a, direction=d, actuated=act)
    if kind == "RPP":
        return isp.RPP(base=A, platform=a, direction=d, angle=rng.uniform(0.4, 2.7), actuated=act)
    if kind == "PRP":
        return isp.PRP(base=A, axis=d, platform=a, direction=rng.normal(size=2), actuated=act)
    return isp.PPR(base=A, axis=d, platform=a, angle=rng.uniform(0.4, 2.7), actuated=act)


def exact_real_root_count(poly):
    """Distinct real roots of a binary form on the projective line: exactly (sympy's Sturm count on
    the square-free part) when the coefficients are rational; when an actuated angle put cos/sin of
    a rational into them, by mpmath's polynomial roots at 80 digits on coefficients evaluated at
    100 digits (an independent numerical count, asserted to be well conditioned: the random designs
    here have no near-double roots)."""
    x0, x1 = isp.image_symbols()[:2]
    expr = sp.expand(poly.as_expr())
    if all(c.is_Rational for c in sp.Poly(expr, x0, x1).coeffs()):
        sqf = sp.Poly(sp.sqf_part(expr), x0, x1)
        u = sp.Poly(sqf.as_expr().subs(x0, 1), x1)
        at_infinity = 1 if u.degree() < sqf.total_degree() else 0
        return u.count_roots() + at_infinity
    P = sp.Poly(expr, x0, x1)
    deg = P.total_degree()
    with mpmath.workdps(100):
        c = [sp.N(P.coeff_monomial(x0 ** (deg - k) * x1 ** k), 100) for k in range(deg + 1)]
        c = [mpmath.mpf(str(v)) for v in c]
    scale = max(abs(v) for v in c)
    at_infinity = 0
    while abs(c[-1]) <= mpmath.mpf(10) ** -60 * scale:   # x0 = 0 a root: the highest x1 power is absent
        c.pop()
        at_infinity = 1
    with mpmath.workdps(80):
        roots = mpmath.polyroots(c[::-1], maxsteps=400, extraprec=400)
        real = sorted(float(r.real) for r in roots if abs(r.imag) < mpmath.mpf(10) ** -40 * (1 + abs(r)))
        assert all(abs(r.imag) > 1e-12 for r in roots if abs(r.imag) >= mpmath.mpf(10) ** -40 * (1 + abs(r)))
    assert all(b - a > 1e-10 for a, b in zip(real, real[1:])), real     # no near-double real root
    return len(real) + at_infinity


@pytest.mark.slow
def test_every_leg_variant_recovers_the_pose_and_the_exact_count(rng):
    kinds = ["RPR", "RRR", "PRR", "RRP", "RPP", "PRP", "PPR"]
    done, counted = 0, 0
    while done < 42:
        kind = kinds[done % 7]
        act = (done // 7) % 3
        others = rng.choice(["RPR", "RRR", "PRR", "RRP"], size=2)
        legs = [any_leg(rng, kind, act)] + [any_leg(rng, k, int(rng.integers(3))) for k in others]
        try:
            m = isp.PlanarParallel(legs)
        except isp.DegenerateDesignError:
            continue
        pose = np.array([rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-np.pi, np.pi)])
        try:
            q = m.inverse_kinematics(pose)
        except isp.InputError:
            continue
        if any(leg.joints == "RPR" and leg.actuated == 1 and q[i] < 0 for i, leg in enumerate(m.legs)):
            continue
        modes = m.direct_kinematics(q)
        assert any(same_pose(mm.pose, pose, 1e-7) for mm in modes), (m, q)
        for mm in modes:
            assert m.joint_residual(mm.pose, q) < 1e-8
        has_pp = any(qd.kind == "PP" for qd in m.quadrics(q))
        if not has_pp:
            # exact count of distinct real roots of the exact polynomial (rational q)
            P = m.kinematic_polynomial([sp.Rational(v) for v in q])
            orientations = {round(float(np.arctan2(mm.image_point[1], mm.image_point[0]) % np.pi), 9)
                            for mm in modes}
            assert len(orientations) == exact_real_root_count(P), (m, q)
            counted += 1
        done += 1
    assert counted >= 20


@pytest.mark.slow
def test_denominator_vanishing_at_a_root_case_b():
    """Build a 2RPR-PPR whose Cramer denominator vanishes at the orientation of a known mode."""
    from imagespace.core.elimination import bf_eval, eliminate

    pose = np.array([0.7, 1.3, 0.4])
    X = isp.image_point(pose)
    c = np.array([2.0, 1.0])
    cw = isp.transform_points(X, c)

    def build(psi):
        u = np.array([np.cos(psi), np.sin(psi)])
        legs = [isp.RPR(base=(0, 0), platform=(0, 0)), isp.RPR(base=(6, 0), platform=(3, 0)),
                isp.PPR(base=cw - 4.0 * u, axis=u, platform=c, angle=np.pi / 2)]
        return isp.PlanarParallel(legs)

    def d_at_pose(psi):
        m = build(psi)
        q = m.inverse_kinematics(pose)
        el = eliminate(m.quadrics(q))
        return bf_eval([float(v) for v in el.D], X[0], X[1])

    from scipy.optimize import brentq
    grid = np.linspace(0, np.pi, 181)
    vals = [d_at_pose(p) for p in grid]
    k = next(i for i in range(180) if vals[i] * vals[i + 1] < 0)
    psi = brentq(d_at_pose, grid[k], grid[k + 1], xtol=1e-15)
    m = build(psi)
    q = m.inverse_kinematics(pose)
    modes = m.direct_kinematics(q)
    assert any(same_pose(mm.pose, pose, 1e-7) for mm in modes)
    assert match(modes, brute_force_dk(m, q), 1e-6)


@pytest.mark.slow
def test_compiled_coefficients_equal_numeric_elimination(rng):
    """The compiled general-q polynomial is proportional to the float elimination at each q."""
    from imagespace.core.elimination import eliminate

    designs = 0
    for m in (isp.examples.stigger_husty(), isp.examples.general_3rpr(), random_design(rng)):
        designs += 1
        comp = m.compiled()
        Q = rng.uniform(3, 12, (20, 3))
        for i, leg in enumerate(m.legs):         # an actuated angle in radians, inside [-pi, pi]
            if leg.actuated_is_angle:
                Q[:, i] = rng.uniform(-np.pi, np.pi, 20)
        C = comp.coefficients(Q)
        assert C.shape == (20, comp.degree + 1)
        el = eliminate(m.quadrics(Q))
        F = np.stack(np.broadcast_arrays(*el.F), axis=1)
        th = rng.uniform(0, np.pi, 7)          # points on the unit circle: x0^2 + x1^2 = 1
        def ev(coeffs):
            d = coeffs.shape[1] - 1
            k = np.arange(d + 1)
            return np.einsum("nk,tk->nt", coeffs, np.cos(th)[:, None] ** (d - k) * np.sin(th)[:, None] ** k)
        a, b = ev(C), ev(F)
        ratio = a / b
        assert np.allclose(ratio, ratio[:, :1], rtol=1e-7)
        assert comp is m.compiled()            # cached
    assert designs == 3


def test_batch_odd_inputs():
    m = isp.examples.stigger_husty()
    q = m.q_example_float
    empty = m.direct_kinematics_batch(np.zeros((0, 3)))
    assert empty.count.shape == (0,) and empty.poses.shape == (0, 6, 3)
    one = m.direct_kinematics_batch(q)               # a single row given as (3,)
    assert one.count.tolist() == [6]
    wide = np.zeros((4, 6))
    wide[:, ::2] = q                                 # a strided (non-contiguous) view
    r = m.direct_kinematics_batch(wide[:, ::2])
    assert r.count.tolist() == [6] * 4
    r32 = m.direct_kinematics_batch(np.tile(q, (2, 1)).astype(np.float32))
    ref = m.direct_kinematics(q.astype(np.float32).astype(float))
    assert r32.count.tolist() == [len(ref)] * 2
    rn = m.direct_kinematics_batch(np.array([q, [np.nan, 1.0, 1.0], q]))
    assert rn.row_ok.tolist() == [True, False, True] and rn.count.tolist() == [6, 0, 6]


@pytest.mark.slow
def test_cli_mesh_and_plot(tmp_path):
    import io

    import trimesh

    from imagespace.cli import main
    out = tmp_path / "s.obj"
    buf = io.StringIO()
    assert main(["mesh", "--chart", "pose", "--resolution", "20", "-o", str(out)], stream=buf) == 0
    assert "triangles" in buf.getvalue()
    assert len(trimesh.load(out, force="mesh").faces) > 100
    assert main(["mesh", "-o", str(tmp_path / "s.xyz")], stream=buf) == 2
    for fig in ("modes", "quadrics", "surface", "conic"):
        png = tmp_path / f"{fig}.png"
        assert main(["plot", fig, "--resolution", "12", "-o", str(png)], stream=buf) == 0
        assert png.stat().st_size > 1000
