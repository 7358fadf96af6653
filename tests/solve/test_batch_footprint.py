"""The ragged DKBatchResult: its padded attributes against per-row solves and identities, its
footprint against the arrays it holds, read-only padded arrays, and the mutation API."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.core.kinematic_map import pose_of
from imagespace.solve.kernel import HAVE_NUMBA
from imagespace.solve.results import CERTIFICATE_PATHS, MAX_MODES, SOLVER_NAMES, DKBatchResult

PADDED = ("image_points", "poses", "valid", "residual", "aspect", "multiplicity")


def random_rows(m, rng, n, spread=6.0):
    """Joint vectors of random poses (as benchmarks/dk_throughput.py makes them), reachable rows only."""
    poses = np.column_stack([rng.uniform(-spread, spread, 3 * n), rng.uniform(-spread, spread, 3 * n),
                             rng.uniform(-np.pi, np.pi, 3 * n)])
    Q = m.inverse_kinematics(poses)
    return Q[np.all(np.isfinite(Q), axis=1)][:n]


def designs():
    return [("seed002", isp.examples.stigger_husty(), 6.0), ("general_3rpr", isp.examples.general_3rpr(), 1.0)]


def reference_padded(m, Q):
    """The padded arrays rebuilt from per-row ``direct_kinematics`` (numpy path, one row per call)."""
    n = len(Q)
    P = np.full((n, MAX_MODES, 3), np.nan)
    R = np.full((n, MAX_MODES), np.nan)
    A = np.zeros((n, MAX_MODES), dtype=int)
    V = np.zeros((n, MAX_MODES), dtype=bool)
    C = np.zeros(n, dtype=int)
    for i, q in enumerate(Q):
        modes = m.direct_kinematics(q)
        C[i] = len(modes)
        for j, mm in enumerate(modes):
            P[i, j], R[i, j], A[i, j], V[i, j] = mm.pose, mm.residual, mm.aspect, True
    return P, R, A, V, C


def arrays_held(res):
    """Every numpy array the result holds: its attributes, and arrays inside dict attributes
    (walked here, independently of DKBatchResult.nbytes)."""
    out = []
    for v in vars(res).values():
        if isinstance(v, np.ndarray):
            out.append(v)
        elif isinstance(v, dict):
            out += [w for w in v.values() if isinstance(w, np.ndarray)]
    return out


@pytest.mark.slow
@pytest.mark.parametrize("name,m,spread", designs(), ids=["seed002", "general_3rpr"])
def test_padded_attributes_equal_per_row_solves(name, m, spread, rng):
    Q = random_rows(m, rng, 80, spread)
    Q = np.concatenate([Q, [[np.nan, 1.0, 1.0]]])               # one masked row
    res = m.direct_kinematics_batch(Q, method="numpy")
    P, R, A, V, C = reference_padded(m, Q[:-1])
    assert res.count.dtype == np.uint8 and res.aspect.dtype == np.int8
    assert res.poses.shape == (len(Q), MAX_MODES, 3) and res.image_points.shape == (len(Q), MAX_MODES, 4)
    assert np.array_equal(res.count[:-1], C) and res.count[-1] == 0
    assert np.array_equal(res.valid[:-1], V) and not res.valid[-1].any()
    assert np.max(np.abs(res.poses[:-1][V] - P[V])) <= 1e-12
    assert np.all(np.isnan(res.poses[~res.valid])) and np.all(np.isnan(res.image_points[~res.valid]))
    assert np.all(np.isnan(res.residual[~res.valid])) and np.all(res.aspect[~res.valid] == 0)
    assert np.array_equal(res.aspect[:-1], A)
    assert np.allclose(res.residual[:-1][V], R[V], rtol=1e-6, atol=1e-15)
    assert np.all(res.multiplicity == 1)
    assert res.solver.tolist() == ["numpy"] * (len(Q) - 1) + ["invalid"]
    # the image points are derived from the poses: identities independent of the storage
    X = res.image_points[res.valid]
    assert np.max(np.abs(X[:, 0] ** 2 + X[:, 1] ** 2 - 1)) <= 1e-15 * 4
    assert np.all((X[:, 0] > 0) | ((X[:, 0] == 0) & (X[:, 1] > 0)))        # the normalised sign
    assert np.max(np.abs(pose_of(X) - res.poses[res.valid])) <= 1e-12 * max(1.0, spread)
    rows = np.repeat(np.arange(len(Q)), res.count)
    for qd in m.quadrics(Q[rows]):          # the constraint quadrics, one per mode's joint vector
        coeffs = np.abs(np.stack([np.broadcast_to(np.asarray(c, float), rows.shape) for c in qd.coefficients()]))
        scale = coeffs.max(axis=0) * np.maximum(1.0, np.max(X ** 2, axis=1))
        assert np.all(np.abs(qd.evaluate(X)) <= 1e-9 * scale)
    # modes(i) is the same row
    for i in range(0, len(Q), 17):
        modes = res.modes(i)
        assert len(modes) == res.count[i]
        for j, mm in enumerate(modes):
            assert np.array_equal(mm.pose, res.poses[i, j]) and np.array_equal(mm.image_point, res.image_points[i, j])
            assert mm.aspect == res.aspect[i, j] and mm.residual == res.residual[i, j]


@pytest.mark.slow
@pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel needs numba")
def test_kernel_result_in_chunks_equals_numpy_result_padded(rng, monkeypatch):
    from imagespace.solve import planar as dispatch

    m = isp.examples.stigger_husty()
    Q = random_rows(m, rng, 3000)
    Q[[5, 2500]] = np.nan                          # masked rows in two chunks
    whole = m.direct_kinematics_batch(Q, method="kernel")
    monkeypatch.setattr(dispatch, "KERNEL_CHUNK_ROWS", 700)
    ker = m.direct_kinematics_batch(Q, method="kernel")
    for name in PADDED + ("count", "row_ok", "special", "near_singular", "solver"):
        assert np.array_equal(getattr(ker, name), getattr(whole, name), equal_nan=name in ("poses", "image_points", "residual")), name
    assert ker.errors == whole.errors and sorted(ker.errors) == [5, 2500]
    num = m.direct_kinematics_batch(Q, method="numpy")
    same = (ker.solver == "kernel")
    assert same.mean() > 0.99
    assert np.array_equal(ker.count[same], num.count[same])
    v = ker.valid & same[:, None]
    assert np.max(np.abs(ker.poses[v] - num.poses[v])) <= 1e-9
    assert np.array_equal(ker.aspect[same], num.aspect[same])


def test_half_turn_image_point_keeps_the_sign_convention():
    m = isp.examples.general_3rpr()
    Q = m.inverse_kinematics(np.array([[0.2, -0.1, np.pi], [0.1, 0.3, -np.pi / 2]]))
    res = m.direct_kinematics_batch(Q, method="numpy")
    half = np.flatnonzero(res.valid[0] & (res.poses[0, :, 2] == np.pi))
    assert half.size == 1
    X = res.image_points[0, half[0]]
    assert X[0] == 0.0 and X[1] == 1.0            # x0 == 0 and x1 > 0: the normalised representative
    # the pose's own image point: x2 = (x1 x - x0 y) / 2, x3 = (x0 x + x1 y) / 2 at x0 = 0, x1 = 1
    x, y, _ = res.poses[0, half[0]]
    assert X[2] == x / 2 and X[3] == y / 2


def benchmark_rows(n):
    """The benchmark's rows (benchmarks/dk_throughput.py, benchmarks/result_memory.py): joint
    vectors of random poses of seed 002, unreachable ones included (masked rows)."""
    m = isp.examples.stigger_husty()
    rng = np.random.default_rng(0)
    poses = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-6, 6, n), rng.uniform(-np.pi, np.pi, n)])
    return m, m.inverse_kinematics(poses)


@pytest.mark.parametrize("method", ["numpy", "kernel"])
def test_footprint_below_150_bytes_a_row_and_equal_to_the_arrays_held(method):
    if method == "kernel" and not HAVE_NUMBA:
        pytest.skip("the kernel needs numba")
    n = 4000
    m, Q = benchmark_rows(n)
    res = m.direct_kinematics_batch(Q, method=method)
    assert res.nbytes == sum(a.nbytes for a in arrays_held(res))
    assert res.nbytes < 150 * n
    # the old padded layout of the same result, from its documented dtypes, for scale
    old = n * MAX_MODES * (4 * 8 + 3 * 8 + 8 + 8 + 1 + 1) + n * (8 + 1 + 1 + 1 + 4 * 9)
    assert res.nbytes < old / 3
    # padded arrays kept from an access are counted, and released
    _ = res.poses, res.valid
    assert res.nbytes == sum(a.nbytes for a in arrays_held(res))
    res.release_padded()
    assert res.nbytes < 150 * n
    # certified results too
    rc = m.direct_kinematics_batch(Q[:300], method=method, certify=True)
    assert rc.nbytes == sum(a.nbytes for a in arrays_held(rc))
    assert rc.certified_roots.dtype == np.int8 and rc.certificate_path_code.dtype == np.uint8
    assert set(rc.certificate_path.tolist()) <= set(CERTIFICATE_PATHS)


def test_padded_arrays_and_codes_are_read_only():
    m = isp.examples.general_3rpr()
    res = m.direct_kinematics_batch([m.q_example_float] * 3, certify=True)
    for name in PADDED + ("count", "solver", "solver_code", "certificate_path", "certificate_path_code"):
        arr = getattr(res, name)
        assert not arr.flags.writeable, name
        with pytest.raises(ValueError):
            arr[0] = arr[1]
    with pytest.raises(AttributeError):
        res.poses = np.zeros((3, 6, 3))
    # the codes decode through the name tables
    assert [SOLVER_NAMES[k] for k in res.solver_code] == res.solver.tolist()
    assert [CERTIFICATE_PATHS[k] for k in res.certificate_path_code] == res.certificate_path.tolist()
    assert np.all(res.solver == "numpy")


@pytest.mark.slow
@pytest.mark.parametrize("block_rows", [512, 0], ids=["blocks", "scatter"])
def test_set_modes_round_trip_against_per_row_solves(rng, monkeypatch, block_rows):
    from imagespace.solve import results

    monkeypatch.setattr(results, "SPLICE_BLOCK_ROWS", block_rows)      # both rebuilds
    m = isp.examples.stigger_husty()
    Q = random_rows(m, rng, 40)
    Q2 = random_rows(m, rng, 40)
    res = m.direct_kinematics_batch(Q, method="numpy")
    rows = [3, 0, 17, 39, 25]
    res.set_modes(rows, [m.direct_kinematics(Q2[i]) for i in rows])
    res.set_modes(5, [])
    expect_q = Q.copy()
    expect_q[rows] = Q2[rows]
    P, R, A, V, C = reference_padded(m, expect_q)
    V[5], C[5] = False, 0
    assert np.array_equal(res.count, C) and np.array_equal(res.valid, V)
    assert np.max(np.abs(res.poses[V] - P[V])) <= 1e-12
    assert np.array_equal(res.aspect[V], A[V])
    assert np.allclose(res.residual[V], R[V], rtol=1e-6, atol=1e-15)
    # singular modes keep their multiplicity
    mm = res.modes(0)[0]
    res.set_modes(1, [isp.AssemblyMode(mm.image_point, mm.pose, mm.residual, 0, True, 2)])
    assert res.multiplicity[1].tolist() == [2, 1, 1, 1, 1, 1] and res.count[1] == 1
    assert np.all(res.multiplicity[np.arange(len(Q)) != 1] == 1)
    with pytest.raises(ValueError):
        res.set_modes([1, 1], [[], []])
    with pytest.raises(IndexError):
        res.set_modes(len(Q), [])


@pytest.mark.parametrize("block_rows", [512, 0], ids=["blocks", "scatter"])
def test_replace_rows_round_trip_against_per_row_solves(rng, monkeypatch, block_rows):
    from imagespace.solve import results

    monkeypatch.setattr(results, "SPLICE_BLOCK_ROWS", block_rows)      # both rebuilds
    m = isp.examples.stigger_husty()
    Q = random_rows(m, rng, 30)
    Q2 = np.concatenate([random_rows(m, rng, 3), [[np.nan, 1.0, 1.0]]])
    res = m.direct_kinematics_batch(Q, method="numpy")
    rows = np.array([29, 4, 11, 0])
    res.replace_rows(rows, m.direct_kinematics_batch(Q2, method="numpy"))
    expect_q = Q.copy()
    expect_q[rows] = Q2
    whole = m.direct_kinematics_batch(expect_q, method="numpy")
    for name in PADDED:
        a, b = getattr(res, name), getattr(whole, name)
        assert np.array_equal(np.isnan(a) if a.dtype.kind == "f" else a, np.isnan(b) if b.dtype.kind == "f" else b)
    v = whole.valid
    assert np.max(np.abs(res.poses[v] - whole.poses[v])) <= 1e-12
    for name in ("count", "row_ok", "special", "near_singular", "solver"):
        assert np.array_equal(getattr(res, name), getattr(whole, name)), name
    assert list(res.errors) == [0] == list(whole.errors)
    P, R, A, V, C = reference_padded(m, expect_q[1:])           # row 0 is the masked one
    assert res.count[0] == 0 and np.array_equal(res.count[1:], C)
    assert np.max(np.abs(res.poses[1:][V] - P[V])) <= 1e-12


def test_concatenate_and_from_padded():
    m = isp.examples.general_3rpr()
    a = m.direct_kinematics_batch([m.q_example_float] * 2, method="numpy")
    b = m.direct_kinematics_batch([[np.nan, 1.0, 1.0], m.q_example_float], method="numpy", certify=True)
    r = DKBatchResult.concatenate([a, b])
    assert r.count.tolist() == [6, 6, 0, 6] and list(r.errors) == [2]
    assert r.certified_roots.tolist() == [-1, -1, -1, 6]
    assert np.array_equal(r.poses[:2], a.poses) and np.array_equal(r.poses[2:], b.poses, equal_nan=True)
    again = DKBatchResult.from_padded(r.poses, r.valid, r.residual, r.aspect, r.row_ok, solver=r.solver_code)
    assert np.array_equal(again.poses, r.poses, equal_nan=True) and again.solver.tolist() == r.solver.tolist()
    bad = r.valid.copy()
    bad[0, 0] = False                        # a hole before a valid slot
    with pytest.raises(ValueError):
        DKBatchResult.from_padded(r.poses, bad, r.residual, r.aspect, r.row_ok)
    with pytest.raises(ValueError):
        a.set_solver([0], "magic")
