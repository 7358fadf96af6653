"""Direct-kinematics throughput on the seed-002 mechanism, every method on the same rows.

Not a test: prints rows per second and ratios against the baselines measured in the same run.
Run with ``python benchmarks/dk_throughput.py [n_rows]``; ``--big N`` streams N rows (default
10**7) through ``direct_kinematics_chunks`` and prints the throughput and the peak memory.

Methods
-------
* ``direct_kinematics_batch`` end to end (coefficients, real roots, back-substitution, Newton
  polish, residual check, masks), with the compiled kernel (the default for large batches: blocks
  of rows in lockstep), with the row-at-a-time kernel it replaced (baseline, the same answers bit
  for bit) and with the numpy path; the kernels alone, lockstep and row at a time;
* ``certify_real_roots_batch`` on the compiled coefficients (certified counts: companion
  eigenvalues, inclusion discs, flint fallback) and ``certified_root_counts`` (the proof inside
  the generic kernel: bounded coefficients and elimination, Bernstein isolation);
* baselines: ``numpy.roots`` in a Python loop, batched companion ``numpy.linalg.eigvals``,
  python-flint exact isolation per row, sympy elimination per row (a few rows), per-call
  ``direct_kinematics``.
"""

import sys
import time

import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.core.certify import certify_real_roots, certify_real_roots_batch


#: interleaved runs of the four kernel lines (this machine drifts: the median and range are printed)
REPEATS = 9


def timed(fn, repeat=3):
    best = []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best.append(time.perf_counter() - t)
    return float(np.median(best)), out


