"""GoughStewart: bad input and degenerate designs (issue 18, "Bad input"), and the inverse kinematics
and constraint quadrics against the Euclidean leg lengths written here (Rodrigues' rotation)."""

import numpy as np
import pytest

from imagespace.exceptions import DegenerateDesignError, InputError
from imagespace.spatial.gough_stewart import GoughStewart
from imagespace.spatial.study import study_point
from imagespace.tolerances import Tolerances


def rodrigues(axis, angle):
    u = np.asarray(axis, dtype=float)
    u = u / np.linalg.norm(u)
    K = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def hexagon(radius, offset, z=0.0):
    ang = np.repeat(np.arange(3) * 2 * np.pi / 3, 2) + np.tile([-offset, offset], 3)
    return np.column_stack([radius * np.cos(ang), radius * np.sin(ang), np.full(6, z)])


def random_design(rng):
    return rng.normal(scale=2.0, size=(6, 3)), rng.normal(size=(6, 3))


def euclidean_lengths(A, B, R, t):
    return np.array([np.linalg.norm(R @ B[i] + t - A[i]) for i in range(6)])


# --------------------------------------------------------------------------- accepted designs

def test_planar_hexapod_is_not_degenerate():
    # base and platform anchors each in one plane (the usual hexapod): a regular design
    gs = GoughStewart(hexagon(2.0, 0.2), hexagon(1.0, 0.5))
    assert gs.base_points.shape == gs.platform_points.shape == (6, 3)
    # coplanar in a tilted plane as well
    R = rodrigues([1.0, 2.0, -0.5], 0.7)
    GoughStewart(hexagon(2.0, 0.2) @ R.T + [1, 2, 3], hexagon(1.0, 0.5) @ R.T)


def test_six_three_and_three_three_special_cases_are_accepted():
    tri = np.array([[1.0, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0]])
    six_three = np.repeat(tri, 2, axis=0)
    GoughStewart(hexagon(2.0, 0.3), six_three)                              # 6-3
    GoughStewart(np.roll(np.repeat(2 * tri, 2, axis=0), 1, axis=0), six_three)   # 3-3 (octahedral)


def test_anchors_are_stored_read_only(rng):
    A, B = random_design(rng)
    gs = GoughStewart(A, B)
    with pytest.raises(ValueError):
        gs.base_points[0, 0] = 1.0
    with pytest.raises(ValueError):
        gs.platform_points[0, 0] = 1.0


def test_the_callers_arrays_are_not_aliased_or_frozen(rng):
    A, B = random_design(rng)
    gs = GoughStewart(A, B)
    A[0, 0] = 99.0
    B[0, 0] = 99.0
    assert gs.base_points[0, 0] != 99.0 and gs.platform_points[0, 0] != 99.0


# --------------------------------------------------------------------------- refused designs

@pytest.mark.parametrize("which", ["base_points", "platform_points"])
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_anchors(rng, which, bad):
    A, B = random_design(rng)
    (A if which == "base_points" else B)[3, 1] = bad
    with pytest.raises(InputError) as info:
        GoughStewart(A, B)
    assert str(info.value).startswith(which)


@pytest.mark.parametrize("which", ["base_points", "platform_points"])
@pytest.mark.parametrize("shape", [(5, 3), (7, 3), (6, 2), (6, 4), (18,), (6, 3, 1), (1, 6, 3)])
def test_wrong_shapes(rng, which, shape):
    A, B = random_design(rng)
    bad = rng.normal(size=shape)
    with pytest.raises(InputError) as info:
        GoughStewart(bad, B) if which == "base_points" else GoughStewart(A, bad)
    msg = str(info.value)
    assert msg.startswith(which) and "(6, 3)" in msg, msg


def test_wrong_kinds(rng):
    A, B = random_design(rng)
    with pytest.raises(TypeError):
        GoughStewart("anchors", B)
    with pytest.raises(TypeError):
        GoughStewart(A, B.astype(complex))
    with pytest.raises(TypeError):
        GoughStewart(A, B, tolerances=1e-3)


@pytest.mark.parametrize("i, j", [(0, 1), (2, 5), (3, 4)])
def test_identical_legs(rng, i, j):
    A, B = random_design(rng)
    A[j], B[j] = A[i], B[i]
    with pytest.raises(DegenerateDesignError) as info:
        GoughStewart(A, B)
    msg = str(info.value)
    assert f"legs {min(i, j)} and {max(i, j)}" in msg and "identical" in msg, msg


def test_shared_base_anchor_alone_is_not_an_identical_leg(rng):
    A, B = random_design(rng)
    A[1] = A[0]                        # same base point, different platform points
    GoughStewart(A, B)


def _collinear_points(rng, n=6, noise=0.0):
    p, d = rng.normal(size=3), rng.normal(size=3)
    P = p + np.outer(rng.normal(scale=3.0, size=n), d)
    return P + noise * rng.normal(size=P.shape)


@pytest.mark.parametrize("which", ["base_points", "platform_points"])
@pytest.mark.parametrize("kind", ["collinear", "collinear within rounding", "all coincident",
                                  "two distinct points"])
def test_collinear_anchors(rng, which, kind):
    A, B = random_design(rng)
    if kind == "collinear":
        P = _collinear_points(rng)
    elif kind == "collinear within rounding":
        P = _collinear_points(rng, noise=1e-15)
    elif kind == "all coincident":
        P = np.tile(rng.normal(size=3), (6, 1))
    else:
        P = np.repeat(rng.normal(size=(2, 3)), 3, axis=0)
    if which == "base_points":
        A = P
    else:
        B = P
    with pytest.raises(DegenerateDesignError) as info:
        GoughStewart(A, B)
    msg = str(info.value)
    assert msg.startswith(which) and "line" in msg, msg


