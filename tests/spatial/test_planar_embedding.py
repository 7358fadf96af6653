"""The planar image space embedded in Study's quadric (issue 18, "Study's map", the planar subspace).

The planar image space is the subspace ``x1 = x2 = y0 = y3 = 0`` with ``(p0, p1, p2, p3) ->
(p0, 0, 0, p1, 0, p3, -p2, 0)``. The issue's test: a planar 3-RPR solved in the spatial model (each
leg a sphere quadric with base and platform points in ``z = 0``, Study's quadric, the four linear
equations of the subspace) has exactly the planar module's assembly modes. The spatial system is
solved exactly with msolve (``tests/msolve_ref.py``) in the chart ``x0 = 1`` and on the stratum
``x0 = 0`` (half-turns, chart ``x3 = 1``); ``x = 0`` is not a displacement and is in neither.
"""

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import imagespace as isp
from imagespace.core.legs import RPR
from imagespace.manipulator import PlanarParallel
from imagespace.spatial.quadrics import sphere_quadric
from imagespace.spatial.study import (compose_study, planar_to_study, rotation_matrix, study_condition,
                                      study_point, study_symbols, study_to_planar, translation)
from msolve_ref import POSITIVE_DIMENSIONAL, msolve_available, real_solutions

needs_msolve = pytest.mark.skipif(not msolve_available(), reason="msolve not installed")

pose_st = st.tuples(st.floats(-20, 20, allow_nan=False), st.floats(-20, 20, allow_nan=False),
                    st.floats(-np.pi, np.pi, allow_nan=False))


