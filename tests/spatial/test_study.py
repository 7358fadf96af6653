"""Study's kinematic map (issue 18, "Study's map"), checked against things written here.

The references are independent of :mod:`imagespace.spatial.study`'s quaternion formulas: rotations
come from Rodrigues' formula (axis-angle), displacements from 4 x 4 homogeneous matrices, the unit
quaternion of an axis-angle rotation from ``(cos(theta/2), sin(theta/2) u)``, and the symbolic face
is compared with the numeric face at exact rationals.
"""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from imagespace.exceptions import InputError
from imagespace.spatial.study import (compose_study, inverse_study, matrix_from_quaternion, normalize_study,
                                      quaternion_conjugate, quaternion_from_matrix, quaternion_multiply,
                                      rotation_matrix, study_condition, study_point, study_symbols,
                                      study_to_planar, transform_matrix, transform_points, translation)

TOL = 1e-12


# --------------------------------------------------------------------------- independent references

def rodrigues(axis, angle):
    """``R = I + sin(a) K + (1 - cos(a)) K^2``, ``K`` the cross-product matrix of the unit axis."""
    u = np.asarray(axis, dtype=float)
    u = u / np.linalg.norm(u)
    K = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def axis_angle_quaternion(axis, angle):
    u = np.asarray(axis, dtype=float)
    u = u / np.linalg.norm(u)
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * u])


def homogeneous(R, t):
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = t
    return T


def random_axis(rng):
    while True:
        u = rng.normal(size=3)
        if np.linalg.norm(u) > 1e-3:
            return u / np.linalg.norm(u)


def random_pose(rng):
    """(axis, angle, R by Rodrigues, t)."""
    u, a, t = random_axis(rng), rng.uniform(-np.pi, np.pi), rng.normal(scale=3.0, size=3)
    return u, a, rodrigues(u, a), t


def same_displacement(s, R, t, tol=TOL):
    scale = 1.0 + np.abs(t).max()
    return (np.allclose(rotation_matrix(s), R, atol=tol, rtol=0)
            and np.allclose(translation(s), t, atol=tol * scale, rtol=0))


# hypothesis strategies: an axis away from zero, any angle, a translation, a non-zero scale
coord = st.floats(-1.0, 1.0, allow_nan=False)
axis_st = st.tuples(coord, coord, coord).filter(lambda v: np.linalg.norm(v) > 1e-2)
angle_st = st.floats(-np.pi, np.pi, allow_nan=False)
trans_st = st.tuples(*[st.floats(-20.0, 20.0, allow_nan=False)] * 3)
scale_st = st.one_of(st.floats(1e-3, 1e3), st.floats(-1e3, -1e-3))


# --------------------------------------------------------------------------- properties (hypothesis)

@pytest.mark.slow
@given(axis_st, angle_st, trans_st)
@settings(max_examples=150, deadline=None)
def test_study_point_of_quaternion_and_matrix_inverts(axis, angle, t):
    R, t = rodrigues(axis, angle), np.array(t)
    q = axis_angle_quaternion(axis, angle)
    for rot in (q, R):
        s = study_point(rot, t)
        # on Study's quadric, written out here
        assert abs(s[:4] @ s[4:]) <= TOL * (1 + np.abs(t).max())
        assert abs(study_condition(s)) <= TOL * (1 + np.abs(t).max())
        # normalised: x . x = 1, first non-zero of x positive
        assert np.isclose(s[:4] @ s[:4], 1.0, atol=1e-14)
        assert s[:4][np.flatnonzero(s[:4])[0]] > 0
        assert same_displacement(s, R, t, tol=1e-11)
    # quaternion and matrix input give the same point (up to the sign of a half-turn's x0 ~ 0)
    a, b = study_point(q, t), study_point(R, t)
    assert np.allclose(a, b, atol=1e-10) or (abs(a[0]) < 1e-10 and np.allclose(a, -b, atol=1e-10))


