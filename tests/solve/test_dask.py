"""direct_kinematics_dask: block by block (on a LocalCluster of worker processes, and with the
synchronous scheduler in the fast lane) it gives what one direct_kinematics_batch gives on the same
rows, its counts are the certified root counts, each block is solved once, and bad input is
refused at the boundary."""

import pickle

import numpy as np
import pytest

import imagespace as isp

da = pytest.importorskip("dask.array")
dask = pytest.importorskip("dask")
from dask.callbacks import Callback  # noqa: E402

from imagespace.solve.distributed import DEFAULT_CHUNK_ROWS, DKDaskResult  # noqa: E402

# uneven row blocks: two take the compiled kernel under method="auto" (>= 2000 rows), the others
# the numpy path; one block is all NaN
CHUNKS = (2500, 7, 1800, 5, 2100, 388)
N = sum(CHUNKS)
MASKS = ("count", "valid", "aspect", "row_ok", "near_singular")


@pytest.fixture(scope="module")
def seed002():
    return isp.examples.stigger_husty()


@pytest.fixture(scope="module")
def rows(seed002):
    """Joint vectors of random poses (seed 002's inverse kinematics; unreachable ones dropped), rows
    around the seed's joint vector (some with fewer modes), a block of NaN rows, NaN entries and
    negative lengths scattered (masked rows)."""
    rng = np.random.default_rng(20261202)
    poses = np.column_stack([rng.uniform(-6, 6, 8000), rng.uniform(-6, 6, 8000),
                             rng.uniform(-np.pi, np.pi, 8000)])
    reach = seed002.inverse_kinematics(poses)
    reach = reach[np.all(np.isfinite(reach), axis=1)][:N // 2]
    q0 = np.asarray(seed002.q_example_float)
    wide = q0 * (1 + 0.15 * rng.standard_normal((N - len(reach), 3)))
    Q = np.concatenate([reach, wide])[rng.permutation(N)]
    start = CHUNKS[0] + CHUNKS[1] + CHUNKS[2]
    Q[start:start + CHUNKS[3]] = np.nan                      # a block of NaN rows only
    bad = rng.choice(N, 40, replace=False)
    Q[bad[:20], rng.integers(0, 3, 20)] = np.nan
    Q[bad[20:], 0] = -1.0                                     # a negative leg length
    return Q


@pytest.fixture(scope="module")
def batch(seed002, rows):
    """One direct_kinematics_batch over all rows, per method."""
    return {method: seed002.direct_kinematics_batch(rows, method=method) for method in ("kernel", "numpy")}


def same_as_batch(out, ref):
    for name in MASKS:
        assert np.array_equal(out[name], getattr(ref, name)), name
    np.testing.assert_array_equal(out["poses"], ref.poses)    # NaN in the same unused slots


class CountTasks(Callback):
    """Counts the tasks a local scheduler runs, by the prefix of their key."""

    def __init__(self):
        super().__init__()
        self.started = []

    def _pretask(self, key, dsk, state):
        self.started.append(key[0] if isinstance(key, tuple) else key)

    def count(self, prefix):
        return sum(1 for k in self.started if str(k).startswith(prefix))


@pytest.mark.slow
@pytest.mark.parametrize("method", ["kernel", "numpy"])
def test_blocks_give_what_one_batch_gives(seed002, rows, batch, method):
    Q = da.from_array(rows, chunks=(CHUNKS, 3))
    out = seed002.direct_kinematics_dask(Q, method=method).compute(scheduler="synchronous")
    same_as_batch(out, batch[method])
    assert out["count"].dtype == np.uint8 and out["aspect"].dtype == np.int8
    assert out["poses"].shape == (N, 6, 3) and out["valid"].shape == (N, 6)


def test_counts_are_the_certified_root_counts(seed002, rows, batch):
    # the certificate (inclusion discs, exact flint fallback) proves the number of distinct
    # real roots of each row's kinematic polynomial; every root of this design carries one mode
    Q = da.from_array(rows, chunks=(CHUNKS, 3))
    out = seed002.direct_kinematics_dask(Q).compute(scheduler="synchronous")
    cert = seed002.direct_kinematics_batch(rows, certify=True)
    ok = cert.row_ok
    assert ok.sum() > N - 60 - CHUNKS[3] and np.array_equal(out["row_ok"], ok)
    assert np.array_equal(out["count"][ok], cert.certified_roots[ok])
    assert set(np.unique(out["count"][ok]).tolist()) >= {0, 2, 4, 6}
    # auto: blocks under 2,000 rows take the numpy path, the others the kernel; the same modes
    kern = batch["kernel"]
    assert np.array_equal(out["count"], kern.count) and np.array_equal(out["valid"], kern.valid)
    np.testing.assert_allclose(out["poses"], kern.poses, rtol=0, atol=1e-9)


def test_masked_rows_are_masked_not_raised(seed002, rows):
    Q = da.from_array(rows, chunks=(CHUNKS, 3))
    out = seed002.direct_kinematics_dask(Q).compute(scheduler="synchronous")
    bad = ~np.all(np.isfinite(rows), axis=1) | (rows[:, 0] < 0)
    assert bad.sum() >= CHUNKS[3] + 20
    assert not out["row_ok"][bad].any() and not out["count"][bad].any()
    assert not out["valid"][bad].any() and np.isnan(out["poses"][bad]).all()
    start = CHUNKS[0] + CHUNKS[1] + CHUNKS[2]
    assert not out["row_ok"][start:start + CHUNKS[3]].any()


def test_certified_fields_match_the_certified_batch(seed002, rows):
    sub = rows[:900]
    Q = da.from_array(sub, chunks=(400, 3))
    r = seed002.direct_kinematics_dask(Q, certify=True)
    assert r.certified_roots is not None and r.consistent is not None
    out = r.compute(scheduler="synchronous")
    ref = seed002.direct_kinematics_batch(sub, certify=True)
    assert np.array_equal(out["certified_roots"], ref.certified_roots)
    assert np.array_equal(out["consistent"], ref.consistent)
    assert np.array_equal(out["count"], ref.count)
    assert seed002.direct_kinematics_dask(Q).certified_roots is None


def test_each_block_is_solved_once(seed002, rows):
    small = (250, 7, 300, 43)
    Q = da.from_array(rows[:sum(small)], chunks=(small, 3))
    r = seed002.direct_kinematics_dask(Q)
    # the manipulator is one key of the graph, not copied into each task
    graph = dict(r.records.__dask_graph__())
    assert sum(1 for k in graph if str(k).startswith("PlanarParallel-")) == 1
    with CountTasks() as tasks:
        r.compute(scheduler="synchronous")               # every array at once
    assert tasks.count("direct-kinematics-dask") == len(small)
    with CountTasks() as tasks:
        dask.compute(r.count, r.poses, r.near_singular, scheduler="synchronous")
    assert tasks.count("direct-kinematics-dask") == len(small)
    with CountTasks() as tasks:                          # a streamed reduction
        hist = da.bincount(r.count, minlength=7).compute(scheduler="synchronous")
    assert tasks.count("direct-kinematics-dask") == len(small) and hist.sum() == sum(small)
    with CountTasks() as tasks:                          # the summaries compute nothing
        text, page = repr(r), r._repr_html_()
    assert tasks.started == []
    assert f"rows={sum(small)}" in text and f"blocks={len(small)}" in text and "<table" in page


def test_numpy_and_column_chunked_input(seed002, rows, batch):
    sub = rows[:3000]
    r = seed002.direct_kinematics_dask(sub, method="kernel")           # numpy input
    assert r.count.chunks == ((3000,),) and 3000 <= DEFAULT_CHUNK_ROWS
    same_as_batch(r.compute(scheduler="synchronous"),
                  seed002.direct_kinematics_batch(sub, method="kernel"))
    cols = da.from_array(rows, chunks=(1000, 1))                       # split along the joints
    r = seed002.direct_kinematics_dask(cols, method="kernel")
    assert r.count.chunks == (cols.chunks[0],)
    same_as_batch(r.compute(scheduler="synchronous"), batch["kernel"])
    ints = seed002.direct_kinematics_dask([[10, 15, 13], [10, 15, 13]])  # a list of integers
    ref = seed002.direct_kinematics_batch([[10, 15, 13], [10, 15, 13]])
    assert ints.compute(scheduler="synchronous")["count"].tolist() == ref.count.tolist()


def test_design_pickles_without_its_compiled_kernel(seed002, rows):
    seed002.direct_kinematics_batch(rows[:2000], method="kernel")      # the kernel is cached now
    assert "kernel" in seed002.cache_keys()
    copy = pickle.loads(pickle.dumps(seed002))
    assert copy.cache_keys() == [] and len(pickle.dumps(seed002)) < 20_000
    assert np.array_equal(copy.direct_kinematics_batch(rows[:50], method="numpy").count,
                          seed002.direct_kinematics_batch(rows[:50], method="numpy").count)


@pytest.mark.parametrize("Q, call, exc, words", [
    (np.ones((4, 3), dtype=bool), {}, TypeError, "Q must be a real float or integer array"),
    (np.ones((4, 3), dtype=complex), {}, TypeError, "Q must be a real float or integer array"),
    ("dask-bool", {}, TypeError, "Q must be a real float or integer array, got a dask array"),
    ("dask-complex", {}, TypeError, "got a dask array of dtype complex128"),
    (np.ones((4, 4)), {}, isp.InputError, r"Q must have shape \(n, 3\)"),
    ("dask-4cols", {}, isp.InputError, r"Q must have shape \(n, 3\).*\(4, 4\)"),
    ("dask-1d", {}, isp.InputError, r"Q must have shape \(n, 3\).*\(3,\)"),
    (np.ones(3), {}, isp.InputError, r"Q must have shape \(n, 3\)"),
    (np.ones((2, 2, 3)), {}, isp.InputError, r"Q must have shape"),
    ([["10", "15", "13"]], {}, TypeError, "strings are never parsed"),
    (None, {}, TypeError, "Q must be numeric"),
    (np.ones((4, 3)), {"method": "fast"}, isp.InputError, "method must be 'auto', 'kernel' or 'numpy'"),
    (np.ones((4, 3)), {"method": None}, isp.InputError, "method must be"),
    (np.ones((4, 3)), {"certify": "yes"}, TypeError, "certify must be True or False"),
])
def test_bad_input_is_refused_at_the_boundary(seed002, Q, call, exc, words):
    if isinstance(Q, str) and Q.startswith("dask-"):
        Q = {"dask-bool": da.ones((4, 3), dtype=bool, chunks=2),
             "dask-complex": da.ones((4, 3), dtype=complex, chunks=2),
             "dask-4cols": da.ones((4, 4), chunks=2),
             "dask-1d": da.ones(3, chunks=2)}[Q]
    with pytest.raises(exc, match=words):
        seed002.direct_kinematics_dask(Q, **call)


def test_kernel_refused_for_a_design_it_does_not_take_when_computed():
    m = isp.examples.collinear_3rpr()     # Cramer denominator identically zero: no compiled kernel
    r = m.direct_kinematics_dask(np.tile(m.q_example_float, (3, 1)), method="kernel")
    assert isinstance(r, DKDaskResult)
    with pytest.raises(isp.InputError, match="method='kernel' is not available"):
        r.compute(scheduler="synchronous")


# --- on a cluster of worker processes --------------------------------------------------------

@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as c:
        yield c


def kept_on_worker():
    """Run on a worker: the designs it keeps and the artefacts cached on each."""
    from imagespace.solve import distributed as worker_side      # the worker's module, not ours

    return [(k, d.cache_keys()) for k, d in worker_side.KEPT_DESIGNS.items()]


@pytest.mark.slow
def test_a_local_cluster_gives_what_one_batch_gives(seed002, rows, batch, client):
    Q = da.from_array(rows, chunks=(CHUNKS, 3))
    out = seed002.direct_kinematics_dask(Q, method="kernel").compute()       # on the client
    same_as_batch(out, batch["kernel"])
    auto = seed002.direct_kinematics_dask(Q).compute()
    assert np.array_equal(auto["count"], batch["kernel"].count)
    hist = da.bincount(seed002.direct_kinematics_dask(Q).count, minlength=7).compute()
    assert hist.tolist() == np.bincount(batch["kernel"].count, minlength=7).tolist()
    # each worker process kept one copy of the design, which holds the compiled kernel it built
    kept = client.run(kept_on_worker)
    assert len(kept) == 2
    assert all(len(v) == 1 and "kernel" in v[0][1] for v in kept.values())


@pytest.mark.slow
def test_a_local_cluster_certifies(seed002, rows, client):
    sub = rows[:1200]
    out = seed002.direct_kinematics_dask(da.from_array(sub, chunks=(300, 3)), certify=True).compute()
    ref = seed002.direct_kinematics_batch(sub, certify=True)
    ok = ref.row_ok
    assert np.array_equal(out["certified_roots"], ref.certified_roots)
    assert np.array_equal(out["count"][ok], ref.certified_roots[ok])
