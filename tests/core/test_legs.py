import numpy as np
import pytest
import sympy as sp

import imagespace as isp


def e(a):
    return np.array([np.cos(a), np.sin(a)])


def ang(v):
    return np.arctan2(v[1], v[0])


def same_angle(a, b):
    return abs(np.angle(np.exp(1j * (a - b)))) < 1e-9


def T(pose, p):
    c, s = np.cos(pose[2]), np.sin(pose[2])
    return np.array([c * p[0] - s * p[1] + pose[0], s * p[0] + c * p[1] + pose[1]])


A, a, b = np.array([1.0, 2.0]), np.array([0.3, -0.5]), np.array([0.3, -0.5])
u = np.array([1.0, 1.0]) / np.sqrt(2)
v = np.array([1.0, 2.0]) / np.sqrt(5)

LEGS = {
    "RPR": lambda act: isp.RPR(base=A, platform=a, actuated=act),
    "RRR": lambda act: isp.RRR(base=A, platform=a, lengths=(2.0, 1.5), actuated=act),
    "PRR": lambda act: isp.PRR(base=A, axis=(1, 1), platform=a, length=1.7, actuated=act),
    "RRP": lambda act: isp.RRP(base=A, length=2.0, platform=b, direction=(1, 2), actuated=act),
    "RPP": lambda act: isp.RPP(base=A, platform=b, direction=(1, 2), angle=1.0, actuated=act),
    "PRP": lambda act: isp.PRP(base=A, axis=(1, 1), platform=b, direction=(1, 2), actuated=act),
    "PPR": lambda act: isp.PPR(base=A, axis=(1, 1), platform=a, angle=1.2, actuated=act),
}


def forward_check(kind, q, pose):
    """The chain closes: written here from the joint definitions of the legs module."""
    phi = pose[2]
    if kind == "RPR":
        return np.allclose(A + q[1] * e(q[0]), T(pose, a)) and same_angle(phi, q[0] + q[2])
    if kind == "RRR":
        return (np.allclose(A + 2.0 * e(q[0]) + 1.5 * e(q[0] + q[1]), T(pose, a))
                and same_angle(phi, q[0] + q[1] + q[2]))
    if kind == "PRR":
        g = ang(u)
        return (np.allclose(A + q[0] * u + 1.7 * e(g + q[1]), T(pose, a))
                and same_angle(phi, g + q[1] + q[2]))
    if kind == "RRP":
        return (np.allclose(A + 2.0 * e(q[0]), T(pose, b + q[2] * v))
                and same_angle(phi + ang(v), q[0] + q[1]))
    if kind == "RPP":
        return (np.allclose(A + q[1] * e(q[0]), T(pose, b + q[2] * v))
                and same_angle(phi + ang(v), q[0] + 1.0))
    if kind == "PRP":
        return (np.allclose(A + q[0] * u, T(pose, b + q[2] * v))
                and same_angle(phi + ang(v), ang(u) + q[1]))
    if kind == "PPR":
        w = e(ang(u) + 1.2)
        return np.allclose(A + q[0] * u + q[1] * w, T(pose, a)) and same_angle(phi, q[2])
    raise AssertionError(kind)


@pytest.mark.slow
@pytest.mark.parametrize("kind", sorted(LEGS))
def test_ik_closes_the_chain_and_dyads_vanish(kind, rng):
    checked = 0
    for act in range(3):
        leg = LEGS[kind](act)
        assert leg.joints == kind
        for _ in range(40):
            pose = np.array([rng.normal(1, 1.5), rng.normal(2, 1.5), rng.uniform(-np.pi, np.pi)])
            X = isp.image_point(pose)
            for q in leg.inverse_kinematics(pose):
                if np.any(np.isnan(q)):
                    continue
                assert forward_check(kind, q, pose)
                if kind == "RPR" and act == 1 and q[1] < 0:
                    continue
                d = leg.dyad(q[act])
                assert abs(d.evaluate(X)) <= 1e-10 * np.linalg.norm(d.gradient(X))
                checked += 1
    assert checked >= 100


def test_ik_batch_matches_single(rng):
    leg = LEGS["RRR"](0)
    poses = np.column_stack([rng.normal(1, 1, 20), rng.normal(2, 1, 20), rng.uniform(-3, 3, 20)])
    batch = leg.inverse_kinematics(poses)
    assert batch.shape == (20, 2, 3)
    for i in range(20):
        assert np.allclose(batch[i], leg.inverse_kinematics(poses[i]), equal_nan=True)


