"""The referee's generator: seeded cases of every class the planar direct kinematics must answer.

``generate(seed, sizes)`` -> list of cases (JSON-able dicts, :mod:`spec`), ``sizes`` mapping a class
name to its number of cases (:data:`FAST`, :data:`SLOW`). Case ``i`` of class ``c`` draws from
``numpy.random.default_rng([seed, CLASS_INDEX[c], i])``: a case is the same whatever else is drawn.
A case is one design with one or more rows (joint vectors); each row is judged on its own, and the
rows of a case go into one batch together.

Classes (the construction in brackets; "IK" = imagespace's public ``inverse_kinematics`` of a
random pose, allowed as input generation: the truth comes from msolve):

``generic``          [IK] leg ``i % 21`` of the 21 (type, actuated) combinations and two random legs
                     (at most one PP dyad), float joint values.
``rational_angle``   [IK] an angle-actuated leg whose value is an exact rational (``"p/q"``, handed to
                     the certified per-call path as a sympy Rational; the float paths get its double).
``exact_pose``       [exact] the three legs built through a Pythagorean pose (:mod:`construct`):
                     exact angles ``atan2(s, c)`` and dyadic slider values, and the same as doubles.
``half_turn``        modes exactly at ``phi = pi`` [exact], at ``pi -+ 1.5e-8`` and ``pi -+ 1.8e-12``
                     [exact Pythagorean orientations next to (-1, 0)], at ``phi = fl(pi)``,
                     ``pi - 1e-8``, ``-pi + 1e-8`` [IK], and a double root at the half-turn [exact].
``irrational_fixed`` [IK] a PPR or RPP leg (any joint actuated) with ``angle = +-acos(r)``, ``1 - r^2``
                     not a square (an irrational sine).
``double_root``      [exact] three wrench lines through one point (or parallel, with a PP dyad): the
                     pose is a multiple solution, confirmed by msolve (``degree > distinct``).
``near_fold``        a double-root design, one joint moved by ``1e-3 ... 1e-12`` and by 1, 2 ulps
                     (two modes ``~sqrt(dist)`` apart on one side, none on the other).
``continuum``        congruent RR dyads (a circular translation), the classic congruent 3-RPR, two
                     PP dyads fixing the same orientation (exact: positive-dimensional, a real
                     witness), and near-continua (one joint moved by ``1e-9`` or an ulp), similar
                     3-RPR (base = 2 x platform) [IK].
``cramer``           parallel lines: collinear 3-RPR [IK], two PR dyads with parallel fixed lines,
                     two RP dyads with parallel platform lines, a PR and an RP line parallel at the
                     pose (the Cramer denominator zero identically or at a root) [exact].
``scaled``           a case of ``generic``/``exact_pose``/``half_turn``/``double_root`` in design units
                     scaled by ``2^k``, ``|k| <= 20`` (1e-6 ... 1e6): every length, point and slider value.
``extreme_q``        huge slider values (``2^27, 2^50, 2^997`` times the design's size), slider values
                     0, ``2^-60``, ``2^-1000`` at an exact mode, huge angles (``2e10 pi + a`` exact, and
                     the doubles ``fl(a + 2e10 pi)``, ``fl(a + 2^41 pi)``), angles 0, ``5e-324``, ``1e-300``.

The issue's three reproductions are the fixed class ``regression`` (:mod:`regressions`).
"""

from __future__ import annotations

import math
import warnings
from fractions import Fraction

import mpmath
import numpy as np

from . import construct as cs
from .construct import Incompatible, Mode, Pose, design_through, dyadic, is_pp, unit, unit_not_axis
from .spec import (ALL_COMBOS, ANGLE_COMBOS, PP_COMBOS, PRISMATIC_COMBOS, atan2_entry, build_design,
                   check_roundtrip, design_size, enc, float_row, leg_is_angle, mp_angle, scale_case)

NON_PP = [c for c in ALL_COMBOS if c not in PP_COMBOS]
PRISMATIC_NON_PP = [c for c in PRISMATIC_COMBOS if c not in PP_COMBOS]
ANGLE_NON_PP = [c for c in ANGLE_COMBOS if c not in PP_COMBOS]


# --------------------------------------------------------------------------- random designs (IK)

