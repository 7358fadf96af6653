"""Cost of certainty: certified direct kinematics against the float paths on the same inputs.

    python benchmarks/certified_dk.py [rows]

Prints per-call times (float path vs certified path, median of repeated calls) and batch
throughput with and without ``certify=True`` on the same rows, for random reachable joint vectors
and for rows near the discriminant (two modes about to merge), with the ratio against the float
path measured in the same run. Asserts nothing.
"""

import sys
import time
import warnings

import numpy as np

import imagespace as isp


def median_time(fn, repeat):
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t)
    return float(np.median(ts))


def near_discriminant(m, rng, n):
    """Joint vectors of random poses pushed towards the singularity surface: a pose is moved
    along x until the DK count changes (bisection), then q is perturbed by 1e-12 .. 1e-4."""
    out = []
    while len(out) < max(8, n // 500):
        p0 = np.array([rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-np.pi, np.pi)])
        p1 = p0 + np.array([rng.uniform(1, 3), 0.0, 0.0])
        S = m.singularity_surface()
        f0, f1 = S.at_poses(p0[None])[0], S.at_poses(p1[None])[0]
        if not (np.isfinite(f0) and np.isfinite(f1)) or f0 * f1 > 0:
            continue
        for _ in range(60):
            pm = (p0 + p1) / 2
            fm = S.at_poses(pm[None])[0]
            if fm * f0 > 0:
                p0, f0 = pm, fm
            else:
                p1 = pm
        q = m.inverse_kinematics(p0[None])[0]
        if np.all(np.isfinite(q)) and np.all(q > 0.5):
            out.append(q)
    base = np.array(out)[rng.integers(len(out), size=n)]
    eps = 10.0 ** rng.uniform(-12, -4, size=(n, 3)) * rng.choice([-1, 1], size=(n, 3))
    return base * (1 + eps)


def main(rows=20000):
    rng = np.random.default_rng(0)
    warnings.simplefilter("ignore", isp.NearSingularWarning)
    for name, m in (("general 3-RPR", isp.examples.general_3rpr()), ("seed 002", isp.examples.stigger_husty())):
        q = m.q_example_float
        m.direct_kinematics(q)
        m.direct_kinematics(q, certify=True)
        tf = median_time(lambda: m.direct_kinematics(q), 30)
        tc = median_time(lambda: m.direct_kinematics(q, certify=True), 30)
        print(f"{name}: per call float {tf * 1e3:.2f} ms, certified {tc * 1e3:.2f} ms "
              f"(certified / float = {tc / tf:.2f}x)")
        poses = np.column_stack([rng.uniform(-3, 3, rows), rng.uniform(-3, 3, rows),
                                 rng.uniform(-np.pi, np.pi, rows)])
        Q = m.inverse_kinematics(poses)
        Q = Q[np.all(np.isfinite(Q), axis=1)]
        for label, QQ in (("random poses", Q), ("near the discriminant", near_discriminant(m, rng, rows))):
            m.direct_kinematics_batch(QQ[:3000], certify=True)        # compile / derive once
            t = time.perf_counter()
            rf = m.direct_kinematics_batch(QQ)
            tf = time.perf_counter() - t
            t = time.perf_counter()
            rc = m.direct_kinematics_batch(QQ, certify=True)
            tc = time.perf_counter() - t
            n = QQ.shape[0]
            resolved = int(np.sum(rc.solver == "certified"))
            flagged = int(np.sum(rf.near_singular))
            differ = int(np.sum(rf.count != rc.count))
            print(f"  batch, {label} ({n} rows): float {n / tf:,.0f} rows/s, certified {n / tc:,.0f} rows/s "
                  f"(float / certified = {tc / tf:.2f}x); {resolved} rows re-solved root by root; "
                  f"float count differs on {differ} rows, {flagged} rows flagged near_singular")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 20000)
