"""imagespace.spatial.exact: the four Study strata, against hand-solved systems and Gough-Stewart
platforms whose leg constraints are written here from quaternion algebra (the convention of
docs: a platform point b lands at R b + t = (x b x~ + 2 y x~) / (x . x))."""

import time
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from imagespace.core.msolve import msolve_available
from imagespace.exceptions import DegenerateDesignError, InputError
from imagespace.spatial.exact import STUDY_STRATA, ExactStudyResult, exact_real_study_points

pytestmark = pytest.mark.skipif(not msolve_available(), reason="msolve is not installed")

S = sp.symbols("x0:4") + sp.symbols("y0:4")
x0, x1, x2, x3, y0, y1, y2, y3 = S
X, Y = S[:4], S[4:]
XX = sum(v * v for v in X)


# --------------------------------------------------------------------------- quaternions

def qmul(p, q):
    a0, a1, a2, a3 = p
    b0, b1, b2, b3 = q
    return (a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
            a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
            a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0)


def conj(q):
    return (q[0], -q[1], -q[2], -q[3])


def pure(v):
    return (0, v[0], v[1], v[2])


def rotate(q, v):
    """R v = q v q~ / (q . q), exact for rational q and v."""
    w = qmul(qmul(q, pure(v)), conj(q))
    n = sum(c * c for c in q)
    return [c / n for c in w[1:]]


def study_of(q, t):
    """Study point (x : y) of the pose (rotation quaternion q, translation t): y = t x / 2."""
    return list(q) + [c / 2 for c in qmul(pure(t), q)]


def leg_quadric(a, b, length2):
    """|R b + t - a|^2 = L^2 as a quadric in Study coordinates: |x b + 2 y - a x|^2 - L^2 x . x.

    N = x b x~ + 2 y x~ - a (x . x) = M x~ with M = x b + 2 y - a x, and N is (x . x)(R b + t - a)
    plus the scalar part 2 (x . y), which vanishes on Study's quadric. So there
    (x . x)^2 (|R b + t - a|^2 - L^2) = |N|^2 - L^2 (x . x)^2 = (x . x)(|M|^2 - L^2 x . x),
    and the quadric is the second factor (test_leg_quadric_is_the_reduced_quartic checks it).
    """
    M = [u + 2 * v - w for u, v, w in zip(qmul(X, pure(b)), Y, qmul(pure(a), X))]
    return sp.expand(sum(c * c for c in M) - length2 * XX)


def leg_quartic(a, b, length2):
    """|N|^2 - L^2 (x . x)^2, the leg condition times (x . x)^2 on Study's quadric."""
    N = [u + 2 * v - w * XX for u, v, w in zip(qmul(qmul(X, pure(b)), conj(X)),
                                                 qmul(Y, conj(X)), pure(a))]
    return sp.expand(sum(c * c for c in N) - length2 * XX**2)


def rational(rng, scale=8, span=40):
    return sp.Rational(int(rng.integers(-span, span + 1)), scale)


def random_design(rng):
    a = [[rational(rng) for _ in range(3)] for _ in range(6)]
    b = [[rational(rng) for _ in range(3)] for _ in range(6)]
    return a, b


def squared_lengths(a, b, q, t):
    out = []
    for ai, bi in zip(a, b):
        d = [r + tt - s for r, tt, s in zip(rotate(q, bi), t, ai)]
        out.append(sum(c * c for c in d))
    return out


def chart_point(study, k):
    """The stratum-k representative (x_k = 1) as Fractions."""
    lead = sp.Rational(study[k])
    return [Fraction(int(sp.Rational(c / lead).p), int(sp.Rational(c / lead).q)) for c in study]


def contains(box, point):
    return all(lo <= p <= hi for (lo, hi), p in zip(box, point))


def euclidean_residuals(a, b, length2, points):
    """max | |R b + t - a|^2 - L^2 | over the legs, for each normalised Study point (numpy)."""
    out = []
    for s in points:
        q, yv = s[:4], s[4:]
        n = q @ q
        t = 2 * np.array(qmul(yv, conj(q))[1:]) / n
        R_b = [np.array(qmul(qmul(q, pure(np.array(bi, float))), conj(q))[1:]) / n for bi in b]
        out.append(max(abs(np.sum((rb + t - np.array(ai, float))**2) - float(l2))
                       for rb, ai, l2 in zip(R_b, a, length2)))
    return np.array(out)


# --------------------------------------------------------------------------- hand-solved systems