def _p(v):
    return [enc(v[0]), enc(v[1])]


def random_leg(rng, kind, act):
    """A leg spec with random rational geometry (dyadic points and lengths, Pythagorean directions
    and slider angles)."""
    pt = lambda r: _p(cs.point(rng, r))
    ln = lambda: enc(dyadic(rng, 2, 6, nonzero=True))
    s = {"type": kind, "actuated": int(act)}
    if kind == "RPR":
        s.update(base=pt(6), platform=pt(3))
    elif kind == "RRR":
        s.update(base=pt(6), platform=pt(3), lengths=[ln(), ln()])
    elif kind == "PRR":
        s.update(base=pt(6), axis=_p(unit(rng)), platform=pt(3), length=ln())
    elif kind == "RRP":
        s.update(base=pt(6), length=ln(), platform=pt(3), direction=_p(unit(rng)))
    elif kind == "RPP":
        s.update(base=pt(6), platform=pt(3), direction=_p(unit(rng)), angle=atan2_entry(*unit_not_axis(rng)))
    elif kind == "PRP":
        s.update(base=pt(6), axis=_p(unit(rng)), platform=pt(3), direction=_p(unit(rng)))
    elif kind == "PPR":
        s.update(base=pt(6), axis=_p(unit(rng)), platform=pt(3), angle=atan2_entry(*unit_not_axis(rng)))
    return s


def random_combos(rng, first, n_pp_max=1, pool=ALL_COMBOS):
    combos = [tuple(first)]
    while len(combos) < 3:
        c = pool[int(rng.integers(len(pool)))]
        if is_pp(c) and sum(is_pp(x) for x in combos) >= n_pp_max:
            continue
        combos.append(c)
    order = [int(i) for i in rng.permutation(3)]
    return [combos[i] for i in order]


def ik_rows(rng, legs, n, phis=None, tries=60):
    """``n`` float rows from imagespace's inverse kinematics of random poses (input generation)."""
    import imagespace as isp

    m = build_design(legs)
    rows = []
    for t in range(tries):
        if len(rows) == n:
            break
        phi = float(phis[len(rows) % len(phis)]) if phis is not None else float(rng.uniform(-np.pi, np.pi))
        pose = np.array([rng.uniform(-2, 2), rng.uniform(-2, 2), phi])
        wm = [int(rng.integers(leg.n_branches)) for leg in m.legs]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                q = m.inverse_kinematics(pose, working_modes=wm)
                m.check_q(q)
            except (isp.ImageSpaceError, ValueError):
                continue
        rows.append({"q": [float(v).hex() for v in q], "note": f"IK of pose {pose.tolist()}"})
    return rows


def ik_case(rng, first, n=2, phis=None, legs=None, n_pp_max=1):
    for _ in range(30):
        if legs is None:
            specs = [random_leg(rng, k, a) for k, a in random_combos(rng, first, n_pp_max)]
        else:
            specs = legs
        try:
            rows = ik_rows(rng, specs, n, phis)
        except Exception:                   # a degenerate random design: draw another
            rows = []
        if rows:
            return specs, rows
        legs = None
    return None, None


# --------------------------------------------------------------------------- exact designs

def exact_rows(legs, q, note):
    """The exact row and its float twin (when they differ)."""
    rows = [{"q": list(q), "note": note + " (exact)"}]
    fq = float_row(legs, q)
    if fq != list(q):
        rows.append({"q": fq, "note": note + " (doubles)"})
    return rows


def _through(rng, pose, combos, modes, tries=20, **kw):
    for _ in range(tries):
        try:
            return design_through(rng, pose, combos, modes, **kw)
        except Incompatible:
            continue
    return None, None


def _multiple(legs, q):
    """msolve: the exact system has a multiple solution (degree > distinct); None if not decided."""
    from msolve_ref import POSITIVE_DIMENSIONAL, VARIABLES, solution_degrees

    from .truth import system

    polys, _, exact, _, _ = system(legs, q)
    if not exact:
        return None
    deg = solution_degrees(polys, VARIABLES)
    if deg == POSITIVE_DIMENSIONAL:
        return None
    return deg[0] > deg[1]


