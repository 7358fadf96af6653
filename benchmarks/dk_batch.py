"""Batch direct kinematics of the seed-002 mechanism: rows per second, against a numpy.roots loop.

Not a test: prints medians of a few repetitions and the ratio against the baseline measured in
the same run. Run with ``python benchmarks/dk_batch.py [n_rows]``.
"""

import sys
import time

import numpy as np

import imagespace as isp
from imagespace.elimination import eliminate


def median_time(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def main(n=20000):
    m = isp.examples.stigger_husty()
    rng = np.random.default_rng(0)
    poses = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-6, 6, n), rng.uniform(-np.pi, np.pi, n)])
    Q = m.inverse_kinematics(poses)

    t_batch = median_time(lambda: m.direct_kinematics_batch(Q))

    # baseline: sextic coefficients (vectorised) + numpy.roots per row in a Python loop
    el = eliminate(m.quadrics(Q))
    F = np.stack(np.broadcast_arrays(*el.F), axis=1)
    k = min(n, 5000)
    t_roots = median_time(lambda: [np.roots(F[i, ::-1]) for i in range(k)]) * n / k

    k1 = min(n, 200)
    t_single = median_time(lambda: [m.direct_kinematics(Q[i]) for i in range(k1)], repeat=1) * n / k1

    print(f"rows: {n}")
    print(f"direct_kinematics_batch      : {n / t_batch:12,.0f} rows/s  ({1e6 * t_batch / n:7.2f} us/row)")
    print(f"numpy.roots loop (roots only): {n / t_roots:12,.0f} rows/s  ({1e6 * t_roots / n:7.2f} us/row)")
    print(f"direct_kinematics per call   : {n / t_single:12,.0f} rows/s  ({1e6 * t_single / n:7.2f} us/row)")
    print(f"ratio batch / numpy.roots loop: {t_roots / t_batch:.2f}x")
    print(f"ratio batch / per-call        : {t_single / t_batch:.2f}x")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20000)
