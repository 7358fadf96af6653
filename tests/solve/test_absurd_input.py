"""Absurd joint values (issue [14]): answered exactly and at once where a reach bound decides,
the float and certified paths agree far out, a bad row is masked and never aborts a batch.
Truth: sympy's Sturm count of the real roots of the exact kinematic polynomial (not the code's
root finder) and the reach inequality worked out by hand."""

import warnings

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.exceptions import DegenerateDesignError, InputError
from imagespace.solve.certified import exact_coefficients


def sturm_count(m, q):
    """Distinct real roots of the exact kinematic polynomial (sympy), half-turn included."""
    t = sp.Symbol("t")
    P = exact_coefficients(m, q)
    count = sp.Poly(sum(c * t**k for k, c in enumerate(P)), t).count_roots() \
        if any(c != 0 for c in P[:-1]) else 0
    return count + int(P[-1] == 0)


@pytest.fixture(scope="module")
def m():
    return isp.examples.general_3rpr()


def test_a_leg_far_beyond_reach_is_decided_exactly(m):
    # legs 0 and 1: |rho0 - rho1| <= |A0 - A1| + |a0 - a1| = sqrt(226) + sqrt(85) < 25
    q = [1e300, 5, 10]
    cm = m.direct_kinematics(q, certify=True)
    assert list(cm) == [] and cm.certificate.certified and cm.certificate.count == 0
    assert cm.certificate.method.startswith("reach bound")
    assert m.direct_kinematics(q) == []
    counts, path = m.certified_root_counts([q, m.q_example_float])
    assert counts.tolist() == [0, 6] and path.tolist()[0] == "reach"


def test_absurdly_small_legs(m):
    cm = m.direct_kinematics([1e-300] * 3, certify=True)
    assert list(cm) == [] and "base distance" in cm.certificate.method
    assert m.direct_kinematics([1e-300] * 3) == []


@pytest.mark.parametrize("e", [1e7, 1e20, 1e300])
def test_float_and_certified_paths_agree_far_out(m, e):
    """Equal legs far beyond the design: the float path said "architecture singularity" from
    1e7 on; both paths must now give the exact count (0 for this design)."""
    truth = sturm_count(m, [e] * 3) if e < 1e100 else 0
    assert len(m.direct_kinematics([e] * 3)) == truth
    assert len(m.direct_kinematics([e] * 3, certify=True)) == truth


def test_far_modes_are_found(m):
    """[1e7, 1e7 + 3, 1e7 - 4] has two real modes ten million units away; the float path
    returned none, silently."""
    q = [1e7, 1e7 + 3, 1e7 - 4]
    truth = sturm_count(m, q)
    assert truth == 2
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(m.direct_kinematics(q)) == truth
    modes = m.direct_kinematics(q, certify=True)
    assert len(modes) == truth
    assert max(md.residual for md in modes) < 1e-7


@pytest.mark.parametrize("certify", [False, True])
@pytest.mark.parametrize("method", ["numpy", "kernel"])
def test_a_batch_is_not_aborted(m, certify, method):
    if method == "kernel" and isp.solve.proof.batch_kernel(m) is None:
        pytest.skip("no kernel (numba missing)")
    Q = np.array([m.q_example_float, [1e300, 5, 10], [1e20] * 3, [np.nan, 1, 1],
                  [1e7, 1e7 + 3, 1e7 - 4], [1e-300] * 3])
    r = m.direct_kinematics_batch(Q, certify=certify, method=method)
    assert r.count.tolist() == [6, 0, 0, 0, 2, 0]
    assert r.row_ok.tolist() == [True, True, True, False, True, True]
    assert list(r.errors) == [3]
    if certify:
        assert r.certified_roots.tolist() == [6, 0, 0, -1, 2, 0]
        assert r.certificate_path.tolist()[1] == "reach"


def test_dask_masks_nothing_it_can_answer(m):
    pytest.importorskip("dask")
    Q = np.array([m.q_example_float, [1e300, 5, 10], [np.nan, 1, 1]])
    out = m.direct_kinematics_dask(Q, certify=True).compute(scheduler="synchronous")
    assert out["count"].tolist() == [6, 0, 0] and out["row_ok"].tolist() == [True, True, False]
    assert out["certified_roots"].tolist() == [6, 0, -1]


