"""The spatial fast path (parameter homotopy) and its certificate, against msolve and identities.

Independent references: msolve on the exact system (``method="exact"``, a Groebner-basis solver
we did not write), the published 40 real modes of Dietmaier's design, and residuals of the
Euclidean leg equations written here.
"""

import warnings

import numpy as np
import pytest

import imagespace as isp
from imagespace.exceptions import DegenerateDesignError, InputError, NearSingularWarning
from imagespace.spatial.certify import exact_matrix, krawczyk_certify
from imagespace.spatial.study import rotation_matrix, study_point, translation

msolve = pytest.importorskip("imagespace.core.msolve")
needs_msolve = pytest.mark.skipif(not msolve.msolve_available(), reason="msolve is not installed")


def _design(seed):
    rng = np.random.default_rng(seed)
    return isp.GoughStewart(rng.integers(-8, 9, (6, 3)) / 8.0, rng.integers(-8, 9, (6, 3)) / 16.0), rng


def _euclidean_lengths(gs, s):
    R, t = rotation_matrix(s), translation(s)
    return np.linalg.norm(np.einsum("...ij,kj->...ki", R, gs.platform_points) + t[..., None, :]
                          - gs.base_points, axis=-1)


def test_dietmaier_40_real_modes_certified():
    gs, L = isp.examples.dietmaier_1998()
    res = gs.direct_kinematics(L, certify=True)
    assert res.certified and res.method == "homotopy+krawczyk"
    assert res.count == 40 and res.complex_count == 40                 # Dietmaier 1998
    assert np.allclose(_euclidean_lengths(gs, res.study_points), L, atol=1e-9)
    # the published posture (Martyushev's quotation of the data) is among them
    R_pub = np.array([[-0.040450357031281, -0.932229494397471, 0.359599691867884],
                      [0.983337493748685, 0.026695523074364, 0.179818582009314],
                      [-0.177231887661606, 0.360881585597300, 0.915616371179918]])
    t_pub = np.array([0.955868038233880, -0.046995628998516, -0.290013283037649])
    err = [np.abs(R - R_pub).max() + np.abs(t - t_pub).max()
           for R, t in zip(res.rotations, res.translations)]
    assert min(err) < 1e-6                                             # 6-decimal data


@needs_msolve
@pytest.mark.parametrize("seed", [3, pytest.param(4, marks=pytest.mark.slow),
                                  pytest.param(9, marks=pytest.mark.slow)])
def test_certified_equals_exact(seed):
    gs, rng = _design(seed)
    for L in (gs.inverse_kinematics(study_point(rng.normal(size=4), rng.uniform(-0.3, 0.3, 3) + [0, 0, 1.2])),
              rng.integers(48, 112, 6) / 64.0):
        cert = gs.direct_kinematics(L, certify=True)
        exact = gs.direct_kinematics(L, method="exact")
        assert cert.certified and exact.certified
        assert cert.count == exact.count
        if cert.count:
            key = lambda p: p[np.lexsort(p.T[::-1])]                    # noqa: E731
            assert np.allclose(key(cert.study_points), key(exact.study_points), atol=1e-9)


def test_krawczyk_refuses_a_point_that_is_not_a_solution():
    gs, rng = _design(3)
    s = study_point(rng.normal(size=4), [0.1, -0.2, 1.3])
    L = gs.inverse_kinematics(s)
    from imagespace.spatial.quadrics import sphere_quadric_exact, study_quadric_matrix
    Q = np.array([sphere_quadric_exact(gs.base_points[i], gs.platform_points[i], L[i]) for i in range(6)]
                 + [exact_matrix(study_quadric_matrix())])
    good = krawczyk_certify(Q, s[None].astype(complex))
    assert good.certified[0] and good.real[0] == 1
    # the proven box holds the generating pose (in the chart r . x = 1 of the result)
    r = good.chart
    z = s / (r @ s[:4])
    assert np.all(np.abs(good.points[0] - z) <= good.radii[0])
    # a float proposal 1e-3 off is polished by Newton first: the box proven is the same solution's
    moved = s.copy()
    moved[5] += 1e-3
    again = krawczyk_certify(Q, moved[None].astype(complex))
    assert again.certified[0] and np.all(np.abs(again.points[0] - z) <= again.radii[0])
    # a singular point is never proven: the double point of x^2 = 0 style systems has no
    # non-singular solution in any box (Study quadric taken twice: a rank-deficient Jacobian)
    Q2 = Q.copy()
    Q2[5] = Q2[6]
    sing = krawczyk_certify(Q2, s[None].astype(complex))
    assert not sing.certified[0]