def planar_R(phi):
    c, s = np.cos(phi), np.sin(phi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


# --------------------------------------------------------------------------- the embedding

@pytest.mark.slow
@given(pose_st)
@settings(max_examples=150, deadline=None)
def test_embedded_image_point_has_the_planar_pose(pose):
    x, y, phi = pose
    s = planar_to_study(isp.image_point(pose))
    assert s[1] == s[2] == s[4] == s[7] == 0.0
    assert abs(study_condition(s)) < 1e-12
    assert np.allclose(rotation_matrix(s), planar_R(phi), atol=1e-12)
    assert np.allclose(translation(s), [x, y, 0.0], atol=1e-12 * (1 + abs(x) + abs(y)))
    # the same point as Study's map of the pose (up to the factor of a representative)
    ref = study_point(planar_R(phi), [x, y, 0.0])
    ratio = s[np.argmax(np.abs(s))] / ref[np.argmax(np.abs(s))]
    assert np.allclose(s, ratio * ref, atol=1e-11 * (1 + abs(x) + abs(y)))
    # and back
    back = study_to_planar(s)
    assert np.array_equal(back, isp.image_point(pose))
    assert np.allclose(isp.pose_of(study_to_planar(ref))[:2], [x, y], atol=1e-10 * (1 + abs(x) + abs(y)))


@given(pose_st, pose_st)
@settings(max_examples=100, deadline=None)
def test_composition_commutes_with_the_embedding(a, b):
    pa, pb = isp.image_point(a), isp.image_point(b)
    planar = planar_to_study(isp.compose(pa, pb))
    spatial = compose_study(planar_to_study(pa), planar_to_study(pb))
    assert np.allclose(planar / np.linalg.norm(planar[:4]), spatial, atol=1e-10 * (1 + np.abs(a[:2]).max()
                                                                                    + np.abs(b[:2]).max())) \
        or np.allclose(-planar / np.linalg.norm(planar[:4]), spatial, atol=1e-10 * (1 + np.abs(a[:2]).max()
                                                                                      + np.abs(b[:2]).max()))


def test_embedding_of_batches_and_symbols(rng):
    poses = np.column_stack([rng.normal(size=(20, 2)) * 5, rng.uniform(-np.pi, np.pi, 20)])
    P = isp.image_point(poses)
    S = planar_to_study(P)
    assert S.shape == (20, 8)
    assert np.array_equal(study_to_planar(S), P)
    p = sp.symbols("p0:4")
    assert list(planar_to_study(list(p))) == [p[0], 0, 0, p[1], 0, p[3], -p[2], 0]
    # the exact planar map of a symbolic pose lands on Study's quadric and on the subspace
    x, y, phi = sp.symbols("x y phi", real=True)
    s = planar_to_study(list(isp.image_point([x, y, phi])))
    assert sp.simplify(study_condition(list(s))) == 0


def test_study_to_planar_refuses_non_planar_points():
    from imagespace.exceptions import InputError
    for bad in ([1, 0.1, 0, 0, 0, 0, 0, 0], [1, 0, 0, 0, 0, 0, 0, 0.3], [1, 0, 0, 0, 1e-3, 0, 0, 0]):
        with pytest.raises(InputError, match="^s must be a planar displacement"):
            study_to_planar(bad)


# --------------------------------------------------------------------------- the test

def spatial_planar_dk(m, q):
    """Real modes of the planar 3-RPR ``m`` at ``q`` from the spatial model, solved by msolve.

    Returns the planar poses ``(k, 3)`` of the real solutions.
    """
    z = study_symbols()
    x0, x1, x2, x3, y0, y1, y2, y3 = z
    zz = sp.Matrix(z)
    quads = []
    for leg, qi in zip(m.legs, q):
        a = [sp.Rational(v) for v in leg.base] + [0]       # floats would enter as binary rationals
        b = [sp.Rational(v) for v in leg.platform] + [0]
        L = qi if isinstance(qi, sp.Basic) else sp.Rational(float(qi))
        Q = sphere_quadric(a, b, L)                         # exact: the symbolic face
        quads.append(sp.expand((zz.T * Q * zz)[0, 0]))
    study = x0 * y0 + x1 * y1 + x2 * y2 + x3 * y3
    subspace = {x1: 0, x2: 0, y0: 0, y3: 0}
    polys = [sp.expand(e.subs(subspace)) for e in quads + [study]]
    assert polys[-1] == 0          # Study's quadric holds on the whole planar subspace
    polys = [p for p in polys if p != 0]
    for p in polys:                  # exact coefficients, no float entered
        assert all(c.is_Rational for c in sp.Poly(p, x0, x3, y1, y2).coeffs())
    poses = []
    # chart x0 = 1: unknowns x3, y1, y2
    sols = real_solutions([p.subs(x0, 1) for p in polys], [x3, y1, y2])
    assert sols != POSITIVE_DIMENSIONAL
    for box in sols:
        v = [float((lo + hi) / 2) for lo, hi in box]
        s = np.array([1.0, 0, 0, v[0], 0, v[1], v[2], 0])
        poses.append(isp.pose_of(study_to_planar(s)))
    # the half-turn stratum x0 = 0, chart x3 = 1: unknowns y1, y2
    sols = real_solutions([p.subs({x0: 0, x3: 1}) for p in polys], [y1, y2])
    assert sols != POSITIVE_DIMENSIONAL
    for box in sols:
        v = [float((lo + hi) / 2) for lo, hi in box]
        s = np.array([0.0, 0, 0, 1.0, 0, v[0], v[1], 0])
        poses.append(isp.pose_of(study_to_planar(s)))
    return np.array(poses).reshape(-1, 3)


def assert_same_modes(spatial, planar, tol=1e-9):
    assert len(spatial) == len(planar), (spatial, planar)
    unused = list(range(len(planar)))
    for p in spatial:
        match = [j for j in unused
                 if np.allclose(p[:2], planar[j][:2], atol=tol * (1 + np.abs(p[:2]).max()))
                 and abs(wrap(p[2] - planar[j][2])) <= tol]
        assert match, (p, planar)
        unused.remove(match[0])


def half_turn_lengths(m, x, y):
    """Exact leg lengths (sympy square roots) of the planar pose ``(x, y, pi)``."""
    out = []
    for leg in m.legs:
        X = (x - leg.platform[0] - leg.base[0], y - leg.platform[1] - leg.base[1])   # R = -I
        out.append(sp.sqrt(sp.Integer(X[0]) ** 2 + sp.Integer(X[1]) ** 2))
    return out


def rational_3rpr(rng):
    legs = [RPR(base=tuple(int(v) for v in rng.integers(-9, 10, 2)),
                platform=tuple(int(v) for v in rng.integers(-6, 7, 2))) for _ in range(3)]
    return PlanarParallel(legs, name="seeded rational 3-RPR")


CASES = ["general_3rpr q_example", "general_3rpr half-turn", "seeded design, IK of a random pose",
         "seeded design, half-turn"]


@pytest.mark.slow
@needs_msolve
@pytest.mark.parametrize("case", CASES)
def test_planar_mechanism_solved_in_the_spatial_model_gives_the_planar_modes(case):
    rng = np.random.default_rng(18 + CASES.index(case))
    if case.startswith("general_3rpr"):
        m = isp.examples.general_3rpr()
    else:
        while True:          # a seeded design with a non-degenerate triangle on both sides
            m = rational_3rpr(rng)
            A = np.array([leg.base for leg in m.legs], dtype=float)
            B = np.array([leg.platform for leg in m.legs], dtype=float)
            if abs(np.linalg.det(A[1:] - A[0])) > 4 and \
                    abs(np.linalg.det(B[1:] - B[0])) > 4:
                break
    if case == "general_3rpr q_example":
        q = list(m.q_example)
    elif case.endswith("half-turn"):
        q = half_turn_lengths(m, int(rng.integers(-3, 4)), int(rng.integers(-3, 4)))
    else:
        pose = np.array([rng.normal() * 2, rng.normal() * 2, rng.uniform(-np.pi, np.pi)])
        q = list(m.inverse_kinematics(pose))
    planar = np.array([md.pose for md in m.direct_kinematics(q, certify=True)]).reshape(-1, 3)
    spatial = spatial_planar_dk(m, q)
    assert len(spatial) >= 2
    assert_same_modes(spatial, planar)
    if case == "general_3rpr q_example":
        assert len(spatial) == 6
    if case.endswith("half-turn"):
        assert any(abs(abs(p[2]) - np.pi) < 1e-12 for p in spatial)
