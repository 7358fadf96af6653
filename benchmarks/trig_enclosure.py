"""Rigorous cos/sin enclosures: the compiled ``cos_sin_enclosure`` against the python-flint arb loop
it replaced in ``CoefficientEnclosure._features`` and against plain ``np.cos`` + ``np.sin`` (no
bound), measured in the same run on the same joint values.

Run with ``python benchmarks/trig_enclosure.py [n_elements]``.
"""

import sys
import time

import flint
import numpy as np

from imagespace.core.bounded_trig import cos_sin_enclosure
from imagespace.core.certify import flint_precision

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


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000)
