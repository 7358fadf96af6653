"""Certified path checks against independent exact computations (the integer polynomial of
eq. (11), exact rational sampling, sympy's Sturm counts), the batched test against the exact one,
and the assembly-mode-change planner for seed 002."""

import warnings
from concurrent.futures import ThreadPoolExecutor
from fractions import Fraction

import flint
import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.paths.modechange import joint_trajectory, plan_mode_change
from imagespace.paths.check import (ImagePath, check_path, polyline, polynomial_curve, pose_segment, rational_curve,
                              segment, segments_free)

x0, x1, x2, x3 = isp.image_symbols()
EQ11 = sp.Poly(-18944*x0**3*x2 + 15360*x0**2*x1*x2 + 274944*x0**2*x1*x3 - 25600*x0**2*x2**2
               - 23040*x0**2*x2*x3 + 180224*x0*x1**2*x2 + 803840*x0*x1**2*x3 - 23040*x0*x1*x2**2
               - 23040*x0*x1*x3**2 - 113664*x1**3*x3 - 23040*x1**2*x2*x3 + 25600*x1**2*x3**2,
               x0, x1, x2, x3)
T = sp.Symbol("t")


@pytest.fixture(scope="module")
def m():
    return isp.examples.stigger_husty()


def eq11_along(a, b):
    """S(X(t)) of eq. (11) along (1-t) a + t b, exact (independent of the library's quartic)."""
    X = [sp.Rational(Fraction(float(u))) * (1 - T) + sp.Rational(Fraction(float(v))) * T for u, v in zip(a, b)]
    return sp.Poly(sp.expand(EQ11.as_expr().xreplace(dict(zip((x0, x1, x2, x3), X)))), T)


@pytest.mark.slow
def test_check_agrees_with_dense_exact_sampling_and_sturm(m, rng):
    sampled_crossing = 0
    for _ in range(40):
        a = isp.image_point([rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-3, 3)])
        b = isp.image_point([rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-3, 3)])
        res = check_path(m, segment(a, b))
        p = eq11_along(a, b)
        n_roots = p.count_roots(0, 1)
        assert res.certified and len(res.crossings) == len(set(r for r, _ in p.intervals(inf=0, sup=1)))
        assert res.singularity_free == (n_roots == 0)
        vals = [p.eval(sp.Rational(k, 200)) for k in range(201)]
        if any(v1 * v2 <= 0 for v1, v2 in zip(vals, vals[1:])):
            assert not res.singularity_free
        if any(v1 * v2 < 0 for v1, v2 in zip(vals, vals[1:])):      # det J changes sign: a crossing
            assert res.crosses
            sampled_crossing += 1
        for c in res.crossings:                   # each interval contains a root of p
            assert c.t[1] - c.t[0] < 1e-12
            lo, hi = sp.Rational(Fraction(c.t[0])), sp.Rational(Fraction(c.t[1]))
            assert p.eval(lo) == 0 or p.eval(hi) == 0 or p.eval(lo) * p.eval(hi) < 0 or c.multiplicity % 2 == 0
    assert 5 <= sampled_crossing <= 35                        # both kinds of segment were checked


def _smooth_surface_point():
    """A rational point of the seed-002 surface (the surface contains the line x1 = x2 = 0) and
    the exact gradient there."""
    P = [sp.Integer(1), sp.Integer(0), sp.Integer(0), sp.Rational(3, 2)]
    grad = [sp.diff(EQ11.as_expr(), v).xreplace(dict(zip((x0, x1, x2, x3), P))) for v in (x0, x1, x2, x3)]
    assert EQ11.eval(tuple(P)) == 0 and any(g != 0 for g in grad)
    return P, grad


def test_tangential_contact_is_caught_as_touching(m):
    P, g = _smooth_surface_point()
    d = [sp.Rational(1, 3), sp.Rational(1, 5), sp.Rational(1, 7), sp.Rational(-2, 7)]
    k = next(i for i in range(4) if g[i] != 0)
    d[k] = -sum(g[i] * d[i] for i in range(4) if i != k) / g[k]          # grad . d = 0
    a = [P[i] - d[i] / 2 for i in range(4)]
    path = polynomial_curve([a, d])                                       # P at t = 1/2
    res = check_path(m, path)
    at_half = [c for c in res.crossings if c.t[0] <= 0.5 <= c.t[1]]
    assert at_half and at_half[0].multiplicity == 2 and not at_half[0].crosses
    assert res.touches and not res.crosses and not res.singularity_free


