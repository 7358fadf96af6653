"""Certified real-root counts of seed-002 kinematic sextics: vectorised inclusion discs and the
compiled Bernstein-Descartes kernel (imagespace.core.isolate) against python-flint exact isolation
per row, measured in the same run on the same rows.

Run with ``python benchmarks/certified_counts.py [n_rows]``.
"""

import sys
import time

import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.core.certify import certify_real_roots, certify_real_roots_batch
from imagespace.core.isolate import certified_root_counts


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
    certified_root_counts(F[:10])           # load (or compile) the kernel, not timed
    t = time.perf_counter()
    iso, _, _ = certified_root_counts(F)
    t_iso = time.perf_counter() - t
    k = min(n, 500)
    t = time.perf_counter()
    exact = [certify_real_roots([sp.Rational(float(v)) for v in F[i]]).count for i in range(k)]
    t_flint = (time.perf_counter() - t) / k
    assert exact == counts[:k].tolist()
    decided = iso >= 0
    assert np.array_equal(iso[decided], counts[decided])
    # the same rows from the rigorous enclosure of the exact (irrational) coefficients
    enc = m.enclosure()
    t = time.perf_counter()
    Fe, Ee = enc.evaluate(Q)
    t_enc = time.perf_counter() - t
    t = time.perf_counter()
    iso_e, _, _ = certified_root_counts(Fe, Ee)
    t_iso_e = time.perf_counter() - t
    print(f"rows: {n}")
    print(f"compiled sextic coefficients      : {n / t_coef:12,.0f} rows/s")
    print(f"certified counts, discs + fallback: {n / t_batch:12,.0f} rows/s  "
          f"({np.sum(path == 'flint')} rows fell back to flint)")
    print(f"certified counts, isolate kernel  : {n / t_iso:12,.0f} rows/s  "
          f"({np.sum(~decided)} rows undecided (-1), the rest equal to the discs' counts)")
    print(f"certified counts, flint per row   : {1 / t_flint:12,.0f} rows/s")
    print(f"ratio discs / flint per row       : {t_flint * n / t_batch:.1f}x")
    print(f"ratio isolate / discs             : {t_batch / t_iso:.1f}x")
    print(f"ratio isolate / flint per row     : {t_flint * n / t_iso:.1f}x")
    print(f"enclosure F +- E (exact q)        : {n / t_enc:12,.0f} rows/s")
    print(f"isolate kernel on F +- E          : {n / t_iso_e:12,.0f} rows/s  "
          f"({np.sum(iso_e < 0)} rows undecided)")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100000)
