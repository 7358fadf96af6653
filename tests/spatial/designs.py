"""Seeded rational Gough-Stewart designs, poses and leg lengths for the spatial tests.

Conventions (see docs/spatial_designs.md):

* Design points are dyadic rationals ``k / 16`` (small denominators that doubles hold exactly),
  so the API, which takes floats, and the exact referee see the very same design.
* Poses are exact: a rotation from an integer quaternion ``(a, b, c, d)`` is
  ``R = R~(a, b, c, d) / n`` with ``n = a^2 + b^2 + c^2 + d^2`` and ``R~`` the Euler-Rodrigues
  matrix (rational for every integer quaternion, the Cayley-type parametrisation; the unit
  quaternion ``(a, b, c, d) / sqrt(n)`` itself may be irrational and is never needed); the
  translation is dyadic.
* Lengths from a pose: ``L_i^2 = |R b_i + t - a_i|^2`` is an exact rational, ``L_i`` in general
  irrational. Tests pass the float ``sqrt(L_i^2)`` to the API and the referee solves for
  ``Fraction(float(L_i)) ** 2`` (the exact square of the float the API gets); the generating pose
  is then a solution of a problem ``~1e-16`` away, not of the referee's problem exactly.
  :func:`exact_half_turn_design` instead builds a design whose lengths are dyadic (exact floats),
  with a half-turn (``q0 = 0``) as an exact solution.
* Lengths "from random values": dyadic ``k / 64`` drawn around the lengths of a random pose.

Everything is a pure function of an integer seed (``np.random.default_rng(seed)``).
"""

from __future__ import annotations

from fractions import Fraction
from typing import List, NamedTuple

import numpy as np

__all__ = ["Design", "Pose", "random_design", "random_design_63", "random_design_33",
           "random_rotation_quaternion", "random_pose", "half_turn_pose", "pose_rotation",
           "squared_lengths_of_pose", "float_lengths", "random_lengths", "exact_half_turn_design",
           "reference_designs", "as_float", "search_many_real_modes", "DIETMAIER_1998", "SEARCHED_DESIGN", "PublishedDesign", "SearchedDesign"]

GRID = 16            # design points are multiples of 1/GRID
LENGTH_GRID = 64     # random lengths are multiples of 1/LENGTH_GRID


class Design(NamedTuple):
    """A 6-SPS design: ``base`` and ``platform`` six 3D points each, as Fractions (lists)."""

    base: List[List[Fraction]]
    platform: List[List[Fraction]]


class Pose(NamedTuple):
    """An exact pose: integer quaternion ``quat`` (4 ints, not normalised) and Fraction ``t``."""

    quat: tuple
    t: List[Fraction]


def as_float(points):
    """Fractions (nested lists) as a float array (exact for dyadic entries)."""
    return np.array([[float(v) for v in row] for row in points], dtype=float)


def _dyadic(rng, shape, lo, hi):
    k = rng.integers(int(lo * GRID), int(hi * GRID) + 1, size=shape)
    return [[Fraction(int(v), GRID) for v in row] for row in k]


def _ring(rng, n, radius, jitter, z=0.0, zjitter=0.0):
    """``n`` points near a circle of the given radius at height ``z``, as dyadic Fractions."""
    out = []
    ang = np.sort(rng.uniform(0, 2 * np.pi, n)) if n else []
    for a in ang:
        r = radius * (1 + rng.uniform(-jitter, jitter))
        p = (r * np.cos(a), r * np.sin(a), z + rng.uniform(-zjitter, zjitter))
        out.append([Fraction(int(round(v * GRID)), GRID) for v in p])
    return out


def random_design(seed):
    """A general 6-6 design: base near a circle of radius 2, platform near radius 1, both with
    random height jitter (non-planar, so no architecture singularity), dyadic ``k / 16`` points."""
    rng = np.random.default_rng(seed)
    base = _ring(rng, 6, 2.0, 0.3, 0.0, 0.25)
    platform = _ring(rng, 6, 1.0, 0.3, 0.0, 0.25)
    return Design(base, platform)


