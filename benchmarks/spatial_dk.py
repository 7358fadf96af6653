"""Spatial direct kinematics (issues [13], [18]): fast, compiled-certified, arb-certified and exact
paths, in one run.

Not a test. Designs: one seeded general 6-6 Gough-Stewart design (anchors on a 1/8 grid, lengths
from random poses) and Dietmaier's 40-real-mode design (its lengths moved by 1e-6 .. 1e-2 relative
in random directions); then a 6-3, a 3-3 and a 3-RPS design (issue [18] target 3: certified
without msolve). Printed per design, rows per second (wall clock, numba threads on every core):

Rows/s of ``tracking``, ``fast`` and ``compiled-certified`` are the median of ``FAST_REPEATS``
interleaved runs; the others one run.

* ``tracking``: the previous fast path (40 compiled paths a row and the float classification, no
  certificate) -- the baseline of the certificate's cost;
* ``fast``: ``direct_kinematics_batch`` (tracking plus the compiled certificate: ``reliable`` and
  ``certified`` rows);
* ``certificate``: the compiled Krawczyk test alone on the tracked endpoints;
* ``compiled-certified``: ``direct_kinematics_batch(certify=True)`` (the compiled certificate,
  arb and msolve only for rows it does not prove);
* ``arb-certified``: the previous certified implementation (:func:`arb_certified_row`: tracking
  and Krawczyk in arb on every endpoint, msolve where that fails) -- the baseline;
* ``msolve``: ``method="exact"``;
* whether the certified paths agree (counts and modes) on the shared rows;
* ``fast path, kernel=...`` (issue [18] target 5: >= 2,000 poses/s on 2 cores): the fast path's
  back end (:func:`~imagespace.spatial.solver.solve_rows`: re-centring, tracking, compiled
  certificate, classification) with the one-path tracker (``kernel="scalar"``, the baseline) and
  the lockstep tracker (``kernel="lanes"``) on the same rows, interleaved, on ``KERNEL_THREADS``
  numba threads: the median poses/s of ``KERNEL_REPEATS`` runs each (range in brackets), the
  ratio, and whether the two give the same counts and ``reliable`` flags.

``python benchmarks/spatial_dk.py [N_FAST N_ARB N_EXACT N_COMPARE]``: ``N_COMPARE`` more rows per
6-6 design compared between the compiled and the arb certified paths (the issue's 10,000-row check:
``N_COMPARE = 5000`` for the two 6-6 designs).

``python benchmarks/spatial_dk.py --kernels [N_FAST]``: the kernel comparison alone (a few seconds),
on the two 6-6 designs.
"""

import sys
import time

import numba
import numpy as np

import imagespace as isp
from imagespace.spatial.certify import krawczyk_certify
from imagespace.spatial.fastcert import certify_endpoints, family_enclosure, parameter_enclosure
from imagespace.spatial.homotopy import PATH_OK, classify_batch, recentre, track_parameters
from imagespace.spatial.solver import RECENTRE_MIN_ROWS, exact_study_solver, solve_rows
from imagespace.spatial.study import normalize_study, study_point


def arb_certified_row(platform, L):
    """The previous certified implementation (before the compiled certificate), kept as the
    baseline: track the row, Krawczyk in arb on every arrived endpoint, msolve when arb does not
    prove all ``bound`` solutions. Returns (real count, study points, how)."""
    from fractions import Fraction

    fam = platform.family()
    P = (np.asarray(L, float) / fam.scale) ** 2
    Z, st, _ = track_parameters(platform.start_system, P[None])
    Qx = fam.exact([(Fraction(float(v)) / Fraction(fam.scale)) ** 2 for v in L])
    arrived = Z[0][st[0] == PATH_OK]
    if fam.bound is not None and arrived.shape[0] >= fam.bound:
        c = krawczyk_certify(Qx, arrived)
        if c.complete(fam.bound):
            pts = c.points[c.certified & (c.real == 1)].real
            pts = fam.unscale(normalize_study(pts)) if pts.shape[0] else np.zeros((0, 8))
            return c.real_count, pts, "arb"
    pts, _ = exact_study_solver(Qx)
    return pts.shape[0], fam.unscale(pts), "msolve"


def _tracking_only(platform, L):
    """The previous fast path: tracking and the float classification (no certificate)."""
    fam = platform.family()
    P = (L / fam.scale) ** 2
    start = platform.start_system
    if P.shape[0] >= RECENTRE_MIN_ROWS:
        start = recentre(start, np.median(P, axis=0))
    Z, st, _ = track_parameters(start, P)
    W, real, distinct, ok = classify_batch(Z, st, platform.tolerances)
    return Z, st, real.sum(axis=1), ok


def _same_modes(a, b):
    if a.shape[0] != b.shape[0]:
        return False
    if not a.shape[0]:
        return True
    key = lambda p: p[np.lexsort(p.T[::-1])]                      # noqa: E731
    return bool(np.allclose(key(a), key(b), atol=1e-8))


