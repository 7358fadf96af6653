"""Certified straight-segment checks against the seed-002 singularity quartic: the batched
Bernstein exclusion test (numpy, rigorous rounding bounds, exact fallback) against the exact
python-flint path and sympy, measured in the same run; and the planner's wall time.

Run with ``python benchmarks/segment_checks.py [n_segments]`` (default 100000).
"""

import sys
import time

import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.paths.modechange import plan_mode_change
from imagespace.core.exact_roots import roots_in_unit_interval
from imagespace.paths.check import _piece_polynomial, _prepare, segment, segments_free


def random_segments(n, rng):
    P = np.column_stack([rng.uniform(-12, 12, n), rng.uniform(-12, 12, n), rng.uniform(-np.pi, np.pi, n)])
    A = isp.image_point(P)
    B = isp.image_point(P + np.column_stack([rng.normal(0, 2, (n, 2)), rng.normal(0, 0.5, n)]))
    return A, B


def main(n=100000):
    m = isp.examples.stigger_husty()
    rng = np.random.default_rng(0)
    A, B = random_segments(n, rng)
    quartic = _prepare(m)                                  # derivation, not timed
    segments_free(m, A[:100], B[:100])
    t = time.perf_counter()
    free, how = segments_free(m, A, B)
    t_batch = time.perf_counter() - t
    undecided = int(np.sum(how == "exact"))
    # exact flint path on every segment (the reference answers)
    t = time.perf_counter()
    exact = np.empty(n, dtype=bool)
    for i in range(n):
        p = _piece_polynomial(quartic, segment(A[i], B[i]).pieces[0])
        exact[i] = not roots_in_unit_interval(p)
    t_exact = time.perf_counter() - t
    # sympy: polynomial by substitution and a Sturm count, on a subset
    k = 300
    x = isp.image_symbols()
    T = sp.Symbol("t")
    S = quartic.poly.as_expr()
    t = time.perf_counter()
    sym = []
    for i in range(k):
        X = [sp.Rational(float(a)) * (1 - T) + sp.Rational(float(b)) * T for a, b in zip(A[i], B[i])]
        sym.append(sp.Poly(sp.expand(S.xreplace(dict(zip(x, X)))), T).count_roots(0, 1) == 0)
    t_sym = (time.perf_counter() - t) / k
    same = np.array_equal(free, exact) and np.array_equal(np.array(sym), exact[:k])
    print(f"{n} random segments (pose-space steps ~N(0, 2) in x, y and N(0, 0.5) in phi), {exact.mean():.1%} free")
    print(f"  batched Bernstein test + exact fallback: {n / t_batch:,.0f} segments/s "
          f"({undecided} = {undecided / n:.3%} sent to the exact path)")
    print(f"  exact python-flint per segment:          {n / t_exact:,.0f} segments/s ({1e6 * t_exact / n:.0f} us each)"
          f"  -> batched / flint = {t_exact / t_batch:.1f}x")
    print(f"  sympy per segment:                       {1 / t_sym:,.0f} segments/s ({1e3 * t_sym:.2f} ms each)")
    print(f"  same answers as the exact path on all {n}: {same}")
    modes = m.direct_kinematics(m.q_example)
    neg = [j for j, mm in enumerate(modes) if mm.aspect < 0]
    plan_mode_change(m, m.q_example_float, modes[neg[0]], modes[neg[1]])      # warm
    ts = []
    for _ in range(5):
        t = time.perf_counter()
        plan = plan_mode_change(m, m.q_example_float, modes[neg[0]], modes[neg[1]])
        ts.append(time.perf_counter() - t)
    print(f"  planner, seed 002 modes {neg[0] + 1} -> {neg[1] + 1}: {1e3 * np.median(ts):.0f} ms median "
          f"({len(plan.path)} segments, certified: {plan.check.certified})")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100000)
