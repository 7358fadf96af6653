"""Constraint quadrics in Study coordinates (issue 18, "Constraint quadrics").

Each quadric is checked against its Euclidean condition at random poses, with the rotation from
Rodrigues' formula and the translation given (both written here), at Study points scaled by a random
factor (the identities are homogeneous of degree 2 in the Study point, ``N = x . x`` not 1). The
sphere condition's derivation is checked exactly with sympy; the plane and line quadrics' float
entries are compared with exact Fraction arithmetic written here.
"""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from imagespace.exceptions import InputError
from imagespace.spatial.quadrics import (form_matrix, point_on_line_quadrics, point_on_plane_quadric,
                                         quadric_value, sphere_quadric, sphere_quadric_symbolic,
                                         study_quadric_matrix)
from imagespace.spatial.study import study_point, study_symbols


def rodrigues(axis, angle):
    u = np.asarray(axis, dtype=float)
    u = u / np.linalg.norm(u)
    K = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def random_pose(rng):
    u = rng.normal(size=3)
    return rodrigues(u, rng.uniform(-np.pi, np.pi)), rng.normal(scale=2.0, size=3)


def scaled_point(rng, R, t):
    """A Study point of (R, t) times a random non-zero factor, and N = x . x."""
    lam = rng.choice([-1.0, 1.0]) * rng.uniform(0.2, 5.0)
    z = lam * study_point(R, t)
    return z, z[:4] @ z[:4]


# --------------------------------------------------------------------------- sphere

def test_sphere_quadric_is_the_euclidean_condition_at_random_poses(rng):
    for _ in range(200):
        a, b = rng.normal(scale=3.0, size=3), rng.normal(scale=2.0, size=3)
        L = rng.uniform(0.0, 6.0)
        R, t = random_pose(rng)
        z, N = scaled_point(rng, R, t)
        Q = sphere_quadric(a, b, L)
        assert Q.shape == (8, 8) and np.array_equal(Q, Q.T)
        X = R @ b + t
        expected = N * ((X - a) @ (X - a) - L * L)
        scale = N * ((np.abs(X).max() + np.abs(a).max()) ** 2 + L * L + 1)
        assert abs(z @ Q @ z - expected) <= 1e-12 * scale
        assert abs(quadric_value(Q, z) - expected) <= 1e-12 * scale


def test_sphere_quadric_vanishes_exactly_where_the_leg_fits(rng):
    for _ in range(50):
        a, b = rng.normal(size=3), rng.normal(size=3)
        R, t = random_pose(rng)
        z, N = scaled_point(rng, R, t)
        L = np.linalg.norm(R @ b + t - a)
        assert abs(z @ sphere_quadric(a, b, L) @ z) <= 1e-12 * N * (1 + L * L + np.abs(a).max() ** 2)


def test_sphere_quadric_batch_matches_single(rng):
    n = 12
    A, B, L = rng.normal(size=(n, 3)), rng.normal(size=(n, 3)), rng.uniform(0.5, 3.0, size=n)
    Qs = sphere_quadric(A, B, L)
    assert Qs.shape == (n, 8, 8)
    for i in range(n):
        assert np.array_equal(Qs[i], sphere_quadric(A[i], B[i], L[i]))
    # broadcasting one base point over many platform points
    assert sphere_quadric(A[0], B, L).shape == (n, 8, 8)
    R, t = random_pose(rng)
    z = study_point(R, t)
    vals = quadric_value(Qs, z)
    assert vals.shape == (n,)
    X = B @ R.T + t
    assert np.allclose(vals, ((X - A) ** 2).sum(axis=1) - L ** 2, atol=1e-11)


