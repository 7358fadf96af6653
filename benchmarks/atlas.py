"""The joint-space atlas and one cuspidality decision, each beside the naive way in the same run.

* the atlas of the general 3-RPR and of seed 002 at the notebook's resolution (40 nodes per axis,
  cusp curves included), against the naive atlas: the float direct kinematics
  (``direct_kinematics_batch``, uncertified) on the same grid, which gives counts and nothing else;
* one cuspidality decision (``is_cuspidal``: Krawczyk witness), warm (the design's exact system
  already derived) and cold (a new design object: kinematic polynomial, compiled derivatives and
  exact system derived in the call), against a dense grid search for a triple root (64^3 joint
  vectors, companion eigenvalues, the closest cluster of three roots: no proof at all), and against
  sympy's Groebner basis of the cusp system on one section (q3 fixed), stopped after 60 s;
* one proof of absence (msolve) on a box without cusps, first call (critical points of the cusp
  curve computed and cached for the design) and a second box of the same design.

Run with ``python benchmarks/atlas.py``.
"""

import multiprocessing as mp
import statistics
import time

import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.atlas import is_cuspidal, joint_atlas


def median_time(f, repeat=3):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def dense_triple_root_search(m, box, n=64):
    axes = [np.linspace(lo, hi, n) for lo, hi in box]
    Q = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    C = m.compiled().coefficients(Q)
    d = C.shape[1] - 1
    comp = np.zeros((len(Q), d, d))
    comp[:, 1:, :-1] = np.eye(d - 1)
    comp[:, :, -1] = -C[:, :-1] / C[:, -1:]
    t = np.linalg.eigvals(comp)
    D = np.abs(t[:, :, None] - t[:, None, :])
    D[:, np.arange(d), np.arange(d)] = np.inf
    spread = np.sort(D, axis=2)[:, :, 1].min(axis=1)
    return float(spread.min())


def _groebner(queue, exprs, gens):
    t = time.perf_counter()
    sp.groebner(exprs, *gens, order="lex")
    queue.put(time.perf_counter() - t)


def sympy_section(m, value, limit=60.0):
    P = m.kinematic_polynomial()
    x0, x1 = P.gens
    t = sp.Symbol("t")
    q1, q2, q3 = m.joint_symbols
    p = sp.expand(P.as_expr().subs({x0: 1, x1: t, q3: value}))
    exprs = [p, sp.diff(p, t), sp.diff(p, t, 2)]
    queue = mp.Queue()
    proc = mp.Process(target=_groebner, args=(queue, exprs, (t, q1, q2)))
    start = time.perf_counter()
    proc.start()
    proc.join(limit)
    if proc.is_alive():
        proc.terminate()
        proc.join()
        return None, time.perf_counter() - start
    return queue.get(), time.perf_counter() - start


def main():
    print("== joint-space atlas, 40 nodes per axis (64,000 certified counts + surface + cusp curves)")
    for name, box in (("general_3rpr", [(8, 14), (2, 8), (7, 13)]), ("stigger_husty", [(6, 14), (11, 19), (9, 17)])):
        m = getattr(isp.examples, name)()
        joint_atlas(m, box, 12)                               # derivations and kernels, once per design
        a = None

        def run():
            nonlocal a
            a = joint_atlas(m, box, 40)
        t_atlas = median_time(run)
        axes = [np.linspace(lo, hi, 40) for lo, hi in box]
        Q = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        t_naive = median_time(lambda: m.direct_kinematics_batch(Q))
        stages = ", ".join(f"{k} {v:.2f} s" for k, v in a.seconds.items())
        print(f"{name:14s} atlas {t_atlas:6.2f} s ({stages}); {len(a.vertices)} vertices, "
              f"{a.removed} removed, {len(a.cusp_curves)} cusp curves")
        print(f"{'':14s} naive float counts on the same grid {t_naive:6.2f} s (uncertified, no surface): "
              f"atlas / naive = {t_atlas / t_naive:.1f}")

    print("== one cuspidality decision (general 3-RPR, box [8,14]x[2,8]x[7,13])")
    box = [(8, 14), (2, 8), (7, 13)]
    m = isp.examples.general_3rpr()
    is_cuspidal(m, box)
    t_warm = median_time(lambda: is_cuspidal(m, box), repeat=5)
    t_cold = median_time(lambda: is_cuspidal(isp.examples.general_3rpr(), box), repeat=3)
    r = is_cuspidal(m, box)
    print(f"is_cuspidal warm {t_warm:.3f} s, cold (new design object) {t_cold:.3f} s: cuspidal={r.cuspidal}, "
          f"certificate {r.witness.certificate}")
    t_grid = median_time(lambda: dense_triple_root_search(m, box), repeat=3)
    print(f"naive dense grid search, 64^3 joint vectors (closest three roots {dense_triple_root_search(m, box):.2e}, "
          f"no proof): {t_grid:.3f} s; grid / warm = {t_grid / t_warm:.1f}")
    took, wall = sympy_section(m, 10)
    if took is None:
        print(f"sympy groebner of the cusp system on the section q3 = 10: not finished after {wall:.0f} s "
              f"(> {wall / t_warm:.0f} x the warm decision)")
    else:
        print(f"sympy groebner of the cusp system on the section q3 = 10: {took:.1f} s; "
              f"sympy / warm = {took / t_warm:.0f}")

    print("== proof of absence (msolve), general 3-RPR")
    m2 = isp.examples.general_3rpr()
    t = time.perf_counter()
    r1 = is_cuspidal(m2, [(13, 14), (2, 3), (7, 8)])
    t1 = time.perf_counter() - t
    t = time.perf_counter()
    r2 = is_cuspidal(m2, [(13, 14), (2, 3.5), (7, 8)])
    t2 = time.perf_counter() - t
    print(f"box [13,14]x[2,3]x[7,8]: cuspidal={r1.cuspidal}, {r1.systems} msolve systems, {t1:.1f} s "
          f"(critical points of the cusp curve computed once per design)")
    print(f"box [13,14]x[2,3.5]x[7,8]: cuspidal={r2.cuspidal}, {t2:.1f} s (critical points cached)")


if __name__ == "__main__":
    main()