def test_nearly_collinear_but_resolved_anchors_are_accepted(rng):
    A, B = random_design(rng)
    P = _collinear_points(rng)
    P[2] += np.array([0.0, 0.0, 1e-6])
    GoughStewart(P, B)
    # the threshold is the named tolerance: a looser one refuses the same design
    with pytest.raises(DegenerateDesignError):
        GoughStewart(P, B, tolerances=Tolerances(spatial_collinear=1e-4))


# --------------------------------------------------------------------------- lengths

@pytest.mark.parametrize("index", [0, 3, 5])
@pytest.mark.parametrize("value", [-1.0, 0.0, -0.0, -1e-300])
def test_non_positive_lengths_name_lengths_and_the_index(rng, index, value):
    gs = GoughStewart(*random_design(rng))
    L = rng.uniform(1, 3, size=6)
    L[index] = value
    with pytest.raises(InputError) as info:
        gs.constraint_quadrics(L)
    msg = str(info.value)
    assert msg.startswith("lengths") and f"index {index}" in msg, msg


@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_non_finite_lengths_name_lengths(rng, value):
    gs = GoughStewart(*random_design(rng))
    L = rng.uniform(1, 3, size=6)
    L[2] = value
    with pytest.raises(InputError) as info:
        gs.constraint_quadrics(L)
    assert str(info.value).startswith("lengths")


def test_nan_length_error_names_the_index(rng):
    gs = GoughStewart(*random_design(rng))
    L = rng.uniform(1, 3, size=6)
    L[4] = np.nan
    with pytest.raises(InputError, match="index 4"):
        gs.constraint_quadrics(L)


@pytest.mark.parametrize("L", [np.ones(5), np.ones(7), np.ones((2, 6)), np.ones((6, 1)), 1.0])
def test_lengths_of_the_wrong_shape(rng, L):
    gs = GoughStewart(*random_design(rng))
    with pytest.raises(InputError) as info:
        gs.constraint_quadrics(L)
    assert str(info.value).startswith("lengths")


# --------------------------------------------------------------------------- IK and the quadrics

def test_inverse_kinematics_is_the_euclidean_leg_length(rng):
    for _ in range(20):
        A, B = random_design(rng)
        gs = GoughStewart(A, B)
        R = rodrigues(rng.normal(size=3), rng.uniform(-np.pi, np.pi))
        t = rng.normal(scale=2.0, size=3)
        ref = euclidean_lengths(A, B, R, t)
        s = study_point(R, t)
        assert np.allclose(gs.inverse_kinematics(s), ref, rtol=1e-12, atol=1e-12)
        # any non-zero multiple is the same pose
        assert np.allclose(gs.inverse_kinematics(-3.7 * s), ref, rtol=1e-12, atol=1e-12)
        # leg vectors
        assert np.allclose(gs.leg_vectors(s), B @ R.T + t - A, atol=1e-12)


def test_inverse_kinematics_batch(rng):
    A, B = random_design(rng)
    gs = GoughStewart(A, B)
    n = 25
    Rs = [rodrigues(rng.normal(size=3), rng.uniform(-np.pi, np.pi)) for _ in range(n)]
    ts = rng.normal(size=(n, 3))
    S = study_point(np.array(Rs), ts)
    Ls = gs.inverse_kinematics(S)
    assert Ls.shape == (n, 6)
    for k in range(n):
        assert np.allclose(Ls[k], euclidean_lengths(A, B, Rs[k], ts[k]), rtol=1e-12, atol=1e-12)
    # a half-turn pose (x0 = 0)
    u = rng.normal(size=3)
    s = study_point(np.concatenate([[0.0], u]), ts[0])
    assert np.allclose(gs.inverse_kinematics(s), euclidean_lengths(A, B, rodrigues(u, np.pi), ts[0]), atol=1e-12)


def test_constraint_quadrics_vanish_at_the_pose_of_the_lengths(rng):
    for _ in range(10):
        A, B = random_design(rng)
        gs = GoughStewart(A, B)
        R = rodrigues(rng.normal(size=3), rng.uniform(-np.pi, np.pi))
        t = rng.normal(size=3)
        L = euclidean_lengths(A, B, R, t)
        Qs = gs.constraint_quadrics(L)
        assert Qs.shape == (7, 8, 8)
        z = 2.5 * study_point(R, t)
        vals = np.einsum("i,kij,j->k", z, Qs, z)
        assert np.allclose(vals, 0.0, atol=1e-10)
        # at other lengths each leg's value is N (|R b + t - a|^2 - L^2), N = 2.5^2
        L2 = rng.uniform(0.5, 4.0, size=6)
        vals2 = np.einsum("i,kij,j->k", z, gs.constraint_quadrics(L2), z)
        assert np.allclose(vals2[:6], 6.25 * (L ** 2 - L2 ** 2), atol=1e-10)
        assert abs(vals2[6]) < 1e-12


@pytest.mark.parametrize("s", [np.zeros(8), [0, 0, 0, 0, 1, 2, 3, 4], [np.nan] + [0] * 7, np.ones(7)])
def test_inverse_kinematics_bad_study_points(rng, s):
    gs = GoughStewart(*random_design(rng))
    with pytest.raises(InputError) as info:
        gs.inverse_kinematics(s)
    assert str(info.value).startswith("s ")