@pytest.mark.slow
def test_symbolic_dyad_equals_numeric():
    for kind, make in LEGS.items():
        for act in range(3):
            leg = make(act)
            q = sp.Symbol("q", real=True)
            expr = leg.dyad(q).expr()
            val = 0.7
            num = leg.dyad(val)
            X = np.array([0.8, 0.6, 1.1, -0.4])
            sym = float(expr.subs(q, val).subs(dict(zip(isp.image_symbols(), X))))
            assert np.isclose(sym, float(num.evaluate(X)), rtol=1e-9, atol=1e-12), (kind, act)


def test_unreachable_pose_gives_nan():
    leg = isp.RRR(base=(0, 0), platform=(0, 0), lengths=(1, 1))
    assert np.all(np.isnan(leg.inverse_kinematics([5.0, 0.0, 0.0])))


def test_bad_input():
    with pytest.raises(isp.InputError, match="axis"):
        isp.PPR(base=(0, 0), axis=(0, 0), platform=(0, 0), angle=1.0)
    with pytest.raises(isp.InputError, match="direction"):
        isp.RRP(base=(0, 0), length=1, platform=(0, 0), direction=(0.0, 0.0))
    with pytest.raises(isp.DegenerateDesignError, match="angle"):
        isp.PPR(base=(0, 0), axis=(1, 0), platform=(0, 0), angle=0.0)
    with pytest.raises(isp.InputError, match="rho"):
        isp.RPR(base=(0, 0), platform=(0, 0)).dyad(-1.0)
    with pytest.raises(isp.InputError, match="lengths"):
        isp.RRR(base=(0, 0), platform=(0, 0), lengths=(1, -2))
    with pytest.raises(isp.InputError, match="length"):
        isp.PRR(base=(0, 0), axis=(1, 0), platform=(0, 0), length=0)
    with pytest.raises(isp.InputError, match="base"):
        isp.RPR(base=(0, 0, 0), platform=(0, 0))
    with pytest.raises(isp.InputError, match="finite"):
        isp.RPR(base=(np.nan, 0), platform=(0, 0))
    with pytest.raises(isp.InputError, match="actuated"):
        isp.RPR(base=(0, 0), platform=(0, 0), actuated=3)
    with pytest.raises(TypeError, match="platform"):
        isp.RPR(base=(0, 0), platform=None)
    with pytest.raises(isp.InputError, match="pose"):
        isp.RPR(base=(0, 0), platform=(0, 0)).inverse_kinematics([1.0, 2.0])


def test_joint_distance_and_nearest_branch_against_a_direct_computation():
    """Angles compare modulo 2 pi, lengths plainly; the nearest branch is the one whose IK value a
    brute-force search over the branches picks (written here independently)."""
    rrr = isp.RRR(base=(0, 0), lengths=(1.0, 1.0), platform=(0, 0), actuated=0)
    assert abs(float(rrr.joint_distance(np.pi - 0.01, -np.pi + 0.01)) - 0.02) < 1e-12
    rpr = isp.RPR(base=(0, 0), platform=(3, 4))
    assert float(rpr.joint_distance(-5.0, 5.0)) == 10.0
    rng = np.random.default_rng(11)
    poses = np.column_stack([rng.uniform(-1, 1, 40), rng.uniform(-1, 1, 40), rng.uniform(-3, 3, 40)])
    q = rng.uniform(-np.pi, np.pi, 40)
    got = rrr.nearest_branch(poses, q)
    for k in range(40):
        vals = rrr.actuated_values(poses[k])
        dist = [abs((v - q[k] + np.pi) % (2 * np.pi) - np.pi) if np.isfinite(v) else np.inf for v in vals]
        expect = int(np.argmin(dist)) if np.isfinite(min(dist)) else -1
        assert got[k] == expect


def test_leg_ik_tangency_threshold_is_the_tolerances_field():
    """A pose a hair beyond the RRR leg's reach is the stretched elbow (one tangent branch) within
    ``ik_tangent``, out of reach with a tighter one; the default reproduces the old literal."""
    leg = isp.RRR(base=(0, 0), lengths=(1, 1), platform=(0, 0))
    pose = [2.0 * (1 + 1e-14), 0.0, 0.0]
    assert np.all(np.isfinite(leg.inverse_kinematics(pose)))
    assert np.all(np.isfinite(leg.inverse_kinematics(pose, tolerances=isp.Tolerances())))
    assert np.all(np.isnan(leg.inverse_kinematics(pose, tolerances=isp.Tolerances(ik_tangent=1e-17))))
    assert isp.Tolerances().ik_tangent == 1e-12 and isp.Tolerances().ik_parallel == 1e-14


def test_leg_ik_refuses_a_non_tolerances_object():
    leg = isp.RPR(base=(0, 0), platform=(1, 0))
    with pytest.raises(TypeError, match="tolerances must be an imagespace.Tolerances"):
        leg.inverse_kinematics([0.0, 0.0, 0.0], tolerances=1e-12)