def random_design_63(seed):
    """A 6-3 design: six distinct base points, platform points coinciding in pairs (3 distinct)."""
    rng = np.random.default_rng(seed)
    base = _ring(rng, 6, 2.0, 0.3, 0.0, 0.25)
    tri = _ring(rng, 3, 1.0, 0.3, 0.0, 0.25)
    platform = [tri[0], tri[1], tri[1], tri[2], tri[2], tri[0]]
    return Design(base, platform)


def random_design_33(seed):
    """A 3-3 design: base and platform points coinciding in pairs, paired as an octahedron."""
    rng = np.random.default_rng(seed)
    btri = _ring(rng, 3, 2.0, 0.3, 0.0, 0.25)
    ptri = _ring(rng, 3, 1.0, 0.3, 0.0, 0.25)
    base = [btri[0], btri[0], btri[1], btri[1], btri[2], btri[2]]
    platform = [ptri[0], ptri[1], ptri[1], ptri[2], ptri[2], ptri[0]]
    return Design(base, platform)


def random_rotation_quaternion(rng, size=4):
    """An integer quaternion ``(a, b, c, d)`` with entries in ``[-size, size]``, not all zero."""
    while True:
        q = tuple(int(v) for v in rng.integers(-size, size + 1, 4))
        if any(q):
            return q


def pose_rotation(quat):
    """The exact rotation matrix (Fractions, 3x3 list) of an integer quaternion ``R~(q) / q.q``."""
    a, b, c, d = (Fraction(v) for v in quat)
    n = a * a + b * b + c * c + d * d
    R = [[a * a + b * b - c * c - d * d, 2 * (b * c - a * d), 2 * (b * d + a * c)],
         [2 * (b * c + a * d), a * a - b * b + c * c - d * d, 2 * (c * d - a * b)],
         [2 * (b * d - a * c), 2 * (c * d + a * b), a * a - b * b - c * c + d * d]]
    return [[v / n for v in row] for row in R]


def random_pose(seed, height=(1.0, 2.0)):
    """A random exact pose: integer quaternion with a dominant ``a`` (a tilt of at most ~60
    degrees) and a dyadic translation with ``z`` in ``height`` (platform above the base)."""
    rng = np.random.default_rng(seed)
    while True:
        q = random_rotation_quaternion(rng, 3)
        q = (abs(q[0]) + 3,) + q[1:]
        if q[0] * q[0] >= sum(v * v for v in q[1:]):
            break
    t = [Fraction(int(rng.integers(-8, 9)), GRID), Fraction(int(rng.integers(-8, 9)), GRID),
         Fraction(int(rng.integers(int(height[0] * GRID), int(height[1] * GRID) + 1)), GRID)]
    return Pose(q, t)


def half_turn_pose(seed, height=(1.0, 2.0)):
    """A half-turn (rotation by pi, quaternion ``(0, b, c, d)``) about a random rational axis
    with a non-zero vertical component, and a dyadic translation."""
    rng = np.random.default_rng(seed)
    while True:
        b, c, d = (int(v) for v in rng.integers(-4, 5, 3))
        if d != 0 and (b, c) != (0, 0):
            break
    t = [Fraction(int(rng.integers(-8, 9)), GRID), Fraction(int(rng.integers(-8, 9)), GRID),
         Fraction(int(rng.integers(int(height[0] * GRID), int(height[1] * GRID) + 1)), GRID)]
    return Pose((0, b, c, d), t)