def double_root_design(rng, pose, combos=None, pool=NON_PP, allow_pp=True, tries=40):
    """``(legs, q, how)``: three legs through ``pose`` whose wrench lines meet (or are parallel):
    a multiple solution, confirmed by msolve."""
    for _ in range(tries):
        cmb = list(combos) if combos is not None else [pool[int(rng.integers(len(pool)))] for _ in range(3)]
        if allow_pp and combos is None and rng.integers(4) == 0:
            cmb[int(rng.integers(3))] = sorted(PP_COMBOS)[int(rng.integers(3))]
        if any(is_pp(c) for c in cmb) or rng.integers(3) == 0:
            mode, how = Mode("dir", D=unit(rng)), "parallel wrench lines"
        else:
            mode, how = Mode("point", O=cs.point(rng, 2)), "concurrent wrench lines"
        legs, q = _through(rng, pose, cmb, [mode] * 3)
        if legs is None:
            continue
        if _multiple(legs, q):
            return legs, q, how
    return None, None, None


def _with(q, j, e):
    q = list(q)
    q[j] = e
    return q


def _fl(x):
    return float(x).hex()


def _offsets(f0, deltas, ulps):
    """Doubles next to ``f0``: ``f0 +- delta`` and ``+- k`` ulps."""
    out = []
    for d in deltas:
        out += [(f"{d:+.0e}", float(f0 + d))]
    for k in ulps:
        v = f0
        for _ in range(abs(k)):
            v = float(np.nextafter(v, np.inf if k > 0 else -np.inf))
        out.append((f"{k:+d} ulp", v))
    return out


# --------------------------------------------------------------------------- the classes

def make_generic(rng, i):
    legs, rows = ik_case(rng, ALL_COMBOS[i % 21], n=2)
    return legs and {"legs": legs, "rows": rows, "note": f"leg {ALL_COMBOS[i % 21]}"}


def make_rational_angle(rng, i):
    first = ANGLE_COMBOS[i % len(ANGLE_COMBOS)]
    legs, rows = ik_case(rng, first, n=2)
    if legs is None:
        return None
    for r in rows:
        for j, s in enumerate(legs):
            if leg_is_angle(s) and (tuple((s["type"], s["actuated"])) == first or rng.integers(2)):
                v = Fraction(float.fromhex(r["q"][j])).limit_denominator(int(rng.integers(7, 1000)))
                r["q"][j] = enc(v)
        r["note"] += ", angles as exact rationals"
    return {"legs": legs, "rows": rows, "note": f"leg {first}"}


def make_exact_pose(rng, i):
    first = ALL_COMBOS[i % 21]
    pose = cs.random_pose(rng)
    legs, q = _through(rng, pose, random_combos(rng, first), [Mode("free")] * 3)
    return legs and {"legs": legs, "rows": exact_rows(legs, q, "constructed mode"), "witness": pose.witness(),
                     "note": f"leg {first}"}


def make_half_turn(rng, i):
    v = i % 5
    if v == 0:                                       # exactly at pi
        pose = cs.random_pose(rng, (-1, 0))
        legs, q = _through(rng, pose, random_combos(rng, ALL_COMBOS[i % 21]), [Mode("free")] * 3)
        return legs and {"legs": legs, "rows": exact_rows(legs, q, "mode at phi = pi"), "note": "phi = pi exactly"}
    if v == 1:                                       # exact, within 1.5e-8 or 1.8e-12 of pi
        t = Fraction(1, 2 ** (27 if rng.integers(2) else 40))
        sign = 1 if rng.integers(2) else -1
        pose = cs.random_pose(rng, cs.pose_cs_near_pi(t, sign))
        legs, q = _through(rng, pose, random_combos(rng, ALL_COMBOS[i % 21]), [Mode("free")] * 3)
        phi = math.pi - sign * 2 * float(t)
        return legs and {"legs": legs, "rows": exact_rows(legs, q, f"mode at phi = pi - {sign * 2 * float(t):.3g}"),
                         "note": f"phi = {phi!r} (exact Pythagorean)"}
    if v == 2 or v == 3:                             # IK at fl(pi), pi - 1e-8, -pi + 1e-8
        phis = [math.pi, math.pi - 1e-8, -math.pi + 1e-8] if v == 2 else [math.pi - 1e-8, math.pi - 2e-16 * 7]
        first = ANGLE_COMBOS[i % len(ANGLE_COMBOS)] if rng.integers(2) else ALL_COMBOS[i % 21]
        legs, rows = ik_case(rng, first, n=len(phis), phis=phis)
        return legs and {"legs": legs, "rows": rows, "note": f"IK at phi near pi, leg {first}"}
    pose = cs.random_pose(rng, (-1, 0))              # a double root at the half-turn
    legs, q, how = double_root_design(rng, pose)
    return legs and {"legs": legs, "rows": exact_rows(legs, q, f"double root at phi = pi ({how})"),
                     "note": "double root at phi = pi"}


