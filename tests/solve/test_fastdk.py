"""The compiled batch kernel against independent references (certified counts by discs and flint,
mpmath roots of the exact polynomial, msolve on the Euclidean DK system of ``tests/msolve_ref.py``)
and, as consistency checks beside them, against the numpy path and the per-call path."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.core.certify import certify_real_roots_batch
from imagespace.solve.kernel import HAVE_NUMBA
from imagespace.core.kinematic_map import pose_of
from msolve_ref import msolve_available, planar_dk_reference

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel needs numba")


def distinct_orientations(res):
    """Number of distinct orientations (x0 : x1) among each row's modes (two modes of one
    orientation, as in case (a), count once), like the certified root count."""
    half = np.arctan2(res.image_points[..., 1], res.image_points[..., 0])
    out = np.zeros(len(res.count), dtype=int)
    for i in range(len(out)):
        h = np.sort(half[i][res.valid[i]])
        out[i] = 0 if h.size == 0 else 1 + int(np.sum(np.diff(h) > 1e-9))
    return out


def boundary_rows(m, rng, n_lines, record=(16, 24, 32, 44)):
    """Joint vectors next to the discriminant (two modes about to merge): on random segments of
    joint space whose ends have different certified real-root counts, bisect on the certified
    count (not on the kernel); both ends of the bracket are kept after 16, 24, 32 and 44 halvings
    (root pairs from ~1e-2 down to ~1e-7 apart). Returns the rows and, per row, its partner on
    the other side of the bracket."""
    F = m.compiled().coefficients
    q0 = np.asarray(m.q_example_float)
    lo = q0 * (1 + 0.2 * rng.standard_normal((20 * n_lines, 3)))
    hi = q0 * (1 + 0.2 * rng.standard_normal((20 * n_lines, 3)))
    ca, _ = certify_real_roots_batch(F(lo))
    cb, _ = certify_real_roots_batch(F(hi))
    keep = np.flatnonzero((ca != cb) & (ca >= 0) & (cb >= 0))[:n_lines]
    lo, hi, ca = lo[keep], hi[keep], ca[keep]
    out = []
    for step in range(1, max(record) + 1):
        mid = 0.5 * (lo + hi)
        cm, _ = certify_real_roots_batch(F(mid))
        same = cm == ca
        lo = np.where(same[:, None], mid, lo)
        hi = np.where(same[:, None], hi, mid)
        if step in record:
            out += [lo.copy(), hi.copy()]
    return np.concatenate(out), len(keep)


@pytest.fixture(scope="module")
def seed002():
    return isp.examples.stigger_husty()


@pytest.fixture(scope="module")
def hundred_thousand(seed002):
    rng = np.random.default_rng(20261122)
    near, lines = boundary_rows(seed002, rng, 500)
    q0 = np.asarray(seed002.q_example_float)
    # joint vectors of random poses all over the workspace (small legs, polynomials with tiny
    # low-order coefficients: the rows that once caught a crawling root solver) ...
    poses = np.column_stack([rng.uniform(-6, 6, 60_000), rng.uniform(-6, 6, 60_000),
                             rng.uniform(-np.pi, np.pi, 60_000)])
    reach = seed002.inverse_kinematics(poses)
    reach = reach[np.all(np.isfinite(reach), axis=1)][:30_000]
    # ... and around the seed's joint vector
    wide = q0 * (1 + 0.15 * rng.standard_normal((100_000 - len(near) - len(reach), 3)))
    Q = np.concatenate([near, reach, wide])
    return Q, len(near), lines


@pytest.mark.slow
def test_kernel_counts_equal_certified_counts_on_100000_rows(seed002, hundred_thousand):
    Q, n_near, lines = hundred_thousand
    assert lines == 500
    res = seed002.direct_kinematics_batch(Q, method="kernel")
    certified, path = certify_real_roots_batch(seed002.compiled().coefficients(Q))
    assert np.all(certified >= 0)
    mine = distinct_orientations(res)
    by_kernel = res.solver == "kernel"
    # every row the kernel answered itself has the proven number of real roots
    assert np.array_equal(mine[by_kernel], certified[by_kernel])
    # the rows it handed on (roots it could not separate in floating point) are rare among the
    # random rows; with certify=True every one of them ends consistent with the proof
    handed = np.flatnonzero(~by_kernel)
    assert np.mean(~by_kernel[n_near:]) <= 0.001
    assert set(res.solver[handed]) <= {"numpy"}
    sample = handed[handed >= n_near]
    again = seed002.direct_kinematics_batch(Q[sample], method="kernel", certify=True)
    assert np.all(again.consistent)
    level = handed[handed < n_near] // (2 * lines)
    assert np.all(level >= 1)       # only pairs closer than ~1e-5 are handed on
    # next to the discriminant: the two sides of each bracket differ by a pair of real roots
    # about to merge, and the kernel sees the same step wherever it answered both sides
    near = res.count[:n_near].reshape(-1, 2, lines)
    cert_near = certified[:n_near].reshape(-1, 2, lines)
    mine_near = mine[:n_near].reshape(-1, 2, lines)
    kern_near = by_kernel[:n_near].reshape(-1, 2, lines)
    assert np.all(np.abs(cert_near[:, 0] - cert_near[:, 1]) == 2)
    both = kern_near[:, 0] & kern_near[:, 1]
    assert np.all(both[0])          # 16 halvings: roots ~1e-2 apart, the kernel decides
    assert np.array_equal((mine_near[:, 0] - mine_near[:, 1])[both],
                          (cert_near[:, 0] - cert_near[:, 1])[both])
    assert near.shape[0] == 4


@pytest.mark.slow
def test_kernel_roots_within_1e_10_of_the_exact_polynomial(seed002, hundred_thousand):
    """The reference: the exact kinematic polynomial (general in q, coefficients in Q(sqrt 181))
    evaluated at the float joint values with 50-digit mpmath arithmetic, its roots by
    mpmath.polyroots; the real ones compared as half-angles atan(x1/x0)."""
    import mpmath
    import sympy as sp

    Q, n_near, lines = hundred_thousand
    P = seed002.kinematic_polynomial()
    d = P.total_degree()
    coeff = sp.lambdify(seed002.joint_symbols, [P.coeff_monomial((d - k, k)) for k in range(d + 1)],
                        "mpmath")
    rows = np.concatenate([np.arange(0, n_near, 12), np.arange(n_near, n_near + 500)])
    res = seed002.direct_kinematics_batch(Q[rows], method="kernel")
    worst_far = 0.0
    checked = 0
    with mpmath.workdps(50):
        for i in range(len(rows)):
            if res.solver[i] != "kernel":
                continue
            c = coeff(*[mpmath.mpf(float(v)) for v in Q[rows[i]]])
            r = mpmath.polyroots(c[::-1], maxsteps=200, extraprec=200)
            exact = np.sort([float(mpmath.atan(z.real)) for z in r if abs(z.imag) < mpmath.mpf(10) ** -30])
            theta = np.sort(np.arctan2(res.image_points[i, res.valid[i], 1],
                                       res.image_points[i, res.valid[i], 0]))
            assert len(theta) == len(exact), (i, theta, exact)
            cplx = [z for z in r if abs(z.imag) >= mpmath.mpf(10) ** -30]
            for k, m in enumerate(exact):
                err = abs(theta[k] - m)
                # distance to the nearest other root, complex ones included (in t = tan theta)
                others = [abs(complex(z) - np.tan(m)) for z in cplx] + \
                         [abs(np.tan(o) - np.tan(m)) for j, o in enumerate(exact) if j != k]
                sep = min(others) / (1 + np.tan(m) ** 2) if others else np.inf
                # a root closer than 1e-4 to another is fixed by double-precision data only to
                # about 1e-14 / separation: the limit of any float method, not of the kernel
                allowed = 1e-10 if sep > 1e-4 else 1e-14 / sep
                assert err <= allowed, (i, m, err, sep)
                if sep > 1e-4:
                    worst_far = max(worst_far, err)
            checked += 1
    assert checked >= 0.8 * len(rows)
    assert worst_far <= 1e-10
    print(f"checked {checked} rows, worst far-root error {worst_far:.2e}")


def assert_modes_match_msolve(m, Q, res, rows, tol):
    """The kernel's modes of each row in ``rows`` against msolve's real solutions of the Euclidean
    DK system (exact rational input: the floats as binary rationals), poses sorted by ``phi``."""
    for i in rows:
        ref = planar_dk_reference(m, Q[i])
        assert len(ref.poses) == res.count[i], (i, Q[i].tolist())
        mine = res.poses[i, res.valid[i]]
        mine = mine[np.argsort(mine[:, 2])]
        assert np.max(np.abs(mine - ref.poses), initial=0.0) <= tol, (i, Q[i].tolist())


@pytest.mark.slow
def test_kernel_equals_numpy_path_and_per_call_on_10000_rows(seed002):
    """A consistency check (the three paths of imagespace agree row by row), beside the
    independent ones: msolve on a sample of these rows here, the certified counts and the mpmath
    roots above."""
    rng = np.random.default_rng(7)
    q0 = np.asarray(seed002.q_example_float)
    Q = q0 * (1 + 0.1 * rng.standard_normal((10_000, 3)))
    ker = seed002.direct_kinematics_batch(Q, method="kernel")
    num = seed002.direct_kinematics_batch(Q, method="numpy")
    assert np.array_equal(ker.count, num.count)
    assert np.array_equal(ker.valid, num.valid)
    v = ker.valid
    assert np.max(np.abs(ker.image_points[v] - num.image_points[v])) < 1e-9
    assert np.array_equal(ker.aspect, num.aspect)
    # the pose columns follow from the image points by the kinematic map
    assert np.max(np.abs(pose_of(ker.image_points[v]) - ker.poses[v])) < 1e-12
    # the kernel's residual is a joint-space residual: compare with the legs' IK
    assert np.max(ker.residual[v]) < 1e-9
    assert np.max(np.abs(seed002.joint_residual(ker.poses[v], np.repeat(Q, ker.count, axis=0)))) < 1e-8
    for i in range(len(Q)):
        single = seed002.direct_kinematics(Q[i])
        assert len(single) == ker.count[i]
        for j, mm in enumerate(single):
            assert np.max(np.abs(mm.image_point - ker.image_points[i, j])) < 1e-9
            assert mm.aspect == ker.aspect[i, j]
    if msolve_available():
        assert_modes_match_msolve(seed002, Q, ker, range(0, len(Q), 400), 1e-8)


@pytest.mark.slow
def test_kernel_on_other_leg_types(rng):
    """RRR, PRR, RRP legs with actuated angles and offsets: the kernel's modes against msolve on a
    sample of rows (independent), then kernel = numpy path on all rows (a consistency check)."""
    legs = [isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3.0, 2.5), actuated=0),
            isp.PRR(base=(6, 0), axis=(0.4, 1.0), platform=(1.5, 0), length=2.8),
            isp.RRP(base=(2, 5), length=2.0, platform=(0, 1.2), direction=(1.0, 0.3))]
    m = isp.PlanarParallel(legs)
    poses = np.column_stack([rng.uniform(1, 3, 3000), rng.uniform(0.5, 2.5, 3000),
                             rng.uniform(-0.6, 0.6, 3000)])
    Q = m.inverse_kinematics(poses, working_modes=[1, 0, 0])
    keep = np.all(np.isfinite(Q), axis=1)
    Q = Q[keep]
    ker = m.direct_kinematics_batch(Q, method="kernel")
    num = m.direct_kinematics_batch(Q, method="numpy")
    same = ker.solver == "kernel"
    assert same.mean() > 0.98
    if msolve_available():
        assert_modes_match_msolve(m, Q, ker, np.flatnonzero(same)[:30], 1e-7)
    assert np.array_equal(ker.count[same], num.count[same])
    v = ker.valid & same[:, None]
    assert np.max(np.abs(ker.image_points[v] - num.image_points[v])) < 1e-8
    # the generating pose is among the modes of its row
    found = [np.min(np.max(np.abs(ker.poses[i, ker.valid[i]] - poses[keep][i]), axis=1)) < 1e-7
             for i in range(len(Q)) if ker.count[i]]
    assert np.mean(found) == 1.0


def test_kernel_masks_bad_rows_and_refuses_unsuited_designs(seed002):
    Q = np.tile(seed002.q_example_float, (5, 1))
    Q[1] = np.nan
    Q[3, 0] = -2.0
    r = seed002.direct_kinematics_batch(Q, method="kernel")
    assert r.row_ok.tolist() == [True, False, True, False, True]
    assert r.solver.tolist() == ["kernel", "invalid", "kernel", "invalid", "kernel"]
    assert r.count.tolist() == [6, 0, 6, 0, 6]
    assert set(r.errors) == {1, 3}
    assert seed002.direct_kinematics_batch(np.zeros((0, 3)), method="kernel").count.shape == (0,)
    with pytest.raises(isp.InputError, match="method='kernel' is not available"):
        isp.examples.collinear_3rpr().direct_kinematics_batch(Q[:1], method="kernel")
    with pytest.raises(isp.InputError, match="method must be"):
        seed002.direct_kinematics_batch(Q, method="fast")


def test_chunks_cover_the_batch(seed002):
    rng = np.random.default_rng(3)
    Q = np.asarray(seed002.q_example_float) * (1 + 0.05 * rng.standard_normal((2500, 3)))
    whole = seed002.direct_kinematics_batch(Q, method="kernel")
    starts, counts = [], []
    for start, part in seed002.direct_kinematics_chunks(Q, chunk_size=1000, method="kernel"):
        starts.append(start)
        counts.append(part.count)
    assert starts == [0, 1000, 2000]
    assert np.array_equal(np.concatenate(counts), whole.count)
    with pytest.raises(isp.InputError, match="chunk_size"):
        next(seed002.direct_kinematics_chunks(Q, chunk_size=0))


@pytest.mark.slow
def test_the_kernel_reads_its_thresholds_from_the_design_tolerances():
    """With kernel_residual so small that no float mode meets it, the kernel must hand every
    row to the numpy path (solver 'numpy'), and the counts stay those of the numpy path."""
    from imagespace.solve.kernel import HAVE_NUMBA
    if not HAVE_NUMBA:
        pytest.skip("needs numba")
    base = isp.examples.general_3rpr()
    strict = isp.PlanarParallel(base.legs, tolerances=isp.Tolerances(kernel_residual=1e-300))
    rng = np.random.default_rng(7)
    Q = base.q_example_float * (1 + 0.05 * rng.standard_normal((50, 3)))
    loose = base.direct_kinematics_batch(Q, method="kernel")
    tight = strict.direct_kinematics_batch(Q, method="kernel")
    assert np.all(loose.solver == "kernel")
    assert np.all(tight.solver[tight.count > 0] != "kernel")
    assert np.array_equal(tight.count, base.direct_kinematics_batch(Q, method="numpy").count)