@pytest.mark.slow
def test_sphere_form_identity_exactly():
    """``form * N == |N X - N a|^2 - N^2 L^2 + 4 (x . y)^2`` as polynomials (a, b, L symbolic).

    ``N X = R_num b + 2 vec(y x~)`` is written here from the textbook rotation matrix of a
    non-unit quaternion; the identity shows the form equals ``N (|X - a|^2 - L^2)`` exactly on
    Study's quadric (and by how much off it).
    """
    z = study_symbols()
    x0, x1, x2, x3, y0, y1, y2, y3 = z
    Q, syms = sphere_quadric_symbolic()
    a, b, L = sp.Matrix(syms[:3]), sp.Matrix(syms[3:6]), syms[6]
    zz = sp.Matrix(z)
    form = sp.expand((zz.T * Q * zz)[0, 0])
    N = x0 ** 2 + x1 ** 2 + x2 ** 2 + x3 ** 2
    Rn = sp.Matrix([[x0**2 + x1**2 - x2**2 - x3**2, 2 * (x1 * x2 - x0 * x3), 2 * (x1 * x3 + x0 * x2)],
                    [2 * (x1 * x2 + x0 * x3), x0**2 - x1**2 + x2**2 - x3**2, 2 * (x2 * x3 - x0 * x1)],
                    [2 * (x1 * x3 - x0 * x2), 2 * (x2 * x3 + x0 * x1), x0**2 - x1**2 - x2**2 + x3**2]])
    # vec(y x~) for x~ = (x0, -xv): x0 yv - y0 xv + xv cross yv
    xv, yv = sp.Matrix([x1, x2, x3]), sp.Matrix([y1, y2, y3])
    T = 2 * (x0 * yv - y0 * xv + xv.cross(yv))
    NX = Rn * b + T
    D = NX - N * a
    xy = x0 * y0 + x1 * y1 + x2 * y2 + x3 * y3
    assert sp.expand(form * N - (D.dot(D) - N ** 2 * L ** 2) - 4 * xy ** 2) == 0
    # and so, modulo Study's quadric (x0 y0 = -(x1 y1 + x2 y2 + x3 y3)), form N - N^2 (..) vanishes
    assert sp.reduced(sp.expand(form * N - (D.dot(D) - N ** 2 * L ** 2)), [xy], *z)[1] == 0
    # the y.y part is 4 y.y, independent of the geometry
    assert Q[4:, 4:] == 4 * sp.eye(4)


def test_difference_of_two_sphere_quadrics_is_linear_in_y(rng):
    for _ in range(20):
        Q1 = sphere_quadric(rng.normal(size=3), rng.normal(size=3), rng.uniform(1, 3))
        Q2 = sphere_quadric(rng.normal(size=3), rng.normal(size=3), rng.uniform(1, 3))
        D = Q1 - Q2
        assert np.array_equal(D[4:, 4:], np.zeros((4, 4)))
        assert np.any(D[:4, 4:] != 0)
    # symbolically, for any two legs
    Q, syms = sphere_quadric_symbolic()
    other = sp.symbols("c1:8")
    D = Q - Q.subs(dict(zip(syms, other)))
    assert D[4:, 4:].applyfunc(sp.expand) == sp.zeros(4, 4)


def test_sphere_symbolic_face_equals_numeric_face(rng):
    Q, syms = sphere_quadric_symbolic()
    for _ in range(5):
        vals = [sp.Rational(int(rng.integers(-30, 31)), int(rng.integers(1, 9))) for _ in range(6)]
        L = sp.Rational(int(rng.integers(1, 40)), int(rng.integers(1, 9)))
        sym = sphere_quadric(vals[:3], vals[3:], L)
        assert sym == Q.subs(dict(zip(syms, vals + [L])))
        num = sphere_quadric([float(v) for v in vals[:3]], [float(v) for v in vals[3:]], float(L))
        assert np.allclose(np.array(sym.tolist(), dtype=float), num, rtol=1e-14, atol=1e-12)


@pytest.mark.slow
def test_sphere_quadric_float_entries_within_a_few_ulps_of_exact(rng):
    """The compiled numeric face against the exact rational matrix of the same float input."""
    Q, syms = sphere_quadric_symbolic()
    for _ in range(10):
        a, b, L = rng.normal(scale=3, size=3), rng.normal(size=3), rng.uniform(0.5, 5)
        num = sphere_quadric(a, b, L)
        exact = Q.subs(dict(zip(syms, [sp.Rational(float(v)) for v in [*a, *b, L]])))
        mag = (np.abs(a).max() + np.abs(b).max() + L) ** 2
        for i in range(8):
            for j in range(8):
                assert abs(Fraction(float(num[i, j])) - Fraction(int(exact[i, j].p), int(exact[i, j].q))) \
                    <= Fraction(8 * np.finfo(float).eps * mag)


# --------------------------------------------------------------------------- plane and line