def test_crossing_at_t_1e_minus_9_is_caught(m):
    P, g = _smooth_surface_point()
    D = [sp.Rational(1, 2), sp.Rational(1, 3), sp.Integer(1), sp.Integer(2)]
    assert sum(gi * di for gi, di in zip(g, D)) != 0                      # transversal
    eps = sp.Rational(1, 10**9)
    a = [P[i] - eps * D[i] for i in range(4)]
    res = check_path(m, polynomial_curve([a, D]))                         # root exactly at t = 1e-9
    hit = [c for c in res.crossings if c.t[0] <= 1e-9 <= c.t[1]]
    assert hit and hit[0].crosses
    assert res.crosses and not res.touches and not res.singularity_free


@pytest.mark.slow
def test_two_crossings_between_samples_are_caught(m):
    P, g = _smooth_surface_point()
    d = [sp.Rational(1, 3), sp.Rational(1, 5), sp.Rational(1, 7), sp.Rational(-2, 7)]
    k = next(i for i in range(4) if g[i] != 0)
    d[k] = -sum(g[i] * d[i] for i in range(4) if i != k) / g[k]
    # curvature along d decides on which side of the tangent the surface lies
    t = sp.Symbol("t")
    curve = [P[i] + (t - sp.Rational(1, 2)) * d[i] for i in range(4)]
    second = sp.diff(EQ11.as_expr().xreplace(dict(zip((x0, x1, x2, x3), curve))), t, 2).subs(t, sp.Rational(1, 2))
    assert second != 0
    n = [gi / sum(gj**2 for gj in g) for gi in g]
    eta = -sp.sign(second) * sp.Rational(1, 10**11)       # push through the surface: two close roots
    a = [P[i] - d[i] / 2 + eta * n[i] for i in range(4)]
    path = polynomial_curve([a, d])
    p = sp.Poly(sp.expand(EQ11.as_expr().xreplace(dict(zip((x0, x1, x2, x3), [a[i] + t * d[i] for i in range(4)])))), t)
    assert p.count_roots(0, 1) >= 2
    roots = sorted(float(r) for r in sp.Poly(p, t).nroots() if abs(sp.im(r)) < 1e-20 and 0 <= sp.re(r) <= 1)
    assert roots[1] - roots[0] < 1e-3                     # both between two samples of a 1000-point grid
    grid = [sp.Rational(2 * k + 1, 2000) for k in range(1000)]          # 1000 samples, none at t = 1/2
    assert len({sp.sign(p.eval(s)) for s in grid}) == 1   # sampling on that grid sees no crossing at all
    res = check_path(m, path)
    near = [c for c in res.crossings if abs(c.t[0] - 0.5) < 1e-3]
    assert len(near) == 2 and all(c.crosses for c in near)


def test_batched_test_equals_the_exact_one(m, rng):
    n = 3000
    P = np.column_stack([rng.uniform(-12, 12, n), rng.uniform(-12, 12, n), rng.uniform(-np.pi, np.pi, n)])
    A = isp.image_point(P)
    B = isp.image_point(P + np.column_stack([rng.normal(0, 2, (n, 2)), rng.normal(0, 0.5, n)]))
    free, how = segments_free(m, A, B)
    assert 0.2 < free.mean() < 0.98
    for i in range(0, n, 30):
        assert free[i] == check_path(m, segment(A[i], B[i])).singularity_free
    free2, how2 = segments_free(m, A, B, exact=False)
    assert np.all(free2[how2 == "bernstein"] == free[how2 == "bernstein"])


def test_pose_segments_are_certified_by_intervals(m, rng):
    modes = m.direct_kinematics(m.q_example)
    res = check_path(m, pose_segment(modes[0].pose, modes[1].pose))
    assert res.crosses and res.certified and "arb" in res.method
    S = m.singularity_surface()
    sampled_crossing = certified_free = 0
    for _ in range(10):
        p0 = np.array([rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-3, 3)])
        p1 = p0 + np.array([rng.normal(0, 3), rng.normal(0, 3), rng.normal(0, 0.5)])
        res = check_path(m, pose_segment(p0, p1))
        v = S.at_poses(p0[None] + np.linspace(0, 1, 2001)[:, None] * (p1 - p0)[None])
        if np.any(np.sign(v[1:]) != np.sign(v[:-1])):
            assert res.crosses
            sampled_crossing += 1
        if res.certified and res.singularity_free:
            assert np.all(np.sign(v) == np.sign(v[0]))
            certified_free += 1
    assert sampled_crossing >= 1 and certified_free >= 1            # both branches were checked


