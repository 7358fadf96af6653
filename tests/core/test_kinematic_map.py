import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import imagespace as isp

finite = st.floats(-50, 50, allow_nan=False)
angle = st.floats(-np.pi + 1e-6, np.pi, allow_nan=False)
pose_st = st.tuples(finite, finite, angle)


def rot(phi):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s], [s, c]])


@pytest.mark.slow
@given(pose_st)
@settings(max_examples=200, deadline=None)
def test_pose_image_round_trip(pose):
    x = isp.image_point(pose)
    assert np.isclose(x[0] ** 2 + x[1] ** 2, 1.0)
    back = isp.pose_of(x)
    assert np.allclose(back[:2], pose[:2], atol=1e-9)
    assert np.isclose(np.angle(np.exp(1j * (back[2] - pose[2]))), 0.0, atol=1e-9)
    # any multiple is the same point
    assert np.allclose(isp.pose_of(-3.5 * x), back, atol=1e-9)


@pytest.mark.slow
@given(pose_st, st.tuples(finite, finite))
@settings(max_examples=100, deadline=None)
def test_transform_matrix_moves_points_like_a_rigid_motion(pose, p):
    # independent: R(phi) p + t written here
    expected = rot(pose[2]) @ np.array(p) + np.array(pose[:2])
    got = isp.transform_points(isp.image_point(pose), np.array(p))
    assert np.allclose(got, expected, atol=1e-9 * (1 + np.abs(expected).max()))


def _composition_is_the_product(a, b):
    A, B = isp.image_point(a), isp.image_point(b)
    T = isp.transform_matrix(isp.compose(A, B))
    assert np.allclose(T, isp.transform_matrix(A) @ isp.transform_matrix(B), atol=1e-9 * 100)


def _inverse(a):
    A = isp.image_point(a)
    T = isp.transform_matrix(isp.compose(A, isp.inverse(A)))
    assert np.allclose(T, np.eye(3), atol=1e-9)


# the property in the fast lane with 25 examples, the full 100-example sweep with the slow checks
test_composition_is_the_product = settings(max_examples=25, deadline=None)(
    given(pose_st, pose_st)(_composition_is_the_product))
test_composition_is_the_product_sweep = pytest.mark.slow(settings(max_examples=100, deadline=None)(
    given(pose_st, pose_st)(_composition_is_the_product)))
test_inverse = settings(max_examples=25, deadline=None)(given(pose_st)(_inverse))
test_inverse_sweep = pytest.mark.slow(settings(max_examples=100, deadline=None)(given(pose_st)(_inverse)))


def test_batch_shapes_and_half_turn():
    poses = np.array([[1.0, 2.0, np.pi], [1.0, 2.0, -np.pi], [0.0, 0.0, 0.0]])
    X = isp.image_point(poses)
    assert X.shape == (3, 4)
    assert np.allclose(X[0], X[1]) and X[0, 0] == pytest.approx(0.0, abs=1e-16) and X[0, 1] == 1.0
    P = isp.pose_of(X)
    assert P.shape == (3, 3)
    assert np.allclose(P[:2, 2], np.pi)
    n = isp.normalize(np.array([[0.0, -2.0, 1.0, 1.0]]))
    assert np.allclose(n, [[0.0, 1.0, -0.5, -0.5]])


@pytest.mark.slow
def test_symbolic_face_matches_numeric():
    x, y, phi = sp.symbols("x y phi", real=True)
    X = isp.image_point((x, y, phi))
    P = isp.pose_of(X)
    assert sp.simplify(P[0] - x) == 0 and sp.simplify(P[1] - y) == 0
    vals = {x: 1.5, y: -0.5, phi: 0.7}
    assert np.allclose([float(v.subs(vals)) for v in X], isp.image_point([1.5, -0.5, 0.7]))
    T = isp.transform_matrix(X)
    assert np.allclose(np.array(T.subs(vals), dtype=float), isp.transform_matrix(isp.image_point([1.5, -0.5, 0.7])))
    a = sp.symbols("a0:4")
    b = sp.symbols("b0:4")
    C = isp.compose(a, b)
    num_a, num_b = np.array([0.3, 0.4, 1.0, -2.0]), np.array([1.0, -0.5, 0.5, 0.25])
    sub = dict(zip(a + b, np.concatenate([num_a, num_b])))
    assert np.allclose(np.array(C.subs(sub), dtype=float).ravel(), isp.compose(num_a, num_b))


def test_bad_input():
    with pytest.raises(isp.InputError, match="absolute line"):
        isp.pose_of([0.0, 0.0, 1.0, 2.0])
    with pytest.raises(isp.InputError, match="shape"):
        isp.image_point([1.0, 2.0])
    with pytest.raises(isp.InputError, match="finite"):
        isp.image_point([np.nan, 0.0, 0.0])
    with pytest.raises(isp.InputError, match="finite"):
        isp.pose_of([1.0, 0.0, np.inf, 0.0])
    with pytest.raises(TypeError):
        isp.image_point("pose")
    with pytest.raises(isp.InputError, match="image_point"):
        isp.normalize(np.zeros((2, 4)))
