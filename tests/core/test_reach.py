"""The reach bounds (imagespace.core.reach): never refuse an input that has a real pose (joint
values computed from random real poses by the legs' inverse kinematics, every leg type and every
actuated joint), never decide an exact tie, and every claim they make confirmed by an exact
count of the real roots of the kinematic polynomial (sympy's Sturm count, not the bound)."""

import itertools
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.core.reach import (ReachObstruction, planar_design_scale, planar_reach_obstruction,
                                   point_pairs_obstruction, prismatic_magnitude)
from imagespace.exceptions import InputError


def random_leg(rng, kind, actuated):
    """A leg of type ``kind`` with random geometry (floats and small rationals mixed)."""
    def pt():
        if rng.random() < 0.5:
            return tuple(float(v) for v in rng.uniform(-6, 6, 2))
        return tuple(sp.Rational(int(v), 4) for v in rng.integers(-24, 25, 2))

    def direction():
        v = rng.normal(size=2)
        return tuple(float(c) for c in v) if rng.random() < 0.5 else \
            tuple(int(c) for c in np.sign(v) * rng.integers(1, 5, 2))

    def length():
        return float(rng.uniform(0.5, 5)) if rng.random() < 0.5 else sp.Rational(int(rng.integers(2, 20)), 4)

    def angle():
        return float(rng.uniform(0.3, 2.8)) * (1 if rng.random() < 0.5 else -1)

    if kind == "RPR":
        return isp.RPR(base=pt(), platform=pt(), actuated=actuated)
    if kind == "RRR":
        return isp.RRR(base=pt(), platform=pt(), lengths=(length(), length()), actuated=actuated)
    if kind == "PRR":
        return isp.PRR(base=pt(), axis=direction(), platform=pt(), length=length(), actuated=actuated)
    if kind == "RRP":
        return isp.RRP(base=pt(), length=length(), platform=pt(), direction=direction(), actuated=actuated)
    if kind == "RPP":
        return isp.RPP(base=pt(), platform=pt(), direction=direction(), angle=angle(), actuated=actuated)
    if kind == "PRP":
        return isp.PRP(base=pt(), axis=direction(), platform=pt(), direction=direction(), actuated=actuated)
    return isp.PPR(base=pt(), axis=direction(), platform=pt(), angle=angle(), actuated=actuated)


KINDS = ("RPR", "RRR", "PRR", "RRP", "RPP", "PRP", "PPR")


@pytest.mark.slow
def test_joint_values_of_real_poses_are_never_refused():
    """Every leg type and actuation, random geometry, random poses (some far out, some with the
    platform at the base): the joint values of each IK branch have a real pose, the bound must
    not refuse them."""
    rng = np.random.default_rng(20261203)
    checked = 0
    for trial in range(160):
        kinds = [KINDS[(trial + k) % 7] for k in (0, 2, 5)]
        legs = [random_leg(rng, kind, int(rng.integers(0, 3))) for kind in kinds]
        scale = [1.0, 10.0, 1e3, 1e-3][trial % 4]
        for _ in range(4):
            pose = np.array([*(rng.normal(size=2) * scale), rng.uniform(-np.pi, np.pi)])
            branches = [leg.inverse_kinematics(pose)[:, leg.actuated] for leg in legs]
            for combo in itertools.product(*branches):
                q = np.array(combo, dtype=float)
                if not np.all(np.isfinite(q)) or any(
                        not leg.joint_values_ok(v) for leg, v in zip(legs, q)):
                    continue
                ob = planar_reach_obstruction(legs, q)
                assert ob is None, (legs, pose.tolist(), q.tolist(), str(ob))
                checked += 1
    assert checked > 300


def test_spatial_leg_lengths_of_real_poses_are_never_refused():
    rng = np.random.default_rng(7)
    from imagespace.spatial.study import study_point
    for trial in range(150):
        A, B = rng.normal(size=(6, 3)) * 2, rng.normal(size=(6, 3))
        gs = isp.GoughStewart(A, B)
        q = rng.normal(size=4)
        s = study_point(q / np.linalg.norm(q), rng.normal(size=3) * [0.1, 10, 1e3][trial % 3])
        L = gs.inverse_kinematics(s)
        assert point_pairs_obstruction(A, B, L) is None


