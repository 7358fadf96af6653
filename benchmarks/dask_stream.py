"""Streamed direct kinematics on a dask LocalCluster: 10**8 joint vectors of seed 002, never in memory.

Not a test: prints rows per second, the total time and the peak resident memory of each process,
against a baseline measured in the same run.

Run with ``python benchmarks/dask_stream.py [--rows N] [--chunk C] [--baseline-rows B]``
(defaults: ``--rows 100000000 --chunk 262144 --baseline-rows 10000000``);
``--worker-numba-threads 1`` limits the compiled kernel to one thread in each worker.

* The rows are generated inside dask, block by block: joint vectors of seeded random poses
  (``x, y`` uniform in [-6, 6], ``phi`` uniform in [-pi, pi]) through the inverse kinematics of
  ``isp.examples.stigger_husty()``, as ``benchmarks/dk_throughput.py`` draws them.
* ``direct_kinematics_dask`` solves them on a ``LocalCluster`` of 2 worker processes x 1 thread
  (the compiled kernel inside each worker still uses numba's threads), and the result is
  reduced to the histogram of the mode counts (``da.bincount``), the number of near-singular
  rows and of solved rows: nothing of size ``n`` is ever materialised.
* Peak resident memory: ``ru_maxrss`` of each worker (asked through ``client.run``) after a
  warm-up block and after the stream, and of this (client) process.
* Baselines in the same run, in this process: ``direct_kinematics_chunks`` serially over
  ``--baseline-rows`` rows generated beforehand (chunks of ``--chunk``), and the generation of
  the rows alone (the inverse kinematics), which the streamed figure includes.
"""

import argparse
import resource
import time

import numpy as np


def joint_block(block_id=None, block_info=None, seed=2026):
    """Joint vectors of random poses for one block (seeded by the block's index)."""
    rows = block_info[None]["chunk-shape"][0]
    return random_joint_vectors(rows, (seed, block_id[0]))


def random_joint_vectors(rows, seed):
    """``rows`` joint vectors of seed 002 at random poses (its inverse kinematics)."""
    m = design()
    rng = np.random.default_rng(seed)
    poses = np.column_stack([rng.uniform(-6, 6, rows), rng.uniform(-6, 6, rows),
                             rng.uniform(-np.pi, np.pi, rows)])
    return m.inverse_kinematics(poses)


_DESIGN = []


def design():
    """Seed 002, built once per process (the functions of this script are shipped to the workers
    by value: they import imagespace inside, since cloudpickle cannot pickle the package module)."""
    if not _DESIGN:
        import imagespace

        _DESIGN.append(imagespace.examples.stigger_husty())
    return _DESIGN[0]


def lazy_rows(n, chunk):
    """An (n, 3) dask array of joint vectors, generated block by block when computed."""
    import dask.array as da

    blocks = (chunk,) * (n // chunk) + ((n % chunk,) if n % chunk else ())
    return da.map_blocks(joint_block, dtype=float, chunks=(blocks, (3,)), meta=np.empty((0, 3)))


def peak_mb():
    """Peak resident memory of the calling process, MB (ru_maxrss is in kB on Linux)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def stream(n, chunk, numba_threads=None):
    import dask
    import dask.array as da
    from distributed import Client, LocalCluster

    m = design()
    env = {} if numba_threads is None else {"NUMBA_NUM_THREADS": str(numba_threads)}
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      env=env) as cluster, Client(cluster) as client:
        # warm-up: each worker derives the kernel and loads it from the numba cache (not timed)
        t = time.perf_counter()
        warm = m.direct_kinematics_dask(lazy_rows(4 * 4096, 4096)).count.sum().compute()
        warm_s = time.perf_counter() - t
        before = client.run(peak_mb)
        t = time.perf_counter()
        r = m.direct_kinematics_dask(lazy_rows(n, chunk))
        hist, near, solved = dask.compute(da.bincount(r.count, minlength=7), r.near_singular.sum(),
                                          r.row_ok.sum())
        dt = time.perf_counter() - t
        after = client.run(peak_mb)
        client_peak = peak_mb()
        # the generation alone on the cluster, on a tenth of the rows
        k = max(chunk, (n // 10) // chunk * chunk)
        t = time.perf_counter()
        lazy_rows(k, chunk).sum().compute()
        gen_rate = k / (time.perf_counter() - t)
    print(f"dask LocalCluster, 2 worker processes x 1 thread (numba threads per worker: "
          f"{numba_threads or 'default'}), blocks of {chunk:,} rows "
          f"({-(-n // chunk)} blocks); warm-up of 16,384 rows (kernel per worker, {warm} modes) "
          f"{warm_s:.1f} s")
    print(f"  {n:,} rows streamed (generation + direct kinematics + reduction): {dt:.1f} s, "
          f"{n / dt:,.0f} rows/s")
    print(f"  modes per row {hist.tolist()}; solved rows {int(solved):,}; near-singular rows "
          f"{int(near):,} ({near / n:.2e})")
    for addr in sorted(after):
        print(f"  worker {addr}: peak RSS {before[addr]:,.0f} MB after the warm-up, "
              f"{after[addr]:,.0f} MB after the stream")
    print(f"  client process: peak RSS {client_peak:,.0f} MB")
    print(f"  generation alone on the cluster ({k:,} rows): {gen_rate:,.0f} rows/s")
    return n / dt, gen_rate


def baseline(n, chunk):
    m = design()
    m.direct_kinematics_batch(random_joint_vectors(4096, 0), method="kernel")   # kernel, not timed
    t = time.perf_counter()
    Q = np.concatenate([random_joint_vectors(min(chunk, n - s), (2026, s // chunk))
                        for s in range(0, n, chunk)])
    gen_s = time.perf_counter() - t
    hist = np.zeros(7, dtype=np.int64)
    t = time.perf_counter()
    for _, part in m.direct_kinematics_chunks(Q, chunk_size=chunk):
        hist += np.bincount(part.count, minlength=7)
    dt = time.perf_counter() - t
    print(f"baseline, this process: direct_kinematics_chunks over {n:,} rows in memory "
          f"({Q.nbytes / 2**20:,.0f} MB): {dt:.1f} s, {n / dt:,.0f} rows/s; modes per row "
          f"{hist.tolist()}; generation alone {n / gen_s:,.0f} rows/s; peak RSS of this process "
          f"now {peak_mb():,.0f} MB")
    return n / dt, n / gen_s


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=10**8)
    ap.add_argument("--chunk", type=int, default=1 << 18)
    ap.add_argument("--baseline-rows", type=int, default=10**7)
    ap.add_argument("--worker-numba-threads", type=int, default=None,
                    help="NUMBA_NUM_THREADS of the workers (default: numba's, one per core)")
    args = ap.parse_args()
    rate, gen_cluster = stream(args.rows, args.chunk, args.worker_numba_threads)
    base, gen_serial = baseline(min(args.baseline_rows, args.rows), args.chunk)
    serial_total = 1 / (1 / base + 1 / gen_serial)
    print(f"ratio: streamed on the cluster {rate:,.0f} rows/s = {rate / base:.2f}x the serial "
          f"direct_kinematics_chunks ({base:,.0f} rows/s, rows in memory), {rate / serial_total:.2f}x "
          f"serial generation + solve ({serial_total:,.0f} rows/s)")


if __name__ == "__main__":
    main()
