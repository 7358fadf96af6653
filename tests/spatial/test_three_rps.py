"""ThreeRPS: the plane and sphere conditions against Euclidean geometry, the fast path against
msolve on the exact system, and bad input."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.exceptions import DegenerateDesignError, InputError
from imagespace.spatial.study import study_point

msolve = pytest.importorskip("imagespace.core.msolve")
needs_msolve = pytest.mark.skipif(not msolve.msolve_available(), reason="msolve is not installed")


def _rodrigues(axis, angle):
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def _design(seed):
    rng = np.random.default_rng(seed)
    return rng.integers(-4, 5, (3, 3)) / 2.0, rng.integers(-4, 5, (3, 3)) / 4.0, rng.integers(-3, 4, (3, 3))


@pytest.mark.slow
def test_quadrics_are_the_euclidean_conditions():
    rng = np.random.default_rng(11)
    a, b, u = _design(3)
    m = isp.ThreeRPS(a, b, base_axes=u)
    for _ in range(10):
        R = _rodrigues(rng.normal(size=3), rng.uniform(-3, 3))
        t = rng.normal(size=3)
        s = study_point(R, t) * rng.uniform(0.5, 2.0)            # any scale: the forms are homogeneous
        N = s[:4] @ s[:4]
        L = rng.uniform(1, 3, 3)
        Q = m.constraint_quadrics(L)
        legs = b @ R.T + t - a
        for i in range(3):
            assert np.isclose(s @ Q[i] @ s, N * (legs[i] @ legs[i] - L[i] ** 2), atol=1e-9)
            assert np.isclose(s @ Q[3 + i] @ s, N * (u[i] @ legs[i]), atol=1e-9)
        assert abs(s @ Q[6] @ s) < 1e-12


@needs_msolve
@pytest.mark.slow
@pytest.mark.parametrize("seed", [1, 2, 5])
def test_fast_path_equals_msolve(seed):
    a, b, u = _design(seed)
    m = isp.ThreeRPS(a, b, base_axes=u)
    rng = np.random.default_rng(seed + 100)
    L = rng.integers(4, 13, 3) / 4.0
    fast = m.direct_kinematics(L)
    exact = m.direct_kinematics(L, method="exact")
    assert exact.certified and exact.complex_count == 16          # a general 3-RPS: 16 complex
    assert fast.reliable and fast.count == exact.count
    key = lambda p: p[np.lexsort(p.T[::-1])]                      # noqa: E731
    assert np.allclose(key(fast.study_points), key(exact.study_points), atol=1e-9)
    # every mode satisfies the Euclidean conditions
    for R, t in zip(exact.rotations, exact.translations):
        legs = b @ R.T + t - a
        assert np.allclose(np.linalg.norm(legs, axis=1), L, atol=1e-9)
        assert np.allclose(np.einsum("ij,ij->i", u, legs), 0, atol=1e-9)


@pytest.mark.slow
def test_inverse_of_a_reachable_pose():
    # a pose reached by the fast path: its leg lengths come back
    m = isp.ThreeRPS([[1, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0]],
                     [[0.5, 0, 0], [-0.25, 0.4, 0], [-0.25, -0.4, 0]])
    res = m.direct_kinematics([1.5, 1.75, 2.0])
    assert res.count > 0
    assert np.allclose(m.inverse_kinematics(res.study_points), [1.5, 1.75, 2.0], atol=1e-10)


def test_a_pose_off_the_planes_is_refused():
    m = isp.ThreeRPS([[1, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0]],
                     [[0.5, 0, 0], [-0.25, 0.4, 0], [-0.25, -0.4, 0]])
    with pytest.raises(InputError, match="plane"):
        m.inverse_kinematics(study_point(_rodrigues([1, 2, 3], 0.4), [0.3, -0.2, 1.0]))


def test_bad_input():
    with pytest.raises(DegenerateDesignError, match="collinear"):
        isp.ThreeRPS([[0, 0, 0], [1, 1, 1], [2, 2, 2]], np.eye(3))
    with pytest.raises(DegenerateDesignError, match="platform_points"):
        isp.ThreeRPS(np.eye(3), [[0, 0, 0], [0, 0, 1], [0, 0, 2]])
    with pytest.raises(InputError, match="base_points"):
        isp.ThreeRPS(np.eye(4, 3), np.eye(3))
    with pytest.raises(InputError, match="base_axes"):
        isp.ThreeRPS(np.eye(3), np.eye(3), base_axes=[[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    m = isp.ThreeRPS(np.eye(3), 0.5 * np.eye(3))
    with pytest.raises(InputError, match="lengths"):
        m.direct_kinematics([1.0, -1.0, 1.0])
    with pytest.raises(InputError, match="lengths"):
        m.direct_kinematics([1.0, float("nan"), 1.0])
    with pytest.raises(InputError, match="method"):
        m.direct_kinematics([1.0, 1.0, 1.0], method="magic")


@pytest.mark.slow
@needs_msolve
def test_complex_count_includes_half_turn_modes():
    # a symmetric design whose modes include half-turns (x0 = 0): msolve's count in the chart
    # x0 = 1 alone misses them; the count over the four strata equals the homotopy's 16
    m = isp.ThreeRPS([[1, 0, 0], [-0.5, 0.8, 0], [-0.5, -0.8, 0]],
                     [[0.5, 0, 0], [-0.25, 0.4, 0], [-0.25, -0.4, 0]])
    exact = m.direct_kinematics([2.0, 2.0, 2.0], method="exact")
    fast = m.direct_kinematics([2.0, 2.0, 2.0])
    assert exact.complex_count == 16 == len(m.start_system.solutions)
    assert exact.count == fast.count == 16
    assert np.any(np.abs(exact.study_points[:, 0]) < 1e-12)           # some modes are half-turns