@pytest.mark.slow
@given(st.tuples(*[st.floats(-5.0, 5.0, allow_nan=False)] * 4).filter(lambda v: np.linalg.norm(v) > 1e-2))
@settings(max_examples=150, deadline=None)
def test_rotation_matrix_is_orthogonal_with_det_one_for_any_x(x):
    s = np.concatenate([x, np.arange(4.0)])       # y is irrelevant for R
    R = rotation_matrix(s)
    assert np.allclose(R.T @ R, np.eye(3), atol=1e-12)
    assert np.isclose(np.linalg.det(R), 1.0, atol=1e-12)
    # and it is Rodrigues' rotation of the quaternion's axis and angle
    x = np.array(x, dtype=float)
    v = x[1:]
    if np.linalg.norm(v) > 1e-6:
        angle = 2 * np.arctan2(np.linalg.norm(v), x[0])
        assert np.allclose(R, rodrigues(v, angle), atol=1e-11)


@pytest.mark.slow
@given(axis_st, angle_st, trans_st, axis_st, angle_st, trans_st)
@settings(max_examples=100, deadline=None)
def test_compose_is_the_product_of_homogeneous_matrices(ua, aa, ta, ub, ab, tb):
    Ta, Tb = homogeneous(rodrigues(ua, aa), ta), homogeneous(rodrigues(ub, ab), tb)
    sa, sb = study_point(Ta[:3, :3], Ta[:3, 3]), study_point(Tb[:3, :3], Tb[:3, 3])
    T = Ta @ Tb
    s = compose_study(sa, sb)
    assert abs(study_condition(s)) < 1e-10
    assert np.allclose(transform_matrix(s), T, atol=1e-10)
    # first b, then a, on points
    p = np.array([0.3, -1.2, 2.0])
    assert np.allclose(transform_points(s, p), (T @ np.append(p, 1.0))[:3], atol=1e-10)


@given(axis_st, angle_st, trans_st)
@settings(max_examples=100, deadline=None)
def test_inverse_composes_to_the_identity(axis, angle, t):
    s = study_point(rodrigues(axis, angle), t)
    ident = np.array([1.0, 0, 0, 0, 0, 0, 0, 0])
    assert np.allclose(compose_study(s, inverse_study(s)), ident, atol=1e-10)
    assert np.allclose(compose_study(inverse_study(s), s), ident, atol=1e-10)
    assert np.allclose(transform_matrix(inverse_study(s)), np.linalg.inv(homogeneous(rodrigues(axis, angle), t)),
                       atol=1e-10)


@pytest.mark.slow
@given(axis_st, angle_st, trans_st, scale_st)
@settings(max_examples=150, deadline=None)
def test_normalize_keeps_the_displacement_and_fixes_the_sign(axis, angle, t, lam):
    R, t = rodrigues(axis, angle), np.array(t)
    s = study_point(R, t)
    z = lam * s                                      # any non-zero multiple, either sign
    assert same_displacement(z, R, t, tol=1e-10)    # R, t are homogeneous of degree 0
    n = normalize_study(z)
    assert np.isclose(n[:4] @ n[:4], 1.0, atol=1e-14)
    assert n[:4][np.flatnonzero(n[:4])[0]] > 0
    assert np.allclose(n, s, atol=1e-12 * (1 + np.abs(t).max()))
    assert same_displacement(n, R, t, tol=1e-10)


# --------------------------------------------------------------------------- seeded numpy batches

def test_batches_match_row_by_row_and_have_the_documented_shapes(rng):
    n = 40
    poses = [random_pose(rng) for _ in range(n)]
    Rs = np.array([p[2] for p in poses])
    ts = np.array([p[3] for p in poses])
    qs = np.array([axis_angle_quaternion(p[0], p[1]) for p in poses])
    S = study_point(Rs, ts)
    assert S.shape == (n, 8)
    assert study_point(qs, ts).shape == (n, 8)
    assert rotation_matrix(S).shape == (n, 3, 3)
    assert translation(S).shape == (n, 3)
    assert transform_matrix(S).shape == (n, 4, 4)
    assert study_condition(S).shape == (n,)
    assert normalize_study(S).shape == (n, 8)
    assert compose_study(S, S[::-1]).shape == (n, 8)
    assert inverse_study(S).shape == (n, 8)
    assert matrix_from_quaternion(qs).shape == (n, 3, 3)
    assert quaternion_from_matrix(Rs).shape == (n, 4)
    assert quaternion_multiply(qs, qs).shape == (n, 4)
    assert np.allclose(rotation_matrix(S), Rs, atol=1e-12)
    assert np.allclose(translation(S), ts, atol=1e-11)
    assert np.allclose(matrix_from_quaternion(qs), Rs, atol=1e-12)
    C = compose_study(S, S[::-1])
    for i in range(n):
        assert np.array_equal(S[i], study_point(Rs[i], ts[i]))
        assert np.allclose(C[i], compose_study(S[i], S[n - 1 - i]), atol=1e-15)
        T = homogeneous(Rs[i], ts[i]) @ homogeneous(Rs[n - 1 - i], ts[n - 1 - i])
        assert np.allclose(transform_matrix(C[i]), T, atol=1e-10)
    # broadcasting one rotation over many translations, and one point against a batch
    B = study_point(qs[0], ts)
    assert B.shape == (n, 8)
    assert np.allclose(rotation_matrix(B), Rs[0], atol=1e-12)
    assert compose_study(S[0], S).shape == (n, 8)