@pytest.mark.slow
def test_every_chord_between_two_modes_is_singular_at_its_midpoint(rng):
    """The midpoint lemma of modechange.py, on random joint values of two designs."""
    checked = {}
    for mech in (isp.examples.general_3rpr(), isp.examples.stigger_husty()):
        S = mech.singularity_surface()
        checked[mech.name] = 0
        for _ in range(5):
            pose = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-2, 2)])
            modes = mech.direct_kinematics(mech.inverse_kinematics(pose))
            for a in modes:
                for b in modes:
                    if a is b:
                        continue
                    M = (a.image_point + b.image_point) / 2
                    v, g = S.value_and_gradient(M)
                    assert abs(v) <= 1e-9 * np.linalg.norm(g) * np.linalg.norm(M)
                    checked[mech.name] += 1
    # not vacuous: at every pose drawn the pose itself is a real mode, and real roots of the real
    # sextic come in an even number (non-real ones pair up), so >= 2 ordered pairs per pose
    assert all(n >= 10 for n in checked.values()), checked


def test_planner_reproduces_a_two_segment_change_for_seed_002(m):
    modes = m.direct_kinematics(m.q_example)
    neg = [k for k, mm in enumerate(modes) if mm.aspect < 0]
    plan = plan_mode_change(m, m.q_example_float, modes[neg[0]], modes[neg[1]])
    assert plan.found and len(plan.path) == 2 and plan.check.singularity_free and plan.check.certified
    # independent: exact Sturm count of eq. (11) on each segment's endpoints
    for piece in plan.path.pieces:
        a = [float(c) for c in piece[0]]
        b = [float(piece[0][j] + piece[1][j]) for j in range(4)]
        assert eq11_along(a, b).count_roots(0, 1) == 0
    assert np.allclose(plan.joint_loop[0], m.q_example_float, atol=1e-9)
    assert np.allclose(plan.joint_loop[-1], m.q_example_float, atol=1e-9)
    assert np.ptp(plan.joint_loop, axis=0).max() > 0.1          # a genuine loop, not a constant
    assert np.all(m.joint_residual(plan.poses, plan.joint_loop) < 1e-9)


def test_opposite_aspects_are_refused_with_the_reason(m):
    modes = m.direct_kinematics(m.q_example)
    a = next(mm for mm in modes if mm.aspect > 0)
    b = next(mm for mm in modes if mm.aspect < 0)
    plan = plan_mode_change(m, m.q_example_float, a, b)
    assert not plan.found and "opposite aspects" in plan.reason


def test_domain_exit_when_a_leg_reaches_zero_length():
    """Zero length is a point condition (P = A): build an exact rational path through it."""
    mech = isp.examples.general_3rpr()
    A0, p0 = sp.Matrix([7, -5]), sp.Matrix([-1, -7])                 # leg 0's anchors
    t0 = sp.Rational(1, 3)                                            # tan(phi/2)
    R = sp.Matrix([[1 - t0**2, -2 * t0], [2 * t0, 1 - t0**2]]) / (1 + t0**2)
    d = A0 - R * p0                                                    # leg 0 has length zero here
    X = [sp.Integer(1), t0, (t0 * d[0] - d[1]) / 2, (d[0] + t0 * d[1]) / 2]
    D = [sp.Rational(1, 10), sp.Rational(1, 20), sp.Rational(1, 3), sp.Rational(-1, 4)]
    path = polynomial_curve([[X[i] - D[i] for i in range(4)], [2 * D[i] for i in range(4)]])
    res = check_path(mech, path)
    hits = [e for e in res.domain_exits if e["leg"] == 0 and e["what"] == "zero length"]
    assert hits and hits[0]["t"][0] <= 0.5 <= hits[0]["t"][1]
    # a joint limit is crossed by an ordinary float segment
    pose = np.array([1.0, 2.0, 0.3])
    q = mech.inverse_kinematics(pose)
    a, b = isp.image_point(pose), isp.image_point(pose + [1.0, 0.5, 0.1])
    qb = mech.inverse_kinematics(pose + [1.0, 0.5, 0.1])
    lim = (q[0] + qb[0]) / 2
    lim_res = check_path(mech, segment(a, b), joint_limits=[[min(q[0], lim), max(q[0], lim)], [0, 100], [0, 100]])
    assert any(e["leg"] == 0 and "limit" in e["what"] for e in lim_res.domain_exits)


