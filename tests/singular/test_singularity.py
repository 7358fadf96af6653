"""The singularity quartic: joint values drop out for radius/offset actuation, and its zero set is
where the legs of a 3-RPR are concurrent (an independent Euclidean criterion)."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.core.kinematic_map import image_point


def concurrency(m, pose):
    """det of the three leg lines' homogeneous coordinates (zero iff concurrent or parallel)."""
    x, y, phi = pose
    R = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
    rows = []
    for leg in m.legs:
        A = np.array([float(v) for v in leg.base])
        P = R @ np.array([float(v) for v in leg.platform]) + [x, y]
        rows.append(np.cross(np.append(A, 1.0), np.append(P, 1.0)))
    return np.linalg.det(np.array(rows))


@pytest.mark.slow
def test_joint_values_drop_out_for_radius_and_offset_actuation():
    for m in (isp.examples.general_3rpr(), isp.examples.stigger_husty()):
        S = m.singularity_polynomial()
        assert S.is_homogeneous and S.total_degree() == 4
        assert not (S.free_symbols & set(m.joint_symbols))
        # equal to the surface at any particular joint vector
        assert sp.expand(S.as_expr() - m.singularity_polynomial(m.q_example).as_expr()) == 0


@pytest.mark.slow
def test_joint_values_stay_for_an_actuated_base_revolute():
    m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                            isp.RPR(base=(6, 0), platform=(1, 0)),
                            isp.RPR(base=(2, 5), platform=(0, 1))])
    assert m.joint_symbols[0] in m.singularity_polynomial().free_symbols


@pytest.mark.slow
def test_zero_set_is_where_the_legs_are_concurrent(rng):
    m = isp.examples.general_3rpr()
    S = m.singularity_polynomial()
    f = sp.lambdify(S.gens, S.as_expr(), "numpy")
    found = 0
    for _ in range(200):
        a = np.array([rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(-np.pi, np.pi)])
        b = a + rng.normal(size=3)
        ca, cb = concurrency(m, a), concurrency(m, b)
        if ca * cb > 0:
            continue
        for _ in range(60):                      # bisect on the Euclidean criterion
            c = 0.5 * (a + b)
            if concurrency(m, c) * ca > 0:
                a = c
            else:
                b = c
        x = image_point(0.5 * (a + b))
        x = x / np.hypot(x[0], x[1])
        grad_scale = np.sum(np.abs(x)) ** 4
        assert abs(f(*x)) <= 1e-9 * grad_scale
        found += 1
        # and away from it the quartic does not vanish
        x2 = image_point(a + np.array([0.3, -0.2, 0.1]))
        if abs(concurrency(m, a + np.array([0.3, -0.2, 0.1]))) > 1e-2:
            assert abs(f(*(x2 / np.hypot(x2[0], x2[1])))) > 1e-9 * grad_scale
    assert found > 20


def test_aspect_is_the_sign_of_the_quartic():
    m = isp.examples.stigger_husty()
    S = m.singularity_polynomial()
    f = sp.lambdify(S.gens, S.as_expr(), "numpy")
    modes = m.direct_kinematics(m.q_example_float)
    signs = [int(np.sign(f(*mm.image_point))) for mm in modes]
    assert signs == [mm.aspect for mm in modes]
    # the quartic is even: the representative's sign does not matter
    assert all(np.sign(f(*(-mm.image_point))) == s for mm, s in zip(modes, signs))
    assert sorted(signs) == [-1, -1, -1, 1, 1, 1]


# --- seed 002, eq. (11) ---------------------------------------------------------------------------
def test_seed_002_quartic_is_eq_11_up_to_a_constant():
    x0, x1, x2, x3 = isp.image_symbols()
    eq11 = (-18944*x0**3*x2 + 15360*x0**2*x1*x2 + 274944*x0**2*x1*x3 - 25600*x0**2*x2**2
            - 23040*x0**2*x2*x3 + 180224*x0*x1**2*x2 + 803840*x0*x1**2*x3 - 23040*x0*x1*x2**2
            - 23040*x0*x1*x3**2 - 113664*x1**3*x3 - 23040*x1**2*x2*x3 + 25600*x1**2*x3**2)
    S = isp.examples.stigger_husty().singularity_polynomial().as_expr()
    k = sp.Poly(S, x0, x1, x2, x3).coeff_monomial(x0**3 * x2) / sp.Integer(-18944)
    assert k != 0 and not k.free_symbols
    assert sp.expand(S - k * eq11) == 0


