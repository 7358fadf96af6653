"""Certified direct kinematics at the edges (issue [8]): double roots, modes closer than float
resolution, near-singular rows, units, tolerances, exact caches.

The references are independent of the code under test: msolve (an exact solver this project did
not write, on an independent Euclidean formulation, ``tests/msolve_ref.py``), exact rational
arithmetic written here (python-flint on the exact rational kinematic polynomial, evaluated in
Fractions in the test), and identities that must hold (scaling a design scales its modes).
"""

import warnings
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from msolve_ref import msolve_available, planar_dk_reference
from test_manipulator import any_leg

needs_msolve = pytest.mark.skipif(not msolve_available(), reason="msolve not installed")

# a rational 3-RPR whose legs are concurrent at the pose (1, 2, atan2(4, 3)) with integer lengths:
# the pose is an exact double root (msolve: 6 solutions with multiplicity, 5 distinct)
DOUBLE_LEGS = [((-6, -5), (-5, 0)), ((-10, -4), (11, -8)), ((20, -23), (-3, -11))]
DOUBLE_Q = [5.0, 26.0, 20.0]
DOUBLE_POSE = np.array([1.0, 2.0, np.arctan2(4, 3)])


def double_design():
    return isp.PlanarParallel([isp.RPR(base=A, platform=a) for A, a in DOUBLE_LEGS])


def dphi(a, b):
    return abs((a - b + np.pi) % (2 * np.pi) - np.pi)


def near_pose(p, ref, tol):
    return max(np.max(np.abs(np.asarray(p[:2]) - ref[:2])), dphi(p[2], ref[2])) <= tol


# --------------------------------------------------------------------------- exact test-side count

def exact_counts(m, Q):
    """Distinct real roots (projective line) of the exact kinematic polynomial at each row of Q,
    evaluated exactly here (python-flint rationals) from the general-q polynomial and counted by
    FLINT's isolation on the square-free factors."""
    import flint

    P = m.kinematic_polynomial()
    d = P.total_degree()
    qs = m.joint_symbols
    x0, x1 = P.gens
    terms = []
    for k in range(d + 1):
        c = sp.Poly(P.coeff_monomial(x0 ** (d - k) * x1 ** k), *qs)
        terms.append([(tuple(int(v) for v in e), flint.fmpq(int(v.p), int(v.q))) for e, v in c.terms()])
    top = max(max(e) for tk in terms for e, _ in tk)
    out = []
    for row in Q:
        pw = []
        for v in row:
            f = Fraction(float(v))
            b = flint.fmpq(f.numerator, f.denominator)
            pw.append([flint.fmpq(1)] + [b ** j for j in range(1, top + 1)])
        coeffs = []
        for tk in terms:
            acc = flint.fmpq(0)
            for e, v in tk:
                acc += v * pw[0][e[0]] * pw[1][e[1]] * pw[2][e[2]]
            coeffs.append(acc)
        at_inf = 0
        while coeffs and coeffs[-1] == 0:
            coeffs.pop()
            at_inf = 1
        poly = flint.fmpq_poly(coeffs)
        real = sum(1 for r, _m in poly.complex_roots() if r.imag.is_zero())
        out.append(real + at_inf)
    return np.array(out)


def concurrency(m, pose):
    """Euclidean concurrency determinant of the three RPR leg lines at pose (zero: singular)."""
    x, y, phi = pose
    c, s = np.cos(phi), np.sin(phi)
    rows = []
    for leg in m.legs:
        g = leg.geometry(exact=False)
        A = np.array(g["base"])
        a = np.array(g["platform"])
        B = np.array([x + c * a[0] - s * a[1], y + s * a[0] + c * a[1]])
        rows.append(np.cross(np.append(A, 1.0), np.append(B, 1.0)))
    return np.linalg.det(np.array(rows))