def test_bad_input(m):
    X = np.array([mm.image_point for mm in m.direct_kinematics(m.q_example)])
    with pytest.raises(isp.InputError, match="zero-length"):
        segment(X[0], X[0])
    with pytest.raises(isp.InputError, match="finite"):
        segment(X[0], [1.0, np.nan, 0.0, 0.0])
    with pytest.raises(isp.InputError, match="absolute line"):
        segment(X[0], [0.0, 0.0, 1.0, 0.0])
    with pytest.raises(isp.InputError, match="zero-length"):
        pose_segment([0, 0, 0], [0, 0, 0])
    with pytest.raises(isp.InputError, match="denominator"):
        rational_curve([[1, 0, 0, 0], [0, 1, 0, 0]], [1, -2])
    with pytest.raises(isp.InputError, match="does not start"):
        joint_trajectory(m, segment(X[0] + [0, 0, 0.5, 0], X[1]), m.q_example_float)
    with pytest.raises(isp.InputError, match="not an assembly mode"):
        plan_mode_change(m, m.q_example_float, X[0] + [0, 0, 0.3, 0], X[3])
    with pytest.raises(TypeError, match="ImagePath"):
        check_path(m, [X[0], X[1]])
    with pytest.raises(isp.InputError, match="points must"):
        polyline([X[0]])


# -- certificates do not depend on python-flint's global precision, nor on other threads ----------
# The reference below is computed here, independently of imagespace.paths.check: S is the library's
# singularity polynomial divided by its leading coefficient (exactly rational for seed 002, and a
# multiple of eq. (11)), the float endpoints are the exact binary rationals they are, and the
# roots of S(X(t)) in [0, 1] are counted by sympy's Sturm sequences on the square-free factors.
FLINT_SETTINGS = [("dps", 30), ("prec", 64), ("prec", 100), ("prec", 212)]


@pytest.fixture
def user_flint_precision():
    """Restore the process-global flint precision whatever a test sets."""
    old = flint.ctx.prec
    yield
    flint.ctx.prec = old


@pytest.fixture(scope="module")
def S_rational(m):
    S = sp.Poly(m.singularity_polynomial(), x0, x1, x2, x3)
    lead = S.coeffs()[0]
    Sq = sp.Poly({mono: sp.radsimp(c / lead) for mono, c in S.terms()}, x0, x1, x2, x3, domain=sp.QQ)
    ratio = sp.radsimp(EQ11.coeffs()[0] / Sq.coeffs()[0])
    assert sp.Poly(EQ11.as_expr() - ratio * Sq.as_expr(), x0, x1, x2, x3).is_zero      # eq. (11) up to a factor
    return Sq


def exact_root_counts(Sq, a, b):
    """(odd, even): distinct roots of S((1-t) a + t b) in [0, 1] of odd / even multiplicity."""
    X = [sp.Poly([sp.Rational(Fraction(float(v))) - sp.Rational(Fraction(float(u))), sp.Rational(Fraction(float(u)))],
                 T, domain=sp.QQ) for u, v in zip(a, b)]
    p = sp.Poly(0, T, domain=sp.QQ)
    for mono, c in Sq.terms():
        term = sp.Poly(c, T, domain=sp.QQ)
        for Xj, e in zip(X, mono):
            if e:
                term = term * Xj**e
        p = p + term
    assert not p.is_zero
    odd = even = 0
    for f, k in p.sqf_list()[1]:
        n = int(f.count_roots(0, 1))
        odd, even = (odd + n, even) if k % 2 else (odd, even + n)
    return odd, even


