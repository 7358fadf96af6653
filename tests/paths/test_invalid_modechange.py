"""Bad input to imagespace.paths.modechange gets a clear error naming the parameter (issue [14])."""

import numpy as np
import pytest

import imagespace as isp


@pytest.fixture(scope="module")
def setup():
    m = isp.examples.general_3rpr()
    q = m.q_example_float
    modes = m.direct_kinematics(q)
    path = isp.segment(isp.image_point([0, 0, 0]), isp.image_point([0.1, 0, 0]))
    return m, q, modes, path


@pytest.mark.parametrize("call, exc, words", [
    (lambda m, q, a, b, p: isp.joint_trajectory(m, None, q), TypeError, "path must be an ImagePath"),
    (lambda m, q, a, b, p: isp.joint_trajectory(m, p, q, per_piece=0), isp.InputError,
     "per_piece must be at least 1"),
    (lambda m, q, a, b, p: isp.joint_trajectory(m, p, q, per_piece=2.5), TypeError,
     "per_piece must be a whole number"),
    (lambda m, q, a, b, p: isp.joint_trajectory(m, p, q, per_piece=2**1100), isp.InputError,
     "per_piece must be at most"),
    (lambda m, q, a, b, p: isp.joint_trajectory(None, p, q), TypeError, "manipulator must be a PlanarParallel"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, a, b, samples=0), isp.InputError,
     "samples must be at least 1"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, a, b, samples=2.5), TypeError, "samples must be a whole"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, a, b, samples=10**12), isp.InputError,
     "samples must be at most"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, a, b, seed=-1), isp.InputError, "seed must be"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, a, b, seed="x"), TypeError, "seed must be"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, a, b, seed=1.5), TypeError, "seed must be"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, a, b, box=[[0, 1]] * 2), isp.InputError, "box must be"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, a, b, box=[[1, 0]] * 3), isp.InputError, "box must be"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, a, b, box="abc"), TypeError, "box must be numeric"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, "a", 1), TypeError, "mode_a"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, q, [0, 0, 1, 1], b), isp.InputError,
     r"mode_a must have \(x0, x1\) != \(0, 0\)"),
    (lambda m, q, a, b, p: isp.plan_mode_change(m, [-1.0, 5, 10], a, b), isp.InputError, r"q\[0\]"),
    (lambda m, q, a, b, p: isp.plan_mode_change(None, q, a, b), TypeError, "manipulator must be a PlanarParallel"),
])
def test_bad_input(setup, call, exc, words):
    m, q, modes, path = setup
    with pytest.raises(exc, match=words):
        call(m, q, modes[0], modes[1], path)


def test_valid_input_still_works(setup):
    m, q, modes, path = setup
    X = isp.image_point(m.direct_kinematics(q)[0].pose)
    seg = isp.segment(X, X * np.array([1, 1, 1.001, 1.0]))
    P, Q = isp.joint_trajectory(m, seg, q, per_piece=np.int64(4))
    assert P.shape == Q.shape == (5, 3)