def rows_near_discriminant(m, rng, n, eps_range=(-12, -3)):
    """Joint vectors near the discriminant: a singular pose (legs concurrent, found by bisection
    of the concurrency determinant along a random direction in x), then q perturbed relatively
    by +-10^u, u uniform in eps_range."""
    sing = []
    while len(sing) < max(8, n // 200):
        p0 = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-np.pi, np.pi)])
        p1 = p0 + np.array([rng.uniform(1, 3), 0.0, 0.0])
        f0, f1 = concurrency(m, p0), concurrency(m, p1)
        if f0 * f1 > 0:
            continue
        for _ in range(80):
            pm = (p0 + p1) / 2
            fm = concurrency(m, pm)
            if fm * f0 > 0:
                p0, f0 = pm, fm
            else:
                p1 = pm
        q = m.inverse_kinematics(p0[None, :])[0]
        if np.all(np.isfinite(q)) and np.all(q > 0.5):
            sing.append(q)
    sing = np.array(sing)
    Q = sing[rng.integers(len(sing), size=n)]
    eps = 10.0 ** rng.uniform(*eps_range, size=(n, 3)) * rng.choice([-1, 1], size=(n, 3))
    return Q * (1 + eps)


# --------------------------------------------------------------------------- item 1

@pytest.mark.slow
def test_exact_double_root_is_one_singular_mode_on_every_path():
    m = double_design()
    res = m.direct_kinematics(DOUBLE_Q, certify=True)
    assert res.certificate.count == 3 and sorted(res.certificate.multiplicities) == [1, 1, 2]
    assert sum(res.modes_per_root) == len(res) == 3
    singular = [mm for mm in res if mm.singular]
    assert len(singular) == 1 and singular[0].multiplicity == 2 and singular[0].aspect == 0
    assert near_pose(singular[0].pose, DOUBLE_POSE, 1e-9)
    for method in ("numpy", "kernel"):
        b = m.direct_kinematics_batch([DOUBLE_Q] * 3, certify=True, method=method)
        assert b.count.tolist() == [3, 3, 3] and b.certified_roots.tolist() == [3, 3, 3]
        assert b.consistent.all() and not b.near_singular.any()
        assert sorted(b.multiplicity[0][b.valid[0]].tolist()) == [1, 1, 2]
        for i in range(3):
            assert sum(near_pose(p, DOUBLE_POSE, 1e-9) for p in b.poses[i][b.valid[i]]) == 1
    # the float path cannot separate a double root: it must say so
    with pytest.warns(isp.NearSingularWarning):
        m.direct_kinematics(DOUBLE_Q)
    b = m.direct_kinematics_batch([DOUBLE_Q] * 2)
    assert b.near_singular.all()


# --------------------------------------------------------------------------- item 2

