"""The singularity quartic: joint values drop out for radius/offset actuation, and its zero set is
where the legs of a 3-RPR are concurrent (an independent Euclidean criterion)."""

import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.kinematic_map import image_point


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


def test_joint_values_drop_out_for_radius_and_offset_actuation():
    for m in (isp.examples.general_3rpr(), isp.examples.stigger_husty()):
        S = m.singularity_polynomial()
        assert S.is_homogeneous and S.total_degree() == 4
        assert not (S.free_symbols & set(m.joint_symbols))
        # equal to the surface at any particular joint vector
        assert sp.expand(S.as_expr() - m.singularity_polynomial(m.q_example).as_expr()) == 0


def test_joint_values_stay_for_an_actuated_base_revolute():
    m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                            isp.RPR(base=(6, 0), platform=(1, 0)),
                            isp.RPR(base=(2, 5), platform=(0, 1))])
    assert m.joint_symbols[0] in m.singularity_polynomial().free_symbols


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
