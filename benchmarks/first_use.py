"""First use: what a user waits for before the first answer (issue [12]).

Not a test: every figure comes from a fresh Python process (``subprocess``), so nothing is warm
but what the installation keeps on disk (numba's cache of the generic kernel). Printed:

* ``import imagespace``;
* a NEW design (random 3-RPR, and a design with three RRR legs whose actuated joints are base
  revolutes) built after import, then its first 10**5-row ``direct_kinematics_batch``;
* the first ``direct_kinematics_batch(..., certify=True)`` on the three-RRR design (10**4 rows);
* the same with an empty kernel cache (``IMAGESPACE_CACHE`` pointing at a fresh directory): the
  one-time compilation per installation.

Baseline in the same run: the symbolic general-q kinematic polynomial of each design
(``m.kinematic_polynomial()``), which the per-design kernel of earlier versions derived and
compiled before its first batch (``--old`` to include the three-RRR one, about 2 minutes).

``python benchmarks/first_use.py [--old]``
"""

import json
import os
import subprocess
import sys
import tempfile
import time

DESIGNS = """
import numpy as np
import imagespace as isp

def rpr(seed):
    rng = np.random.default_rng(seed)
    legs = [isp.RPR(base=tuple(rng.uniform(-10, 10, 2).round(3)), platform=tuple(rng.uniform(-3, 3, 2).round(3)))
            for _ in range(3)]
    return isp.PlanarParallel(legs)

def rrr3():
    return isp.PlanarParallel([
        isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3.0, 2.5), actuated=0),
        isp.RRR(base=(7, 0), platform=(2, 0), lengths=(2.5, 3.0), actuated=0),
        isp.RRR(base=(3, 6), platform=(1, 1.5), lengths=(3.5, 2.0), actuated=0)])

def rows(m, n, seed=1):
    rng = np.random.default_rng(seed)
    out = []
    while sum(len(o) for o in out) < n:
        poses = np.column_stack([rng.uniform(1, 4, n), rng.uniform(0.5, 3.5, n), rng.uniform(-0.7, 0.7, n)])
        Q = m.inverse_kinematics(poses)
        out.append(Q[np.all(np.isfinite(Q), axis=1)])
    return np.concatenate(out)[:n]
"""

SCRIPT = """
import time, json
t0 = time.perf_counter()
import imagespace as isp
t_import = time.perf_counter() - t0
exec(DESIGNS)
out = {"import": t_import}
m = rpr(SEED)
Q = rows(m, 100000)
t = time.perf_counter()
r = m.direct_kinematics_batch(Q)
out["rpr_first_batch"] = time.perf_counter() - t
out["rpr_solver"] = sorted(set(r.solver.tolist()))
m3 = rrr3()
Q3 = rows(m3, 100000)
t = time.perf_counter()
r3 = m3.direct_kinematics_batch(Q3)
out["rrr_first_batch"] = time.perf_counter() - t
out["rrr_solver"] = sorted(set(r3.solver.tolist()))
m3b = rrr3()                            # a fresh object: nothing cached on the design
t = time.perf_counter()
rc = m3b.direct_kinematics_batch(Q3[:10000], certify=True)
out["rrr_first_certified"] = time.perf_counter() - t
out["rrr_certified_paths"] = {k: int(v) for k, v in zip(*__import__("numpy").unique(rc.certificate_path, return_counts=True))}
out["since_import"] = time.perf_counter() - t0
print("JSON" + json.dumps(out))
"""

OLD = """
import time, json
exec(DESIGNS)
out = {}
t = time.perf_counter(); rpr(SEED).kinematic_polynomial(); out["rpr_symbolic"] = time.perf_counter() - t
if WITH_RRR:
    t = time.perf_counter(); rrr3().kinematic_polynomial(); out["rrr_symbolic"] = time.perf_counter() - t
print("JSON" + json.dumps(out))
"""


def fresh(code, env=None):
    t = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=dict(os.environ, **(env or {})), timeout=3600)
    wall = time.perf_counter() - t
    if proc.returncode:
        raise RuntimeError(proc.stderr[-3000:])
    line = [ln for ln in proc.stdout.splitlines() if ln.startswith("JSON")][-1]
    return json.loads(line[4:]), wall


def main(with_old_rrr=False):
    prelude = f"DESIGNS = {DESIGNS!r}\nSEED = 12\n"
    fresh(prelude + SCRIPT)                        # make sure the installation's cache is filled
    warm, wall = fresh(prelude + SCRIPT)
    print(f"warm kernel cache (the usual case), one fresh process, {wall:.1f} s wall in all:")
    for k, v in warm.items():
        print(f"  {k:24s} {v if not isinstance(v, float) else f'{v:8.3f} s'}")
    with tempfile.TemporaryDirectory() as d:
        cold, wall = fresh(prelude + SCRIPT, {"IMAGESPACE_CACHE": d})
    print(f"empty kernel cache (once per installation), {wall:.1f} s wall in all:")
    for k, v in cold.items():
        print(f"  {k:24s} {v if not isinstance(v, float) else f'{v:8.3f} s'}")
    old, _ = fresh(prelude + f"WITH_RRR = {with_old_rrr}\n" + OLD)
    print("baseline, same run: the symbolic general-q polynomial the per-design kernel needed first:")
    for k, v in old.items():
        print(f"  {k:24s} {v:8.3f} s")


if __name__ == "__main__":
    main("--old" in sys.argv)