HALF_TURN_SYSTEM = [
    x0**2 + x2**2,          # real points: x0 = x2 = 0, so x0 = 0: only half-turns are real
    x3,
    y0 - x1,
    y1 - x0,
    y2**2 - 4 * x1**2,
    y3 - 3 * x1 - x0,
]


def test_half_turns_are_found():
    # Real solutions: x0 = x2 = x3 = 0, stratum x1 = 1: y0 = 1, y1 = 0, y2 = +-2, y3 = 3, and
    # Study's quadric x1 y1 + x2 y2 = 0 holds. In the chart x0 = 1: x2 = +-i, x3 = 0, y0 = x1,
    # y1 = 1, Study gives 2 x1 + x2 y2 = 0, so 4 x1^2 = x2^2 y2^2 = -y2^2 and y2^2 = 4 x1^2
    # forces y2^2 = 0: two non-real points of multiplicity 2, complex count 4. In the stratum
    # x1 = 1: x2 y2 = 0 with y2 = +-2 makes x2 = 0 simple: 2 points. x0 = x1 = 0 contradicts
    # x0^2 + x2^2 = 0 with x2 = 1, and x3 = 1 contradicts x3 = 0.
    res = exact_real_study_points(HALF_TURN_SYSTEM)
    assert isinstance(res, ExactStudyResult)
    assert res.count == 2 and res.strata.tolist() == [1, 1]
    assert res.complex_count == 4 and res.stratum_complex_counts == (4, 2, 0, 0)
    expected = [[0, 1, 0, 0, 1, 0, -2, 3], [0, 1, 0, 0, 1, 0, 2, 3]]
    assert np.array_equal(res.study_points, np.array(expected, float))
    for box, point in zip(res.boxes, expected):
        assert contains(box, point)
    assert STUDY_STRATA[1] == "x0 = 0, x1 = 1"


def test_every_stratum_is_searched():
    # one real point in each stratum: x = e_k, y = 0 (the identity and three half-turns) are the
    # solutions of x_i x_j = 0 (i < j) and y = 0; x0 = 1 has exactly the identity
    eqs = [X[i] * X[j] for i in range(4) for j in range(i + 1, 4)] + list(Y)
    res = exact_real_study_points(eqs)
    assert res.strata.tolist() == [0, 1, 2, 3]
    assert np.array_equal(res.study_points, np.hstack([np.eye(4), np.zeros((4, 4))]))
    assert res.stratum_complex_counts[0] >= 1


def test_translation_and_normalisation():
    # rotation by the quaternion (3, 4, 0, 0) (x . x = 25), translation t = (1, 2, 3)
    q, t = [sp.Integer(v) for v in (3, 4, 0, 0)], [sp.Integer(v) for v in (1, 2, 3)]
    s = study_of(q, t)
    eqs = [x2, x3, 4 * x0 - 3 * x1] + [Y[i] * s[0] - s[4 + i] * x0 for i in range(4)]
    res = exact_real_study_points(eqs)
    assert res.count == 1 and res.strata.tolist() == [0]
    assert contains(res.boxes[0], chart_point(s, 0))
    expected = np.array([float(c) for c in s]) / 5.0
    assert np.allclose(res.study_points[0], expected, rtol=0, atol=1e-15)


def test_floats_enter_exactly():
    # y1 = 0.1 x0 with x = (1, 0, 0, 0): the box holds Fraction(0.1), not 1/10
    eqs = [x1, x2, x3, y1 - 0.1 * x0, y2, y3]
    res = exact_real_study_points(eqs)
    box = res.boxes[0]
    assert box[5][0] <= Fraction(0.1) <= box[5][1]
    assert not box[5][0] <= Fraction(1, 10) <= box[5][1]
    assert box[4] == (0, 0)          # y0 = 0 from Study's quadric, added by default


def test_no_solution_at_all():
    # x1 = x2 = x3 = 0 and x . x = 0 leave x0^2 = 0: no point with x != 0, not even complex
    res = exact_real_study_points([x1, x2, x3, XX])
    assert res.count == 0 and res.study_points.shape == (0, 8) and res.strata.shape == (0,)
    assert res.stratum_complex_counts == (0, 0, 0, 0)


def test_study_quadric_can_be_left_out():
    eqs = [x1, x2, x3, y1, y2, y3]
    with pytest.raises(DegenerateDesignError, match="x0 = 1"):
        exact_real_study_points(eqs, study_quadric=False)     # y0 is then free
    assert exact_real_study_points(eqs).count == 1


