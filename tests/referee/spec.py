"""The JSON form of a referee case, and the design it stands for.

A case is a dict that ``json.dumps`` writes and ``json.loads`` reads back unchanged, so that a
failure is replayed exactly (``python -m tests.referee --replay case.json``)::

    {"class": "half_turn", "label": "half_turn-0", "seed": 7, "note": "...",
     "legs": [{"type": "RRR", "actuated": 0, "base": ["3/2", "-5/8"], "platform": [...],
               "lengths": ["35/8", "19/8"]}, ...],
     "rows": [{"q": ["0x1.8p+0", "-7/4", {"atan2": ["4/5", "-3/5"]}], "note": "..."}, ...],
     "witness": ["1/2", "0", "-1", "0"]}          # optional: a real point (x, y, c, s) of a continuum

Numbers are text: a rational ``"p/q"`` (or ``"p"``), a double as ``float.hex`` (``"0x1.8p+0"``, the
exact binary rational it stores). An angle (an actuated revolute joint value in ``q``, the fixed
``angle`` of an RPP or PPR leg) is a number (radians) or one of

* ``{"atan2": [s, c]}``: the exact angle with rational cosine ``c`` and sine ``s`` (``c^2 + s^2 =
  1``), handed to imagespace as ``sympy.atan2(s, c)``;
* ``{"acos": r, "sign": 1 or -1}``: ``sign * acos(r)``, ``r`` rational (an irrational sine when
  ``1 - r^2`` is not a square);
* ``{"pi": k, "plus": angle}``: ``k * pi + angle`` (an exact angle many turns out).

Directions (``axis``, ``direction``) are rational unit vectors here, so that the leg keeps them as
given (imagespace normalises other vectors with square roots, which the referee would round).

This module builds the imagespace design of a case from the legs' public constructors only (that is
what is under test); the referee's own reading of a case is in :mod:`truth`.
"""

from __future__ import annotations

import json
import math
from fractions import Fraction

import mpmath
import numpy as np
import sympy as sp

LEG_FIELDS = {
    "RPR": ("base", "platform"),
    "RRR": ("base", "platform", "lengths"),
    "PRR": ("base", "axis", "platform", "length"),
    "RRP": ("base", "length", "platform", "direction"),
    "RPP": ("base", "platform", "direction", "angle"),
    "PRP": ("base", "axis", "platform", "direction"),
    "PPR": ("base", "axis", "platform", "angle"),
}
#: geometry fields that carry a length (scaled with the design); axis, direction, angle do not
LENGTH_FIELDS = ("base", "platform", "lengths", "length")
#: every (type, actuated) combination, and those whose actuated joint is an angle
ALL_COMBOS = [(k, a) for k in ("RPR", "RRR", "PRR", "RRP", "RPP", "PRP", "PPR") for a in range(3)]
ANGLE_COMBOS = [(k, a) for k, a in ALL_COMBOS if k[a] == "R"]
PRISMATIC_COMBOS = [(k, a) for k, a in ALL_COMBOS if k[a] == "P"]
#: the combinations whose locked dyad is PP (the orientation fixed)
PP_COMBOS = {("RPP", 0), ("PRP", 1), ("PPR", 2)}


# --------------------------------------------------------------------------- numbers

def enc(v):
    """A number as text: floats as ``float.hex``, everything else as an exact rational ``p/q``."""
    if isinstance(v, (float, np.floating)):
        return float(v).hex()
    if isinstance(v, sp.Basic):
        v = Fraction(int(v.p), int(v.q)) if v.is_Rational else None
        if v is None:
            raise TypeError("only rational sympy numbers are encoded as numbers")
    v = Fraction(v)
    return str(v.numerator) if v.denominator == 1 else f"{v.numerator}/{v.denominator}"


def is_float_text(t):
    return isinstance(t, str) and "0x" in t.lower() or t in ("inf", "-inf", "nan")


def dec(t):
    """Text -> Fraction (rational) or float (a hex double)."""
    if isinstance(t, (int, Fraction)):
        return Fraction(t)
    if is_float_text(t):
        return float.fromhex(t)
    return Fraction(t)


def frac(t):
    """The exact rational of a number text (a double as its binary rational)."""
    v = dec(t)
    return Fraction(v) if isinstance(v, float) else v


def to_sympy_number(t):
    """What imagespace is handed for a number: a Python float for a hex double (imagespace takes
    it as its exact binary rational), a sympy Rational for a rational."""
    v = dec(t)
    return v if isinstance(v, float) else sp.Rational(v.numerator, v.denominator)


# --------------------------------------------------------------------------- angles

def atan2_entry(c, s):
    """The exact angle entry of a rational point ``(c, s)`` on the unit circle."""
    c, s = Fraction(c), Fraction(s)
    if c * c + s * s != 1:
        raise ValueError(f"({c}, {s}) is not on the unit circle")
    return {"atan2": [enc(s), enc(c)]}


def sympy_angle(e):
    """The angle entry as imagespace is handed it (a float or an exact sympy expression)."""
    if isinstance(e, str):
        return to_sympy_number(e)
    if "atan2" in e:
        s, c = (sp.Rational(str(frac(v))) for v in e["atan2"])
        return sp.atan2(s, c)
    if "acos" in e:
        a = sp.acos(sp.Rational(str(frac(e["acos"]))))
        return a if int(e.get("sign", 1)) >= 0 else -a
    if "pi" in e:
        plus = sympy_angle(e["plus"])
        if isinstance(plus, float):
            raise ValueError("{'pi': k, 'plus': ...} needs an exact 'plus'")
        return sp.Integer(int(e["pi"])) * sp.pi + plus
    raise ValueError(f"unknown angle entry {e!r}")