def test_half_turn_mode_is_found():
    gs, rng = _design(5)
    s = study_point([0.0, 0.6, 0.0, 0.8], [0.25, -0.125, 1.5])         # x0 = 0: a half-turn
    res = gs.direct_kinematics(gs.inverse_kinematics(s), certify=True)
    assert res.certified
    # projective equality (x0 of the float mode is ~1e-16 of either sign, which fixes its sign)
    err = np.minimum(np.abs(res.study_points - s).max(axis=1), np.abs(res.study_points + s).max(axis=1))
    assert np.min(err) < 1e-9
    k = int(np.argmin(err))
    assert np.allclose(res.rotations[k], rotation_matrix(s), atol=1e-9)
    assert np.allclose(res.translations[k], translation(s), atol=1e-9)


def _singular_pose(gs, rng):
    """A pose on the singularity surface: bisection of det J along a vertical line."""
    q = rng.normal(size=4)
    lo, hi = 0.3, 3.0
    f = lambda z: np.linalg.det(gs.jacobian(study_point(q, [0.05, -0.1, z])))  # noqa: E731
    zs = np.linspace(lo, hi, 400)
    vals = np.array([f(z) for z in zs])
    k = np.flatnonzero(np.sign(vals[:-1]) != np.sign(vals[1:]))
    if not k.size:
        return None
    a, b = zs[k[0]], zs[k[0] + 1]
    for _ in range(200):
        m = 0.5 * (a + b)
        if m in (a, b):
            break
        if np.sign(f(m)) == np.sign(f(a)):
            a = m
        else:
            b = m
    return study_point(q, [0.05, -0.1, a])


@needs_msolve
@pytest.mark.slow
def test_a_double_mode_is_flagged_and_decided_exactly():
    # lengths of a singular pose: two real modes meet there. The fast path must say it is not
    # sure, and the certified answer must equal msolve's
    for seed in range(20, 40):
        gs, rng = _design(seed)
        s = _singular_pose(gs, rng)
        if s is not None:
            break
    L = gs.inverse_kinematics(s)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fast = gs.direct_kinematics(L)
    exact = gs.direct_kinematics(L, method="exact")
    cert = gs.direct_kinematics(L, certify=True)
    assert cert.certified and cert.count == exact.count
    if not fast.reliable:
        assert any(issubclass(w.category, NearSingularWarning) for w in caught)
    else:
        assert fast.count == exact.count                               # reliable means right


def test_batch_masks_bad_rows():
    gs, rng = _design(3)
    L = gs.inverse_kinematics(study_point(rng.normal(size=(3, 4)), [[0, 0, 1.2]] * 3))
    L[1, 2] = np.nan
    L[2, 0] = -1.0
    b = gs.direct_kinematics_batch(L)
    assert b.row_ok.tolist() == [True, False, False]
    assert b.counts[1] == b.counts[2] == 0 and b.counts[0] >= 1
    assert np.allclose(_euclidean_lengths(gs, b[0].study_points), L[0], atol=1e-9)
    with pytest.raises(InputError, match="lengths"):
        gs.direct_kinematics_batch(np.ones((2, 5)))


def test_batch_rows_equal_single_calls():
    gs, rng = _design(6)
    L = gs.inverse_kinematics(study_point(rng.normal(size=(6, 4)), rng.uniform(-0.3, 0.3, (6, 3)) + [0, 0, 1.2]))
    b = gs.direct_kinematics_batch(L)
    for i in range(6):
        one = gs.direct_kinematics(L[i])
        assert b.counts[i] == one.count
        assert np.allclose(b[i].study_points, one.study_points)
        # every mode satisfies the Euclidean leg equations
        assert np.allclose(_euclidean_lengths(gs, one.study_points), L[i], atol=1e-9)


@needs_msolve
def test_architecture_singular_design_is_reported():
    # planar base anchors on a conic (the parabola y = x^2, exact in binary), the platform a
    # half-size copy: affinely related planar hexagons on a conic are architecturally singular
    # (Karger 2003), a continuum of poses for every reachable length vector
    xs = np.array([-1.0, -0.5, 0.25, 0.5, 1.0, 1.5])
    a = np.stack([xs, xs ** 2, np.zeros(6)], axis=1)
    gs = isp.GoughStewart(a, a / 2)
    assert gs.architecturally_singular
    # independent check: the numeric det J is ~0 relative to Hadamard's bound at random poses
    rng = np.random.default_rng(8)
    for _ in range(5):
        J = gs.jacobian(study_point(rng.normal(size=4), rng.normal(size=3)))
        assert abs(np.linalg.det(J)) < 1e-12 * np.prod(np.linalg.norm(J, axis=1))
    L = gs.inverse_kinematics(study_point([1.0, 0.25, -0.5, 0.125], [0.25, 0.5, 2.0]))
    for kw in ({}, {"method": "exact"}, {"certify": True}):
        with pytest.raises(DegenerateDesignError, match="architecturally singular"):
            gs.direct_kinematics(L, **kw)
    with pytest.raises(DegenerateDesignError, match="architecturally singular"):
        gs.direct_kinematics_batch(L[None])
    # a general design is not: its exact det J is non-zero somewhere
    assert not _design(3)[0].architecturally_singular