def test_positive_dimensional_strata_are_named():
    with pytest.raises(DegenerateDesignError, match="stratum x0 = 1 "):
        exact_real_study_points([x1, x2, x3, y1, y2])
    # finite in the chart x0 = 1 (six independent linear forms and Study's quadric), but every
    # equation vanishes on x0 = 0: a continuum of half-turns
    forms = [x1 - x2, x2 + x3, y0, y1 - x3, y2, y3 - x1]
    with pytest.raises(DegenerateDesignError, match="stratum x0 = 0, x1 = 1 "):
        exact_real_study_points([x0 * f for f in forms])


def test_symbols_are_matched_by_name():
    xr = sp.symbols("x0:4", real=True)
    yr = sp.symbols("y0:4", real=True)
    eqs = [xr[1], xr[2], xr[3], yr[1] - xr[0], yr[2], yr[3]]
    res = exact_real_study_points(eqs)
    assert np.array_equal(res.study_points, np.array([[1, 0, 0, 0, 0, 1, 0, 0]], float))


def test_bad_input():
    with pytest.raises(InputError, match=r"polys\[1\].*homogeneous"):
        exact_real_study_points([x1, y1 - 1])
    with pytest.raises(InputError, match=r"polys\[0\].*symbol z"):
        exact_real_study_points([sp.Symbol("z") * x0])
    with pytest.raises(InputError, match="rational"):
        exact_real_study_points([x1 - sp.sqrt(2) * x0])
    with pytest.raises(InputError, match="polynomial"):
        exact_real_study_points([x1 / x0])
    with pytest.raises(TypeError, match="sequence"):
        exact_real_study_points(x0 * y0)
    with pytest.raises(TypeError, match=r"polys\[0\]"):
        exact_real_study_points(["x0"])
    with pytest.raises(TypeError, match="study_quadric"):
        exact_real_study_points([x1], study_quadric=1)
    with pytest.raises(InputError, match="timeout"):
        exact_real_study_points([x1], timeout=-1)


# --------------------------------------------------------------------------- Gough-Stewart

def test_leg_quadric_is_the_reduced_quartic():
    rng = np.random.default_rng(11)
    a, b = [rational(rng) for _ in range(3)], [rational(rng) for _ in range(3)]
    length2 = sp.Rational(37, 4)
    quadric, quartic = leg_quadric(a, b, length2), leg_quartic(a, b, length2)
    # |N|^2 (all four components, the scalar part 2 (x . y) included) = (x . x) |M|^2, exactly
    assert sp.expand(quartic - XX * quadric) == 0
    # at rational poses the quadric is (x . x)(|R b + t - a|^2 - L^2), exactly
    for _ in range(3):
        q = [sp.Integer(int(v)) for v in rng.integers(-5, 6, 4)]
        q[0] += 7
        t = [rational(rng) for _ in range(3)]
        s = dict(zip(S, study_of(q, t)))
        euclid = squared_lengths([a], [b], q, t)[0] - length2
        assert quadric.xreplace(s) == sum(c * c for c in q) * euclid



def gough_stewart(seed, half_turn=False):
    rng = np.random.default_rng(seed)
    a, b = random_design(rng)
    q = [sp.Integer(int(v)) for v in rng.integers(1, 9, 4)]
    if half_turn:
        q[0] = sp.Integer(0)
    t = [rational(rng) for _ in range(3)]
    length2 = squared_lengths(a, b, q, t)
    quadrics = [leg_quadric(ai, bi, l2) for ai, bi, l2 in zip(a, b, length2)]
    return a, b, q, t, length2, quadrics


@pytest.mark.parametrize("seed", [1, pytest.param(2, marks=pytest.mark.slow)])
def test_gough_stewart_known_pose_and_forty_complex_solutions(seed, capsys):
    a, b, q, t, length2, quadrics = gough_stewart(seed)
    start = time.perf_counter()
    res = exact_real_study_points(quadrics)
    elapsed = time.perf_counter() - start
    assert res.complex_count == 40                   # a general 6-6 platform
    assert res.stratum_complex_counts[1:] == (0, 0, 0)
    known = study_of(q, t)
    assert sum(contains(box, chart_point(known, 0)) for box in res.boxes) == 1
    normalised = np.array([float(c) for c in known]) / np.sqrt(float(sum(c * c for c in q)))
    assert np.min(np.max(np.abs(res.study_points - normalised), axis=1)) < 1e-12
    # every real solution is a pose with these leg lengths (an independent numpy check)
    assert np.all(euclidean_residuals(a, b, length2, res.study_points) < 1e-9)
    study = np.einsum("ki,ki->k", res.study_points[:, :4], res.study_points[:, 4:])
    assert np.all(np.abs(study) < 1e-12)
    assert np.allclose(np.linalg.norm(res.study_points[:, :4], axis=1), 1.0)
    with capsys.disabled():
        print(f"\n[seed {seed}] {res.count} real of {res.complex_count}; msolve "
              f"{', '.join(f'{s:.3f}' for s in res.seconds)} s; total {elapsed:.2f} s")


