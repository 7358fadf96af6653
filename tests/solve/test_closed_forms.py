"""The closed forms of seeds 003 and 004 against the image-space direct kinematics."""

import numpy as np
import pytest

import imagespace as isp


# -- seeds 003 and 004 -------------------------------------------------------------------------------------
@pytest.mark.slow
def test_seed_003_closed_form_equals_image_space_dk(rng):
    m = isp.examples.collinear_3rpr(2, 1)
    for _ in range(20):
        pose = np.array([rng.uniform(-1, 1), rng.uniform(0.3, 2), rng.uniform(-1.2, 1.2)])
        d = m.inverse_kinematics(pose)
        cf = isp.examples.collinear_3rpr_closed_form(d, 2, 1)
        dk = np.array([mm.pose for mm in m.direct_kinematics(d)])
        assert len(cf) == len(dk) == 4
        for p in cf:
            assert np.min(np.linalg.norm(dk - p, axis=1)) < 1e-9
        # mirror pairs (x, y, theta) <-> (x, -y, -theta)
        for p in cf:
            assert np.min(np.linalg.norm(cf - p * [1, -1, -1], axis=1)) < 1e-9


def test_seed_003_singular_configurations():
    m = isp.examples.collinear_3rpr(2, 1)
    # theta = 0: the three legs meet in one point (det Jx = 16 R r sin(theta) (...) = 0)
    assert m.jacobians([0.3, 1.2, 0.0]).direct_kinematic
    # the other factor: R y + r x sin(theta) - r y cos(theta) = 0 -> all legs parallel
    th, x = 0.7, 0.4
    y = -x * np.sin(th) / (2 - np.cos(th))
    assert m.jacobians([x, y, th]).direct_kinematic


@pytest.mark.slow
def test_seed_004_closed_form_two_modes_and_det(rng):
    for alpha in (7 * np.pi / 18, 11 * np.pi / 18, np.pi / 3):
        m = isp.examples.choi_3ppr(1, 0.5, alpha)
        for _ in range(5):
            pose = np.array([rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), alpha - np.pi / 2 + rng.uniform(-1.3, 1.3)])
            rho = m.inverse_kinematics(pose)
            cf = isp.examples.choi_3ppr_closed_form(rho, 1, 0.5, alpha)
            dk = np.array([mm.pose for mm in m.direct_kinematics(rho)])
            assert len(cf) == len(dk) == 2
            assert np.allclose(cf[0, :2], cf[1, :2])                                   # shared (x, y)
            wrap = lambda a: np.remainder(a + np.pi, 2 * np.pi) - np.pi
            assert np.isclose(wrap(cf[0, 2] + cf[1, 2] - 2 * alpha), 0, atol=1e-12)  # phi, 2 alpha - phi
            for p in cf:
                assert np.min(np.linalg.norm(dk - p, axis=1)) < 1e-9
            assert np.allclose(m.inverse_kinematics(cf), rho)                          # IK o DK
            det = np.linalg.det(m.jacobians(pose).homogeneous(1.0))
            assert np.isclose(det, isp.examples.choi_det_jh(pose[2] - (alpha - np.pi / 2), 0.5, alpha), rtol=1e-10)


def test_seed_004_rotation_limits_are_where_a_link_enters_the_plate():
    """Independent geometry: is the link direction from B_i towards its slider inside the plate's
    corner at B_i (a positive combination of the two edges)?"""
    alpha, r = 7 * np.pi / 18, 0.5
    lo, hi = isp.examples.choi_rotation_limits(alpha)
    th = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])

    def enters(phi):
        B = r * np.column_stack([np.sin(th + phi), -np.cos(th + phi)])
        out = []
        for i in range(3):
            w = np.array([np.cos(th[i] + alpha), np.sin(th[i] + alpha)])
            e1, e2 = B[(i + 1) % 3] - B[i], B[(i + 2) % 3] - B[i]
            c = np.linalg.solve(np.column_stack([e1, e2]), -w)
            out.append(np.all(c > 0))
        return any(out)

    for phi in np.linspace(lo + 1e-6, hi - 1e-6, 200):
        assert not enters(phi)
    assert enters(hi + 1e-3) and enters(lo - 1e-3)