def random_segments(m, rng, n_long, n_short, n_poses):
    """Long segments between random poses, short steps, and chords between the assembly modes
    of random joint values (every chord meets the surface, near its midpoint)."""
    A, B = [], []
    for i in range(n_long + n_short):
        p0 = np.array([rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-3, 3)])
        p1 = (np.array([rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-3, 3)]) if i < n_long
              else p0 + np.array([rng.normal(0, 2), rng.normal(0, 2), rng.normal(0, 0.5)]))
        A.append(isp.image_point(p0))
        B.append(isp.image_point(p1))
    for _ in range(n_poses):
        pose = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-2, 2)])
        with warnings.catch_warnings():                    # near-singular modes are welcome here
            warnings.simplefilter("ignore", UserWarning)
            modes = m.direct_kinematics(m.inverse_kinematics(pose))
        for i in range(len(modes)):
            for j in range(i + 1, len(modes)):
                A.append(modes[i].image_point)
                B.append(modes[j].image_point)
    return np.array(A), np.array(B)


@pytest.fixture(scope="module")
def segments_and_counts(m, S_rational):
    A, B = random_segments(m, np.random.default_rng(13012026), 120, 90, 24)
    counts = [exact_root_counts(S_rational, a, b) for a, b in zip(A, B)]
    return A, B, counts


def assert_matches_exact(m, A, B, counts):
    for a, b, (odd, even) in zip(A, B, counts):
        res = check_path(m, segment(a, b))
        got = (sum(c.crosses for c in res.crossings), sum(c.touches for c in res.crossings))
        assert got == (odd, even), (a.tolist(), b.tolist(), res)
        assert res.certified and res.singularity_free == (odd + even == 0)
        assert res.crosses == (odd > 0) and res.touches == (even > 0)
    free, how = segments_free(m, A, B)
    assert free.tolist() == [odd + even == 0 for odd, even in counts]
    return how


@pytest.mark.parametrize("kind, value", FLINT_SETTINGS)
def test_opposite_aspect_chords_cross_at_any_flint_precision(m, S_rational, kind, value, user_flint_precision):
    modes = m.direct_kinematics(m.q_example)
    pos = [mm.image_point for mm in modes if mm.aspect > 0]
    neg = [mm.image_point for mm in modes if mm.aspect < 0]
    setattr(flint.ctx, kind, value)
    prec = flint.ctx.prec
    checked = 0
    for a in pos:
        for b in neg:
            assert exact_root_counts(S_rational, a, b)[0] >= 1           # det J changes sign: it must cross
            res = check_path(m, segment(a, b))
            assert res.crosses and not res.singularity_free and res.certified
            free, _ = segments_free(m, a[None], b[None])
            assert not free[0]
            checked += 1
    assert checked == len(pos) * len(neg) >= 9                           # seed 002: 3 + 3 modes
    a = next(mm for mm in modes if mm.aspect > 0)
    b = next(mm for mm in modes if mm.aspect < 0)
    res = check_path(m, pose_segment(a.pose, b.pose))                    # arb, at a precision of its own
    assert res.crosses and res.certified
    assert flint.ctx.prec == prec                                        # the user's setting is left alone


@pytest.mark.slow
@pytest.mark.parametrize("kind, value", [("prec", 53), ("dps", 30)])
def test_crossing_counts_equal_an_exact_sturm_count(m, segments_and_counts, kind, value, user_flint_precision):
    A, B, counts = segments_and_counts
    assert len(A) >= 300
    n_crossing = sum(odd + even > 0 for odd, even in counts)
    assert 100 <= n_crossing <= len(A) - 50                               # both answers well represented
    setattr(flint.ctx, kind, value)
    how = assert_matches_exact(m, A, B, counts)
    assert np.sum(how == "exact") >= 10                                   # the exact fallback is exercised


@pytest.mark.slow
@pytest.mark.parametrize("kind, value", [("prec", 64), ("prec", 212)])
def test_crossing_counts_equal_an_exact_sturm_count_large(m, S_rational, kind, value, user_flint_precision):
    A, B = random_segments(m, np.random.default_rng(value), 300, 200, 25)
    counts = [exact_root_counts(S_rational, a, b) for a, b in zip(A, B)]
    setattr(flint.ctx, kind, value)
    assert_matches_exact(m, A, B, counts)


def _summary(res):
    return (res.singularity_free, res.crosses, res.touches, res.certified,
            tuple((c.piece, c.t, c.multiplicity) for c in res.crossings))