def mp_angle(e, prec=400):
    """The exact angle (mpmath at ``prec`` bits; without its multiple of 2 pi for ``pi`` entries)."""
    with mpmath.workprec(prec):
        if isinstance(e, str):
            f = frac(e)
            return mpmath.mpf(f.numerator) / f.denominator
        if "atan2" in e:
            s, c = (frac(v) for v in e["atan2"])
            return mpmath.atan2(mpmath.mpf(s.numerator) / s.denominator, mpmath.mpf(c.numerator) / c.denominator)
        if "acos" in e:
            r = frac(e["acos"])
            a = mpmath.acos(mpmath.mpf(r.numerator) / r.denominator)
            return a if int(e.get("sign", 1)) >= 0 else -a
        if "pi" in e:
            k = int(e["pi"]) % 2
            v = mp_angle(e["plus"], prec) + k * mpmath.pi
            return v - 2 * mpmath.pi if v > mpmath.pi else v
    raise ValueError(f"unknown angle entry {e!r}")


def float_angle(e):
    """The double a float path is handed for an angle entry: the entry itself for a double, the
    nearest double otherwise (of the remainder mod 2 pi for a ``pi`` entry, as imagespace's
    ``check_q`` does for an exact angle beyond a half-turn)."""
    if isinstance(e, str):
        v = dec(e)
        return v if isinstance(v, float) else float(v)
    return float(mp_angle(e))


# --------------------------------------------------------------------------- legs and designs

def leg_is_angle(spec):
    return spec["type"][spec["actuated"]] == "R"


def build_leg(spec):
    """The imagespace leg of a spec (public constructor)."""
    import imagespace as isp

    kind, act = spec["type"], int(spec["actuated"])
    kw = {}
    for f in LEG_FIELDS[kind]:
        v = spec[f]
        if f == "angle":
            kw[f] = sympy_angle(v)
        elif isinstance(v, list):
            kw[f] = tuple(to_sympy_number(t) for t in v)
        else:
            kw[f] = to_sympy_number(v)
    return getattr(isp, kind)(actuated=act, **kw)


def build_design(legs):
    import imagespace as isp

    return isp.PlanarParallel([build_leg(s) for s in legs])


def design_size(legs):
    """The design's size: the largest coordinate or length of its geometry (not its directions)."""
    out = 0.0
    for s in legs:
        for f in LENGTH_FIELDS:
            if f in s:
                vals = s[f] if isinstance(s[f], list) else [s[f]]
                out = max(out, max(abs(float(frac(t))) for t in vals))
    return out if out > 0 else 1.0


def q_exact(legs, q):
    """The row as the certified per-call path is handed it: floats, sympy rationals and angles."""
    out = []
    for s, e in zip(legs, q):
        out.append(sympy_angle(e) if leg_is_angle(s) else to_sympy_number(e))
    return out


def q_float(legs, q):
    """The row as a float path (and every batch) is handed it: ``(3,)`` float."""
    out = []
    for s, e in zip(legs, q):
        out.append(float_angle(e) if leg_is_angle(s) else float(dec(e)))
    return np.array(out, dtype=float)


def row_is_float(q):
    """True when every entry of the row is a double (the per-call and batch inputs are the same)."""
    return all(isinstance(e, str) and is_float_text(e) for e in q)


def float_row(legs, q):
    """The row's float form as entries (hex), for the truth of the float paths."""
    return [v.hex() for v in q_float(legs, q).tolist()]


# --------------------------------------------------------------------------- JSON

def dumps(case):
    return json.dumps(case, sort_keys=True)


def check_roundtrip(case):
    """The case survives ``json.dumps``/``json.loads`` unchanged (it is replayable exactly)."""
    back = json.loads(json.dumps(case))
    if back != case:
        raise AssertionError(f"case does not survive JSON: {case!r}")
    return back


def scale_case(case, k):
    """The same case in design units scaled by ``2**k``: every length and point of the geometry and
    every prismatic joint value times ``2**k`` (exact: doubles stay doubles), angles unchanged."""
    f = Fraction(2) ** k
    legs = []
    for s in case["legs"]:
        t = dict(s)
        for fld in LENGTH_FIELDS:
            if fld in t:
                t[fld] = [_scaled(v, f, k) for v in t[fld]] if isinstance(t[fld], list) else _scaled(t[fld], f, k)
        legs.append(t)
    rows = []
    for r in case["rows"]:
        q = [e if leg_is_angle(s) else _scaled(e, f, k) for s, e in zip(case["legs"], r["q"])]
        rows.append(dict(r, q=q))
    out = dict(case, legs=legs, rows=rows)
    if "witness" in case:
        w = case["witness"]
        out["witness"] = [_scaled(w[0], f, k), _scaled(w[1], f, k), w[2], w[3]]
    return out


def _scaled(t, f, k):
    v = dec(t)
    if isinstance(v, float):
        return math.ldexp(v, k).hex()
    return enc(v * f)