@pytest.mark.slow
@needs_msolve
@pytest.mark.parametrize("target", [1e-6, 1e-8, 1e-10])
def test_modes_closer_than_float_resolution_are_two_modes(target):
    """Two real modes ``target`` apart next to the double root: rho_1 = 5 + delta (exact
    rational input); the side with two modes and the separation are msolve's, delta is tuned by
    the separation msolve reports (it grows like sqrt(delta) at a fold)."""
    m = double_design()
    delta = Fraction(1, 2**40)

    def cluster(d):
        ref = planar_dk_reference(m, [Fraction(5) + d, 26, 20])
        near = [p for p in ref.poses if near_pose(p, DOUBLE_POSE, 1e-2)]
        return ref, near

    # choose the side of the fold with two real modes (msolve), then scale delta to the target
    side = 1 if len(cluster(delta)[1]) == 2 else -1
    for _ in range(3):
        ref, near = cluster(side * delta)
        assert len(near) == 2
        sep = dphi(near[0][2], near[1][2])
        delta = delta * Fraction(target / sep) ** 2
        delta = Fraction(delta.numerator * 2**80 // delta.denominator, 2**80) or Fraction(1, 2**200)
    ref, near = cluster(side * delta)
    sep = dphi(near[0][2], near[1][2])
    assert target / 3 < sep < target * 3
    q = [sp.Integer(5) + side * sp.Rational(delta.numerator, delta.denominator), 26, 20]
    res = m.direct_kinematics(q, certify=True)
    assert len(res) == len(ref) == 4 and sum(res.modes_per_root) == 4
    assert all(mm.multiplicity == 1 for mm in res)
    mine = [mm for mm in res if near_pose(mm.pose, DOUBLE_POSE, 1e-2)]
    assert len(mine) == 2
    # each certified mode matches one msolve mode, one to one, far below the separation
    for p in near:
        hits = [mm for mm in mine if near_pose(mm.pose, p, target / 100)]
        assert len(hits) == 1
    # opposite aspects across a fold
    assert sorted(mm.aspect for mm in mine) == [-1, 1]


# --------------------------------------------------------------------------- item 3

@pytest.mark.slow
def test_modes_carry_their_roots_near_a_half_turn():
    """The issue's row: two modes ~6e-8 rad apart at t ~ 51 (near a half-turn); every mode's t
    lies in its root's certified interval and the bookkeeping adds up."""
    m = isp.PlanarParallel([isp.RPR(base=(0, 0), platform=(0, 0)), isp.RPR(base=(10, 0), platform=(4, 0)),
                            isp.RPR(base=(3, 8), platform=(1, 3))])
    q = [6.9108834278444995, 10.540266022785426, 6.017463116520176]
    res = m.direct_kinematics(q, certify=True)
    cert = res.certificate
    assert exact_counts(m, [q]).tolist() == [cert.count] == [2]
    assert res.modes_per_root == (1, 1) and len(res) == 2
    for mm, k in zip(res, res.root_of_mode):
        lo, hi = cert.exact_intervals[k]
        t = Fraction(mm.image_point[1]) / Fraction(mm.image_point[0])
        # the float mode is the exact root rounded once: within a few ulps of the interval
        assert abs(t - (lo + hi) / 2) <= 1e-14 * abs(t)
    for method in ("numpy", "kernel"):
        b = m.direct_kinematics_batch([q] * 3, certify=True, method=method)
        assert b.count.tolist() == [2, 2, 2] and b.consistent.all()


# --------------------------------------------------------------------------- item 5

@pytest.mark.slow
@pytest.mark.parametrize("method", ["numpy", "kernel"])
def test_float_paths_flag_every_doubtful_row_near_the_discriminant(method, rng):
    m = isp.examples.general_3rpr()
    Q = rows_near_discriminant(m, rng, 1500)
    b = m.direct_kinematics_batch(Q, method=method)
    exact = exact_counts(m, Q)
    ok = b.row_ok
    assert ok.sum() >= 1400
    wrong = ok & (b.count != exact)
    odd = ok & (b.count % 2 == 1)
    assert wrong.sum() + odd.sum() > 0          # the sample does reach the edge
    assert np.all(b.near_singular[wrong]) and np.all(b.near_singular[odd])
    assert (b.near_singular & ok).sum() < 0.6 * ok.sum()   # the flag is not raised everywhere


@pytest.mark.slow
def test_certified_batch_near_the_discriminant(rng):
    m = isp.examples.general_3rpr()
    Q = rows_near_discriminant(m, rng, 3000, eps_range=(-14, -4))
    b = m.direct_kinematics_batch(Q, certify=True)
    exact = exact_counts(m, Q)
    assert np.all(b.row_ok)
    assert np.array_equal(b.certified_roots, exact)
    # every root carries one mode (3-RPR, Cramer denominator non-zero): modes = roots
    assert np.array_equal(b.count, exact) and b.consistent.all() and not b.near_singular.any()
    # most rows proven by the vectorised certificate (inclusion discs before issue [12], the
    # in-kernel proof since), the rest re-solved root by root
    vectorised = np.isin(b.certificate_path, ["discs", "kernel"])
    assert np.sum(b.solver == "certified") > 0 and np.sum(vectorised) > 1000


@pytest.mark.slow
def test_certified_batch_100k_rows_near_the_discriminant():
    rng = np.random.default_rng(20261201)
    m = isp.examples.general_3rpr()
    Q = rows_near_discriminant(m, rng, 100_000, eps_range=(-12, -3))
    b = m.direct_kinematics_batch(Q, certify=True)
    exact = exact_counts(m, Q)
    assert np.all(b.row_ok)
    assert np.array_equal(b.certified_roots, exact)
    assert np.array_equal(b.count, exact) and b.consistent.all()


# --------------------------------------------------------------------------- item 13: units

def scaled_leg(leg, k):
    g = leg.geometry(exact=False)
    out = {}
    for key, v in g.items():
        if key in ("base", "platform"):
            out[key] = tuple(k * c for c in v)
        elif key in ("lengths",):
            out[key] = tuple(k * c for c in v)
        elif key == "length":
            out[key] = k * v
        elif key in ("angle_cs", "second_axis"):    # stored as cos/sin: the constructor's angle
            out["angle"] = float(leg.angle)
        else:
            out[key] = v                          # directions and angles
    return type(leg)(**out, actuated=leg.actuated)


def unit_cases():
    rng = np.random.default_rng(13)
    kinds = ["RPR", "RRR", "PRR", "RRP", "RPP", "PRP", "PPR"]
    cases = []
    while len(cases) < 7:
        kind = kinds[len(cases)]
        act = int(rng.integers(3))
        others = rng.choice(["RPR", "RRR", "PRR"], size=2)
        legs = [any_leg(rng, kind, act)] + [any_leg(rng, k, int(rng.integers(2))) for k in others]
        try:
            m = isp.PlanarParallel(legs)
            pose = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-np.pi, np.pi)])
            q = m.inverse_kinematics(pose)
        except (isp.DegenerateDesignError, isp.InputError):
            continue
        if not all(leg.joint_values_ok(np.array([q[i]]))[0] for i, leg in enumerate(m.legs)):
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("error", isp.NearSingularWarning)
            try:
                ref = m.direct_kinematics(q)
            except isp.NearSingularWarning:
                continue
        cases.append((kind, m, q, ref))
    return cases


