"""Rigorous cos/sin enclosures: the compiled ``cos_sin_enclosure`` against the python-flint arb loop
it replaced in ``CoefficientEnclosure._features`` and against plain ``np.cos`` + ``np.sin`` (no
bound), measured in the same run on the same joint values; then ``CoefficientEnclosure.evaluate``
end to end on coefficients in the cos/sin of three actuated angles, with the features from
``cos_sin_enclosure`` (now) and from the arb loop (before).

Run with ``python benchmarks/trig_enclosure.py [n_elements]``.
"""

import sys
import time

import flint
import numpy as np
import sympy as sp

import imagespace as isp
from imagespace.core.bounded_trig import cos_sin_enclosure
from imagespace.core.certify import flint_precision
from imagespace.core.codegen import CoefficientEnclosure

U = 2.0**-53


def arb_loop(q):
    """The loop CoefficientEnclosure._features ran before: one arb cos and one arb sin per element."""
    out = np.empty((4, q.size))
    with flint_precision(64):
        for r, v in enumerate(q):
            b = flint.arb(float(v))
            for j, ball in enumerate((b.cos(), b.sin())):
                m = float(ball.mid())
                out[j, r] = m
                out[2 + j, r] = float(ball.rad()) * (1 + 4 * U) + abs(m) * U + 2.0**-1074
    return out


def enclosure_with_angles():
    """Coefficients (and products of them) of the quadrics of two RRR legs and an RRP leg, all
    three actuated by an angle: polynomials in q_i, cos q_i, sin q_i."""
    legs = [isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, sp.Rational(5, 2)), actuated=0),
            isp.RRP(base=(2, 5), length=2, platform=(0, sp.Rational(6, 5)), direction=(3, 4)),
            isp.RRR(base=(6, 0), platform=(sp.Rational(3, 2), 0), lengths=(sp.Rational(7, 2), 3),
                    actuated=0)]
    m = isp.PlanarParallel(legs)
    eqs = [sp.expand(e) for e in m.constraint_equations()]
    x = sorted(set().union(*(e.free_symbols for e in eqs)) - set(m.joint_symbols), key=str)
    cs = [sp.Poly(e, *x).coeffs() for e in eqs]
    exprs = [c for cc in cs for c in cc] + [a * b for a in cs[0] for b in cs[2]]
    return CoefficientEnclosure(exprs, m.joint_symbols)


class ArbFeatures(CoefficientEnclosure):
    """The enclosure with the features of before: the arb loop."""

    def __init__(self, enc):
        self.__dict__.update(enc.__dict__)

    def _features(self, Q):
        val = np.zeros((Q.shape[0], self._expo.shape[1]))
        err = np.zeros_like(val)
        val[:, :3] = Q
        cols = sorted({i for _, i, _ in self._trig})
        for i in cols:
            c, s, ec, es = arb_loop(Q[:, i])
            for g, j, is_cos in self._trig:
                if j == i:
                    val[:, g], err[:, g] = (c, ec) if is_cos else (s, es)
        return val, err


def best_rate(f, n, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t)
    return n / best


def main(n=1_000_000):
    rng = np.random.default_rng(2)
    q = rng.uniform(-np.pi, np.pi, n)                    # joint angles
    cos_sin_enclosure(q[:10])                            # compilation / cache load, not timed
    r_enc = best_rate(lambda: cos_sin_enclosure(q), n)
    r_np = best_rate(lambda: (np.cos(q), np.sin(q)), n)
    k = min(n, 20000)
    r_arb = best_rate(lambda: arb_loop(q[:k]), k, repeat=1)
    c, s, ec, es = cos_sin_enclosure(q)
    try:
        import numba
        threads = numba.get_num_threads()
        numba.set_num_threads(1)
        r_one = best_rate(lambda: cos_sin_enclosure(q), n)
        numba.set_num_threads(threads)
    except ImportError:
        threads, r_one = 1, float("nan")
    print(f"elements: {n} (cos and sin of each; arb loop on the first {k})")
    print(f"cos_sin_enclosure ({threads} threads)  : {r_enc:14,.0f} elements/s")
    print(f"cos_sin_enclosure (1 thread)   : {r_one:14,.0f} elements/s")
    print(f"arb loop (python-flint, 64 bit): {r_arb:14,.0f} elements/s")
    print(f"np.cos + np.sin (no bound)     : {r_np:14,.0f} elements/s")
    print(f"ratio enclosure / arb loop     : {r_enc / r_arb:.0f}x")
    print(f"ratio enclosure / numpy        : {r_enc / r_np:.2f}x")
    print(f"largest bound / ulp(1)         : {max(ec.max(), es.max()) / 2.0**-52:.2f}")
    enc = enclosure_with_angles()
    old = ArbFeatures(enc)
    rows = min(n, 200_000)
    Q = rng.uniform(-np.pi, np.pi, (rows, 3))
    enc.evaluate(Q[:10])
    r_new = best_rate(lambda: enc.evaluate(Q), rows)
    kq = min(rows, 5000)
    r_old = best_rate(lambda: old.evaluate(Q[:kq]), kq, repeat=1)
    F1, E1 = enc.evaluate(Q[:kq])
    F0, E0 = old.evaluate(Q[:kq])
    print(f"CoefficientEnclosure.evaluate, {len(enc._exact[0])} coefficients in 6 trig features:")
    print(f"  features from cos_sin_enclosure : {r_new:12,.0f} rows/s")
    print(f"  features from the arb loop      : {r_old:12,.0f} rows/s")
    print(f"  ratio                           : {r_new / r_old:.0f}x   "
          f"(largest |F_new - F_old| / E_new: {np.max(np.abs(F1 - F0) / E1):.3f}, "
          f"median E_new / E_old: {np.median(E1 / E0):.3f})")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