def test_quaternion_multiply_is_the_rotation_product(rng):
    for _ in range(30):
        (u1, a1, R1, _), (u2, a2, R2, _) = random_pose(rng), random_pose(rng)
        q = quaternion_multiply(axis_angle_quaternion(u1, a1), axis_angle_quaternion(u2, a2))
        assert np.allclose(matrix_from_quaternion(q), R1 @ R2, atol=1e-12)
    # i j = k, j i = -k, conjugate
    assert np.array_equal(quaternion_multiply([0, 0, 1, 0], [0, 1, 0, 0]), [0, 0, 0, -1])
    assert np.array_equal(quaternion_conjugate([1, 2, 3, 4]), [1, -2, -3, -4])


def test_half_turns_round_trip(rng):
    for _ in range(40):
        u, t = random_axis(rng), rng.normal(scale=3.0, size=3)
        R = rodrigues(u, np.pi)
        q = np.concatenate([[0.0], u])              # x0 = 0 exactly
        for rot in (q, R):
            s = study_point(rot, t)
            assert abs(s[0]) < 1e-12
            assert same_displacement(s, R, t, tol=1e-11)
            assert abs(study_condition(s)) < 1e-12
            back = study_point(rotation_matrix(s), translation(s))
            assert np.allclose(back, s, atol=1e-11)
        # the exact half-turn: x0 is exactly 0, the sign is fixed by x1 (or x2, x3)
        s = study_point(q, t)
        assert s[0] == 0.0
        assert s[1:4][np.flatnonzero(s[1:4])[0]] > 0
        assert np.allclose(s[1:4], u * np.sign(u[np.flatnonzero(u)[0]]), atol=1e-15)
    # axis-aligned half-turns
    for k in range(3):
        R = -np.eye(3)
        R[k, k] = 1.0
        q = quaternion_from_matrix(R)
        assert np.array_equal(q, np.eye(4)[k + 1])
        s = study_point(R, [1.0, 2.0, 3.0])
        assert same_displacement(s, R, [1.0, 2.0, 3.0])


@pytest.mark.parametrize("eps", [1e-2, 1e-5, 1e-8, 1e-11, 1e-14, 0.0, -1e-14, -1e-8, -1e-3])
def test_quaternion_from_matrix_near_pi(rng, eps):
    for _ in range(20):
        u = random_axis(rng)
        angle = np.pi - eps
        R = rodrigues(u, angle)
        q = quaternion_from_matrix(R)
        assert np.isclose(q @ q, 1.0, atol=1e-15)
        assert np.allclose(matrix_from_quaternion(q), R, atol=1e-13)
        ref = axis_angle_quaternion(u, angle)
        assert np.allclose(q, ref, atol=1e-13) or np.allclose(q, -ref, atol=1e-13)
        # the sign convention: the first non-zero entry is positive
        assert q[np.flatnonzero(q)[0]] > 0


def test_quaternion_from_matrix_generic_and_near_identity(rng):
    for angle in [0.0, 1e-12, 1e-6, 0.3, 1.5, 2.5, -0.7]:
        u = random_axis(rng)
        q = quaternion_from_matrix(rodrigues(u, angle))
        ref = axis_angle_quaternion(u, angle)
        assert np.allclose(q, ref if ref[0] > 0 else -ref, atol=1e-13)