def test_exact_ties_are_not_decided():
    # two RPR legs, base points 3 apart, platform points 1 apart: with rho0 = 10 the platform
    # turned by pi and moved to (-10, 0) has rho1 = 14 = 10 + 3 + 1 exactly (a real pose); the
    # third leg (its angle actuated) constrains nothing
    legs = [isp.RPR(base=(0, 0), platform=(0, 0)), isp.RPR(base=(3, 0), platform=(1, 0)),
            isp.RPR(base=(0, 5), platform=(0, 1), actuated=0)]
    for q in ([10, 14, 0.3], [Fraction(10), Fraction(14), 0.3],
              [sp.Integer(10), sp.Integer(14), sp.Rational(3, 10)]):
        assert planar_reach_obstruction(legs, q) is None
    # a hair beyond the tie (one binary unit of the float 14): proven impossible
    ob = planar_reach_obstruction(legs, [10.0, np.nextafter(14.0, 15.0), 0.3])
    assert isinstance(ob, ReachObstruction) and ob.legs == (0, 1)
    assert point_pairs_obstruction([[0, 0], [3, 0]], [[0, 0], [1, 0]], [10, 14]) is None
    assert point_pairs_obstruction([[0, 0], [3, 0]], [[0, 0], [-1, 0]], [10, 14]) is None
    assert point_pairs_obstruction([[0, 0], [3, 0]], [[0, 0], [1, 0]],
                                   [10, np.nextafter(14.0, 15.0)]) is not None


def _near_cos_sin(angle, name):
    """cos/sin of a numeric angle as rationals within 2**-200 of the true values (mpmath at 80
    digits): the kinematic polynomial then has rational coefficients that sympy counts exactly,
    for a design within 2**-200 of the given one, far below the margins the reach bound claims."""
    import mpmath

    if isinstance(angle, sp.Basic) and angle.free_symbols:
        return sp.cos(angle), sp.sin(angle)
    with mpmath.workdps(80):
        a = mpmath.mpf(sp.Rational(angle).p) / sp.Rational(angle).q if isinstance(angle, sp.Basic) \
            else mpmath.mpf(float(angle))
        c, s = mpmath.cos(a), mpmath.sin(a)
        return (sp.Rational(int(mpmath.floor(c * 2**200)), 2**200),
                sp.Rational(int(mpmath.floor(s * 2**200)), 2**200))


@pytest.mark.slow
def test_claims_agree_with_an_exact_root_count(monkeypatch):
    """Random joint values on random designs of annulus legs (RPR, RRR with an angle actuated,
    PRR with the slider actuated): wherever the bound claims no pose, sympy's Sturm count of the
    real roots of the exact kinematic polynomial (an algorithm the bound does not use) is 0, and
    so is its value at the half-turn; the bound claims often. cos/sin of the angles enter as
    rationals within 2**-200 (``_near_cos_sin``) so that sympy can count exactly."""
    import imagespace.core.leg_geometry as leg_geometry
    from imagespace.solve.certified import exact_coefficients

    monkeypatch.setattr(leg_geometry, "exact_cos_sin", _near_cos_sin)

    rng = np.random.default_rng(3)
    t = sp.Symbol("t")
    claims = 0
    def pt():
        return tuple(float(v) for v in rng.uniform(-6, 6, 2))

    for trial in range(5):
        legs = [isp.RPR(base=pt(), platform=pt()),
                isp.RRR(base=pt(), platform=pt(), lengths=tuple(rng.uniform(0.5, 4, 2)),
                        actuated=trial % 3),
                isp.PRR(base=pt(), axis=pt(), platform=pt(), length=float(rng.uniform(0.5, 4)))]
        m = isp.PlanarParallel(legs)
        for _ in range(12):
            q = [float(rng.uniform(0, 30)), float(rng.uniform(-3, 3)), float(rng.uniform(-20, 20))]
            ob = planar_reach_obstruction(legs, q)
            if ob is None:
                continue
            claims += 1
            P = exact_coefficients(m, q)            # P[k] multiplies x0^(d-k) x1^k
            poly = sp.Poly(sum(c * t**k for k, c in enumerate(P)), t)
            assert poly.count_roots() == 0 and P[-1] != 0, (legs, q, str(ob))
    assert claims >= 15
@pytest.mark.parametrize("kind, actuated", [("RPR", 1), ("PRR", 0), ("RRP", 2), ("PPR", 0),
                                            ("PPR", 1), ("RPP", 1), ("RPP", 2)])