# --- exact concurrency for random 3-RPR designs built around a concurrent configuration --------
def _rational(rng, lo=-5, hi=5, den=7):
    return sp.Rational(int(rng.integers(lo * den, hi * den)), den)


def _design_through(rng, t, d, meet=None, direction=None):
    """A random 3-RPR whose legs, at the pose (tan(phi/2) = t, translation d), all pass through
    the point ``meet`` (or are all parallel to ``direction``). Exact rationals."""
    c, s = (1 - t**2) / (1 + t**2), 2 * t / (1 + t**2)
    legs = []
    for _ in range(3):
        p = sp.Matrix([_rational(rng), _rational(rng)])
        P = sp.Matrix([[c, -s], [s, c]]) * p + sp.Matrix(d)
        lam = _rational(rng, 1, 3)
        A = P + lam * ((sp.Matrix(meet) - P) if meet is not None else sp.Matrix(direction))
        legs.append(isp.RPR(base=tuple(A), platform=tuple(p)))
    return isp.PlanarParallel(legs)


@pytest.mark.slow
def test_quartic_vanishes_exactly_at_constructed_concurrent_and_parallel_poses(rng):
    checked = 0
    for k in range(8):
        t, d = _rational(rng, -2, 2), (_rational(rng), _rational(rng))
        kw = {"meet": (_rational(rng), _rational(rng))} if k % 2 == 0 else \
             {"direction": (_rational(rng, 1, 3), _rational(rng))}
        try:
            m = _design_through(rng, t, d, **kw)
        except isp.DegenerateDesignError:
            continue
        S = m.singularity_polynomial()
        X = (1, t, (t * d[0] - d[1]) / 2, (d[0] + t * d[1]) / 2)   # exact image point of the pose
        assert S.eval(X) == 0
        # a nearby non-concurrent pose (exactly checked by the Euclidean criterion) is regular
        X2 = (1, t + sp.Rational(1, 10), X[2], X[3])
        pose2 = isp.pose_of(np.array([float(v) for v in X2]))
        if abs(concurrency(m, pose2)) > 1e-6:
            assert S.eval(X2) != 0
        checked += 1
    assert checked >= 6


# --- Jx, Jq and the singularity types (seed 003) ----------------------------------------------------
def test_seed_003_jacobians_match_the_corrected_formulas(rng):
    R, r = 2.0, 1.0
    m = isp.examples.collinear_3rpr(2, 1)
    P = np.column_stack([rng.uniform(-1, 1, 50), rng.uniform(0.5, 2, 50), rng.uniform(-1, 1, 50)])
    jac = m.jacobians(P)
    x, y, th = P.T
    c, s = np.cos(th), np.sin(th)
    Jx = np.stack([np.stack([2 * (x - r * c + R), 2 * (y - r * s), 2 * r * ((x + R) * s - y * c)], -1),
                   np.stack([2 * x, 2 * y, 0 * x], -1),
                   np.stack([2 * (x + r * c - R), 2 * (y + r * s), 2 * r * ((R - x) * s + y * c)], -1)], 1)
    assert np.allclose(jac.Jx, Jx, rtol=1e-12, atol=1e-12)
    assert np.allclose(jac.det_Jx, 16 * R * r * s * (R * y + r * x * s - r * y * c), rtol=1e-10)
    d = np.stack([np.hypot(x - r * c + R, y - r * s), np.hypot(x, y), np.hypot(x + r * c - R, y + r * s)], -1)
    assert np.allclose(np.abs(np.diagonal(jac.Jq, axis1=1, axis2=2)), 2 * d, rtol=1e-12)
    assert np.allclose(np.einsum("nij,njk->nik", jac.Jq, jac.J), jac.Jx, rtol=1e-10, atol=1e-10)