@pytest.mark.slow
def test_point_on_plane_quadric_at_random_poses(rng):
    # 15 designs x 5 poses (each matrix is derived with sympy: ~0.1 s a call)
    for _ in range(15):
        b, c, n = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
        Q = point_on_plane_quadric(b, c, n)
        assert Q.shape == (8, 8) and np.array_equal(Q, Q.T)
        for R, t in [random_pose(rng) for _ in range(5)]:
            z, N = scaled_point(rng, R, t)
            expected = N * (n @ (R @ b + t - c))
            assert abs(z @ Q @ z - expected) <= 1e-12 * N * (1 + np.abs(t).max()) * (1 + np.abs(n).max()) * 4
            # on the plane: move the translation so that b lands on it
            t2 = t - (n @ (R @ b + t - c)) / (n @ n) * n
            z2, N2 = scaled_point(rng, R, t2)
            assert abs(z2 @ Q @ z2) <= 1e-11 * N2 * (1 + np.abs(t2).max()) * (1 + np.abs(n).max())


@pytest.mark.slow
def test_point_on_line_quadrics_at_random_poses(rng):
    for _ in range(12):
        b, c, d = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
        Qs = point_on_line_quadrics(b, c, d)
        assert Qs.shape == (3, 8, 8)
        for R, t in [random_pose(rng) for _ in range(5)]:
            z, N = scaled_point(rng, R, t)
            expected = N * np.cross(R @ b + t - c, d)
            got = np.array([z @ Q @ z for Q in Qs])
            assert np.allclose(got, expected, atol=1e-11 * N * (1 + np.abs(t).max()) * (1 + np.abs(d).max()))
            assert np.allclose(quadric_value(Qs, z), got, atol=1e-12 * N * (1 + np.abs(t).max()))
            # b on the line: t chosen so that R b + t = c + s d
            t2 = c + rng.normal() * d - R @ b
            z2, N2 = scaled_point(rng, R, t2)
            assert np.allclose([z2 @ Q @ z2 for Q in Qs], 0.0, atol=1e-11 * N2 * (1 + np.abs(t2).max()))


def test_point_on_line_axis_parallel_direction_gives_a_zero_quadric():
    Qs = point_on_line_quadrics([1.0, 2.0, 3.0], [0.0, 0.0, 0.0], [0.0, 0.0, 1.0])
    assert np.array_equal(Qs[2], np.zeros((8, 8)))      # (V x e_z)_z = 0 identically
    assert np.any(Qs[0] != 0) and np.any(Qs[1] != 0)


# exact Fraction evaluation of the conditions, written here, and the exact quadric matrix by polarisation

def _exact_NX(b, z):
    """``N X = R_num b + 2 vec(y x~)`` with Fractions."""
    x0, x1, x2, x3, y0, y1, y2, y3 = z
    Rn = [[x0*x0 + x1*x1 - x2*x2 - x3*x3, 2 * (x1*x2 - x0*x3), 2 * (x1*x3 + x0*x2)],
          [2 * (x1*x2 + x0*x3), x0*x0 - x1*x1 + x2*x2 - x3*x3, 2 * (x2*x3 - x0*x1)],
          [2 * (x1*x3 - x0*x2), 2 * (x2*x3 + x0*x1), x0*x0 - x1*x1 - x2*x2 + x3*x3]]
    xv, yv = (x1, x2, x3), (y1, y2, y3)
    cr = (xv[1] * yv[2] - xv[2] * yv[1], xv[2] * yv[0] - xv[0] * yv[2], xv[0] * yv[1] - xv[1] * yv[0])
    return [sum(Rn[i][j] * b[j] for j in range(3)) + 2 * (x0 * yv[i] - y0 * xv[i] + cr[i]) for i in range(3)]


def _polarise(f):
    E = [[Fraction(int(i == k)) for k in range(8)] for i in range(8)]
    diag = [f(E[i]) for i in range(8)]
    M = [[None] * 8 for _ in range(8)]
    for i in range(8):
        for j in range(8):
            if i == j:
                M[i][j] = diag[i]
            else:
                M[i][j] = (f([E[i][k] + E[j][k] for k in range(8)]) - diag[i] - diag[j]) / 2
    return M


def test_plane_quadric_float_entries_are_correctly_rounded(rng):
    for _ in range(5):
        b, c, n = rng.normal(size=3) * 7, rng.normal(size=3) / 3, rng.normal(size=3) * 1e3
        Q = point_on_plane_quadric(b, c, n)
        B, C, Nn = ([Fraction(float(v)) for v in w] for w in (b, c, n))

        def f(z):
            NX = _exact_NX(B, z)
            N = sum(v * v for v in z[:4])
            return sum(Nn[i] * NX[i] for i in range(3)) - sum(Nn[i] * C[i] for i in range(3)) * N
        M = _polarise(f)
        for i in range(8):
            for j in range(8):
                assert Q[i, j] == float(M[i][j]), (i, j)


