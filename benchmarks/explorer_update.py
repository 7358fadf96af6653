"""How long one slider move takes in the Jupyter explorer (seed 002), in the kernel: certified DK +
the drawing data (what the browser adds, round trip and repaint, is measured by the browser test:
tests/browser, timings.json).

Prints the median and 90th percentile of ``Explorer.set_q`` over slider positions of q3, against a
baseline measured in the same run: the certified one-row batch DK alone (what every update must
do), so the ratio is the cost of the redraw. The surface is joint-free here and is not re-meshed.
Also prints the cost of building the explorer (the first mesh included) and of one mode change.

    python benchmarks/explorer_update.py [moves]
"""

import sys
import time

import numpy as np

import imagespace as isp


def main(moves=60):
    m = isp.examples.stigger_husty()
    t0 = time.perf_counter()
    ex = isp.widgets.explore(m)
    build = time.perf_counter() - t0
    ex.wait()                             # the first surface is meshed in the background
    meshed = time.perf_counter() - t0
    q0 = m.q_example_float
    qs = [np.array([q0[0], q0[1], v]) for v in np.linspace(q0[2] - 2.0, q0[2] + 2.0, moves)]
    ex.set_q(qs[0])                       # warm
    m.direct_kinematics_batch(qs[0][None], certify=True)
    update, dk = [], []
    for q in qs:
        t = time.perf_counter()
        m.direct_kinematics_batch(q[None], certify=True)
        dk.append(time.perf_counter() - t)
        t = time.perf_counter()
        ex.set_q(q)
        update.append(time.perf_counter() - t)
    update, dk = np.array(update) * 1e3, np.array(dk) * 1e3
    counts = []
    for q in qs[::10]:
        ex.set_q(q)
        counts.append(ex.status["count"])
    ex.set_q(q0)
    neg = [k for k, mm in enumerate(ex.modes) if mm.aspect < 0]
    t = time.perf_counter()
    plan = ex.change_mode(neg[0], neg[1])
    change = time.perf_counter() - t
    print(f"explorer built (panels, status, certified modes): {build:.2f} s; with the first 48^3 mesh "
          f"(background): {meshed:.2f} s")
    print(f"slider update (set_q: certified DK + redraw), {moves} moves: median {np.median(update):.1f} ms, "
          f"90th percentile {np.percentile(update, 90):.1f} ms")
    print(f"baseline, certified one-row DK alone: median {np.median(dk):.1f} ms "
          f"-> update / DK = {np.median(update) / np.median(dk):.2f}x")
    print(f"mode counts seen along the moves: {sorted(set(counts))}")
    print(f"change mode (plan + draw): {change:.2f} s, found={plan.found}, {len(plan.poses)} samples")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 60)