def test_zero_length_leg_is_an_inverse_kinematic_singularity():
    m = isp.examples.collinear_3rpr(2, 1)
    jac = m.jacobians([0.0, 0.0, 0.4])             # leg 2 (B = E = origin) has length 0
    assert jac.inverse_kinematic and jac.det_Jq == 0
    # with the squared-length constraint the leg's row of Jx vanishes too (seed 003: [2x, 2y, 0])
    assert np.all(jac.Jx[1] == 0) and jac.kind == "both"


def _rrr_design():
    return isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                               isp.RPR(base=(6, 0), platform=(1, 0)),
                               isp.RPR(base=(2, 5), platform=(0, 1))])


def test_stretched_rrr_leg_is_inverse_kinematic_only():
    m = _rrr_design()
    a = 0.7                                          # leg 0 fully stretched along angle a
    pose = [5 * np.cos(a), 5 * np.sin(a), 0.3]
    jac = m.jacobians(pose)
    assert jac.inverse_kinematic and not jac.direct_kinematic
    assert jac.kind == "inverse-kinematic"


def test_direct_kinematic_singularity_found_by_bisection_on_a_euclidean_criterion(rng):
    m = isp.examples.general_3rpr()
    a, b = np.array([0.0, 0.0, 0.0]), None
    for _ in range(100):
        a = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-1, 1)])
        b = a + rng.normal(size=3)
        if concurrency(m, a) * concurrency(m, b) < 0:
            break
    ca = concurrency(m, a)
    for _ in range(60):
        c = (a + b) / 2
        a, b = (c, b) if concurrency(m, c) * ca > 0 else (a, c)
    jac = m.jacobians((a + b) / 2)
    assert jac.kind == "direct-kinematic"


@pytest.mark.slow
def test_image_space_surface_is_the_direct_kinematic_one(rng):
    """S(image_point(pose)) = -16 det Jx(pose) when q is the inverse kinematics (any design)."""
    for m in (isp.examples.general_3rpr(), isp.examples.stigger_husty(), _rrr_design()):
        for S in m.singularity_surfaces():
            P = np.column_stack([rng.uniform(-3, 3, 200), rng.uniform(-3, 3, 200), rng.uniform(-3, 3, 200)])
            wm = tuple(0 if w is None else w for w in (S.working_modes or (0, 0, 0)))
            jac = m.jacobians(P, working_modes=wm)
            v = S.at_poses(P)
            ok = np.isfinite(v) & np.isfinite(jac.det_Jx) & (np.abs(jac.det_Jx) > 1e-6)
            assert ok.sum() > 50
            assert np.allclose(v[ok], -16 * jac.det_Jx[ok], rtol=1e-8)


# --- labelled surfaces ---------------------------------------------------------------------------------
@pytest.mark.slow
def test_working_mode_surfaces_are_labelled_and_their_gradient_is_right(rng):
    m = _rrr_design()
    surfaces = m.singularity_surfaces()
    assert [S.working_modes for S in surfaces] == [(0, None, None), (1, None, None)]
    assert all(S.kind == "working-mode" and S.eliminated == (0,) for S in surfaces)
    X = isp.image_point(np.column_stack([rng.uniform(-1, 4, 40), rng.uniform(-1, 4, 40), rng.uniform(-1, 1, 40)]))
    for S in surfaces:
        v, G = S.value_and_gradient(X)
        ok = np.isfinite(v)
        h = 1e-6
        fd = np.stack([(S(X + h * e) - S(X - h * e)) / (2 * h) for e in np.eye(4)], -1)
        assert np.allclose(G[ok], fd[ok], rtol=1e-5, atol=1e-5 * np.abs(G[ok]).max())
    # the surface at given joint values agrees with the working-mode one where q is that IK
    pose = np.array([2.0, 1.5, 0.3])
    q = m.inverse_kinematics(pose, (1, 0, 0))
    Sq = m.singularity_surface(q=q)
    assert Sq.kind == "given-joints"
    x = isp.image_point(pose)
    assert np.isclose(float(Sq(x)), float(surfaces[1](x)), rtol=1e-9)


