"""Seeded hard rows for the float paths: joint vectors next to the discriminant (two real modes
about to merge), over designs of every leg type and actuated joint.

Each design is random, its geometry full-precision floats (exact binary rationals whose products
are not exact in floating point, so the float elimination does round) and Pythagorean directions
(unit vectors with rational entries, so every number of the design is rational). Rows: on segments of joint space between two reachable joint vectors
whose *certified* numbers of real roots differ (``certified_root_counts``: proven in the kernel,
exact per row where the bounds cannot decide), bisect on that certified count (never on a float
path) and keep both ends of the bracket once it is narrower than 1e-3, 1e-6, 1e-9 ... 1e-14
(relative to the joint values) and at the last bisection (adjacent floats). Two roots merging
at a fold separate like the square root of the distance, so the kept pairs of modes are about
3e-2 ... 1e-7 apart (1e-8 at adjacent floats).
"""

from __future__ import annotations

import numpy as np

import imagespace as isp

#: Bracket widths (relative) at which both ends are kept, and the last one (adjacent floats).
LEVELS = (1e-3, 1e-6, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 0.0)
_PYTHAGOREAN = [(3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25), (20, 21, 29), (12, 35, 37)]


def _coord(rng, lo, hi, size=None):
    return rng.uniform(lo, hi, size)


def _direction(rng):
    a, b, c = _PYTHAGOREAN[rng.integers(len(_PYTHAGOREAN))]
    if rng.integers(2):
        a, b = b, a
    return (a / c * rng.choice([-1, 1]), b / c * rng.choice([-1, 1]))


def random_leg(rng, kind):
    """One leg of type ``kind`` with random float geometry and a random actuated joint."""
    A, a, act = tuple(_coord(rng, -6, 6, 2)), tuple(_coord(rng, -3, 3, 2)), int(rng.integers(3))
    if kind == "RPR":
        return isp.RPR(base=A, platform=a, actuated=act)
    if kind == "RRR":
        return isp.RRR(base=A, platform=a, lengths=tuple(_coord(rng, 2, 5, 2)), actuated=act)
    if kind == "PRR":
        return isp.PRR(base=A, axis=_direction(rng), platform=a, length=float(_coord(rng, 2, 5)), actuated=act)
    if kind == "RRP":
        return isp.RRP(base=A, length=float(_coord(rng, 2, 5)), platform=a, direction=_direction(rng),
                       actuated=act)
    if kind == "RPP":
        return isp.RPP(base=A, platform=a, direction=_direction(rng), angle=float(_coord(rng, 0.5, 2.6)),
                       actuated=act)
    if kind == "PRP":
        return isp.PRP(base=A, axis=_direction(rng), platform=a, direction=_direction(rng), actuated=act)
    return isp.PPR(base=A, axis=_direction(rng), platform=a, angle=float(_coord(rng, 0.5, 2.6)), actuated=act)


def random_design(rng, kinds):
    """A design of three legs of the given types (re-drawn until it is not degenerate)."""
    while True:
        try:
            return isp.PlanarParallel([random_leg(rng, k) for k in kinds])
        except (isp.DegenerateDesignError, isp.InputError):
            continue


def hard_rows(m, rng, n_lines, max_steps=60):
    """Joint vectors next to the discriminant of ``m`` (see the module docstring).

    Returns ``(Q, level)``: the rows and the index in :data:`LEVELS` of each (both ends of each
    bracket, so a pair of rows at one level has certified counts differing by 2)."""
    poses = np.column_stack([rng.uniform(-3, 3, 400), rng.uniform(-3, 3, 400), rng.uniform(-np.pi, np.pi, 400)])
    Q = m.inverse_kinematics(poses)
    Q = Q[np.all(np.isfinite(Q), axis=1)]
    if len(Q) < 4:
        return np.zeros((0, 3)), np.zeros(0, dtype=int)
    counts, _ = m.certified_root_counts(Q)
    good = np.flatnonzero(counts >= 0)
    Q, counts = Q[good], counts[good]
    a = rng.integers(len(Q), size=20 * n_lines)
    b = rng.integers(len(Q), size=20 * n_lines)
    keep = np.flatnonzero(counts[a] != counts[b])[:n_lines]
    lo, hi, ca = Q[a[keep]], Q[b[keep]], counts[a[keep]]
    alive = np.ones(len(keep), dtype=bool)
    out, lev = [], []
    recorded = np.zeros((len(keep), len(LEVELS)), dtype=bool)
    for step in range(max_steps):
        mid = 0.5 * (lo + hi)
        done = np.all((mid == lo) | (mid == hi), axis=1)
        idx = np.flatnonzero(alive & ~done)
        if idx.size:
            cm, _ = m.certified_root_counts(mid[idx])
            alive[idx[cm < 0]] = False            # invalid joint values, continuum, uncertified
            same = cm == ca[idx]
            lo[idx[same]] = mid[idx[same]]
            hi[idx[~same & (cm >= 0)]] = mid[idx[~same & (cm >= 0)]]
        width = np.max(np.abs(hi - lo) / np.maximum(np.abs(hi), 1e-300), axis=1)
        for k, w in enumerate(LEVELS):
            take = alive & ~recorded[:, k] & ((width <= w) if w > 0 else done)
            for i in np.flatnonzero(take):
                out += [lo[i].copy(), hi[i].copy()]
                lev += [k, k]
            recorded[:, k] |= take
        if not np.any(alive & ~done):
            break
    return np.array(out).reshape(-1, 3), np.array(lev, dtype=int)


#: Leg-type triples of the sample: every type, the angle-actuated ones (RRR, and RPR/PRR/RRP
#: actuated at a revolute) included through the random actuated joint.
KIND_SETS = [("RPR", "RPR", "RPR"), ("RRR", "RRR", "RRR"), ("PRR", "RPR", "RRR"), ("RRP", "PRR", "RPR"),
             ("RPP", "RPR", "RRR"), ("PRP", "RRR", "PRR"), ("PPR", "RPR", "RRP"), ("RRR", "PRR", "RRP")]
