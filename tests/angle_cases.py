"""Angle-actuated designs next to their discriminant, with msolve's verdict (issue [14]).

Shared by ``tests/make_angle_cases.py`` (writes ``tests/data/angle_cases.json``) and
``tests/solve/test_angle_referee.py``. Nothing here uses imagespace's elimination, kinematic
polynomial, quadrics or certificates: a design is built from its legs' public constructors only
to hand it to the library under test and to the referee (which reads the legs' public attributes).

How a case is made (all in :func:`make_design_cases`):

1. a random design with exact rational geometry: leg 0 of a given type whose actuated joint is an
   angle, legs 1 and 2 of random types and actuated joints (at most one PP dyad); points and
   lengths dyadic (multiples of 1/8), directions Pythagorean unit vectors, the fixed angle of an
   RPP/PPR leg ``atan2`` of a Pythagorean pair (exact rational cosine and sine);
2. float joint values from the inverse kinematics of a random pose;
3. the angles ``q0*`` of leg 0 where the referee's DK system has a multiple solution, the other
   joints fixed: :func:`msolve_ref.singular_angles` (msolve on the Euclidean system plus its
   Jacobian determinant, angle unknown, boxes of 256 bits), turned into angles with mpmath at 300
   bits; kept when the real mode count differs on the two sides (a fold);
4. rows: floats ``q0`` a few ulps from ``q0*`` (preferring one where the double-rounded cosine
   and sine give a different count than the true ones: a *hard* row) and one float at
   ``q0* +- 10^-e`` (``e`` in 3..12);
5. the truth of a row: msolve on the system whose every actuated angle enters as
   :meth:`msolve_ref.CosSin.true_of` (a rational point on the unit circle within ``2^-120`` of the
   true cosine and sine): the real modes (``modes``, the PP dyad's spurious ``phi + pi`` dropped)
   and the distinct real orientations of all complex solutions (``orientations``: what the
   kinematic polynomial's real roots stand for, see :func:`msolve_ref.real_orientations`). The
   same with double-rounded cosine and sine (``rounded_*``): what a certificate built on rounded
   trigonometry answers. A design is flagged ``orientation_first`` (:func:`orientation_first`)
   when an orientation carries several solutions (a PP dyad, parallel RP or PR dyads): there a
   root of the kinematic polynomial is not one mode.

Why the truth decides: the angle's rational stand-in lies within ``2^-119`` (along the circle) of
the true angle, the only angles where the count can change are the singular angles of step 3,
and a row is kept only when its distance to ``q0*`` exceeds ``2^-100`` (the stand-ins of the
other legs' angles move ``q0*`` by about ``2^-120`` times a moderate factor), and when the count
msolve gives on the row equals the count on the same side of the fold (step 3).
"""

from __future__ import annotations

import math
from fractions import Fraction

import mpmath
import numpy as np
import sympy as sp

import imagespace as isp
from msolve_ref import (POSITIVE_DIMENSIONAL, VARIABLES, _eliminate, planar_dk_reference, planar_dk_system,
                        real_orientations, singular_angles, solution_degrees, true_angles)

#: (leg type, actuated joint) pairs whose actuated joint is an angle (imagespace.core.legs)
ANGLE_ACTUATED = [("RPR", 0), ("RPR", 2), ("RRR", 0), ("RRR", 1), ("RRR", 2), ("PRR", 1), ("PRR", 2),
                  ("RRP", 0), ("RRP", 1), ("RPP", 0), ("PRP", 1), ("PPR", 2)]
#: every (type, actuated) pair; the PP dyads fix the orientation
ALL_LEGS = [(k, a) for k in ("RPR", "RRR", "PRR", "RRP", "RPP", "PRP", "PPR") for a in range(3)]
PP_DYADS = {("RPP", 0), ("PRP", 1), ("PPR", 2)}
TRIPLES = [(3, 4, 5), (5, 12, 13), (8, 15, 17), (7, 24, 25), (20, 21, 29), (12, 35, 37), (9, 40, 41)]
#: rows closer than this to the singular angle are not kept (see the module docstring)
TIE_MARGIN = 2.0 ** -100

