"""Design-sweep throughput (seed 004 indices per design: exact workspaces + global indices) serially,
in local processes and on a 2-worker Dask LocalCluster; and exact vs sampled workspace area.

Run with ``python benchmarks/design_sweep.py``.
"""

import time

import numpy as np

import imagespace as isp
from imagespace.design.sweep import sweep
from imagespace.design.workspace import dexterous_workspace, reachable_workspace, sampled_workspace


def main():
    grid = {"alpha": np.arange(30, 151, 10) * np.pi / 180, "r_over_R": np.round(np.arange(0.1, 1.01, 0.1), 1)}
    n = 13 * 10
    t = time.perf_counter()
    serial = sweep(isp.examples.choi_3ppr_indices, grid, processes=0, progress=False)
    ts = time.perf_counter() - t
    t = time.perf_counter()
    local = sweep(isp.examples.choi_3ppr_indices, grid, processes=2, progress=False)
    tl = time.perf_counter() - t
    print(f"{n} designs: serial {n / ts:.1f} designs/s; 2 local processes {n / tl:.1f} designs/s "
          f"({ts / tl:.2f}x, incl. process start-up); same table: {serial.equals(local)}")
    try:
        import distributed
    except ImportError:
        print("dask.distributed not installed: pip install 'imagespace[dask]'")
    else:
        with distributed.LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, \
                distributed.Client(cluster) as client:
            sweep(isp.examples.choi_3ppr_indices, {"alpha": grid["alpha"][:2], "r_over_R": grid["r_over_R"][:2]},
                  client=client, progress=False)                                  # warm the workers
            t = time.perf_counter()
            remote = sweep(isp.examples.choi_3ppr_indices, grid, client=client, progress=False)
            td = time.perf_counter() - t
        print(f"  Dask LocalCluster (2 workers, warm): {n / td:.1f} designs/s ({ts / td:.2f}x serial); "
              f"same table: {serial.equals(remote)}")
    alpha = 7 * np.pi / 18
    m = isp.examples.choi_3ppr(1, 0.5, alpha)
    lim = [[-np.sqrt(3), np.sqrt(3)]] * 3
    rng = (alpha - np.pi / 2 - 17 * np.pi / 36, alpha - np.pi / 2 + 17 * np.pi / 36)
    t = time.perf_counter()
    for _ in range(10):
        D = dexterous_workspace(m, rng, lim).area
        R = reachable_workspace(m, rng, lim).area
    te = (time.perf_counter() - t) / 10
    for res in (100, 200, 400):
        t = time.perf_counter()
        Ds = sampled_workspace(m, lim, rng, [(-3, 3), (-3, 3)], res, 91, "dexterous").area
        tsam = time.perf_counter() - t
        print(f"  workspace areas: exact (both) {1e3 * te:.1f} ms; sampled dexterous {res}^2 x 91 phi: "
              f"{1e3 * tsam:.0f} ms, relative error {abs(Ds / D - 1):.2e}")


if __name__ == "__main__":
    main()
