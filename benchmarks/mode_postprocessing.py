"""The spatial fast path's work after tracking, on Dietmaier's rows (issue [18], target 5).

Not a test. Dietmaier's design has 40 real modes a row, so after the tracking and the compiled
certificate the batch path normalises, checks and classifies ~160,000 modes per 4,000 rows
(``solver._modes``: normalised Study points, the residual of every quadric, the aspect from the
leg Jacobian). Printed, interleaved in one run (median of ``REPEATS``, milliseconds):

* the residuals ``max_k |z^T (A_k - p_k E) z|`` per mode: now (matrix products, then a row-wise
  dot) against the previous three-operand ``einsum`` (kept below as the baseline);
* the leg vectors ``R b_i + t - a_i``: now (one matrix product) against the previous ``einsum``;
* the whole post-processing of the modes (``solver._modes``) as shipped.

Both versions' results are compared (they differ by rounding only: another summation order).

``python benchmarks/mode_postprocessing.py [N_ROWS]``
"""

import sys
import time

import numpy as np

import imagespace as isp
from imagespace.spatial.solver import MODE_CHUNK, _mode_residuals, _modes
from imagespace.spatial.study import normalize_study, rotation_matrix, translation

REPEATS = 7


def residuals_einsum(family, P_modes, pts):
    """The previous residuals: a three-operand einsum (the baseline)."""
    zAz = np.einsum("ni,kij,nj->nk", pts, family.A, pts)
    zEz = np.einsum("ni,ij,nj->n", pts, family.E, pts)
    has = family.pidx >= 0
    p = np.where(has[None, :], P_modes[:, np.maximum(family.pidx, 0)], 0.0)
    return np.abs(zAz - p * zEz[:, None]).max(axis=1)


def leg_vectors_einsum(design, s):
    """The previous leg vectors: einsum over the anchors (the baseline)."""
    R, t = rotation_matrix(s), translation(s)
    return np.einsum("...ij,kj->...ki", R, design.platform_points) + t[..., None, :] - design.base_points


def main(n=4000):
    dg, L0 = isp.examples.dietmaier_1998()
    rng = np.random.default_rng(2026)
    u = rng.normal(size=(n, 6))
    L = np.asarray(L0) * (1 + 10.0 ** rng.uniform(-6, -2, (n, 1)) * u / np.linalg.norm(u, axis=1)[:, None])
    res = dg.direct_kinematics_batch(L)
    fam = dg.family()
    rows = np.repeat(np.arange(n), res.count)
    pts = np.concatenate([res[i].study_points for i in range(n)])        # unscaled, normalised
    scaled = normalize_study(pts[:MODE_CHUNK] * np.r_[np.ones(4), np.full(4, 1 / fam.scale)])
    P = (L / fam.scale) ** 2
    P_chunk = P[rows[:MODE_CHUNK]]
    s_chunk = pts[:MODE_CHUNK]
    cases = {
        "residuals (one chunk of modes)": (lambda: _mode_residuals(fam, P_chunk, scaled),
                                           lambda: residuals_einsum(fam, P_chunk, scaled)),
        "leg vectors (one chunk of modes)": (lambda: dg.leg_vectors(s_chunk),
                                             lambda: leg_vectors_einsum(dg, s_chunk)),
    }
    print(f"Dietmaier's design, {n} rows, {pts.shape[0]} real modes; a chunk is {MODE_CHUNK} modes "
          f"(median of {REPEATS} interleaved runs)")
    for name, (now, before) in cases.items():
        tn, tb = [], []
        for _ in range(REPEATS):
            t = time.perf_counter(); a = now(); tn.append(time.perf_counter() - t)
            t = time.perf_counter(); b = before(); tb.append(time.perf_counter() - t)
        scale = max(1.0, float(np.abs(b).max()))
        print(f"  {name:34s} now {np.median(tn) * 1e3:7.2f} ms   einsum (before) {np.median(tb) * 1e3:7.2f} ms   "
              f"{np.median(tb) / np.median(tn):5.1f}x   max difference {np.abs(a - b).max() / scale:.1e} (relative)")
    Z = np.concatenate([pts[:, :4], pts[:, 4:] / fam.scale], axis=1)
    tm = []
    for _ in range(REPEATS):
        t = time.perf_counter(); _modes(fam, Z, P, rows); tm.append(time.perf_counter() - t)
    print(f"  {'all modes post-processed (_modes)':34s} now {np.median(tm) * 1e3:7.2f} ms for {pts.shape[0]} modes")


if __name__ == "__main__":
    main(*[int(a) for a in sys.argv[1:2]])
