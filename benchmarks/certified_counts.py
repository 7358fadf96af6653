"""Certified real-root counts of seed-002 kinematic sextics: vectorised inclusion discs against
python-flint exact isolation per row, measured in the same run.

Run with ``python benchmarks/certified_counts.py [n_rows]``.
"""

import sys
import time

import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.core.certify import certify_real_roots, certify_real_roots_batch


def main(n=100000):
    m = isp.examples.stigger_husty()
    rng = np.random.default_rng(0)
    poses = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-6, 6, n), rng.uniform(-np.pi, np.pi, n)])
    Q = m.inverse_kinematics(poses)
    comp = m.compiled()                     # the one-time derivation and compilation, not timed
    t = time.perf_counter()
    F = comp.coefficients(Q)
    t_coef = time.perf_counter() - t
    t = time.perf_counter()
    counts, path = certify_real_roots_batch(F)
    t_batch = time.perf_counter() - t
    k = min(n, 500)
    t = time.perf_counter()
    exact = [certify_real_roots([sp.Rational(float(v)) for v in F[i]]).count for i in range(k)]
    t_flint = (time.perf_counter() - t) / k
    assert exact == counts[:k].tolist()
    print(f"rows: {n}")
    print(f"compiled sextic coefficients     : {n / t_coef:12,.0f} rows/s")
    print(f"certified counts, discs + fallback: {n / t_batch:12,.0f} rows/s  "
          f"({np.sum(path == 'flint')} rows fell back to flint)")
    print(f"certified counts, flint per row   : {1 / t_flint:12,.0f} rows/s")
    print(f"ratio discs / flint per row       : {t_flint * n / t_batch:.1f}x")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100000)