# --------------------------------------------------------------------------- the symbolic face

def random_rational(rng, den=17):
    return sp.Rational(int(rng.integers(-40, 41)), int(rng.integers(1, den)))


@pytest.mark.slow
def test_symbolic_face_is_exact():
    """Identities of the symbolic face hold exactly (as rational functions)."""
    q = sp.symbols("q0:4", real=True)
    t = sp.symbols("t1:4", real=True)
    s = study_point(list(q), list(t))
    assert sp.expand(study_condition(list(s))) == 0
    assert [sp.cancel(v - w) for v, w in zip(translation(list(s)), t)] == [0, 0, 0]
    R = rotation_matrix(list(s))
    assert (R.T * R - sp.eye(3)).applyfunc(sp.cancel) == sp.zeros(3, 3)
    assert sp.cancel(R.det()) == 1
    # the symbols of the face
    assert [str(v) for v in study_symbols()] == ["x0", "x1", "x2", "x3", "y0", "y1", "y2", "y3"]


@pytest.mark.slow
def test_symbolic_face_equals_numeric_face_at_rationals(rng):
    q = sp.symbols("q0:4", real=True)
    t = sp.symbols("t1:4", real=True)
    z = study_symbols()
    sym_point = study_point(list(q), list(t))
    sym_R, sym_t = rotation_matrix(list(z)), translation(list(z))
    sym_mat = matrix_from_quaternion(list(q))
    w = sp.symbols("w0:8")
    sym_comp = compose_study(list(z), list(w))
    sym_inv = inverse_study(list(z))
    for _ in range(6):
        qv = [random_rational(rng) for _ in range(4)]
        tv = [random_rational(rng) for _ in range(3)]
        if all(v == 0 for v in qv):
            qv[0] = sp.Integer(1)
        sub = dict(zip(q + t, qv + tv))
        exact = [sym_point[i].xreplace(sub) for i in range(8)]
        assert all(v.is_Rational for v in exact)
        # exact: y = t x / 2 written out with Fractions (Hamilton product of (0, t) and x)
        F = [Fraction(int(v.p), int(v.q)) for v in qv]
        T = [Fraction(int(v.p), int(v.q)) for v in tv]
        y = [(-T[0] * F[1] - T[1] * F[2] - T[2] * F[3]) / 2,
             (T[0] * F[0] + T[1] * F[3] - T[2] * F[2]) / 2,
             (-T[0] * F[3] + T[1] * F[0] + T[2] * F[1]) / 2,
             (T[0] * F[2] - T[1] * F[1] + T[2] * F[0]) / 2]
        assert [Fraction(int(v.p), int(v.q)) for v in exact] == F + y
        # the numeric face at the same (rounded) values: the normalised multiple of the exact point
        num = study_point([float(v) for v in qv], [float(v) for v in tv])
        ex = np.array([float(v) for v in exact])
        assert np.allclose(num, normalize_study(ex), atol=1e-13)
        zsub = dict(zip(z, exact))
        assert np.allclose(np.array(sym_R.xreplace(zsub), dtype=float), rotation_matrix(ex), atol=1e-13)
        assert np.allclose(np.array(list(sym_t.xreplace(zsub)), dtype=float), translation(ex), atol=1e-12)
        assert np.allclose(np.array(sym_mat.xreplace(sub), dtype=float),
                           matrix_from_quaternion([float(v) for v in qv]), atol=1e-13)
        # composition and inverse (the symbolic face is not normalised)
        other = [random_rational(rng) for _ in range(8)]
        csub = dict(zip(list(z) + list(w), exact + other))
        comp = np.array([float(v.xreplace(csub)) for v in sym_comp])
        assert np.allclose(normalize_study(comp),
                           compose_study(ex, np.array([float(v) for v in other])), atol=1e-12)
        inv = np.array([float(v.xreplace(zsub)) for v in sym_inv])
        assert np.allclose(normalize_study(inv), inverse_study(ex), atol=1e-13)
        assert study_condition(list(exact)) == 0


# --------------------------------------------------------------------------- bad input

NAN8 = [np.nan, 0, 0, 0, 0, 0, 0, 0]