mpmath.mp.prec = 300


# --------------------------------------------------------------------------- designs

def _q(x):
    """A Fraction as text (JSON)."""
    x = Fraction(x)
    return str(x.numerator) if x.denominator == 1 else f"{x.numerator}/{x.denominator}"


def _dyadic(rng, lo, hi, den=8):
    return _q(Fraction(int(rng.integers(int(lo * den), int(hi * den) + 1)), den))


def _unit(rng):
    a, b, c = TRIPLES[int(rng.integers(len(TRIPLES)))]
    if rng.integers(2):
        a, b = b, a
    return [_q(Fraction(int(rng.choice([-1, 1])) * a, c)), _q(Fraction(int(rng.choice([-1, 1])) * b, c))]


def random_leg_spec(rng, kind, actuated):
    """A leg as JSON-able dict: exact rationals as text."""
    spec = {"type": kind, "actuated": int(actuated)}
    pt = lambda r: [_dyadic(rng, -r, r), _dyadic(rng, -r, r)]
    if kind == "RPR":
        spec.update(base=pt(6), platform=pt(3))
    elif kind == "RRR":
        spec.update(base=pt(6), platform=pt(3), lengths=[_dyadic(rng, 2, 6), _dyadic(rng, 2, 6)])
    elif kind == "PRR":
        spec.update(base=pt(6), axis=_unit(rng), platform=pt(3), length=_dyadic(rng, 2, 6))
    elif kind == "RRP":
        spec.update(base=pt(6), length=_dyadic(rng, 2, 6), platform=pt(3), direction=_unit(rng))
    elif kind == "RPP":
        spec.update(base=pt(6), platform=pt(3), direction=_unit(rng), angle=_unit(rng))
    elif kind == "PRP":
        spec.update(base=pt(6), axis=_unit(rng), platform=pt(3), direction=_unit(rng))
    elif kind == "PPR":
        spec.update(base=pt(6), axis=_unit(rng), platform=pt(3), angle=_unit(rng))
    else:
        raise ValueError(kind)
    if kind in ("RPP", "PPR") and Fraction(spec["angle"][1]) == 0:   # never: no triple has a 0
        raise ValueError("the angle between the sliders must not be 0 or pi")
    return spec


def build_leg(spec):
    """The imagespace leg of a spec (angles of RPP/PPR as ``atan2`` of exact rationals)."""
    R = lambda t: sp.Rational(t)
    pair = lambda key: (R(spec[key][0]), R(spec[key][1]))
    kind, act = spec["type"], spec["actuated"]
    if kind == "RPR":
        return isp.RPR(base=pair("base"), platform=pair("platform"), actuated=act)
    if kind == "RRR":
        return isp.RRR(base=pair("base"), platform=pair("platform"), lengths=pair("lengths"), actuated=act)
    if kind == "PRR":
        return isp.PRR(base=pair("base"), axis=pair("axis"), platform=pair("platform"),
                       length=R(spec["length"]), actuated=act)
    if kind == "RRP":
        return isp.RRP(base=pair("base"), length=R(spec["length"]), platform=pair("platform"),
                       direction=pair("direction"), actuated=act)
    if kind == "RPP":
        c, s = pair("angle")
        return isp.RPP(base=pair("base"), platform=pair("platform"), direction=pair("direction"),
                       angle=sp.atan2(s, c), actuated=act)
    if kind == "PRP":
        return isp.PRP(base=pair("base"), axis=pair("axis"), platform=pair("platform"),
                       direction=pair("direction"), actuated=act)
    if kind == "PPR":
        c, s = pair("angle")
        return isp.PPR(base=pair("base"), axis=pair("axis"), platform=pair("platform"),
                       angle=sp.atan2(s, c), actuated=act)
    raise ValueError(kind)


def build_design(specs):
    return isp.PlanarParallel([build_leg(s) for s in specs])


