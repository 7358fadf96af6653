"""Spatial direct kinematics (issue [13]): the fast path against the exact path, in one run.

Not a test. One seeded general 6-6 Gough-Stewart design (anchors of unit size, small dyadic
rationals so msolve is at its fastest), leg lengths from random poses. Printed:

* the design's start system (once per design: 128 total-degree paths, 40 solutions kept);
* ``direct_kinematics_batch`` on ``N_FAST`` rows (the fast path: 40 compiled paths a row, numba's
  threads on every core), rows per second;
* ``direct_kinematics(L, certify=True)`` on ``N_CERT`` rows (Krawczyk boxes in arb on all 40
  solutions), rows per second;
* ``direct_kinematics(L, method="exact")`` on ``N_EXACT`` rows (msolve on the exact system, the
  four strata of x), rows per second -- the baseline;
* the ratios, and whether the three paths give the same real counts on the shared rows.

``python benchmarks/spatial_dk.py [N_FAST N_CERT N_EXACT]``
"""

import sys
import time

import numpy as np

import imagespace as isp
from imagespace.spatial.study import study_point


def main(n_fast=4000, n_cert=40, n_exact=8):
    rng = np.random.default_rng(2026)
    base = rng.integers(-8, 9, (6, 3)) / 8.0
    platform = rng.integers(-8, 9, (6, 3)) / 16.0
    gs = isp.GoughStewart(base, platform)
    poses = study_point(rng.normal(size=(n_fast, 4)), rng.uniform(-0.5, 0.5, (n_fast, 3)) + [0, 0, 1.5])
    L = gs.inverse_kinematics(poses)

    t = time.perf_counter()
    st = gs.start_system
    t_start = time.perf_counter() - t
    gs.direct_kinematics_batch(L[:8])                      # numba's cache loaded, threads started

    t = time.perf_counter()
    batch = gs.direct_kinematics_batch(L)
    t_fast = time.perf_counter() - t
    fast_rate = n_fast / t_fast

    t = time.perf_counter()
    cert = [gs.direct_kinematics(L[i], certify=True) for i in range(n_cert)]
    t_cert = time.perf_counter() - t
    cert_rate = n_cert / t_cert
    methods = {}
    for c in cert:
        methods[c.method] = methods.get(c.method, 0) + 1

    t = time.perf_counter()
    exact = [gs.direct_kinematics(L[i], method="exact") for i in range(n_exact)]
    t_exact = time.perf_counter() - t
    exact_rate = n_exact / t_exact

    same_cert = all(batch.counts[i] == cert[i].count for i in range(n_cert))
    same_exact = all(batch.counts[i] == exact[i].count for i in range(n_exact))
    print(f"design: 6-6, {len(st.solutions)} complex solutions at generic lengths, start system "
          f"{t_start:.2f} s ({st.paths} paths)")
    print(f"fast    direct_kinematics_batch   {n_fast:6d} rows  {t_fast:8.2f} s  {fast_rate:10.1f} rows/s  "
          f"(reliable {int(batch.reliable.sum())}/{n_fast}, real modes per row "
          f"{np.bincount(batch.counts).tolist()})")
    print(f"certify direct_kinematics(certify) {n_cert:6d} rows  {t_cert:8.2f} s  {cert_rate:10.1f} rows/s  "
          f"{methods}")
    print(f"exact   direct_kinematics(exact)   {n_exact:6d} rows  {t_exact:8.2f} s  {exact_rate:10.2f} rows/s  "
          "(msolve, baseline)")
    print(f"ratio fast / exact   {fast_rate / exact_rate:10.0f}x")
    print(f"ratio certify / exact {cert_rate / exact_rate:9.1f}x")
    print(f"same real counts: fast = certified on {n_cert} rows: {same_cert}; fast = exact on "
          f"{n_exact} rows: {same_exact}")


if __name__ == "__main__":
    args = [int(a) for a in sys.argv[1:4]]
    main(*args)