@pytest.mark.parametrize("call, name", [
    (lambda: study_point([np.nan, 0, 0, 0], [0, 0, 0]), "rotation"),
    (lambda: study_point([1, 0, 0, 0], [0, np.inf, 0]), "translation"),
    (lambda: study_point(np.full((3, 3), np.nan), [0, 0, 0]), "rotation"),
    (lambda: study_point([1, 0, 0], [0, 0, 0]), "rotation"),
    (lambda: study_point([1, 0, 0, 0], [0, 0]), "translation"),
    (lambda: study_point(np.zeros((2, 2, 4)), [0, 0, 0]), "rotation"),
    (lambda: study_point(np.tile(np.eye(3), (2, 2, 1, 1)), [0, 0, 0]), "rotation"),
    (lambda: study_point([0, 0, 0, 0], [1, 2, 3]), "rotation"),
    (lambda: study_point(2 * np.eye(3), [0, 0, 0]), "rotation"),                 # not orthogonal
    (lambda: study_point(np.diag([1.0, 1.0, -1.0]), [0, 0, 0]), "rotation"),     # a reflection
    (lambda: study_point(np.array([[1.0, 0.1, 0], [0, 1, 0], [0, 0, 1]]), [0, 0, 0]), "rotation"),
    (lambda: study_point(np.tile([1.0, 0, 0, 0], (2, 1)), np.zeros((3, 3))), "rotation and translation"),
    (lambda: quaternion_from_matrix(np.diag([-1.0, -1.0, -1.0])), "R"),
    (lambda: quaternion_from_matrix(np.eye(4)), "R"),
    (lambda: quaternion_from_matrix(np.eye(3) * np.nan), "R"),
    (lambda: matrix_from_quaternion([0, 0, 0, 0]), "q"),
    (lambda: matrix_from_quaternion([1, 0, 0]), "q"),
    (lambda: rotation_matrix(NAN8), "s"),
    (lambda: rotation_matrix(np.zeros(8)), "s"),
    (lambda: rotation_matrix(np.ones(7)), "s"),
    (lambda: translation([0, 0, 0, 0, 1, 2, 3, 4]), "s"),
    (lambda: translation(np.ones((2, 2, 8))), "s"),
    (lambda: transform_matrix([0, 0, 0, 0, 0, 0, 0, 1]), "s"),
    (lambda: normalize_study([0, 0, 0, 0, 1, 0, 0, 0]), "s"),
    (lambda: normalize_study(NAN8), "s"),
    (lambda: study_condition([1, 2, 3]), "s"),
    (lambda: compose_study(np.zeros(8), [1, 0, 0, 0, 0, 0, 0, 0]), "a"),
    (lambda: compose_study([1, 0, 0, 0, 0, 0, 0, 0], NAN8), "b"),
    (lambda: inverse_study(np.zeros(8)), "s"),
    (lambda: inverse_study(np.ones(9)), "s"),
    (lambda: quaternion_multiply([1, 0, 0], [1, 0, 0, 0]), "p"),
    (lambda: quaternion_multiply([1, 0, 0, 0], [np.nan, 0, 0, 0]), "q"),
    (lambda: quaternion_multiply(np.ones((2, 4)), np.ones((3, 4))), "p and q"),
    (lambda: compose_study(np.ones((2, 8)), np.ones((3, 8))), "a and b"),
    (lambda: study_to_planar([0, 0, 0, 0, 0, 1, 0, 0]), "s"),
])
def test_bad_input_raises_input_error_naming_the_parameter(call, name):
    with pytest.raises(InputError) as info:
        call()
    assert isinstance(info.value, ValueError)
    msg = str(info.value)
    assert msg.startswith(name + " "), msg


@pytest.mark.parametrize("call", [
    lambda: study_point("abc", [0, 0, 0]),
    lambda: study_point([[1, 0], [0, 1, 0]], [0, 0, 0]),
    lambda: study_point([1, 0, 0, 0], ["1", "2", "3"]),
    lambda: rotation_matrix(None),
    lambda: quaternion_from_matrix("R"),
    lambda: quaternion_from_matrix(np.eye(3), tolerances=1e-3),
])
def test_wrong_kinds_raise_type_error(call):
    with pytest.raises(TypeError):
        call()