def random_specs(rng, kind, actuated):
    """Leg 0 of the given type, legs 1, 2 random; at most one PP dyad in the design."""
    specs = [random_leg_spec(rng, kind, actuated)]
    pp = (kind, actuated) in PP_DYADS
    while len(specs) < 3:
        k, a = ALL_LEGS[int(rng.integers(len(ALL_LEGS)))]
        if (k, a) in PP_DYADS and pp:
            continue
        pp = pp or (k, a) in PP_DYADS
        specs.append(random_leg_spec(rng, k, a))
    return specs


# --------------------------------------------------------------------------- the referee's counts

def hexq(q):
    return [float(v).hex() for v in q]


def unhexq(h):
    return np.array([float.fromhex(v) for v in h])


def truth(m, q):
    """msolve's verdict on the true angles: ``(modes, orientations, poses)``; None for a continuum."""
    qt = true_angles(m, q)
    ref = planar_dk_reference(m, qt)
    ori = real_orientations(m, qt)
    if ref == POSITIVE_DIMENSIONAL or ori == POSITIVE_DIMENSIONAL:
        return None
    return len(ref), len(ori), ref.poses


def rounded(m, q):
    """msolve's verdict with double-rounded cosine and sine (the convention of
    :func:`msolve_ref._cs` for a float angle): ``(modes, orientations)``; None for a continuum."""
    ref = planar_dk_reference(m, list(q))
    ori = real_orientations(m, list(q))
    if ref == POSITIVE_DIMENSIONAL or ori == POSITIVE_DIMENSIONAL:
        return None
    return len(ref), len(ori)


def orientation_first(m, q):
    """True when an orientation carries two or more complex solutions at generic joint values:
    the orientation is fixed before the positions (a PP dyad; two RP or two PR dyads whose lines
    are parallel ...), so a count of orientations is not a count of modes. Decided by msolve at
    ``q``: distinct complex solutions of the system vs distinct points of its elimination ideal in
    ``(c, s)``."""
    polys, _ = planar_dk_system(m, true_angles(m, q))
    deg = solution_degrees(polys, VARIABLES)
    gens = _eliminate(polys, VARIABLES, 2)
    if deg == POSITIVE_DIMENSIONAL or gens == ["0"]:
        return None
    ori = solution_degrees(gens, ("c", "s"))
    return None if ori == POSITIVE_DIMENSIONAL else ori[1] < deg[1]


def _angle_of(u, v):
    """The angle (mpmath, 300 bits) of the midpoints of msolve's boxes for (cos, sin)."""
    mid = lambda iv: mpmath.mpf((iv[0] + iv[1]).numerator) / mpmath.mpf(2 * (iv[0] + iv[1]).denominator)
    return mpmath.atan2(mid(v), mid(u))


def _count(m, q):
    """Real modes at the true angles (the fold test)."""
    return len(planar_dk_reference(m, true_angles(m, q)))


def _with(q, j, value):
    q = [float(v) for v in q]
    q[j] = float(value)
    return q