def _rate(n, t):
    return n / t if t > 0 else float("inf")


#: numba threads of the kernel comparison (issue [18] target 5 is stated for 2 cores)
KERNEL_THREADS = 2
#: interleaved runs per kernel (the machine is shared: the median and the range are printed)
KERNEL_REPEATS = 5
#: interleaved runs of the tracking, fast and compiled-certified paths (their median is printed)
FAST_REPEATS = 3


def compare_kernels(name, m, L):
    """The fast path's back end with kernel="scalar" and kernel="lanes" on the same rows,
    interleaved; prints poses/s (median and range of ``KERNEL_REPEATS`` runs) and the ratio."""
    threads = numba.get_num_threads()
    numba.set_num_threads(min(KERNEL_THREADS, numba.config.NUMBA_NUM_THREADS))
    fam = m.family()
    kernels = ("scalar", "lanes")
    batches, times = {}, {k: [] for k in kernels}
    try:
        for k in kernels:                                    # compiled, caches loaded
            solve_rows(fam, m.start_system, L[:8] ** 2, m.tolerances, lengths=L[:8], kernel=k)
        for _ in range(KERNEL_REPEATS):
            for k in kernels:
                t = time.perf_counter()
                batches[k] = solve_rows(fam, m.start_system, L ** 2, m.tolerances, lengths=L, kernel=k)
                times[k].append(time.perf_counter() - t)
    finally:
        used = numba.get_num_threads()
        numba.set_num_threads(threads)
    rate = {k: sorted(L.shape[0] / t for t in times[k]) for k in kernels}
    med = {k: float(np.median(rate[k])) for k in kernels}
    same = (np.array_equal(batches["scalar"].count, batches["lanes"].count)
            and np.array_equal(batches["scalar"].reliable, batches["lanes"].reliable))
    print(f"  fast path on {used} threads, {L.shape[0]} rows, median of {KERNEL_REPEATS} interleaved runs "
          f"({name}):")
    for k in kernels:
        print(f"    kernel={k!r:9s} {med[k]:9.1f} poses/s  [{rate[k][0]:.1f} .. {rate[k][-1]:.1f}]")
    print(f"    lanes / scalar: {med['lanes'] / med['scalar']:.2f}x;  same counts and reliable: {same}; "
          f"reliable {int(batches['lanes'].reliable.sum())}/{L.shape[0]}")
    return med


def run_design(name, m, L, n_arb, n_exact, n_compare, rng):
    fam = m.family()
    t = time.perf_counter()
    st = m.start_system
    t_start = time.perf_counter() - t
    n = L.shape[0]
    m.direct_kinematics_batch(L[:8])                         # caches loaded, threads started
    m.direct_kinematics_batch(L[:8], certify=True)

    # tracking, fast and certified interleaved, FAST_REPEATS times: the median of each (one run of
    # a path is at the mercy of this machine's drift; the first call also pays page faults)
    ts = {"track": [], "fast": [], "certified": []}
    for _ in range(FAST_REPEATS):
        t = time.perf_counter()
        Z, status, counts_track, ok_track = _tracking_only(m, L)
        ts["track"].append(time.perf_counter() - t)
        t = time.perf_counter()
        fast = m.direct_kinematics_batch(L)
        ts["fast"].append(time.perf_counter() - t)
        t = time.perf_counter()
        certified = m.direct_kinematics_batch(L, certify=True)
        ts["certified"].append(time.perf_counter() - t)
    t_track, t_fast, t_certified = (float(np.median(ts[k])) for k in ("track", "fast", "certified"))

    pm, pr = parameter_enclosure(L, fam.scale)
    enc = family_enclosure(fam)
    target = fam.bound
    t = time.perf_counter()
    cert = certify_endpoints(enc, Z, status, pm, pr, target)
    t_cert = time.perf_counter() - t

    by_compiled = int(fast.certified.sum())

    idx = rng.choice(n, min(n_arb + n_compare, n), replace=False)
    t = time.perf_counter()
    arb = [arb_certified_row(m, L[i]) for i in idx[:n_arb]]
    t_arb = time.perf_counter() - t
    arb += [arb_certified_row(m, L[i]) for i in idx[n_arb:]]
    how = {}
    agree = 0
    for (count, pts, h), i in zip(arb, idx):
        how[h] = how.get(h, 0) + 1
        agree += certified.certified[i] and certified.counts[i] == count and \
            _same_modes(certified[i].study_points, pts)

    t = time.perf_counter()
    exact = [m.direct_kinematics(L[i], method="exact") for i in idx[:n_exact]]
    t_exact = time.perf_counter() - t
    agree_exact = sum(int(certified.counts[i] == e.count and _same_modes(certified[i].study_points,
                                                                         e.study_points))
                      for e, i in zip(exact, idx[:n_exact]))
    wrong_track = int(np.sum(ok_track & (counts_track != certified.counts)))

    print(f"\n== {name}: {len(st.solutions)} complex solutions at generic lengths (bound {fam.bound}), "
          f"start system {t_start:.2f} s")
    rows = [("tracking (previous fast path, no certificate)", n, t_track,
             f"float checks pass on {int(ok_track.sum())}, of which {wrong_track} with a wrong count"),
            ("fast: direct_kinematics_batch", n, t_fast,
             f"certified {int(fast.certified.sum())}, reliable {int(fast.reliable.sum())}"),
            ("certificate alone (compiled, on the endpoints)", n, t_cert,
             f"complete {int(cert.complete.sum())}"),
            ("compiled-certified: batch(certify=True)", n, t_certified,
             f"certified {int(certified.certified.sum())}: {by_compiled} compiled, "
             f"{n - by_compiled} by arb/msolve"),
            ("arb-certified (previous implementation)", n_arb, t_arb,
             f"all {len(idx)} rows compared: {how}"),
            ("msolve: method='exact'", len(exact), t_exact, "")]
    for label, k, tt, note in rows:
        print(f"  {label:50s} {k:6d} rows {tt:8.2f} s {_rate(k, tt):9.1f} rows/s  {note}")
    print(f"  compiled-certified / arb-certified: {_rate(n, t_certified) / _rate(n_arb, t_arb):6.1f}x;"
          f"  / msolve: {_rate(n, t_certified) / _rate(len(exact), t_exact):7.0f}x;"
          f"  certificate cost / tracking cost: {t_cert / t_track:.2f}")
    print(f"  same answers: compiled-certified = arb-certified on {agree}/{len(idx)} rows; "
          f"= msolve on {agree_exact}/{len(exact)} rows")
    compare_kernels(name, m, L)