@pytest.mark.slow
def test_line_quadrics_float_entries_are_correctly_rounded(rng):
    for _ in range(3):
        b, c, d = rng.normal(size=3) * 5, rng.normal(size=3) / 7, rng.normal(size=3) * 3
        Qs = point_on_line_quadrics(b, c, d)
        B, C, D = ([Fraction(float(v)) for v in w] for w in (b, c, d))
        for k in range(3):
            def f(z, k=k):
                NX = _exact_NX(B, z)
                N = sum(v * v for v in z[:4])
                V = [NX[i] - C[i] * N for i in range(3)]
                cross = [V[1] * D[2] - V[2] * D[1], V[2] * D[0] - V[0] * D[2], V[0] * D[1] - V[1] * D[0]]
                return cross[k]
            M = _polarise(f)
            for i in range(8):
                for j in range(8):
                    assert Qs[k, i, j] == float(M[i][j]), (k, i, j)


def test_study_quadric_matrix_and_form_matrix():
    S = study_quadric_matrix()
    z = sp.Matrix(study_symbols())
    x0, x1, x2, x3, y0, y1, y2, y3 = study_symbols()
    assert sp.expand((z.T * sp.Matrix(S.tolist()).applyfunc(sp.nsimplify) * z)[0, 0]) == \
        x0 * y0 + x1 * y1 + x2 * y2 + x3 * y3
    M = form_matrix(3 * x0 * y1 - x2 ** 2)
    assert sp.expand((z.T * M * z)[0, 0]) == 3 * x0 * y1 - x2 ** 2 and M == M.T
    assert form_matrix(sp.Integer(0)) == sp.zeros(8, 8)


@given(st.tuples(*[st.floats(-3, 3, allow_nan=False)] * 8))
@settings(max_examples=100, deadline=None)
def test_quadric_value_is_the_bilinear_form(v):
    z = np.array(v)
    S = study_quadric_matrix()
    assert np.isclose(quadric_value(S, z), z[:4] @ z[4:], atol=1e-12)


# --------------------------------------------------------------------------- bad input

@pytest.mark.parametrize("call, name", [
    (lambda: sphere_quadric([0, 0, np.nan], [0, 0, 0], 1.0), "base_point"),
    (lambda: sphere_quadric([0, 0, 0], [0, 0], 1.0), "platform_point"),
    (lambda: sphere_quadric([0, 0, 0], [1, 0, 0], -1.0), "length"),
    (lambda: sphere_quadric([0, 0, 0], [1, 0, 0], np.nan), "length"),
    (lambda: sphere_quadric([0, 0, 0], [1, 0, 0], [[1.0]]), "length"),
    (lambda: sphere_quadric(np.zeros((3, 3)), [1, 0, 0], [1.0, 2.0]), "base_point"),
    (lambda: point_on_plane_quadric([0, 0, 0], [0, 0, 0], [0, 0, 0]), "plane_normal"),
    (lambda: point_on_plane_quadric([0, 0, np.inf], [0, 0, 0], [0, 0, 1]), "platform_point"),
    (lambda: point_on_plane_quadric([0, 0, 0], [0, 0], [0, 0, 1]), "plane_point"),
    (lambda: point_on_line_quadrics([0, 0, 0], [0, 0, 0], [0, 0, 0]), "line_direction"),
    (lambda: point_on_line_quadrics([0, 0, 0], [np.nan, 0, 0], [0, 0, 1]), "line_point"),
    (lambda: point_on_line_quadrics(np.zeros((2, 3)), [0, 0, 0], [0, 0, 1]), "platform_point"),
    (lambda: quadric_value(np.eye(7), np.ones(8)), "Q"),
    (lambda: quadric_value(np.eye(8), np.ones(7)), "s"),
    (lambda: form_matrix(study_symbols()[0] ** 3), "expr"),
    (lambda: form_matrix(study_symbols()[0] + 1), "expr"),
])
def test_bad_input_raises_input_error_naming_the_parameter(call, name):
    with pytest.raises(InputError) as info:
        call()
    assert str(info.value).startswith(name), str(info.value)


def test_wrong_kinds_raise_type_error():
    with pytest.raises(TypeError):
        sphere_quadric([0, 0, 0], [1, 0, 0], "1")
    with pytest.raises(TypeError):
        point_on_plane_quadric("abc", [0, 0, 0], [0, 0, 1])