@pytest.mark.slow
def test_path_checks_from_two_threads_while_one_flips_flint_precision(m, segments_and_counts, user_flint_precision):
    A, B, counts = segments_and_counts
    rng = np.random.default_rng(2)
    P0 = np.column_stack([rng.uniform(-10, 10, 16), rng.uniform(-10, 10, 16), rng.uniform(-3, 3, 16)])
    P1 = P0 + np.column_stack([rng.normal(0, 3, (16, 2)), rng.normal(0, 0.5, 16)])
    jobs = [("pose", k) for k in range(16)] + [("poly", i) for i in range(0, len(A), 4)]

    def check(job):
        kind, k = job
        path = pose_segment(P0[k], P1[k]) if kind == "pose" else segment(A[k], B[k])
        return _summary(check_path(m, path))

    single = {job: check(job) for job in jobs}                          # one thread, default precision
    for (kind, i), s in single.items():
        if kind == "poly":
            assert sum(mult % 2 for _, _, mult in s[4]) == counts[i][0] and len(s[4]) == sum(counts[i])
    assert sum(not s[0] for job, s in single.items() if job[0] == "pose") >= 3      # some pose segments cross

    def worker(my_jobs, flip):
        out = {}
        for n, job in enumerate(my_jobs):
            if flip:
                kind, value = FLINT_SETTINGS[n % len(FLINT_SETTINGS)]
                setattr(flint.ctx, kind, value)
            out[job] = check(job)
        return out

    order = [jobs[k] for k in np.random.default_rng(3).permutation(len(jobs))]
    with ThreadPoolExecutor(max_workers=2) as pool:
        flipping = pool.submit(worker, order[0::2], True)
        steady = pool.submit(worker, order[1::2], False)
        both = {**flipping.result(), **steady.result()}
    assert both.keys() == single.keys()
    wrong = [job for job in jobs if both[job] != single[job]]
    assert not wrong, wrong


def test_touches_means_tangential_contact_and_crosses_an_odd_root(m):
    """Independent: the multiplicity of the root at t = 1/2 from exact derivatives of eq. (11)."""
    P, g = _smooth_surface_point()
    d = [sp.Rational(1, 3), sp.Rational(1, 5), sp.Rational(1, 7), sp.Rational(-2, 7)]
    k = next(i for i in range(4) if g[i] != 0)
    d[k] = -sum(g[i] * d[i] for i in range(4) if i != k) / g[k]          # tangent: grad . d = 0
    D = [sp.Rational(1, 2), sp.Rational(1, 3), sp.Integer(1), sp.Integer(2)]   # transversal
    half = sp.Rational(1, 2)

    def order_at_half(direction):
        a = [P[i] - direction[i] / 2 for i in range(4)]
        p = EQ11.as_expr().xreplace(dict(zip((x0, x1, x2, x3), [a[i] + T * direction[i] for i in range(4)])))
        return next(n for n in range(5) if sp.diff(p, T, n).subs(T, half) != 0), a

    (k_tan, a_tan), (k_tr, a_tr) = order_at_half(d), order_at_half(D)
    assert (k_tan, k_tr) == (2, 1)
    tangential = check_path(m, polynomial_curve([a_tan, d]))
    transversal = check_path(m, polynomial_curve([a_tr, D]))
    assert tangential.touches and not tangential.crosses and not tangential.singularity_free
    assert transversal.crosses and not transversal.touches and not transversal.singularity_free
    assert [c.multiplicity for c in transversal.crossings if c.t[0] <= 0.5 <= c.t[1]] == [1]
    # a path with both contacts reports both (pieces are checked one by one)
    both = check_path(m, ImagePath((polynomial_curve([a_tan, d]).pieces[0], polynomial_curve([a_tr, D]).pieces[0])))
    assert both.crosses and both.touches
    # the opposite-aspect chord of seed 002: ordinary crossings only, however many
    modes = m.direct_kinematics(m.q_example)
    a = next(mm for mm in modes if mm.aspect > 0).image_point
    b = next(mm for mm in modes if mm.aspect < 0).image_point
    chord = check_path(m, segment(a, b))
    assert chord.crosses and not chord.touches and all(c.multiplicity == 1 for c in chord.crossings)
