"""Memory of a large ``DKBatchResult``: the ragged layout against the old padded one, same run.

Not a test: prints figures. Run with ``python benchmarks/result_memory.py [n_rows] [--old REF]``
(default 10**6 rows of seed 002, made like ``benchmarks/dk_throughput.py``: joint vectors of random
poses, the unreachable ones masked).

Printed, for the package being run (each measurement in a fresh process):

* ``nbytes`` of the result and the bytes of each array it holds;
* the tracemalloc peak of the ``direct_kinematics_batch`` call (compiled kernel) and the peak RSS
  of the process (``resource.getrusage``) next to its RSS just before the call;
* the baseline in the same run: the old padded layout built from the result with its old dtypes
  (``image_points`` (n, 6, 4) f8, ``poses`` (n, 6, 3) f8, ``residual`` (n, 6) f8, ``aspect`` (n, 6)
  int64, ``valid`` (n, 6) bool, ``multiplicity`` (n, 6) int8, ``count`` int64, ``solver`` ``<U9``,
  three (n,) bool flags), the sum of their ``nbytes``;
* with ``--old REF`` (a git commit of this repository, e.g. the one before the ragged layout):
  the same call measured with the package as it was at ``REF`` (exported with ``git archive`` to a
  temporary folder), so the peaks have their baseline from the same run too.
"""

import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def rss_now():
    """Current resident set size in bytes (Linux /proc)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def child(n):
    """Runs in a fresh process: solve n rows once, print the figures as JSON."""
    import resource
    import tracemalloc

    import numpy as np

    import imagespace as isp

    m = isp.examples.stigger_husty()
    rng = np.random.default_rng(0)
    poses = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-6, 6, n), rng.uniform(-np.pi, np.pi, n)])
    Q = m.inverse_kinematics(poses)
    del poses
    m.direct_kinematics_batch(Q[:2000], method="kernel")        # compile / load the kernel
    before = rss_now()
    tracemalloc.start()
    t = time.perf_counter()
    res = m.direct_kinematics_batch(Q, method="kernel")
    t = time.perf_counter() - t
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    maxrss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    held = {k: v.nbytes for k, v in vars(res).items() if isinstance(v, np.ndarray)}
    # the old padded layout of the same rows, with its old dtypes, built one array at a time
    old = {}
    for name, dtype in (("image_points", float), ("poses", float), ("residual", float), ("aspect", np.int64),
                        ("valid", bool), ("multiplicity", np.int8)):
        old[name] = np.asarray(getattr(res, name), dtype=dtype).nbytes
    old["count"] = res.count.astype(np.int64).nbytes
    old["solver"] = res.solver.astype("<U9").nbytes
    for name in ("row_ok", "special", "near_singular"):
        old[name] = getattr(res, name).nbytes
    getattr(res, "release_padded", lambda: None)()       # absent in the old package
    print(json.dumps({"rows": n, "seconds": t, "tracemalloc_peak": peak, "rss_before": before,
                      "maxrss": maxrss, "held": held, "old_layout": old,
                      "nbytes": getattr(res, "nbytes", sum(held.values())),
                      "modes": int(np.sum(res.count)), "Q": Q.nbytes}))


def run(n, pythonpath):
    env = dict(os.environ, PYTHONPATH=pythonpath)
    out = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", str(n)], env=env,
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def report(label, r):
    n = r["rows"]
    print(f"{label}: {n:,} rows, {r['modes']:,} modes ({r['modes'] / n:.2f} a row), "
          f"{n / r['seconds']:,.0f} rows/s")
    print(f"  result nbytes            {r['nbytes'] / 1e6:8.1f} MB  ({r['nbytes'] / n:.1f} B a row)")
    for k, v in sorted(r["held"].items(), key=lambda kv: -kv[1]):
        print(f"    {k:22s} {v / 1e6:8.1f} MB")
    print(f"  tracemalloc peak (call)  {r['tracemalloc_peak'] / 1e6:8.1f} MB  ({r['tracemalloc_peak'] / n:.0f} B a row)")
    print(f"  peak RSS (process)       {r['maxrss'] / 1e6:8.1f} MB  (RSS before the call {r['rss_before'] / 1e6:.1f} MB; "
          f"Q itself {r['Q'] / 1e6:.1f} MB)")


def main(argv):
    if argv and argv[0] == "--child":
        child(int(argv[1]))
        return
    old_ref = None
    if "--old" in argv:
        k = argv.index("--old")
        old_ref = argv[k + 1]
        argv = argv[:k] + argv[k + 2:]
    n = int(argv[0]) if argv else 10**6
    new = run(n, ROOT)
    report("ragged DKBatchResult (this checkout)", new)
    old_bytes = sum(new["old_layout"].values())
    print(f"  baseline: the old padded layout of the same rows {old_bytes / 1e6:8.1f} MB "
          f"({old_bytes / n:.1f} B a row); ratio old / new = {old_bytes / new['nbytes']:.2f}")
    for k, v in sorted(new["old_layout"].items(), key=lambda kv: -kv[1]):
        print(f"    {k:22s} {v / 1e6:8.1f} MB")
    if old_ref:
        with tempfile.TemporaryDirectory() as tmp:
            archive = subprocess.run(["git", "-C", ROOT, "archive", old_ref, "imagespace"], capture_output=True,
                                     check=True).stdout
            subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
            old = run(n, tmp)
        report(f"old package at {old_ref} (same run)", old)
        print(f"  ratios old / new: nbytes {old['nbytes'] / new['nbytes']:.2f}, tracemalloc peak "
              f"{old['tracemalloc_peak'] / new['tracemalloc_peak']:.2f}, peak RSS {old['maxrss'] / new['maxrss']:.2f}, "
              f"rows/s {new['seconds'] and old['seconds'] / new['seconds']:.2f} (new / old)")


if __name__ == "__main__":
    main(sys.argv[1:])
