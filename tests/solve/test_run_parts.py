"""The batch kernel's loops are serial functions of a range of items run on a pool of threads
(:func:`imagespace.solve.kernel.loops.run_parts`): every item is run exactly once whatever the
number of threads and parts, and the kernel's outputs do not depend on the number of threads
(each block of rows is solved on its own: the same floats bit for bit)."""

import threading

import numba
import numpy as np
import pytest

import imagespace as isp
from imagespace.solve.kernel import HAVE_NUMBA
from imagespace.solve.kernel.loops import MIN_PART_ROWS, PARTS_PER_THREAD, run_parts

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel needs numba")


@pytest.fixture
def threads():
    """Set numba's number of threads for one test, restored afterwards."""
    before = numba.get_num_threads()
    yield numba.set_num_threads
    numba.set_num_threads(before)


@pytest.mark.parametrize("items", [0, 1, 2, 3, 7, 64, 65, 1000, 4097])
@pytest.mark.parametrize("n_threads", [1, 2])
@pytest.mark.parametrize("rows_per_item", [1, 32])
def test_every_item_runs_once(items, n_threads, rows_per_item, threads):
    threads(min(n_threads, numba.config.NUMBA_NUM_THREADS))
    seen = np.zeros(items, dtype=np.int64)
    ranges = []
    lock = threading.Lock()

    def loop(out, a, b):
        with lock:
            ranges.append((a, b))
        out[a:b] += 1

    run_parts(loop, items, seen, rows_per_item=rows_per_item)
    assert np.all(seen == 1)
    # the parts: contiguous, at least MIN_PART_ROWS rows each unless there is one part, at most
    # PARTS_PER_THREAD a thread
    ranges.sort()
    assert len(ranges) <= max(1, numba.get_num_threads() * PARTS_PER_THREAD)
    if len(ranges) > 1:
        assert all((b - a) * rows_per_item >= MIN_PART_ROWS for a, b in ranges)


def test_an_error_in_a_part_reaches_the_caller(threads):
    threads(min(2, numba.config.NUMBA_NUM_THREADS))

    def loop(a, b):
        if a <= 500 < b:
            raise ValueError("part with item 500")

    with pytest.raises(ValueError, match="item 500"):
        run_parts(loop, 1000)


@pytest.mark.slow
def test_kernel_outputs_do_not_depend_on_threads(threads):
    m = isp.examples.stigger_husty()
    rng = np.random.default_rng(18)
    n = 5000
    poses = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-6, 6, n), rng.uniform(-np.pi, np.pi, n)])
    Q = m.inverse_kinematics(poses)
    from imagespace.solve.proof import batch_kernel
    kern = batch_kernel(m)
    threads(1)
    one = kern(Q)
    one_counts = kern.certified_counts(Q)
    threads(min(2, numba.config.NUMBA_NUM_THREADS))
    for a, b in zip(one, kern(Q)):
        assert np.array_equal(a, b, equal_nan=True)
    for a, b in zip(one_counts, kern.certified_counts(Q)):
        assert np.array_equal(a, b, equal_nan=True)
    assert int(np.sum(one[4])) > 0          # the rows have modes: the comparison sees them
