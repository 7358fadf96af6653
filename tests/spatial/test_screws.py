"""Screws (seed 001): reciprocity, the printed constraint wrenches, constraint singularities exactly
where s1 s2 s3 = c1 c2 c3, and the planar link to the image-space quartic."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.spatial.screws import (TranslationalFiveR, constraint_analysis, helical, planar_leg_wrenches, prismatic,
                               reciprocal_product, reciprocal_system, revolute, singularity_fractions, transfer)


def test_reciprocal_product_is_invariant_under_a_change_of_reference_point(rng):
    for _ in range(20):
        t = helical(rng.normal(size=3), rng.normal(size=3), rng.normal())
        w = np.concatenate([rng.normal(size=3), rng.normal(size=3)])
        r = rng.normal(size=3)
        assert np.isclose(reciprocal_product(t, w),
                          reciprocal_product(transfer(t, r, "twist"), transfer(w, r, "wrench")))
    # and it is not the plain dot product
    t, w = revolute([0, 0, 1], [1, 0, 0]), np.array([0, 0, 0, 0, 0, 1.0])
    assert reciprocal_product(t, w) == 1.0 and t @ w == 0.0


@pytest.mark.slow
def test_chain_1_reciprocal_wrench_symbolically():
    th = sp.Symbol("theta1", real=True)
    e = sp.Matrix([1, 0, 0])
    d = sp.Matrix([0, sp.cos(th), sp.sin(th)])
    pts = [sp.Matrix([sp.Rational(-1), sp.Rational(1, 2), 0]), sp.Matrix([sp.Rational(1, 3), 2, -1]),
           sp.Matrix([sp.Rational(2, 5), sp.Rational(-1, 7), 3]), sp.Matrix([1, 1, 1])]
    twists = [revolute(e, pts[0]), revolute(d, pts[1]), revolute(d, pts[2]), revolute(d, pts[3]), revolute(e, pts[3])]
    W = reciprocal_system(twists)
    assert len(W) == 1
    w = W[0]
    assert all(sp.simplify(w[k]) == 0 for k in range(4))
    assert sp.simplify(w[4] * (-sp.cos(th)) - w[5] * sp.sin(th)) == 0        # proportional to (sin, -cos)


def test_chain_1_reciprocal_wrench_numerically(rng):
    for _ in range(10):
        mech = TranslationalFiveR(a=rng.uniform(0.8, 1.5), b=rng.uniform(0.3, 0.8), c=rng.uniform(0.1, 0.3),
                                  l1=rng.uniform(0.9, 1.3), l2=rng.uniform(0.9, 1.3))
        P = rng.uniform(-0.2, 0.2, 3)
        try:
            legs = mech.leg_twists(P)
        except isp.InputError:
            continue
        th = mech.thetas(P)[0]
        printed = [np.array([0, 0, 0, 0, np.sin(th[0]), -np.cos(th[0])]),
                   np.array([0, 0, 0, -np.cos(th[1]), 0, np.sin(th[1])]),
                   np.array([0, 0, 0, np.sin(th[2]), -np.cos(th[2]), 0])]
        for T, ref in zip(legs, printed):
            W = reciprocal_system(T)
            assert W.shape == (1, 6)
            assert np.isclose(abs(W[0] @ ref), np.linalg.norm(W[0]) * np.linalg.norm(ref))


def _singular_position(mech, rng):
    """Bisect the closed-form condition along a random segment of positions."""
    for _ in range(200):
        a, b = rng.uniform(-0.4, 0.4, 3), rng.uniform(-0.4, 0.4, 3)
        fa, fb = (mech.couple_condition(mech.thetas(p))[0] for p in (a, b))
        if fa * fb < 0:
            for _ in range(80):
                mid = (a + b) / 2
                fm = mech.couple_condition(mech.thetas(mid))[0]
                a, b, fa = (mid, b, fm) if fm * fa > 0 else (a, mid, fa)
            return (a + b) / 2
    raise AssertionError("no sign change found")


@pytest.mark.slow
def test_rank_drops_exactly_on_the_closed_form_condition(rng):
    mech = TranslationalFiveR()
    translations = np.hstack([np.zeros((3, 3)), np.eye(3)])
    hits = 0
    for _ in range(5):
        P = _singular_position(mech, rng)
        try:
            legs = mech.leg_twists(P)
        except isp.InputError:
            continue
        a = constraint_analysis(legs, 3, actuated=[0, 0, 0], tol=1e-7, intended=translations)
        assert a.constraint_singular and "constraint" in a.kind
        # the free rotation: the null vector of the three couples
        M = a.constraint_wrenches[:, 3:]
        omega = np.linalg.svd(M)[2][-1]
        assert a.gained_twists.shape == (1, 6)
        rot = a.gained_twists[0]                      # orthogonal to the translations: a pure rotation
        assert np.isclose(abs(rot[:3] @ omega), 1.0, rtol=1e-6) and np.allclose(rot[3:], 0, atol=1e-6)
        # near but not on the condition: regular
        grad = np.array([(mech.couple_condition(mech.thetas(P + 1e-6 * e))[0] -
                          mech.couple_condition(mech.thetas(P - 1e-6 * e))[0]) / 2e-6 for e in np.eye(3)])
        Q = P + 1e-3 * grad / np.linalg.norm(grad)
        assert not constraint_analysis(mech.leg_twists(Q), 3, tol=1e-7).constraint_singular
        hits += 1
    assert hits >= 3


def test_planar_wrench_determinant_is_the_image_space_quartic(rng):
    m = isp.examples.general_3rpr()
    S = m.singularity_surface()
    for _ in range(50):
        pose = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-2, 2)])
        W, d = planar_leg_wrenches(m, pose)
        assert np.isclose(S.at_poses(pose), -128 * np.prod(d) * np.linalg.det(W), rtol=1e-8)
    # at a concurrent pose (found by bisection on det W) the quartic vanishes too
    det = lambda p: np.linalg.det(planar_leg_wrenches(m, p)[0])
    for _ in range(100):
        a = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-1, 1)])
        b = a + rng.normal(size=3)
        if det(a) * det(b) < 0:
            break
    fa = det(a)
    assert fa * det(b) < 0
    for _ in range(60):
        mid = (a + b) / 2
        fm = np.linalg.det(planar_leg_wrenches(m, mid)[0])
        a, b, fa = (mid, b, fm) if fm * fa > 0 else (a, mid, fa)
    v, g = S.value_and_gradient(isp.image_point((a + b) / 2))
    assert abs(v) < 1e-9 * np.linalg.norm(g)


@pytest.mark.slow
def test_fractions_are_consistent():
    f = singularity_fractions(TranslationalFiveR(), n=300, eps=0.05)
    assert f["reachable"] > 200
    assert f["all"] >= max(f["constraint"], f["ignoring_constraints"])
    assert f["ignoring_constraints"] >= f["input_output"]


def test_bad_input():
    with pytest.raises(isp.InputError, match="zero"):
        reciprocal_product(np.zeros(6), np.ones(6))
    with pytest.raises(isp.InputError, match="6"):
        reciprocal_system(np.ones((3, 5)))
    with pytest.raises(isp.InputError, match="at most 6"):
        reciprocal_system(np.vstack([revolute(np.random.default_rng(k).normal(size=3), [0, 0, k]) for k in range(7)]))
    with pytest.raises(isp.InputError, match="zero vector"):
        revolute([0, 0, 0], [1, 2, 3])
    with pytest.raises(isp.InputError, match="kind"):
        transfer(prismatic([1, 0, 0]), [0, 0, 1], "force")