UNIT_CASES = unit_cases()


def scaled_q(m, q, k):
    return np.array([v if leg.actuated_is_angle else k * v for v, leg in zip(q, m.legs)])


def same_modes(poses, ref_poses, k):
    if len(poses) != len(ref_poses):
        return False
    for p in ref_poses:
        target = np.array([k * p[0], k * p[1], p[2]])
        if not any(np.max(np.abs(np.asarray(r[:2]) - target[:2])) <= 1e-8 * k and dphi(r[2], p[2]) <= 1e-8
                   for r in poses):
            return False
    return True


# the extreme scales 1e-6 and 1e6 in the fast lane, the milder 1e-3 and 1e3 with the slow checks
@pytest.mark.parametrize("case", range(7), ids=[c[0] for c in UNIT_CASES])
@pytest.mark.parametrize("k", [1e-6, pytest.param(1e-3, marks=pytest.mark.slow),
                               pytest.param(1e3, marks=pytest.mark.slow), 1e6])
def test_same_modes_in_any_unit_on_every_path(case, k):
    kind, m, q, ref = UNIT_CASES[case]
    ms = isp.PlanarParallel([scaled_leg(leg, k) for leg in m.legs])
    qs = scaled_q(m, q, k)
    refp = [mm.pose for mm in ref]
    assert same_modes([mm.pose for mm in ms.direct_kinematics(qs)], refp, k)
    assert same_modes([mm.pose for mm in ms.direct_kinematics(qs, certify=True)], refp, k)
    b = ms.direct_kinematics_batch([qs] * 3, method="numpy")
    assert all(same_modes(b.poses[i][b.valid[i]], refp, k) for i in range(3))
    assert not b.near_singular.any()


# --------------------------------------------------------------------------- item 10, 14, 15

def test_tolerances_reach_the_root_filter():
    """A real_root_imag of 0.5 lets complex roots through as candidates; they are then polished
    and checked, so the modes do not change: the knob reaches the filter (the candidates grow),
    and the checks still hold."""
    import imagespace.solve.numpy_path as man

    m = isp.examples.general_3rpr()
    q = m.q_example_float
    seen = []
    orig = man.real_half_angles

    def spy(F, tol=None):
        seen.append(tol)
        return orig(F, tol)

    man.real_half_angles = spy
    try:
        loose = isp.PlanarParallel(m.legs, tolerances=isp.Tolerances(real_root_imag=0.5))
        modes = loose.direct_kinematics(q)
    finally:
        man.real_half_angles = orig
    assert seen and all(t == 0.5 for t in seen)
    assert len(modes) == 6
    with pytest.raises(ValueError, match="real_root_imag"):
        isp.Tolerances(real_root_imag=-1.0)


