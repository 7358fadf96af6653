"""Certified real-root counts of seed-002 kinematic sextics: vectorised inclusion discs and the
compiled Bernstein-Descartes kernel (imagespace.core.isolate) against python-flint exact isolation
per row, measured in the same run on the same rows; and ``certified_root_counts`` end to end
(the in-kernel proof in lockstep, the undecided rows decided exactly in Q(sqrt 181) with FLINT)
against its previous implementation (the row-at-a-time kernel, the undecided rows through the
sympy evaluation of the general certified path), interleaved.

Run with ``python benchmarks/certified_counts.py [n_rows]``.
"""

import sys
import time

import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.core.certify import certify_real_roots, certify_real_roots_batch
from imagespace.core.isolate import certified_root_counts


def certified_counts_baseline(m, Q):
    """``certified_root_counts`` as it was before issue [18] target 4: the row-at-a-time kernel's
    proof, then every undecided row through the general certified path (sympy numbers, arb)."""
    from imagespace.solve.certified import exact_certificate
    from imagespace.solve.proof import batch_kernel

    c = batch_kernel(m).certified_counts(Q, lockstep=False)[0].astype(int)
    for i in np.flatnonzero(c < 0):
        c[i] = exact_certificate(m, Q[i]).count
    return c


def end_to_end(m, Q):
    """Interleaved timings of certified_root_counts and its baseline (5 runs each)."""
    import os

    n = len(Q)
    m.certified_root_counts(Q[:100])
    certified_counts_baseline(m, Q[:100])
    now, base = [], []
    for _ in range(5):
        t = time.perf_counter()
        counts, path = m.certified_root_counts(Q)
        now.append(time.perf_counter() - t)
        t = time.perf_counter()
        ref = certified_counts_baseline(m, Q)
        base.append(time.perf_counter() - t)
    fallback = int(np.sum(path != "kernel"))
    print(f"certified_root_counts end to end (load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; "
          f"{fallback} rows decided exactly outside the kernel; same counts as the baseline: "
          f"{np.array_equal(counts, ref)})")
    for name, ts in (("lockstep kernel + Q(sqrt d) FLINT fallback", now),
                     ("row kernel + sympy fallback (baseline)", base)):
        print(f"  {name:45s} median {n / np.median(ts):12,.0f} rows/s, range {n / max(ts):,.0f} - {n / min(ts):,.0f}")
    print(f"  ratio: {np.median(base) / np.median(now):.2f}x")


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
    end_to_end(m, Q)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100000)
