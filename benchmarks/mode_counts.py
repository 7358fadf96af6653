"""The price of counting modes instead of roots (issue [19]): ``certified_root_counts`` now proves
per row that the Cramer denominator shares no real root with the kinematic form (and, with a PP
dyad, which of its two orientation roots is genuine) before a root count is a mode count.

Measured in the same run on the same rows: the kernel's bare certified root counts (the baseline:
what ``certified_root_counts`` returned before) against ``certified_root_counts`` (modes), for a
general 3-RPR and for a design with a PP dyad (issue 35's h1, RRR-PPR-RPP); and per row, the exact
fallback ``exact_mode_count`` against the exact root certificate ``exact_certificate``.

Run with ``python benchmarks/mode_counts.py [n_rows]``.
"""

import os
import sys
import time

import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.solve.certified import exact_certificate, exact_mode_count
from imagespace.solve.proof import batch_kernel

R = sp.Rational


def h1():
    ang = lambda c: sp.acos(c)
    return isp.PlanarParallel([
        isp.RRR(base=(R(32465, 17168), R(-87557, 17168)), platform=(R(-7, 4), R(-5, 4)), lengths=(R(35, 8), R(19, 8))),
        isp.PPR(base=(R(17369, 8528), R(-64095, 8528)), axis=(R(-5, 13), R(12, 13)), platform=(R(-1), R(23, 8)),
                angle=ang(R(-40, 41))),
        isp.RPP(base=(R(1451, 10064), R(-68809, 10064)), platform=(R(-21, 8), R(15, 8)),
                direction=(R(-35, 37), R(12, 37)), angle=ang(R(-8, 17)))])


def rows_near(m, q0, n, spread, seed=35):
    rng = np.random.default_rng(seed)
    return np.asarray(q0, float) + spread * rng.standard_normal((n, 3))


def median_time(fn, reps=5):
    ts = []
    for _ in range(reps):
        t = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t)
    return float(np.median(ts))


def batch(name, m, Q):
    kernel = batch_kernel(m)
    kernel.certified_counts(Q[:50])
    m.certified_root_counts(Q[:50])
    base = median_time(lambda: kernel.certified_counts(Q))
    now = median_time(lambda: m.certified_root_counts(Q))
    counts, path = m.certified_root_counts(Q)
    roots = kernel.certified_counts(Q)[0]
    differ = int(np.sum((counts >= 0) & (roots >= 0) & (counts != roots)))
    print(f"{name}: {len(Q)} rows; {int(np.sum(path != 'kernel'))} decided outside the kernel; "
          f"{differ} rows where modes != roots")
    print(f"  kernel root counts (baseline)   {len(Q) / base:12,.0f} rows/s")
    print(f"  certified_root_counts (modes)   {len(Q) / now:12,.0f} rows/s   ratio {now / base:.2f}x the baseline")


def per_row(name, m, Q, k=20):
    exact_certificate(m, Q[0])
    exact_mode_count(m, Q[0])
    t = time.perf_counter()
    for q in Q[:k]:
        exact_certificate(m, q)
    base = (time.perf_counter() - t) / k
    t = time.perf_counter()
    for q in Q[:k]:
        exact_mode_count(m, q)
    now = (time.perf_counter() - t) / k
    print(f"  per row, exact: exact_certificate (roots) {base * 1e3:.2f} ms, exact_mode_count (modes) "
          f"{now * 1e3:.2f} ms, ratio {now / base:.2f}x")


def main(n=20000):
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    general = isp.examples.general_3rpr()
    Qg = rows_near(general, general.q_example_float, n, 0.05)
    batch("general 3-RPR", general, Qg)
    per_row("general 3-RPR", general, Qg)
    m = h1()
    Qh = rows_near(m, [0.7610127542247298, -1.75, -3.875], n, 0.02)
    batch("h1 (RRR-PPR-RPP)", m, Qh)
    per_row("h1", m, Qh)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20000)