@pytest.mark.slow
def test_gough_stewart_half_turn_pose_is_found():
    # lengths from a pose with x0 = 0: 39 complex solutions stay in the chart x0 = 1, the
    # half-turn is the one solution of the stratum x0 = 0, x1 = 1
    a, b, q, t, length2, quadrics = gough_stewart(3, half_turn=True)
    res = exact_real_study_points(quadrics)
    assert res.stratum_complex_counts == (39, 1, 0, 0)
    known = chart_point(study_of(q, t), 1)
    hits = [i for i, box in enumerate(res.boxes) if contains(box, known)]
    assert len(hits) == 1 and res.strata[hits[0]] == 1
    assert all(lo == hi == 0 for lo, hi in res.boxes[hits[0]][:1])
    assert np.all(euclidean_residuals(a, b, length2, res.study_points) < 1e-9)


@pytest.mark.slow
@pytest.mark.slow
def test_unreduced_quartic_keeps_the_null_cone():
    # the quartic |N|^2 - L^2 (x . x)^2 has the factor x . x: its zero set contains the complex
    # cone x . x = 0, a continuum in every chart. Without excluding x . x = 0 the stratum is
    # positive-dimensional; excluding it (the default does so where needed) leaves the same real
    # solutions as the quadrics
    a, b, q, t, length2, _ = gough_stewart(1)
    quartics = [leg_quartic(ai, bi, l2) for ai, bi, l2 in zip(a, b, length2)]
    with pytest.raises(DegenerateDesignError, match="x0 = 1"):
        exact_real_study_points(quartics, exclude_null_rotations=False)
    quadrics = [leg_quadric(ai, bi, l2) for ai, bi, l2 in zip(a, b, length2)]
    via_quartics = exact_real_study_points(quartics).study_points
    via_quadrics = exact_real_study_points(quadrics).study_points
    assert via_quartics.shape == via_quadrics.shape
    assert np.allclose(via_quartics, via_quadrics, atol=1e-12)


def test_architecture_singular_design():
    # base points on a circle, the platform a half-size copy (planar, similar, points on a
    # conic): an architecturally singular 6-6 platform (Roeschel & Mick 1998, Karger 2003)
    ts = [sp.Rational(k, 3) for k in (-5, -2, -1, 1, 2, 4)]
    a = [[3 * (1 - u * u) / (1 + u * u), 6 * u / (1 + u * u), 0] for u in ts]
    b = [[c / 2 for c in ai] for ai in a]
    rng = np.random.default_rng(4)
    q = [sp.Integer(int(v)) for v in rng.integers(1, 9, 4)]
    t = [rational(rng) for _ in range(3)]
    quadrics = [leg_quadric(ai, bi, l2) for ai, bi, l2 in zip(a, b, squared_lengths(a, b, q, t))]
    with pytest.raises(DegenerateDesignError, match="infinitely many"):
        exact_real_study_points(quadrics)


@pytest.mark.slow
def test_gough_stewart_float_design():
    # double-precision anchors and lengths enter as their exact binary rationals (53-bit
    # numerators: msolve takes about 10 s here instead of 0.5 s for small rationals); the pose
    # the lengths were computed from is within rounding of one real solution
    rng = np.random.default_rng(5)
    a, b = rng.uniform(-3, 3, (6, 3)), rng.uniform(-1.5, 1.5, (6, 3))
    q = rng.normal(size=4)
    q *= np.sign(q[0]) / np.linalg.norm(q)
    t = rng.uniform(-1, 1, 3)
    s = np.array(study_of(q, t), float)
    w = np.array([np.array(qmul(qmul(q, pure(bi)), conj(q))[1:]) for bi in b])   # R b, |q| = 1
    lengths = np.linalg.norm(w + t - a, axis=1)
    quadrics = [leg_quadric([sp.Rational(v) for v in ai], [sp.Rational(v) for v in bi],
                            sp.Rational(float(l))**2) for ai, bi, l in zip(a, b, lengths)]
    res = exact_real_study_points(quadrics)
    assert res.complex_count == 40
    assert np.min(np.max(np.abs(res.study_points - s), axis=1)) < 1e-12
    assert np.all(euclidean_residuals(a, b, lengths**2, res.study_points) < 1e-9)
