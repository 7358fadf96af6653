"""The first certified pose of a new Gough-Stewart design (issue [18], target 2), in one run.

Not a test. A new design needs its start system (its 40 solutions at generic complex squared
lengths) before its first pose. Two routes, interleaved on the same seeded designs:

* ``design`` (the baseline): a total-degree homotopy per design (128 paths per attempt,
  :func:`~imagespace.spatial.homotopy.solve_start_system`);
* ``family``: the family kind's generic start carried to the design (40 paths,
  :mod:`imagespace.spatial.families`).

Printed: the one-time costs (numba's compiled code loaded, the family's generic start solved
in-process and read back from disk), then over ``N`` new seeded designs (general 6-6, anchors
normal, a pose's lengths; then 3-RPS, anchors normal, default axes, random lengths) the median
per-design start time of both routes, and the median time
from a new ``GoughStewart`` object to its first certified pose (``direct_kinematics`` with the
start system built by each route), their ratio, and whether both routes certify the same counts.

``python benchmarks/first_pose.py [N]`` (default 20).
"""

import sys
import time

import numpy as np

import imagespace as isp
from imagespace.spatial import families
from imagespace.spatial.homotopy import solve_start_system
from imagespace.spatial.solver import start_system
from imagespace.spatial.study import study_point


def _design(seed):
    rng = np.random.default_rng(seed)
    base, platform = rng.normal(size=(6, 3)), rng.normal(size=(6, 3))
    q = np.r_[1.0, 0.3 * rng.normal(size=3)]
    s = study_point(q / np.linalg.norm(q), [0.2 * rng.normal(), 0.2 * rng.normal(), 1.5 + rng.random()])
    return (base, platform), isp.GoughStewart(base, platform).inverse_kinematics(s)


def _design_3rps(seed):
    rng = np.random.default_rng(seed)
    return (rng.normal(size=(3, 3)), rng.normal(size=(3, 3))), 1.0 + 2.0 * rng.random(3)


def _first_pose(cls, args, L, route):
    """Seconds from a new design object to its first certified pose; the result."""
    t = time.perf_counter()
    m = cls(*args)
    m.cached("start_system", lambda: start_system(m.family(), route=route))
    res = m.direct_kinematics(L)
    return time.perf_counter() - t, res


def main(n=20):
    t = time.perf_counter()
    for cls, make in ((isp.GoughStewart, _design), (isp.ThreeRPS, _design_3rps)):
        args, L = make(10 ** 6)
        for route in ("design", "family"):
            _first_pose(cls, args, L, route)
    print(f"warm-up (compiled code loaded or compiled, first family start): {time.perf_counter() - t:.2f} s")
    A = families.generic_member("legs6")
    t = time.perf_counter()
    g = solve_start_system(A, np.diag([1.0, 1, 1, 1, 0, 0, 0, 0]), np.r_[np.arange(6), -1], 6,
                           attempts=families.GENERIC_ATTEMPTS, expected=families.LEG_FAMILY_COUNT)
    t_solve = time.perf_counter() - t
    families.family_start_system.cache_clear()
    t = time.perf_counter()
    families.family_start_system("legs6")
    t_disk = time.perf_counter() - t
    print(f"family start, once per process: solved {t_solve * 1e3:.0f} ms ({len(g.solutions)} solutions, "
          f"{g.paths} paths), read from the kernel cache {t_disk * 1e3:.1f} ms")

    for cls, make, title in ((isp.GoughStewart, _design, "6-6 Gough-Stewart designs"),
                             (isp.ThreeRPS, _design_3rps, "3-RPS designs (random lengths)")):
        _compare(cls, make, title, n)


def _compare(cls, make, title, n):
    starts = {"design": [], "family": []}
    first = {"design": [], "family": []}
    counts = {"design": [], "family": []}
    certified = {"design": 0, "family": 0}
    carried = 0
    for i in range(n):
        args, L = make(i)
        fam = cls(*args).family()
        for route in ("design", "family") if i % 2 else ("family", "design"):
            t = time.perf_counter()
            st = start_system(fam, route=route)
            starts[route].append(time.perf_counter() - t)
            carried += route == "family" and st.paths == families.FAMILY_COUNTS[families.family_kind(fam)]
            dt, res = _first_pose(cls, args, L, route)
            first[route].append(dt)
            counts[route].append((res.count, res.complex_count, len(st.solutions)))
            certified[route] += bool(res.certified)
    med = {k: {r: float(np.median(v[r])) * 1e3 for r in v} for k, v in (("start", starts), ("first", first))}
    print(f"\n{n} new seeded {title}, medians [range] in ms ({carried}/{n} starts carried, "
          "the others fell back to the total-degree route):")
    for what, label in (("start", "per-design start"), ("first", "new design -> first certified pose")):
        src = starts if what == "start" else first
        row = "  ".join(f"{r}: {med[what][r]:7.1f} [{min(src[r]) * 1e3:.1f}-{max(src[r]) * 1e3:.1f}]"
                        for r in ("design", "family"))
        print(f"  {label:36s} {row}   design / family: {med[what]['design'] / med[what]['family']:.2f}x")
    same = counts["design"] == counts["family"]
    print(f"  certified first poses: design {certified['design']}/{n}, family {certified['family']}/{n}; "
          f"same counts (real, complex, start solutions) on every design: {'yes' if same else 'NO'}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20)