def make_design_cases(seed, kind, actuated, ulps=3, hard_only=False, max_tries=30):
    """Rows of one design (see the module docstring), or None after ``max_tries`` designs.

    ``seed`` is a sequence of ints (numpy's SeedSequence entropy). With ``hard_only`` the rows are
    the (up to two) floats within ``ulps`` ulps of ``q0*`` whose rounded count differs from the
    truth, and a design without one is passed over.

    Returns a dict ``{"design": specs, "seed": seed, "q_star": str, "rows": [...]}``; a row holds
    ``q`` (hex floats), ``kind`` ("ulp" or "offset"), ``dist`` (``q0 - q0*``), ``modes``,
    ``orientations``, ``rounded_modes``, ``rounded_orientations``, ``poses`` (hex).
    """
    rng = np.random.default_rng(list(seed))
    for _ in range(max_tries):
        specs = random_specs(rng, kind, actuated)
        try:
            m = build_design(specs)
        except isp.ImageSpaceError:
            continue
        pose = np.array([rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-np.pi, np.pi)])
        branches = [int(rng.integers(leg.n_branches)) for leg in m.legs]
        try:
            q = [float(v) for v in m.inverse_kinematics(pose, working_modes=branches)]
            m.check_q(q)                    # e.g. the mirror branch of an RPR gives rho < 0
        except isp.ImageSpaceError:
            continue
        try:
            sing = singular_angles(m, true_angles(m, q), 0, timeout=60)
            first = orientation_first(m, q)
        except Exception:                   # msolve timeout or failure: another design
            continue
        if first is None:
            continue
        if sing == POSITIVE_DIMENSIONAL or not sing:
            continue
        stars = sorted(float(_angle_of(u, v)) for u, v, _ in sing)
        stars_mp = sorted((_angle_of(u, v) for u, v, _ in sing), key=float)
        order = [int(i) for i in rng.permutation(len(stars_mp))]
        for i in order:
            qs = stars_mp[i]
            gaps = [abs(float(qs) - s) for j, s in enumerate(stars) if j != i] + [1.0]
            d = min(1e-6, min(gaps) / 4)
            if d < 1e-12 or abs(abs(float(qs)) - math.pi) < 1e-3:
                continue
            try:
                left, right = _count(m, _with(q, 0, float(qs) - d)), _count(m, _with(q, 0, float(qs) + d))
            except Exception:
                continue
            if left == right:
                continue
            rows = _rows(m, q, qs, left, right, rng, ulps, hard_only)
            if rows:
                return {"design": specs, "seed": [int(v) for v in seed], "orientation_first": first,
                        "q_star": mpmath.nstr(qs, 60), "rows": rows}
            if hard_only:
                break                       # one singular angle tried: next design
    return None


def _rows(m, q, qs, left, right, rng, ulps, hard_only=False):
    """The ulp row (a hard one when there is one) and the offset row, each checked against the
    count on its side of the fold; with ``hard_only`` up to two hard ulp rows."""
    f0 = float(qs)
    cands = [f0]
    for _ in range(ulps):
        cands = [float(np.nextafter(cands[0], -np.inf))] + cands + [float(np.nextafter(cands[-1], np.inf))]
    cands.sort(key=lambda f: abs(f - f0))          # nearest first: the default row
    rows = []
    best = None
    for f in cands:
        dist = mpmath.mpf(f) - qs
        if abs(dist) < TIE_MARGIN:
            continue
        qq = _with(q, 0, f)
        try:
            rnd = rounded(m, qq)
        except Exception:
            continue
        side = right if dist > 0 else left
        if rnd is None:
            continue
        if hard_only:
            if rnd[0] != side:
                rows.append(("ulp", qq, dist, rnd, side))
            if len(rows) == 2:
                break
            continue
        if best is None or (rnd[0] != side and best[2][0] == best[3]):
            best = (qq, dist, rnd, side)
    if best is not None:
        rows.append(("ulp",) + best)
    if hard_only:
        return _truths(m, rows)
    e = int(rng.integers(3, 13))
    sgn = 1 if rng.integers(2) else -1
    f = float(qs + sgn * mpmath.mpf(10) ** (-e))
    qq = _with(q, 0, f)
    dist = mpmath.mpf(f) - qs
    try:
        rnd = rounded(m, qq)
        if rnd is not None:
            rows.append(("offset", qq, dist, rnd, right if dist > 0 else left))
    except Exception:
        pass
    return _truths(m, rows)


def _truths(m, rows):
    """msolve's truth for each candidate row, kept when it agrees with the side of the fold."""
    out = []
    for kind, qq, dist, rnd, side in rows:
        try:
            t = truth(m, qq)
        except Exception:
            continue
        if t is None or t[0] != side:       # the direct count must agree with the side of the fold
            print(f"  row dropped: msolve {None if t is None else t[0]} modes, {side} on its side")
            continue
        out.append({"q": hexq(qq), "kind": kind, "dist": float(dist), "modes": t[0],
                    "orientations": t[1], "rounded_modes": rnd[0], "rounded_orientations": rnd[1],
                    "poses": [[float(v).hex() for v in p] for p in t[2]]})
    return out