def squared_lengths_of_pose(design, pose):
    """Exact ``L_i^2 = |R b_i + t - a_i|^2`` (six Fractions)."""
    R = pose_rotation(pose.quat)
    out = []
    for a, b in zip(design.base, design.platform):
        d = [sum(R[r][k] * b[k] for k in range(3)) + pose.t[r] - a[r] for r in range(3)]
        out.append(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
    return out


def float_lengths(squared):
    """The float lengths ``sqrt(L^2)`` the API is given (correctly rounded square roots)."""
    return np.array([_sqrt_rounded(v) for v in squared], dtype=float)


def _sqrt_rounded(x):
    """The double nearest to ``sqrt(x)`` for a positive Fraction ``x`` (exact integer arithmetic)."""
    import math
    f = float(math.sqrt(float(x)))
    # fix the last ulp: choose among the neighbours the one whose square is closest to x
    cands = [np.nextafter(f, 0.0), f, np.nextafter(f, np.inf)]
    return float(min(cands, key=lambda c: abs(Fraction(float(c)) ** 2 - x)))


def random_lengths(seed, design, spread=0.06):
    """Dyadic lengths ``k / 64``: the lengths of a random pose, each scaled by a random factor in
    ``[1 - spread, 1 + spread]`` (a random point of the length space near the workspace)."""
    rng = np.random.default_rng(seed)
    base = float_lengths(squared_lengths_of_pose(design, random_pose(seed + 10_000)))
    f = rng.uniform(1 - spread, 1 + spread, 6)
    return np.round(base * f * LENGTH_GRID) / LENGTH_GRID


def exact_half_turn_design(seed):
    """A design for which a half-turn with ``q0 = 0`` is an exact solution with float-exact data.

    The pose: quaternion ``(0, 1, 1, 0)`` (a half-turn about the face diagonal ``(1, 1, 0)``,
    ``R = [[0, 1, 0], [1, 0, 0], [0, 0, -1]]``, integer) and a dyadic translation. Platform points
    are dyadic; each base point is ``a_i = R b_i + t - v_i`` with ``v_i`` a signed permutation of
    ``s (1, 2, 2) / 16`` or ``s (2, 3, 6) / 16`` (Pythagorean quadruples, ``|v| = 3 s / 16`` or
    ``7 s / 16``), so base points and lengths are dyadic and exact as floats.

    Returns ``(design, pose, lengths)`` with ``lengths`` a float array (exact).
    """
    rng = np.random.default_rng(seed)
    pose = Pose((0, 1, 1, 0), [Fraction(int(rng.integers(-4, 5)), GRID),
                               Fraction(int(rng.integers(-4, 5)), GRID), Fraction(3, 2)])
    platform = _ring(rng, 6, 1.0, 0.3, 0.0, 0.25)
    R = pose_rotation(pose.quat)
    base, lengths = [], []
    quads = [((1, 2, 2), 3), ((2, 3, 6), 7)]
    for b in platform:
        (v, n) = quads[int(rng.integers(0, 2))]
        perm = rng.permutation(3)
        v = [v[int(p)] for p in perm]
        v[2] = abs(v[2])                           # the leg points upward
        v = [v[0] * int(rng.choice([-1, 1])), v[1] * int(rng.choice([-1, 1])), v[2]]
        s = int(rng.integers(2, 5)) if n == 7 else int(rng.integers(5, 12))
        P = [sum(R[r][k] * b[k] for k in range(3)) + pose.t[r] for r in range(3)]
        base.append([P[r] - Fraction(s * v[r], GRID) for r in range(3)])
        lengths.append(Fraction(s * n, GRID))
    return Design(base, platform), pose, np.array([float(v) for v in lengths], dtype=float)


def reference_designs(n=56):
    """The seeded reference cases ``(name, design, lengths (6,) float, pose or None)``.

    Even cases: lengths from a random exact pose (float-rounded square roots); odd cases:
    lengths from random values. Case ``i`` with ``i % 14 == 6`` is a 6-3 design, ``i % 14 == 13``
    a 3-3 design, the others general 6-6 designs.
    """
    cases = []
    for i in range(n):
        seed = 1800 + i
        if i % 14 == 6:
            design = random_design_63(seed)
        elif i % 14 == 13:
            design = random_design_33(seed)
        else:
            design = random_design(seed)
        if i % 2 == 0:
            pose = random_pose(seed + 5000)
            lengths = float_lengths(squared_lengths_of_pose(design, pose))
            cases.append((f"seed{seed}-pose", design, lengths, pose))
        else:
            cases.append((f"seed{seed}-random", design, random_lengths(seed, design), None))
    return cases


def search_many_real_modes(seed, evaluations, log=None, timeout=30.0):
    """The documented seeded search for a design with many real assembly modes (hill climbing).

    Start: :func:`random_design` ``(seed)`` with the lengths of :func:`random_pose` ``(seed)``.
    Step: perturb either the leg lengths (all six by ``k / 256``, ``|k| <= 16``), or one base or
    platform point (each coordinate by ``k / 64``, ``|k| <= 8``), and keep the step if the
    referee's real count does not drop (plateau moves allowed). Points stay on the ``1 / 64``
    grid and lengths on the ``1 / 256`` grid: the data are exact as floats. Degenerate or slow
    candidates (positive-dimensional, msolve timeout) are rejected.

    Returns ``(count, design, lengths (6,) float, evaluations used)`` of the best design seen.
    """
    from euclid_ref import POSITIVE_DIMENSIONAL, gough_stewart_reference
    from msolve_ref import MsolveError

    rng = np.random.default_rng(seed)
    d0 = random_design(seed)
    base = np.array(as_float(d0.base))
    plat = np.array(as_float(d0.platform))
    L = np.round(float_lengths(squared_lengths_of_pose(d0, random_pose(seed))) * 256) / 256

    def count(b, p, l):
        try:
            ref = gough_stewart_reference(b, p, lengths=l, timeout=timeout)
        except (MsolveError, RuntimeError):
            return -1
        return -1 if ref == POSITIVE_DIMENSIONAL else len(ref)

    cur = count(base, plat, L)
    best = (cur, base.copy(), plat.copy(), L.copy())
    for ev in range(1, evaluations + 1):
        b, p, l = base.copy(), plat.copy(), L.copy()
        move = rng.integers(0, 3)
        if move == 0:
            l = l + rng.integers(-16, 17, 6) / 256
            if np.any(l <= 0.1):
                continue
        else:
            arr = b if move == 1 else p
            arr[rng.integers(0, 6)] += rng.integers(-8, 9, 3) / 64
        c = count(b, p, l)
        if c >= cur:
            base, plat, L, cur = b, p, l, c
            if c > best[0]:
                best = (c, b.copy(), p.copy(), l.copy())
        if log is not None:
            log(f"eval {ev}: candidate {c}, current {cur}, best {best[0]}")
    c, b, p, l = best
    frac = lambda a: [[Fraction(float(v)) for v in row] for row in a]
    return c, Design(frac(b), frac(p)), l, evaluations


# --------------------------------------------------------------------------- Dietmaier 1998
#
# P. Dietmaier, "The Stewart-Gough platform of general geometry can have 40 real postures",
# in J. Lenarcic, M. L. Husty (eds.), Advances in Robot Kinematics: Analysis and Control,
# Kluwer 1998, pp. 7-16. The numbers below (six decimals) are those quoted as "general 6-6 SGP
# with 40 real postures (by P. Dietmaier)" in the test data of E. Martyushev's solvers for
# "Forward kinematics of a general Stewart-Gough platform by elimination templates", Mechanism
# and Machine Theory 215 (2025) 106170 (https://github.com/martyushev/fkSGP, file
# python/genSGP.py, sgpType 100), with the convention L_i = |R x_i + t - X_i|, X the fixed
# (base) points and x the moving (platform) points -- the convention of this project.
# Verified here with the exact referee (tests/spatial/euclid_ref.py): 40 real poses, 40 complex,
# both for the decimal data as exact rationals and for their nearest doubles.
_DIETMAIER_BASE = (("0", "0", "0"), ("1.107915", "0", "0"), ("0.549094", "0.756063", "0"),
                   ("0.735077", "-0.223935", "0.525991"), ("0.514188", "-0.526063", "-0.368418"),
                   ("0.590473", "0.094733", "-0.205018"))
_DIETMAIER_PLATFORM = (("0", "0", "0"), ("0.542805", "0", "0"), ("0.956919", "-0.528915", "0"),
                       ("0.665885", "-0.353482", "1.402538"), ("0.478359", "1.158742", "0.107672"),
                       ("-0.137087", "-0.235121", "0.353913"))
_DIETMAIER_LENGTHS = ("1", "0.645275", "1.086284", "1.503439", "1.281933", "0.771071")
# one of the 40 postures, as published with the data (rotation matrix, translation)
_DIETMAIER_POSE = (((-0.040450357031281, -0.932229494397471, 0.359599691867884),
                    (0.983337493748685, 0.026695523074364, 0.179818582009314),
                    (-0.177231887661606, 0.360881585597300, 0.915616371179918)),
                   (0.955868038233880, -0.046995628998516, -0.290013283037649))


class PublishedDesign(NamedTuple):
    """A design from the literature: exact decimal data and one published pose."""

    design: Design                  # decimal data as exact Fractions
    lengths: List[Fraction]         # the six leg lengths, exact decimals
    real_count: int                 # the published number of real poses
    pose_rotation: np.ndarray       # (3, 3) one published pose
    pose_translation: np.ndarray    # (3,)

    @property
    def float_base(self):
        return as_float(self.design.base)

    @property
    def float_platform(self):
        return as_float(self.design.platform)

    @property
    def float_lengths(self):
        return np.array([float(v) for v in self.lengths], dtype=float)


DIETMAIER_1998 = PublishedDesign(
    Design([[Fraction(v) for v in row] for row in _DIETMAIER_BASE],
           [[Fraction(v) for v in row] for row in _DIETMAIER_PLATFORM]),
    [Fraction(v) for v in _DIETMAIER_LENGTHS], 40,
    np.array(_DIETMAIER_POSE[0], dtype=float), np.array(_DIETMAIER_POSE[1], dtype=float))

# --------------------------------------------------------------------------- searched design
#
# The best design of the documented seeded search ``search_many_real_modes(seed=7,
# evaluations=126)`` (reproducible: the same call returns it), 12 real poses (referee), found
# before Dietmaier's data turned up; kept as a second, cheap reference count (the referee solves
# it in about a second). Points on the 1/64 grid, lengths on the 1/256 grid: exact as doubles.
_SEARCHED_BASE = (("9/32", "11/8", "1/4"), ("-39/64", "153/64", "7/32"), ("-39/32", "-41/32", "-3/16"),
                  ("1/8", "-109/64", "3/64"), ("47/32", "-85/64", "5/64"), ("35/16", "-39/32", "3/32"))
_SEARCHED_PLATFORM = (("35/64", "5/32", "-3/64"), ("15/32", "63/64", "1/8"),
                      ("1/64", "33/32", "-3/64"), ("-1", "-1/2", "-1/32"),
                      ("-9/16", "-13/32", "-11/64"), ("57/64", "5/64", "-25/64"))
_SEARCHED_LENGTHS = ("29/16", "173/64", "427/128", "495/256", "579/256", "421/128")


class SearchedDesign(NamedTuple):
    """A design from the seeded search: exact dyadic data and its real count (referee)."""

    design: Design
    lengths: List[Fraction]
    real_count: int
    seed: int
    evaluations: int

    @property
    def float_base(self):
        return as_float(self.design.base)

    @property
    def float_platform(self):
        return as_float(self.design.platform)

    @property
    def float_lengths(self):
        return np.array([float(v) for v in self.lengths], dtype=float)


SEARCHED_DESIGN = SearchedDesign(
    Design([[Fraction(v) for v in row] for row in _SEARCHED_BASE],
           [[Fraction(v) for v in row] for row in _SEARCHED_PLATFORM]),
    [Fraction(v) for v in _SEARCHED_LENGTHS], 12, 7, 126)