def designs_66(n_fast, rng):
    """The two 6-6 designs and their rows: (name, platform, lengths)."""
    base = rng.integers(-8, 9, (6, 3)) / 8.0
    platform = rng.integers(-8, 9, (6, 3)) / 16.0
    gs = isp.GoughStewart(base, platform)
    poses = study_point(rng.normal(size=(n_fast, 4)), rng.uniform(-0.5, 0.5, (n_fast, 3)) + [0, 0, 1.5])
    dg, Ld = isp.examples.dietmaier_1998()
    u = rng.normal(size=(n_fast, 6))
    Ld = np.asarray(Ld) * (1 + 10.0 ** rng.uniform(-6, -2, (n_fast, 1)) * u / np.linalg.norm(u, axis=1)[:, None])
    return [("general 6-6", gs, gs.inverse_kinematics(poses)),
            ("Dietmaier 1998 (lengths moved 1e-6 .. 1e-2)", dg, Ld)]


def kernels_only(n_fast=4000):
    rng = np.random.default_rng(2026)
    for name, m, L in designs_66(n_fast, rng):
        compare_kernels(name, m, L)


def main(n_fast=4000, n_arb=40, n_exact=8, n_compare=0):
    rng = np.random.default_rng(2026)
    for name, m, L in designs_66(n_fast, rng):
        run_design(name, m, L, n_arb, n_exact, n_compare, rng)

    tri = rng.integers(-16, 17, (3, 3)) / 16.0
    g63 = isp.GoughStewart(rng.integers(-16, 17, (6, 3)) / 8.0, tri[[0, 1, 1, 2, 2, 0]])
    btri = rng.integers(-16, 17, (3, 3)) / 8.0
    g33 = isp.GoughStewart(btri[[0, 0, 1, 1, 2, 2]], tri[[0, 1, 1, 2, 2, 0]])
    n_small = max(n_fast // 4, 16)
    for name, m in (("6-3", g63), ("3-3", g33)):
        poses = study_point(rng.normal(size=(n_small, 4)), rng.uniform(-0.3, 0.3, (n_small, 3)) + [0, 0, 1.5])
        run_design(name, m, m.inverse_kinematics(poses), n_arb // 2, n_exact // 2, 0, rng)
    while True:                                              # a seeded non-degenerate design
        try:
            rps = isp.ThreeRPS(rng.integers(-4, 5, (3, 3)) / 2.0, rng.integers(-4, 5, (3, 3)) / 4.0,
                               base_axes=rng.integers(-3, 4, (3, 3)))
            break
        except isp.exceptions.DegenerateDesignError:
            continue
    run_design("3-RPS", rps, rng.uniform(0.8, 3.0, (n_small, 3)), n_arb // 2, n_exact // 2, 0, rng)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--kernels"]:
        kernels_only(*[int(a) for a in sys.argv[2:3]])
    else:
        main(*[int(a) for a in sys.argv[1:5]])