def test_absurd_prismatic_values_are_decided(kind, actuated):
    """A leg with a prismatic joint at 1e300 next to two RPR legs of moderate length: the bound
    proves no pose for every leg type whose locked dyad keeps a point or a line far away. (A
    PRP leg's does not: its platform line through a far point of the guide, or its far
    platform point on the guide, can be reached by a platform near the base.)"""
    rng = np.random.default_rng(11)
    leg = random_leg(rng, kind, actuated)
    legs = [leg, isp.RPR(base=(1, 2), platform=(0.5, 0)), isp.RPR(base=(-3, 1), platform=(0, 1))]
    for big in (1e300, -1e300) if kind != "RPR" else (1e300,):
        ob = planar_reach_obstruction(legs, [big, 4.0, 5.0])
        assert ob is not None and 0 in ob.legs, (kind, actuated, big)


def test_absurdly_small_values_are_decided():
    m = isp.examples.general_3rpr()
    ob = planar_reach_obstruction(m.legs, [1e-300] * 3)
    assert ob is not None and "base distance" in ob.reason
    # a 3-RPS whose base triangle is twice the platform's: legs of 1e-300 cannot close it
    A, B = np.eye(3), 0.5 * np.eye(3)
    assert point_pairs_obstruction(A, B, [1e-300] * 3) is not None
    assert point_pairs_obstruction(A, B, [1e300] * 3) is None      # equal and far: no claim


def test_angle_actuated_legs_use_no_cosine():
    """An RRR leg's reach is its annulus whatever the angle: absurd angles decide nothing by
    themselves, the annulus does (|l1 - l2| <= |a - A| <= l1 + l2)."""
    rrr = isp.RRR(base=(0, 0), platform=(0, 0), lengths=(2, 1), actuated=0)
    legs = [rrr, isp.RPR(base=(1, 0), platform=(0, 0)), isp.RPR(base=(0, 1), platform=(0, 0))]
    assert planar_reach_obstruction(legs, [1e300, 1.0, 1.0]) is None
    assert planar_reach_obstruction(legs, [0.3, 40.0, 1.0]) is not None   # 40 > 3 + 1 + 0


def test_symbolic_legs_are_skipped_and_bad_input_refused():
    a = sp.Symbol("a", positive=True)
    legs = [isp.RPR(base=(a, 0), platform=(0, 0)), isp.RPR(base=(1, 0), platform=(0, 0)),
            isp.RPR(base=(0, 1), platform=(0, 0))]
    assert planar_reach_obstruction(legs, [1e300, 1.0, 1.0]) is None     # the first leg is skipped
    legs = isp.examples.general_3rpr().legs
    with pytest.raises(InputError, match="one value per leg"):
        planar_reach_obstruction(legs, [1.0, 2.0])
    with pytest.raises(InputError, match=r"q\[1\]"):
        planar_reach_obstruction(legs, [1.0, float("nan"), 2.0])
    with pytest.raises(TypeError):
        planar_reach_obstruction(legs, "1, 2, 3")
    with pytest.raises(TypeError, match=r"q\[0\]"):
        planar_reach_obstruction(legs, [True, 2.0, 3.0])
    with pytest.raises(InputError, match="shape"):
        point_pairs_obstruction(np.zeros((3, 3)), np.zeros((2, 3)), [1, 1, 1])
    with pytest.raises(InputError, match="finite"):
        point_pairs_obstruction(np.zeros((2, 3)), np.zeros((2, 3)), [1, np.inf])
    with pytest.raises(InputError, match="non-negative"):
        point_pairs_obstruction(np.zeros((2, 3)), np.zeros((2, 3)), [1, -1])


def test_magnitudes():
    m = isp.examples.general_3rpr()
    assert planar_design_scale(m.legs) == 8.0
    got = prismatic_magnitude(m.legs, np.array([[1.0, -7.0, 2.0], [np.nan, 0, 0]]))
    assert got.tolist() == [7.0, np.inf]
    rrr = isp.examples.stigger_husty() if hasattr(isp.examples, "stigger_husty") else m
    assert prismatic_magnitude(rrr.legs, np.zeros((0, 3))).shape == (0,)
    with pytest.raises(InputError, match="shape"):
        prismatic_magnitude(m.legs, np.zeros((2, 2)))
