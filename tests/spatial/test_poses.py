"""Spatial pose constructors (issue [16]) against rotations and transforms written here with numpy:
a pose must move points as ``R p + t`` with the ``R`` the user meant."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.spatial import pose_from_matrix, pose_from_quaternion, pose_from_rotation, pose_from_rpy
from imagespace.spatial.study import transform_points


def rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


@pytest.fixture
def points():
    return np.random.default_rng(16).normal(size=(5, 3))


def test_every_constructor_moves_points_as_r_p_plus_t(points):
    roll, pitch, yaw = 0.3, -0.7, 2.1
    R = rz(yaw) @ ry(pitch) @ rx(roll)
    t = np.array([0.5, -1.0, 2.0])
    want = points @ R.T + t
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    # the quaternion of R by Rodrigues: axis and angle from R itself
    angle = np.arccos((np.trace(R) - 1) / 2)
    axis = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / (2 * np.sin(angle))
    q = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])
    poses = {"rotation": pose_from_rotation(R, t), "quaternion": pose_from_quaternion(3.0 * q, t),
             "rpy": pose_from_rpy([roll, pitch, yaw], t),
             "rpy degrees": pose_from_rpy(np.degrees([roll, pitch, yaw]), t, degrees=True),
             "matrix": pose_from_matrix(T)}
    for name, s in poses.items():
        assert s.shape == (8,) and abs(s[:4] @ s[4:]) < 1e-12, name          # on Study's quadric
        assert np.allclose(transform_points(s, points), want, atol=1e-12), name


def test_rpy_axes_and_batches():
    # yaw 90 deg takes x to y; pitch 90 deg takes z to x; roll 90 deg takes y to z
    for rpy, p, img in (([0, 0, 90], [1, 0, 0], [0, 1, 0]), ([0, 90, 0], [0, 0, 1], [1, 0, 0]),
                        ([90, 0, 0], [0, 1, 0], [0, 0, 1])):
        assert np.allclose(transform_points(pose_from_rpy(rpy, [0, 0, 0], degrees=True), p), img, atol=1e-15)
    batch = pose_from_rpy(np.array([[0.1, 0.2, 0.3], [0.0, 0.0, 1.0]]), np.zeros((2, 3)))
    assert batch.shape == (2, 8)
    assert np.allclose(batch[1], pose_from_rotation(rz(1.0), [0, 0, 0]))


def test_a_wrong_shape_names_the_constructors():
    names = r"pose_from_rotation.*pose_from_quaternion.*pose_from_rpy.*pose_from_matrix"
    for call in (lambda: pose_from_rotation(np.eye(4), [0, 0, 0]), lambda: pose_from_quaternion([1, 0, 0], [0, 0, 0]),
                 lambda: pose_from_rpy([0, 0], [0, 0, 0]), lambda: pose_from_matrix(np.eye(3)),
                 lambda: pose_from_rotation(np.eye(3), [0, 0]),
                 lambda: isp.spatial.study_point(np.eye(2), [0, 0, 0])):
        with pytest.raises(isp.InputError, match=names):
            call()
    with pytest.raises(isp.InputError, match=r"\(a 4x4 matrix: pose_from_matrix\(T\)\)"):
        pose_from_rotation(np.eye(4), [0, 0, 0])
    with pytest.warns(UserWarning, match="pose_from_matrix"):      # four quaternions, or a 4x4 transform?
        isp.spatial.study_point(np.eye(4), [0, 0, 0])


def test_bad_values_are_refused():
    T = np.eye(4)
    T[3] = [0, 0, 1, 1]
    with pytest.raises(isp.InputError, match=r"\(0, 0, 0, 1\)"):
        pose_from_matrix(T)
    with pytest.raises(isp.InputError, match="rotation matrix"):
        pose_from_rotation(2 * np.eye(3), [0, 0, 0])
    with pytest.raises(isp.InputError, match="finite"):
        pose_from_rpy([np.nan, 0, 0], [0, 0, 0])
    with pytest.raises(TypeError):
        pose_from_rpy([0, 0, 0], [0, 0, 0], degrees="yes")
    with pytest.raises(TypeError):
        pose_from_quaternion(["1", 0, 0, 0], [0, 0, 0])