def test_surface_requests_that_cannot_be_answered_raise_clearly():
    m = _rrr_design()
    with pytest.raises(isp.InputError, match="depends on the joint values"):
        m.singularity_surface()
    with pytest.raises(isp.InputError, match="not both"):
        m.singularity_surface(q=(0.1, 4, 4), working_modes=(0, 0, 0))
    with pytest.raises(isp.InputError, match=r"working_modes\[0\]"):
        m.singularity_surface(working_modes=(2, 0, 0))
    with pytest.raises(isp.InputError, match="section"):
        m.singularity_surfaces()[0].section(0.3)
    with pytest.raises(isp.InputError, match="X"):
        isp.examples.general_3rpr().singularity_surface()([1.0, 2.0])


def test_batch_aspects_are_the_sign_of_the_surface():
    m = isp.examples.stigger_husty()
    S = m.singularity_surface()
    Q = m.q_example_float * np.array([[1.0, 1.0, 1.0], [1.01, 0.99, 1.0], [0.98, 1.0, 1.02]])
    res = m.direct_kinematics_batch(Q)
    sign = np.sign(S(res.image_points[res.valid]))
    assert np.array_equal(sign, res.aspect[res.valid])


# --- fixed-orientation conics -------------------------------------------------------------------------
def test_conic_coefficients_evaluate_the_surface(rng):
    for m in (isp.examples.general_3rpr(), isp.examples.stigger_husty()):
        S = m.singularity_surface()
        for phi in rng.uniform(-3, 3, 5):
            con = S.section(phi)
            xy = rng.uniform(-10, 10, (20, 2))
            ref = S.at_poses(np.column_stack([xy, np.full(20, phi)]))
            assert np.allclose(con(xy[:, 0], xy[:, 1]), ref, rtol=1e-9, atol=1e-9 * np.abs(ref).max())


def test_exact_and_float_conic_types_agree():
    S = isp.examples.stigger_husty().singularity_surface()
    for t in (sp.Rational(1, 3), sp.Rational(-2), sp.Rational(5, 4)):
        exact = S.section(2 * sp.atan(t))
        assert exact.exact
        assert S.section(float(2 * sp.atan(t))).type == exact.type


def test_conic_types_of_the_collinear_3rpr_follow_seed_003():
    """det Jx = 16 R r sin(theta) (R y + r x sin(theta) - r y cos(theta)): a line at fixed theta,
    identically zero at theta = 0."""
    S = isp.examples.collinear_3rpr(2, 1).singularity_surface()
    assert S.section(sp.pi / 3).type == "line"
    assert S.section(sp.Integer(0)).type == "plane"


def test_conic_classifier_on_textbook_conics():
    from imagespace.singular.conics import conic_type, exact_sign
    cases = {"ellipse": (1, 0, 2, 0, 0, -1), "imaginary ellipse": (1, 0, 1, 0, 0, 1),
             "parabola": (1, 0, 0, 0, -1, 0), "hyperbola": (1, 0, -1, 0, 0, -1),
             "intersecting lines": (1, 0, -1, 0, 0, 0), "parallel lines": (1, 0, 0, 0, 0, -1),
             "coincident lines": (1, 2, 1, 0, 0, 0), "imaginary parallel lines": (1, 0, 0, 0, 0, 1),
             "point": (1, 0, 1, 0, 0, 0), "line": (0, 0, 0, 1, 1, 0), "empty": (0, 0, 0, 0, 0, 3),
             "plane": (0, 0, 0, 0, 0, 0)}
    for name, co in cases.items():
        # a rotated, shifted, scaled copy has the same type
        assert conic_type([sp.Integer(c) for c in co], exact_sign) == name