def main(n=20000):
    m = isp.examples.stigger_husty()
    rng = np.random.default_rng(0)
    poses = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-6, 6, n), rng.uniform(-np.pi, np.pi, n)])
    Q = m.inverse_kinematics(poses)
    comp = m.compiled()                                  # one-time derivation, not timed
    F = comp.coefficients(Q)

    rows = {}
    from imagespace.solve.kernel.batch import BatchKernel
    from imagespace.solve.proof import batch_kernel
    kern = batch_kernel(m)
    m.direct_kinematics_batch(Q[:2000], method="kernel")  # compile / load the kernel, not timed
    kern(Q[:2000], lockstep=False)

    lockstep_call = BatchKernel.__call__

    def rows_end_to_end():
        """direct_kinematics_batch with the row-at-a-time loop in the kernel's place: the same
        front end (validation, reach, chunks, the careful path), only the loop differs."""
        BatchKernel.__call__ = lambda self, Qc, proof=True, lockstep=True: lockstep_call(self, Qc, proof, False)
        try:
            return m.direct_kinematics_batch(Q, method="kernel")
        finally:
            BatchKernel.__call__ = lockstep_call

    # interleaved, so that the machine's load changes hit both alike
    t_end, t_end_rows, t_k, t_k_rows = [], [], [], []
    for _ in range(REPEATS):
        t_end.append(timed(lambda: m.direct_kinematics_batch(Q, method="kernel"), 1)[0])
        t_end_rows.append(timed(rows_end_to_end, 1)[0])
        t_k.append(timed(lambda: kern(Q), 1)[0])
        t_k_rows.append(timed(lambda: kern(Q, lockstep=False), 1)[0])
    res = m.direct_kinematics_batch(Q, method="kernel")
    res_rows = rows_end_to_end()
    spans = {}
    for name, ts in (("direct_kinematics_batch, compiled kernel (lockstep)", t_end),
                     ("direct_kinematics_batch, row-at-a-time kernel (baseline)", t_end_rows),
                     ("batch kernel alone, lockstep (no masks, no result assembly)", t_k),
                     ("batch kernel alone, row at a time (baseline)", t_k_rows)):
        rows[name] = n / float(np.median(ts))
        spans[name] = (n / max(ts), n / min(ts))
    same_rows = all(np.array_equal(a, b, equal_nan=True) for a, b in zip(kern(Q), kern(Q, lockstep=False)))
    same_end = np.array_equal(res.count, res_rows.count) and np.array_equal(res.solver, res_rows.solver)
    # baseline in the same run: the isolation on the float coefficients taken as exact (no bounds;
    # an unflagged count could be wrong next to a double root), the kernel before issue [14]
    t, (_, _, _, _, cnt_np, flag_np) = timed(lambda: kern(Q, proof=False))
    rows["batch kernel alone, isolation without bounds (baseline)"] = n / t
    _, _, _, _, cnt_p, flag_p = kern(Q)
    t, res_np = timed(lambda: m.direct_kinematics_batch(Q, method="numpy"), 1)
    rows["direct_kinematics_batch, numpy path"] = n / t
    same = np.array_equal(res.count, res_np.count)
    t, (counts, path) = timed(lambda: certify_real_roots_batch(F))
    rows["certified counts (discs + flint fallback)"] = n / t
    m.certified_root_counts(Q[:100])                       # load the kernel, not timed
    t, (kcounts, kpath) = timed(lambda: m.certified_root_counts(Q))
    rows["certified_root_counts (in-kernel proof)"] = n / t
    t, _ = timed(lambda: kern.certified_counts(Q))
    rows["in-kernel proof alone (no exact fallback rows)"] = n / t
    kernel_same = np.array_equal(kcounts, counts)

    k = min(n, 3000)
    t, _ = timed(lambda: [np.roots(F[i, ::-1]) for i in range(k)])
    rows["numpy.roots loop (roots only)"] = k / t

    def eig():
        comp_m = np.zeros((n, 6, 6))
        comp_m[:, np.arange(1, 6), np.arange(5)] = 1.0
        comp_m[:, :, 5] = -F[:, :6] / F[:, 6:7]
        return np.linalg.eigvals(comp_m)
    t, _ = timed(eig)
    rows["batched companion eigvals (roots only)"] = n / t

    k = min(n, 300)
    t, exact = timed(lambda: [certify_real_roots([sp.Rational(float(v)) for v in F[i]]).count for i in range(k)], 1)
    rows["python-flint exact isolation per row"] = k / t
    assert exact == counts[:k].tolist()

    k = min(n, 5)
    def sym():
        return [m.kinematic_polynomial([sp.Rational(float(v)) for v in Q[i]]) for i in range(k)]
    m.clear_cache()
    t, _ = timed(sym, 1)
    rows["sympy elimination per row (exact)"] = k / t
    m.clear_cache()

    k = min(n, 200)
    t, _ = timed(lambda: [m.direct_kinematics(Q[i]) for i in range(k)], 1)
    rows["direct_kinematics per call"] = k / t

    import os
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; lockstep kernel outputs equal the "
          f"row kernel's bit for bit: {same_rows}; end to end the same counts and solvers: {same_end}")
    for name, (lo, hi) in spans.items():
        print(f"  {name:60s} median {rows[name]:12,.0f} rows/s, range {lo:,.0f} - {hi:,.0f} ({REPEATS} interleaved runs)")
    print(f"  lockstep / row at a time: kernel alone "
          f"{rows['batch kernel alone, lockstep (no masks, no result assembly)'] / rows['batch kernel alone, row at a time (baseline)']:.2f}x, "
          f"end to end {rows['direct_kinematics_batch, compiled kernel (lockstep)'] / rows['direct_kinematics_batch, row-at-a-time kernel (baseline)']:.2f}x")
    print(f"rows: {n}  (kernel rows flagged with bounds: {int(np.sum(flag_p != 0))}, without: "
          f"{int(np.sum(flag_np != 0))}; unflagged counts differing: "
          f"{int(np.sum((flag_p == 0) & (flag_np == 0) & (cnt_p != cnt_np)))})")
    solver = {k: int(v) for k, v in zip(*np.unique(res.solver, return_counts=True))}
    print(f"rows: {n}  (in-kernel certified counts = disc counts on every row: {kernel_same}; "
          f"decided in the kernel: {np.sum(kpath == 'kernel')}, exact fallback: {np.sum(kpath != 'kernel')})")
    print(f"rows: {n}  (kernel and numpy paths give the same counts on every row: {same}; "
          f"solver per row: {solver})")
    print(f"rows: {n}  (modes per row: {np.bincount(res.count).tolist()}; "
          f"certified rows by discs: {np.sum(path == 'discs')}, by flint: {np.sum(path == 'flint')})")
    base = rows["numpy.roots loop (roots only)"]
    eigb = rows["batched companion eigvals (roots only)"]
    for name, rate in rows.items():
        print(f"{name:45s} {rate:14,.0f} rows/s  {rate / base:8.2f}x roots loop  {rate / eigb:8.2f}x eigvals")


def big(n=10**7, chunk=1 << 18):
    """Stream n reachable joint vectors through direct_kinematics_chunks; peak memory."""
    import resource

    m = isp.examples.stigger_husty()
    rng = np.random.default_rng(1)
    q0 = np.asarray(m.q_example_float)
    Q = q0 * (1 + 0.15 * rng.standard_normal((n, 3)))      # 240 MB for 10**7 rows
    m.direct_kinematics_batch(Q[:2000], method="kernel")
    hist = np.zeros(7, dtype=np.int64)
    t = time.perf_counter()
    for _, part in m.direct_kinematics_chunks(Q, chunk_size=chunk):
        hist += np.bincount(part.count, minlength=7)
    dt = time.perf_counter() - t
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"{n:,} rows in chunks of {chunk:,}: {n / dt:,.0f} rows/s ({dt:.1f} s); modes per row "
          f"{hist.tolist()}; peak resident memory {peak:,.0f} MB (the input alone: {Q.nbytes / 2**20:,.0f} MB)")


if __name__ == "__main__":
    if "--big" in sys.argv:
        rest = sys.argv[sys.argv.index("--big") + 1:]
        big(int(rest[0]) if rest else 10**7)
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 20000)