def test_exact_cache_keys():
    m = isp.examples.general_3rpr()
    a = m.kinematic_polynomial([2**53, 5, 10])
    b = m.kinematic_polynomial([2**53 + 1, 5, 10])
    assert a != b
    x0, x1 = isp.image_symbols()[:2]
    direct = m.kinematic_polynomial([sp.Integer(2**53 + 1), 5, 10])
    assert b == direct
    c = m.kinematic_polynomial([1 / 3, 5, 10])
    d = m.kinematic_polynomial([Fraction(1, 3), 5, 10])
    assert c != d and d == m.kinematic_polynomial([sp.Rational(1, 3), 5, 10])


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_coefficients_are_refused(bad):
    with pytest.raises(isp.InputError, match="finite"):
        isp.certify_real_roots([1.0, bad, 1.0])
    with pytest.raises(isp.InputError, match="finite"):
        isp.certify_real_roots([1.0, sp.nan, 1.0] if bad != bad else [1.0, sp.oo, 1.0])
    counts, path = isp.certify_real_roots_batch(np.array([[1.0, bad, 1.0], [1.0, 0.0, -1.0]]))
    assert counts.tolist() == [-1, 2] and path.tolist() == ["invalid", "discs"]


def test_strings_are_not_coefficients(tmp_path):
    target = tmp_path / "x"
    with pytest.raises(TypeError):
        isp.certify_real_roots([f"__import__('pathlib').Path({str(target)!r}).write_text('x') and 0", 0, -1])
    assert not target.exists()


def test_distinct_orientation_count_equals_a_plain_loop(rng):
    """The vectorised count of distinct orientations (used to decide near_singular) against a
    plain per-row loop written here, with near-duplicates and the identified ends +-pi/2."""
    from imagespace.solve.numpy_path import _distinct_orientations_batch

    def plain(h, tol):
        h = sorted(h)
        if not h:
            return 0
        gaps = [b - a for a, b in zip(h, h[1:])] + [h[0] + np.pi - h[-1]]
        return max(1, sum(g > tol for g in gaps))

    H = rng.uniform(-np.pi / 2, np.pi / 2, (3000, 6))
    H[:, 1] = H[:, 0] + rng.choice([0.0, 1e-9, 1e-3], 3000)
    H[:, 2] = np.where(rng.random(3000) < 0.2, np.pi / 2, H[:, 2])
    H[:, 3] = np.where(rng.random(3000) < 0.2, -np.pi / 2 + 1e-12, H[:, 3])
    V = rng.random((3000, 6)) < 0.7
    got = _distinct_orientations_batch(H, V, 1e-7)
    want = np.array([plain(list(H[i][V[i]]), 1e-7) for i in range(3000)])
    assert np.array_equal(got, want) and len(set(want.tolist())) >= 4


@pytest.mark.slow
@pytest.mark.parametrize("method", ["numpy", "kernel"])
def test_certified_batch_at_and_near_half_turns(method):
    """Rows whose modes sit at phi = pi exactly or within 1e-9 of it: certified counts equal the
    exact count of the test, and every mode is accounted for on every row."""
    m = isp.examples.general_3rpr()
    rng = np.random.default_rng(5)
    poses = np.column_stack([rng.uniform(-1, 1, 60), rng.uniform(-1, 1, 60),
                             np.pi - rng.choice([0.0, 1e-9, -1e-9, 1e-12], 60)])
    Q = m.inverse_kinematics(poses)
    Q = Q[np.all(np.isfinite(Q) & (Q > 0), axis=1)]
    b = m.direct_kinematics_batch(Q, certify=True, method=method)
    exact = exact_counts(m, Q)
    assert len(Q) >= 40 and np.all(b.row_ok)
    assert np.array_equal(b.certified_roots, exact) and np.array_equal(b.count, exact)
    assert b.consistent.all()
    hits = sum(any(abs(abs(ph) - np.pi) < 1e-8 for ph in b.poses[i][b.valid[i]][:, 2]) for i in range(len(Q)))
    assert hits == len(Q)                        # each row's own half-turn pose is among its modes


@pytest.mark.slow
@pytest.mark.parametrize("k", [1e-6, 1e6])
def test_kernel_path_in_any_unit(k):
    m = isp.examples.general_3rpr()
    q = m.q_example_float
    ms = isp.PlanarParallel([scaled_leg(leg, k) for leg in m.legs])
    ref = [mm.pose for mm in m.direct_kinematics(q, certify=True)]
    b = ms.direct_kinematics_batch(np.tile(k * q, (4, 1)), method="kernel")
    assert all(same_modes(b.poses[i][b.valid[i]], ref, k) for i in range(4))
    assert np.all(b.solver == "kernel") and not b.near_singular.any()