def test_include_complex_far_out_is_refused(m):
    with pytest.raises(InputError, match="include_complex"):
        m.direct_kinematics([1e20] * 3, include_complex=True)


def test_a_true_continuum_still_raises_far_out():
    """Congruent base and platform, equal legs: the platform translates on a circle (phi = 0), a
    continuum at every length; far out, even beyond the float range, the certified path finds it
    exactly (the positions at phi = 0 are a circle: the 2x2 minors of the position rows vanish
    there), per call and per batch row, with a message."""
    legs = [isp.RPR(base=(0, 0), platform=(0, 0)), isp.RPR(base=(4, 0), platform=(4, 0)),
            isp.RPR(base=(1, 3), platform=(1, 3))]
    m = isp.PlanarParallel(legs)
    for certify in (False, True):
        for q in ([1e5] * 3, [1e300] * 3):
            with pytest.raises(DegenerateDesignError, match="continuum"):
                m.direct_kinematics(q, certify=certify)
    r = m.direct_kinematics_batch(np.array([[1e5] * 3, [1e300] * 3, [3.0, 2.0, 4.0]]), certify=True)
    assert r.row_ok.tolist() == [False, False, True]
    assert r.certificate_path.tolist()[:2] == ["continuum", "continuum"]
    assert "continuum" in r.errors[0] and "continuum" in r.errors[1]


# --------------------------------------------------------------------------- spatial

@pytest.fixture(scope="module")
def gs():
    rng = np.random.default_rng(0)
    return isp.GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))


def test_spatial_tiny_legs_are_proven_empty(gs):
    # the base anchors are not congruent to the platform's: legs of 1e-300 cannot close them
    for kw in ({}, {"certify": True}, {"method": "exact"}):
        r = gs.direct_kinematics([1e-300] * 6, **kw)
        assert r.count == 0 and r.certified and r.method == "reach" and r.complex_count == -1
    m = isp.spatial.ThreeRPS(np.eye(3), 0.5 * np.eye(3))
    r = m.direct_kinematics([1e-300] * 3, certify=True)
    assert r.count == 0 and r.certified and r.method == "reach"


def test_spatial_leg_beyond_reach_is_proven_empty(gs):
    # leg 0 of 1e300 next to leg 1 of length 1: |L0 - L1| > |a0 - a1| + |b0 - b1|
    r = gs.direct_kinematics([1e300, 1, 1, 1, 1, 1], certify=True)
    assert r.count == 0 and r.certified and r.method == "reach"


def test_spatial_far_lengths_are_refused_clearly(gs):
    for kw in ({}, {"certify": True}, {"method": "exact"}):
        with pytest.raises(InputError, match=r"lengths = \[1e\+300"):
            gs.direct_kinematics([1e300] * 6, **kw)
    with pytest.raises(InputError, match="certify=True or method='exact'"):
        gs.direct_kinematics([1e4] * 6)
    m = isp.spatial.ThreeRPS(np.eye(3), 0.5 * np.eye(3))
    with pytest.raises(InputError, match="lengths"):
        m.direct_kinematics([1e300] * 3, certify=True)


@pytest.mark.slow
def test_spatial_batch_masks_far_rows(gs):
    L = np.array([[2.0] * 6, [1e300] * 6, [1e-300] * 6, [1e300, 1, 1, 1, 1, 1]])
    b = gs.direct_kinematics_batch(L)
    ref = gs.direct_kinematics(L[0])
    assert b.row_ok.tolist() == [True, False, True, True]
    assert b.counts.tolist() == [ref.count, 0, 0, 0]
    assert b.certified.tolist()[1:] == [False, True, True]
    assert b[2].method == "reach"
    m = isp.spatial.ThreeRPS(np.eye(3), 0.5 * np.eye(3))
    b = m.direct_kinematics_batch([[1.0] * 3, [1e300] * 3, [1e-300] * 3], certify=True)
    assert b.row_ok.tolist() == [True, False, True] and b.certified.tolist() == [True, False, True]