def make_irrational_fixed(rng, i):
    kind = ("PPR", "RPP")[i % 2]
    act = (i // 2) % 3
    while True:
        r = Fraction(int(rng.integers(-9, 10)), int(rng.integers(2, 11)))
        if abs(r) < 1:
            from .truth import _is_square

            if _is_square(1 - r * r) is None:
                break
    sign = 1 if rng.integers(2) else -1
    for _ in range(10):
        legs = [random_leg(rng, k, a) for k, a in random_combos(rng, (kind, act))]
        for s in legs:
            if s["type"] == kind and s["actuated"] == act:
                s["angle"] = {"acos": enc(r), "sign": sign}
                break
        legs_, rows = ik_case(rng, (kind, act), n=2, legs=legs)
        if legs_ is not None:
            return {"legs": legs_, "rows": rows, "note": f"{kind}{act} angle {'-' if sign < 0 else ''}acos({r})"}
    return None


def make_double_root(rng, i):
    pose = cs.random_pose(rng, (-1, 0) if rng.integers(4) == 0 else None)
    legs, q, how = double_root_design(rng, pose)
    return legs and {"legs": legs, "rows": exact_rows(legs, q, f"double root ({how})"), "witness": pose.witness(),
                     "note": how}


def make_near_fold(rng, i, rows_per_side=None):
    """A double-root design, one leg's joint moved off the fold (the other legs sliders, so that
    their doubles are exact)."""
    angle = i % 2 == 1
    for _ in range(10):
        pose = cs.random_pose(rng, (-1, 0) if rng.integers(5) == 0 else None)
        pool_j = ANGLE_NON_PP if angle else PRISMATIC_NON_PP
        cmb = [pool_j[int(rng.integers(len(pool_j)))]] + \
              [PRISMATIC_NON_PP[int(rng.integers(len(PRISMATIC_NON_PP)))] for _ in range(2)]
        legs, q, how = double_root_design(rng, pose, combos=cmb, allow_pp=False)
        if legs is not None:
            break
    else:
        return None
    j = 0
    rows = [{"q": list(q), "note": f"the double root ({how})"}]
    fq = float_row(legs, q)
    if angle:
        f0 = float.fromhex(fq[j])
        exact_angle = mp_angle(q[j])
        offs = [(lab, v) for lab, v in _offsets(f0, (), (-2, -1, 1, 2))] + [("nearest", f0)]
        with mpmath.workprec(300):
            for d in (1e-3, 1e-6, 1e-9, 1e-12):
                for sg in (1, -1):
                    offs.append((f"{sg * d:+.0e}", float(exact_angle + sg * mpmath.mpf(d))))
    else:
        f0 = float.fromhex(fq[j])
        offs = [(lab, v) for lab, v in _offsets(f0, (1e-3, -1e-3, 1e-6, -1e-6, 1e-9, -1e-9, 1e-12, -1e-12),
                                                (-2, -1, 1, 2))]
        if legs[j]["type"] == "RPR" and legs[j]["actuated"] == 1:
            offs = [(lab, v) for lab, v in offs if v >= 0]
    if rows_per_side is not None:
        pick = sorted(rng.choice(len(offs), size=min(rows_per_side, len(offs)), replace=False).tolist())
        offs = [offs[k] for k in pick]
    for lab, v in offs:
        rows.append({"q": _with(fq, j, _fl(v)), "note": f"leg 0 at the fold {lab}"})
    return {"legs": legs, "rows": rows, "note": f"near fold, leg {legs[0]['type']}{legs[0]['actuated']}"}


def make_continuum(rng, i):
    v = i % 4
    if v == 0:                                       # congruent RR dyads: a circular translation
        pose = cs.random_pose(rng)
        D = unit(rng)
        rho = dyadic(rng, 1, 3, nonzero=True)
        cmb = [cs.RR_COMBOS[int(rng.integers(len(cs.RR_COMBOS)))] for _ in range(3)]
        legs, q = _through(rng, pose, cmb, [Mode("dir", D=D)] * 3, radius=[rho] * 3)
        if legs is None:
            return None
        rows = exact_rows(legs, q, "congruent RR dyads (circular translation)")
        rows += _near_rows(rng, legs, q, "near the circular translation")
        return {"legs": legs, "rows": rows, "witness": pose.witness(), "note": f"congruent RR {cmb}"}
    if v == 1:                                       # two PP dyads, the same orientation
        pose = cs.random_pose(rng)
        pps = sorted(PP_COMBOS)
        cmb = [pps[int(rng.integers(3))], pps[int(rng.integers(3))], NON_PP[int(rng.integers(len(NON_PP)))]]
        legs, q = _through(rng, pose, cmb, [Mode("free")] * 3)
        if legs is None:
            return None
        rows = exact_rows(legs, q, "two PP dyads fix the same orientation")
        fq = float_row(legs, q)
        for k in (1, -1):
            rows.append({"q": _with(fq, 0, _fl(np.nextafter(float.fromhex(fq[0]), k * np.inf))),
                         "note": f"the PP orientations 1 ulp apart ({k:+d})"})
        return {"legs": legs, "rows": rows, "witness": pose.witness(), "note": f"two PP {cmb}"}
    if v == 2:                                       # the classic congruent 3-RPR
        tri = [cs.point(rng, 3) for _ in range(3)]
        legs = [{"type": "RPR", "actuated": 1, "base": _p(A), "platform": _p(A)} for A in tri]
        rho = dyadic(rng, 1, 3, nonzero=True)
        r = float(rho)
        rows = [{"q": [_fl(r)] * 3, "note": "congruent 3-RPR, equal lengths (continuum)"},
                {"q": [_fl(r), _fl(r), _fl(r + 1e-9)], "note": "congruent 3-RPR, one length + 1e-9"},
                {"q": [_fl(r), _fl(r), _fl(np.nextafter(r, np.inf))], "note": "congruent 3-RPR, one length + 1 ulp"}]
        _, more = ik_case(rng, ("RPR", 1), n=1, legs=legs)
        rows += more or []
        return {"legs": legs, "rows": rows, "witness": [enc(rho), "0", "1", "0"], "note": "congruent 3-RPR"}
    # similar, not congruent: base = 2 x platform (turned); IK rows and equal lengths
    rot = unit(rng)
    plat = [cs.point(rng, 2) for _ in range(3)]
    legs = [{"type": "RPR", "actuated": 1, "base": _p(cs.mul(rot, (2 * a[0], 2 * a[1]))), "platform": _p(a)}
            for a in plat]
    _, rows = ik_case(rng, ("RPR", 1), n=2, legs=legs)
    r = float(dyadic(rng, 1, 4, nonzero=True))
    rows = (rows or []) + [{"q": [_fl(r)] * 3, "note": "similar 3-RPR, equal lengths"}]
    return {"legs": legs, "rows": rows, "note": "similar 3-RPR (base = 2 x platform)"}


def _near_rows(rng, legs, q, note):
    """Rows with one slider value moved by 1e-9 and by 1 ulp (none if every joint is an angle)."""
    fq = float_row(legs, q)
    js = [j for j, s in enumerate(legs) if not leg_is_angle(s)]
    if not js:
        return []
    j = js[int(rng.integers(len(js)))]
    f0 = float.fromhex(fq[j])
    return [{"q": _with(fq, j, _fl(f0 + 1e-9)), "note": f"{note}: leg {j} + 1e-9"},
            {"q": _with(fq, j, _fl(np.nextafter(f0, np.inf))), "note": f"{note}: leg {j} + 1 ulp"}]


PR_LINE = [("RPR", 0), ("PRR", 1), ("PRR", 2), ("PRP", 2), ("PPR", 0), ("PPR", 1)]
RP_LINE = [("RPR", 2), ("RRP", 0), ("RRP", 1), ("RPP", 1), ("RPP", 2), ("PRP", 0)]


def make_cramer(rng, i):
    v = i % 4
    if v == 0:                                       # collinear 3-RPR
        B, e, b, f = cs.point(rng, 4), unit(rng), cs.point(rng, 1), unit(rng)
        ts = rng.choice(np.arange(-24, 25), size=3, replace=False) / 4
        ss = rng.choice(np.arange(-12, 13), size=3, replace=False) / 4
        legs = [{"type": "RPR", "actuated": 1, "base": _p(cs.add(B, e, Fraction(t))),
                 "platform": _p(cs.add(b, f, Fraction(s)))} for t, s in zip(ts, ss)]
        _, rows = ik_case(rng, ("RPR", 1), n=2, legs=legs)
        return rows and {"legs": legs, "rows": rows, "note": "collinear 3-RPR"}
    pools = {1: (PR_LINE, PR_LINE, "two PR dyads, parallel fixed lines"),
             2: (RP_LINE, RP_LINE, "two RP dyads, parallel platform lines"),
             3: (PR_LINE, RP_LINE, "a PR and an RP line parallel at the pose")}[v]
    pose = cs.random_pose(rng, (-1, 0) if rng.integers(4) == 0 else None)
    D = unit(rng)
    cmb = [pools[0][int(rng.integers(6))], pools[1][int(rng.integers(6))], NON_PP[int(rng.integers(len(NON_PP)))]]
    legs, q = _through(rng, pose, cmb, [Mode("dir", D=D), Mode("dir", D=D), Mode("free")])
    return legs and {"legs": legs, "rows": exact_rows(legs, q, pools[2]), "witness": pose.witness(),
                     "note": f"{pools[2]}: {cmb}"}


def make_scaled(rng, i):
    base_cls = ("generic", "exact_pose", "half_turn", "double_root")[i % 4]
    base = MAKERS[base_cls](rng, int(rng.integers(100)))
    if not base:
        return None
    k = int(rng.choice([-20, -19, -17, -13, -10, -7, 7, 10, 13, 17, 19, 20]))
    out = scale_case(base, k)
    out["note"] = f"{base_cls} case scaled by 2^{k} ({base.get('note', '')})"
    return out


def make_extreme_q(rng, i):
    v = i % 4
    if v == 0:                                       # huge slider values
        first = PRISMATIC_COMBOS[i % len(PRISMATIC_COMBOS)]
        legs, rows = ik_case(rng, first, n=1)
        if legs is None:
            return None
        js = [j for j, s in enumerate(legs) if not leg_is_angle(s)]
        j = js[0]
        size = design_size(legs)
        base = rows[0]["q"]
        rows = [rows[0]]
        for e in (27, 50, 997):
            sg = 1 if (legs[j]["type"], legs[j]["actuated"]) == ("RPR", 1) or rng.integers(2) else -1
            rows.append({"q": _with(base, j, _fl(sg * math.ldexp(size, e))), "note": f"leg {j} at {sg:+d} 2^{e} x size"})
        return {"legs": legs, "rows": rows, "note": f"huge slider value, leg {legs[j]['type']}{legs[j]['actuated']}"}
    if v == 1:                                       # slider values 0 and tiny at an exact mode
        pose = cs.random_pose(rng)
        first = PRISMATIC_NON_PP[i % len(PRISMATIC_NON_PP)]
        cmb = random_combos(rng, first)
        j = cmb.index(first)
        qv = [None] * 3
        qv[j] = Fraction(0)
        legs, q = _through(rng, pose, cmb, [Mode("free")] * 3, qval=qv)
        if legs is None:
            return None
        rows = exact_rows(legs, q, f"leg {j} slider at 0")
        fq = float_row(legs, q)
        for t in (2.0 ** -60, 2.0 ** -1000, -2.0 ** -1000):
            if t < 0 and first == ("RPR", 1):
                continue
            rows.append({"q": _with(fq, j, _fl(t)), "note": f"leg {j} slider at {t:.3g}"})
        return {"legs": legs, "rows": rows, "witness": pose.witness(), "note": f"tiny slider values, leg {first}"}
    if v == 2:                                       # huge angles
        pose = cs.random_pose(rng)
        first = ANGLE_COMBOS[i % len(ANGLE_COMBOS)]
        cmb = random_combos(rng, first)
        j = cmb.index(first)
        legs, q = _through(rng, pose, cmb, [Mode("free")] * 3)
        if legs is None:
            return None
        k = 10 ** 10
        rows = [{"q": _with(q, j, {"pi": 2 * k, "plus": q[j]}), "note": f"leg {j} angle + 2e10 pi (exact)"}]
        fq = float_row(legs, q)
        a = mp_angle(q[j])
        with mpmath.workprec(400):
            for kk, lab in ((k, "2e10 pi"), (2 ** 40, "2^41 pi")):
                rows.append({"q": _with(fq, j, _fl(a + 2 * kk * mpmath.pi)), "note": f"leg {j} at fl(angle + {lab})"})
        return {"legs": legs, "rows": rows, "note": f"huge angles, leg {first}"}
    pose = cs.random_pose(rng)                       # angles 0 and tiny
    targ = sorted(cs.TARGETABLE)
    first = targ[i % len(targ)]
    cmb = random_combos(rng, first)
    j = cmb.index(first)
    tg = [None] * 3
    tg[j] = (Fraction(1), Fraction(0))
    legs, q = _through(rng, pose, cmb, [Mode("free")] * 3, target=tg)
    if legs is None:
        return None
    rows = exact_rows(legs, q, f"leg {j} angle 0")
    fq = float_row(legs, q)
    for t in (5e-324, -1e-300, 2.0 ** -60):
        rows.append({"q": _with(fq, j, _fl(t)), "note": f"leg {j} angle {t:.3g}"})
    return {"legs": legs, "rows": rows, "witness": pose.witness(), "note": f"tiny angles, leg {first}"}


MAKERS = {
    "generic": make_generic,
    "rational_angle": make_rational_angle,
    "exact_pose": make_exact_pose,
    "half_turn": make_half_turn,
    "irrational_fixed": make_irrational_fixed,
    "double_root": make_double_root,
    "near_fold": make_near_fold,
    "continuum": make_continuum,
    "cramer": make_cramer,
    "scaled": make_scaled,
    "extreme_q": make_extreme_q,
}
CLASSES = list(MAKERS)
CLASS_INDEX = {c: k for k, c in enumerate(CLASSES)}

#: cases per class in the fast lane (a fresh seed each run) and in the slow lane (fixed seeds)
FAST = {"generic": 7, "rational_angle": 3, "exact_pose": 7, "half_turn": 5, "irrational_fixed": 3,
        "double_root": 4, "near_fold": 2, "continuum": 4, "cramer": 4, "scaled": 4, "extreme_q": 4}
SLOW = {"generic": 42, "rational_angle": 12, "exact_pose": 42, "half_turn": 30, "irrational_fixed": 12,
        "double_root": 24, "near_fold": 12, "continuum": 16, "cramer": 16, "scaled": 24, "extreme_q": 16}
#: rows of a near-fold case kept in the fast lane (of up to 16)
FAST_FOLD_ROWS = 6


def make_case(seed, cls, i, fast=False):
    """Case ``i`` of class ``cls`` at ``seed`` (None when the class could not build one)."""
    rng = np.random.default_rng([int(seed), CLASS_INDEX[cls], int(i)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if cls == "near_fold":
            case = make_near_fold(rng, i, rows_per_side=FAST_FOLD_ROWS if fast else None)
        else:
            case = MAKERS[cls](rng, i)
    if not case:
        return None
    case = dict(case, **{"class": cls, "label": f"{cls}-{i}", "seed": int(seed), "index": int(i)})
    return check_roundtrip(case)


def generate(seed, sizes=None, classes=None, fast=False):
    """Cases of every class (``sizes``: cases per class, default :data:`FAST` or :data:`SLOW`)."""
    sizes = dict(sizes or (FAST if fast else SLOW))
    out = []
    for cls in classes or CLASSES:
        for i in range(int(sizes.get(cls, 0))):
            c = make_case(seed, cls, i, fast=fast)
            if c is not None:
                out.append(c)
    return out
