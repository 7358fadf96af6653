"""Gough-Stewart singularities: the line-coordinate Jacobian against finite differences of the
inverse kinematics under exponentials of twists, its Study forms against exact rational arithmetic,
the constant-orientation locus (its degree read off the determinant, its zeros singular poses by
SVD) and its certified mesh."""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from imagespace.exceptions import DegenerateDesignError, InputError
from imagespace.spatial.gough_stewart import GoughStewart
from imagespace.spatial.singularities import (ConstantOrientationSingularity, aspect,
                                              constant_orientation_singularity, jacobian_determinant,
                                              jacobian_matrix, leg_line_forms)
from imagespace.spatial.study import matrix_from_quaternion, study_point, transform_matrix


def random_design(rng):
    return GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))


def random_pose(rng):
    """A Study point (normalised) of a random rotation and a translation lifting the platform."""
    q = rng.normal(size=4)
    t = rng.normal(size=3) + [0.0, 0.0, 2.0]
    return study_point(q, t)


def hat(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def displaced(s, v, w, h):
    """The pose ``exp(h [w, v]) . pose(s)``: the 4x4 twist exponential in the base frame
    (``X' = v + w x X`` at ``h = 0``), then back to a Study point."""
    from scipy.linalg import expm

    xi = np.zeros((4, 4))
    xi[:3, :3], xi[:3, 3] = hat(w), v
    T = expm(h * xi) @ transform_matrix(s)
    return study_point(T[:3, :3], T[:3, 3])


# --------------------------------------------------------------------------- Euclidean Jacobian

def test_jacobian_maps_twists_to_leg_rates_finite_differences(rng):
    h = 1e-6
    for _ in range(10):
        gs = random_design(rng)
        s = random_pose(rng)
        v, w = rng.normal(size=3), rng.normal(size=3)
        L = gs.inverse_kinematics(s)
        dL = (gs.inverse_kinematics(displaced(s, v, w, h)) - gs.inverse_kinematics(displaced(s, v, w, -h))) / (2 * h)
        predicted = jacobian_matrix(gs, s) @ np.concatenate([v, w])
        assert np.allclose(L * dL, predicted, rtol=1e-6, atol=1e-7 * np.abs(predicted).max())


def test_jacobian_batch_against_line_coordinates_written_here(rng):
    """A batch of poses: every row ``(s_i, a_i x s_i)`` with ``s_i = R b_i + t - a_i``, the leg's
    Pluecker coordinates built here from scipy's rotation of the quaternion (independent of
    imagespace's Study map); the determinant and the aspect against numpy's ``det`` of those rows.
    Then a consistency check beside it: each batch row is bit-identical to the single-pose call."""
    from scipy.spatial.transform import Rotation

    gs = random_design(rng)
    quats = rng.normal(size=(5, 4))
    T = rng.normal(size=(5, 3)) + [0.0, 0.0, 2.0]
    S = study_point(quats, T)
    J = jacobian_matrix(gs, S)
    assert J.shape == (5, 6, 6)
    A, B = gs.base_points, gs.platform_points
    expected = np.empty((5, 6, 6))
    for k in range(5):
        R = Rotation.from_quat(np.roll(quats[k], -1)).as_matrix()        # scipy: scalar last
        s = B @ R.T + T[k] - A
        expected[k] = np.hstack([s, np.cross(A, s)])
    assert np.allclose(J, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
    det = np.linalg.det(expected)
    assert np.allclose(jacobian_determinant(gs, S), det, rtol=1e-9)      # normalised points: N = 1
    a = aspect(gs, S)
    assert a.shape == (5,) and a.dtype == np.int8 and np.array_equal(a, np.sign(det).astype(np.int8))
    for k in range(5):
        assert np.array_equal(J[k], jacobian_matrix(gs, S[k]))


# --------------------------------------------------------------------------- Study forms

def _qmul(p, q):
    a0, a1, a2, a3 = p
    b0, b1, b2, b3 = q
    return [a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3, a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1, a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0]


def test_study_forms_equal_n_times_line_coordinates_exactly(rng):
    """Anchors and Study points on a dyadic grid: the float forms hold exact values, and
    ``z^T Q z`` in Fractions equals ``N (s, a x s)`` computed here from quaternions in Fractions
    (``N (R b + t) = vec(x b x~ + 2 y x~)``), at points on and off Study's quadric."""
    A = np.round(rng.normal(size=(6, 3)) * 8) / 8
    B = np.round(rng.normal(size=(6, 3)) * 8) / 8
    gs = GoughStewart(A, B)
    Q = leg_line_forms(gs)
    for _ in range(5):
        z = [Fraction(int(v), 4) for v in rng.integers(-8, 9, size=8)]
        z[0] += 1 if all(v == 0 for v in z[:4]) else 0
        x, y = z[:4], z[4:]
        xc = [x[0], -x[1], -x[2], -x[3]]
        N = sum(v * v for v in x)
        for i in range(6):
            a = [Fraction(float(v)) for v in A[i]]
            b = [Fraction(0)] + [Fraction(float(v)) for v in B[i]]
            landed = [r + 2 * t for r, t in zip(_qmul(_qmul(x, b), xc), _qmul(y, xc))]
            ns = [landed[1 + k] - a[k] * N for k in range(3)]
            m = [a[1] * ns[2] - a[2] * ns[1], a[2] * ns[0] - a[0] * ns[2], a[0] * ns[1] - a[1] * ns[0]]
            expected = ns + m
            for k in range(6):
                got = sum(z[p] * Fraction(float(Q[i, k, p, r])) * z[r] for p in range(8) for r in range(8))
                assert got == expected[k]


def test_study_forms_are_symmetric_and_cached_copies(rng):
    gs = random_design(rng)
    Q = leg_line_forms(gs)
    assert np.array_equal(Q, np.swapaxes(Q, -1, -2))
    Q[0, 0, 0, 0] = 99.0
    assert leg_line_forms(gs)[0, 0, 0, 0] != 99.0


def test_determinant_of_study_forms_is_n6_times_euclidean_det(rng):
    for _ in range(10):
        gs = random_design(rng)
        s = random_pose(rng) * rng.uniform(0.3, 3.0)           # any representative
        N = s[:4] @ s[:4]
        d = np.linalg.det(jacobian_matrix(gs, s))
        assert np.isclose(jacobian_determinant(gs, s), N ** 6 * d, rtol=1e-9)
        assert aspect(gs, s) == np.sign(d)


# --------------------------------------------------------------------------- aspect

def test_aspect_is_scale_free_and_zero_at_a_singularity(rng):
    gs = random_design(rng)
    for scale in (1e-3, 1e3, 1e6):          # metres, millimetres, micrometres
        big = GoughStewart(scale * gs.base_points, scale * gs.platform_points)
        for _ in range(10):
            q, t = rng.normal(size=4), rng.normal(size=3)
            a = aspect(gs, study_point(q, t))
            assert a != 0 and a == aspect(big, study_point(q, scale * t))
    # a point of the constant-orientation locus (found below by roots) is aspect 0
    locus = constant_orientation_singularity(gs, np.eye(3))
    t = point_on_locus(locus, rng)
    assert aspect(gs, study_point(np.eye(3), t)) == 0


# --------------------------------------------------------------------------- constant orientation

def point_on_locus(locus, rng):
    """A real point of the locus on a random line ``p + lam d``: the exact polynomial restricted
    to the line, its real roots by numpy."""
    x, y, z = locus.variables
    lam = sp.Symbol("lam")
    while True:
        p = rng.normal(size=3)
        d = rng.normal(size=3)
        sub = {v: sp.Rational(float(pi)) + lam * sp.Rational(float(di)) for v, pi, di in zip((x, y, z), p, d)}
        coeffs = [float(c) for c in sp.Poly(sp.expand(locus.polynomial.xreplace(sub)), lam).all_coeffs()]
        real = [r.real for r in np.roots(coeffs) if abs(r.imag) <= 1e-12 * max(1.0, abs(r))]
        if real:
            return p + real[0] * d


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(4))
def test_constant_orientation_locus_is_a_cubic(seed):
    """Read off the exact determinant: total degree 3 for general 6-6 designs and orientations."""
    rng = np.random.default_rng(seed)
    gs = random_design(rng)
    locus = constant_orientation_singularity(gs, rng.normal(size=4))
    P = sp.Poly(locus.polynomial, *locus.variables)
    assert P.total_degree() == 3 == locus.degree
    assert all(isinstance(c, sp.Rational) for c in P.coeffs())


def test_constant_orientation_polynomial_equals_exact_determinant_at_rational_points(rng):
    """The determinant evaluated exactly at a point (rows built here in Fractions) equals the
    polynomial at that point."""
    gs = random_design(rng)
    q = [Fraction(int(v), 3) for v in rng.integers(1, 9, size=4)]
    locus = constant_orientation_singularity(gs, [float(v) for v in q])    # thirds are not dyadic
    # use the rotation of the dyadic quaternion actually used: float(q) as binary rationals
    qf = [Fraction(float(v)) for v in q]
    n = sum(v * v for v in qf)
    w0, w1, w2, w3 = qf
    R = [[w0 * w0 + w1 * w1 - w2 * w2 - w3 * w3, 2 * (w1 * w2 - w0 * w3), 2 * (w1 * w3 + w0 * w2)],
         [2 * (w1 * w2 + w0 * w3), w0 * w0 - w1 * w1 + w2 * w2 - w3 * w3, 2 * (w2 * w3 - w0 * w1)],
         [2 * (w1 * w3 - w0 * w2), 2 * (w2 * w3 + w0 * w1), w0 * w0 - w1 * w1 - w2 * w2 + w3 * w3]]
    R = [[v / n for v in r] for r in R]
    for _ in range(2):
        t = [Fraction(int(v), 7) for v in rng.integers(-10, 11, size=3)]
        rows = []
        for a_f, b_f in zip(gs.base_points, gs.platform_points):
            a = [Fraction(float(v)) for v in a_f]
            b = [Fraction(float(v)) for v in b_f]
            s = [t[k] + sum(R[k][j] * b[j] for j in range(3)) - a[k] for k in range(3)]
            m = [a[1] * s[2] - a[2] * s[1], a[2] * s[0] - a[0] * s[2], a[0] * s[1] - a[1] * s[0]]
            rows.append(s + m)
        exact = sp.Matrix(rows).applyfunc(lambda v: sp.Rational(v.numerator, v.denominator)).det()
        value = locus.polynomial.xreplace({v: sp.Rational(c.numerator, c.denominator)
                                           for v, c in zip(locus.variables, t)})
        assert sp.nsimplify(value - exact) == 0


def test_constant_orientation_value_matches_numeric_determinant(rng):
    gs = random_design(rng)
    R = matrix_from_quaternion(rng.normal(size=4))
    locus = constant_orientation_singularity(gs, R)
    assert isinstance(locus, ConstantOrientationSingularity)
    T = rng.normal(size=(20, 3))
    dets = np.linalg.det(jacobian_matrix(gs, study_point(np.broadcast_to(R, (20, 3, 3)), T)))
    assert np.allclose(locus.value(T), dets, rtol=1e-8, atol=1e-10 * np.abs(dets).max())
    assert locus(T[0]) == locus.value(T[0])


def test_matrix_and_quaternion_give_the_same_locus(rng):
    gs = random_design(rng)
    q = rng.normal(size=4)
    a = constant_orientation_singularity(gs, q)
    b = constant_orientation_singularity(gs, matrix_from_quaternion(q))
    T = rng.normal(size=(10, 3))
    assert np.allclose(a.value(T), b.value(T), rtol=1e-9, atol=1e-12 * np.abs(a.value(T)).max())


@pytest.mark.slow
def test_zeros_of_the_locus_are_rank_5_jacobians(rng):
    for _ in range(5):
        gs = random_design(rng)
        q = rng.normal(size=4)
        locus = constant_orientation_singularity(gs, q)
        t = point_on_locus(locus, rng)
        sv = np.linalg.svd(jacobian_matrix(gs, study_point(q, t)), compute_uv=False)
        assert sv[5] <= 1e-9 * sv[0]          # singular
        assert sv[4] >= 1e-6 * sv[0]          # of rank exactly 5 (a general point of the cubic)


# --------------------------------------------------------------------------- mesh and export

def test_mesh_of_the_locus_is_certified_and_exports(rng, tmp_path):
    import trimesh
    from imagespace.singular.meshing import export_mesh
    from imagespace.spatial_surfaces import mesh_constant_orientation_singularity

    gs = random_design(rng)
    q = rng.normal(size=4)
    box = [(-2.0, 2.0)] * 3
    mesh = mesh_constant_orientation_singularity(gs, q, box, resolution=24)
    md = mesh.metadata["imagespace"]
    assert len(mesh.faces) > 0 and md["removed"] == 0 and md["uncertified"] == 0
    assert md["max_distance"] <= 1e-9 * 4
    assert md["sign_test"].startswith("rounding-error bound")
    # independent of the polynomial: the numeric Jacobian at the vertices' poses is singular
    V = mesh.vertices[rng.choice(len(mesh.vertices), 50, replace=False)]
    J = jacobian_matrix(gs, study_point(np.broadcast_to(q, (50, 4)), V))
    sv = np.linalg.svd(J, compute_uv=False)
    assert np.all(sv[:, 5] <= 1e-7 * sv[:, 0])
    path = export_mesh(mesh, tmp_path / "cubic.ply")
    back = trimesh.load(path, process=False)
    assert len(back.faces) == len(mesh.faces) and np.array_equal(back.vertices, mesh.vertices)
    # a locus passed in is meshed as it is
    locus = constant_orientation_singularity(gs, q)
    again = mesh_constant_orientation_singularity(gs, locus, box, resolution=24)
    assert np.array_equal(again.vertices, mesh.vertices)


# --------------------------------------------------------------------------- bad input

def test_bad_input(rng):
    gs = random_design(rng)
    with pytest.raises(TypeError, match="gs must be"):
        jacobian_matrix("design", [1, 0, 0, 0, 0, 0, 0, 0])
    with pytest.raises(TypeError, match="gs must be"):
        leg_line_forms(None)
    with pytest.raises(InputError, match="x = 0"):
        jacobian_determinant(gs, [0, 0, 0, 0, 1, 0, 0, 0])
    with pytest.raises(InputError, match="x = 0"):
        aspect(gs, [0, 0, 0, 0, 1, 0, 0, 0])
    with pytest.raises(InputError, match="shape"):
        jacobian_matrix(gs, [1, 0, 0])
    with pytest.raises(InputError, match="finite"):
        jacobian_matrix(gs, [np.nan, 0, 0, 0, 0, 0, 0, 0])
    with pytest.raises(InputError, match="rotation must be a rotation matrix"):
        constant_orientation_singularity(gs, 2 * np.eye(3))
    with pytest.raises(InputError, match="non-zero quaternion"):
        constant_orientation_singularity(gs, [0, 0, 0, 0])
    with pytest.raises(InputError, match="rotation must be"):
        constant_orientation_singularity(gs, [1.0, 0.0])
    with pytest.raises(TypeError, match="tolerances"):
        aspect(gs, [1, 0, 0, 0, 0, 0, 0, 0], tolerances=1e-9)


def test_architecture_singular_design_is_refused(rng):
    """Four legs through one platform point: four concurrent lines span at most a 3-space, so
    det J vanishes at every pose."""
    B = rng.normal(size=(6, 3))
    B[1:4] = B[0]
    gs = GoughStewart(rng.normal(size=(6, 3)), B)
    assert abs(np.linalg.det(jacobian_matrix(gs, random_pose(rng)))) < 1e-12
    with pytest.raises(DegenerateDesignError, match="every position"):
        constant_orientation_singularity(gs, np.eye(3))
    assert aspect(gs, random_pose(rng)) == 0
