"""Certified direct kinematics of designs with an actuated angle (issue [14]): cos/sin of the exact
binary-rational joint angle enclosed, never rounded.

Three ways to the same exact question, timed on the same joint vectors in one run:

* ``certify=True`` as shipped: the quadrics at the exact angles, eliminated exactly over
  Q(tan(r/2)) with python-flint polynomials (``imagespace.core.transcendental``), real roots isolated
  on arb enclosures;
* the naive exact way, the baseline: the sympy elimination of the same exact quadrics (``cos(r)``,
  ``sin(r)`` as sympy atoms) and the arb isolation of its coefficients;
* for reference only, the way before issue [14] (cos/sin rounded to doubles, then exact rational
  arithmetic): fast, but a certificate of a different question; its counts that differ from the
  true ones are printed.

Run with ``python benchmarks/angle_certify.py [n_rows]``.
"""

import sys
import time

import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.core.certify import certify_real_roots

R = sp.Rational


def design():
    """The 3-RRR-type design of issue [14]: RRR actuated at the base, RRP, PRR."""
    return isp.PlanarParallel([
        isp.RRR(base=(R(58169, 7450), R(310161, 59600)), platform=(R(-23, 8), R(3, 4)), lengths=(R(19, 8), R(47, 8))),
        isp.RRP(base=(R(441627, 106760), R(68531, 106760)), length=R(25, 4), platform=(R(-9, 4), R(25, 8)),
                direction=(R(-85, 157), R(132, 157))),
        isp.PRR(base=(R(43131, 7400), R(35541, 14800)), axis=(R(-3, 5), R(-4, 5)), platform=(R(-21, 8), R(17, 8)),
                length=R(19, 4))])


def sympy_exact_count(m, q):
    """The baseline: the sympy elimination with exact cos/sin atoms, then arb isolation."""
    m.clear_cache()
    P, _, _ = m.exact_forms([sp.Rational(float(v)) for v in q])
    return certify_real_roots(P).count


def rounded_count(m, q):
    """Before issue [14]: cos/sin of each angle rounded to doubles, then exact rational arithmetic."""
    eqs = []
    for leg, v in zip(m.legs, q):
        if leg.actuated_is_angle:
            c, s = sp.Rational(np.cos(v)), sp.Rational(np.sin(v))
            cs_sym = sp.Symbol("qq")
            quad = leg.dyad(cs_sym)
            coeffs = [sp.sympify(x).subs({sp.cos(cs_sym): c, sp.sin(cs_sym): s}) for x in quad.coefficients()]
            eqs.append(type(quad)(quad.kind, *coeffs))
        else:
            eqs.append(leg.dyad(sp.Rational(float(v))))
    from imagespace.core.elimination import eliminate
    el = eliminate(eqs, m.elimination_plan)
    F = [sp.expand(v) for v in el.F]
    return certify_real_roots(F).count


def main(n=40):
    m = design()
    rng = np.random.default_rng(14)
    poses = np.column_stack([rng.uniform(0, 6, 4 * n), rng.uniform(-2, 4, 4 * n), rng.uniform(-np.pi, np.pi, 4 * n)])
    Q = m.inverse_kinematics(poses)
    Q = Q[np.all(np.isfinite(Q), axis=1)][:n]
    Q = np.vstack([Q, [[-1.920140724811376, -1.4172525442553405, 0.24711037622577975]]])
    n = len(Q)
    m.direct_kinematics(Q[0], certify=True)               # warm caches (not timed)
    t = time.perf_counter()
    new = [len(m.direct_kinematics(q, certify=True)) for q in Q]
    t_new = (time.perf_counter() - t) / n
    k = min(n, 6)
    t = time.perf_counter()
    base = [sympy_exact_count(m, q) for q in Q[-k:]]
    t_base = (time.perf_counter() - t) / k
    t = time.perf_counter()
    old = [rounded_count(m, q) for q in Q]
    t_old = (time.perf_counter() - t) / n
    counts = m.certified_root_counts(Q)[0].tolist()
    print(f"{n} joint vectors of {m.name} (an actuated RRR base revolute and an RRP leg angle)")
    print(f"certify=True (exact over Q(tan(r/2)), arb isolation): {1e3 * t_new:8.1f} ms per call")
    print(f"baseline: sympy elimination with exact cos/sin atoms: {1e3 * t_base:8.1f} ms per call "
          f"({t_base / t_new:.0f}x slower)")
    print(f"reference, rounded cos/sin (before issue [14]):       {1e3 * t_old:8.1f} ms per call")
    print(f"modes from certify=True == baseline counts on the last {k}: {new[-k:] == base}")
    print(f"certified_root_counts == modes from certify=True: {counts == new}")
    wrong = [i for i in range(n) if old[i] != new[i]]
    print(f"rows where the rounded cos/sin gave another count: {len(wrong)} "
          f"(issue [14]'s case, the last row: rounded {old[-1]}, exact {new[-1]})")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 40)
