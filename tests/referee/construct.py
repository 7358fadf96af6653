"""Exact designs through a chosen pose: half-turns, double roots, continua, parallel lines.

Every leg of every (type, actuated) combination is built *through* a given exact pose ``(x, y, c,
s)`` (rationals, ``c^2 + s^2 = 1``: a Pythagorean orientation, the half-turn ``(-1, 0)`` included)
with rational geometry and an exact actuated value: a dyadic rational (a double) for a slider, an
angle with rational cosine and sine (``{"atan2": ...}``) for a revolute. So the pose is an exact
assembly mode; a double root and a continuum are exact too, not merely near.

Each locked dyad has a *wrench line* at the pose (the line of the constraint force: RR -- through
the platform point and the circle's centre; PR -- through the point, normal to its line; RP --
through the fixed point, normal to the platform line; PP -- a pure moment, the line at infinity).
Three wrench lines through one point (or three parallel ones, or a PP dyad and two parallel lines)
make the Jacobian of the system singular at the pose: a multiple solution. A :class:`Mode` chooses
the wrench line of each leg: ``free`` (random), ``point`` (through ``O``), ``dir`` (parallel to
``D``). The constructions are checked here against :func:`msolve_ref.leg_constraint` (the pose
satisfies every constraint exactly), and a multiple root is confirmed by msolve
(:func:`msolve_ref.solution_degrees`) by the generator; nothing here trusts the geometry above.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from .spec import PP_COMBOS, atan2_entry, enc

F = Fraction


class Incompatible(Exception):
    """The leg cannot be built with the wrench line the mode asks for."""


# --------------------------------------------------------------------------- rational geometry

def mul(a, b):
    """Complex product: the angle of ``a`` plus the angle of ``b`` (both unit)."""
    return (a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0])


def div(a, b):
    """The angle of ``a`` minus the angle of ``b`` (``b`` unit)."""
    return (a[0] * b[0] + a[1] * b[1], a[1] * b[0] - a[0] * b[1])


def rot90(v):
    return (-v[1], v[0])


def add(a, b, t=1):
    return (a[0] + t * b[0], a[1] + t * b[1])


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def dyadic(rng, lo, hi, den=8, nonzero=False):
    while True:
        v = F(int(rng.integers(int(lo * den), int(hi * den) + 1)), den)
        if v or not nonzero:
            return v


def unit(rng):
    """A random rational unit vector (from a rational tangent of the half-angle, turned by k * 90 deg)."""
    t = F(int(rng.integers(-7, 8)), int(rng.integers(1, 8)))
    v = ((1 - t * t) / (1 + t * t), 2 * t / (1 + t * t))
    for _ in range(int(rng.integers(4))):
        v = rot90(v)
    return v


def unit_not_axis(rng):
    """A unit vector that is not ``(+-1, 0)`` (a slider angle must not be 0 or pi)."""
    while True:
        v = unit(rng)
        if v[1] != 0:
            return v


def point(rng, r=4):
    return (dyadic(rng, -r, r), dyadic(rng, -r, r))


def pose_cs_near_pi(t, sign=1):
    """The rational orientation ``(c, s)`` at ``phi = pi - sign * 2 atan(t)``."""
    t = F(t)
    d = 1 + t * t
    return (-(1 - t * t) / d, sign * 2 * t / d)


class Pose:
    """An exact pose: position ``(x, y)``, orientation ``(c, s)``."""

    def __init__(self, x, y, c, s):
        self.x, self.y, self.c, self.s = F(x), F(y), F(c), F(s)
        if self.c ** 2 + self.s ** 2 != 1:
            raise ValueError("(c, s) must be on the unit circle")

    @property
    def cs(self):
        return (self.c, self.s)

    def world(self, p):
        return (self.x + self.c * p[0] - self.s * p[1], self.y + self.s * p[0] + self.c * p[1])

    def local(self, P):
        dx, dy = P[0] - self.x, P[1] - self.y
        return (self.c * dx + self.s * dy, -self.s * dx + self.c * dy)

    def local_dir(self, h):
        return (self.c * h[0] + self.s * h[1], -self.s * h[0] + self.c * h[1])

    def witness(self):
        return [enc(self.x), enc(self.y), enc(self.c), enc(self.s)]


class Mode:
    """How a leg's wrench line is chosen: ``free``, ``point`` (through ``O``) or ``dir`` (along ``D``)."""

    def __init__(self, kind="free", O=None, D=None):
        self.kind, self.O, self.D = kind, O, D

    def line(self, rng, d=None):
        """``(W, d)``: a point ``W`` of the wrench line and its (unit) direction ``d``."""
        if self.kind == "dir":
            if d is not None and cross(d, self.D) != 0:
                raise Incompatible("the wrench direction is fixed by the leg and by the mode")
            return point(rng), (self.D if d is None else d)
        d = unit(rng) if d is None else d
        if self.kind == "point":
            return add(self.O, d, dyadic(rng, -3, 3, nonzero=True)), d
        return point(rng), d


HERON = [(3, 4, 5), (5, 5, 6), (5, 5, 8), (13, 14, 15), (10, 13, 13), (9, 10, 17), (7, 15, 20),
         (13, 20, 21), (11, 13, 20), (4, 13, 15), (10, 17, 21), (12, 17, 25)]


def _heron(rng, radius=None):
    """``(l1, l2, r, (cos t2, sin t2))``: a triangle with rational sides and a rational elbow."""
    while True:
        tri = list(HERON[int(rng.integers(len(HERON)))])
        rng.shuffle(tri)
        l1, l2, r = (F(v) for v in tri)
        c = (r * r - l1 * l1 - l2 * l2) / (2 * l1 * l2)
        s2 = 1 - c * c
        n, d = math.isqrt(s2.numerator), math.isqrt(s2.denominator)
        if n * n == s2.numerator and d * d == s2.denominator and abs(c) < 1:
            s = F(n, d) * (1 if rng.integers(2) else -1)
            k = (F(radius) / r) if radius is not None else F(int(rng.integers(1, 5)), 8)
            return l1 * k, l2 * k, r * k, (c, s)


# --------------------------------------------------------------------------- the legs

def _sign(rng, v):
    return v if rng.integers(2) else (-v[0], -v[1])


def _p(v):
    return [enc(v[0]), enc(v[1])]


def _qd(v):
    """A dyadic slider value as a double's hex (exact)."""
    f = float(v)
    if F(f) != v:
        raise ValueError(f"{v} is not a double")
    return f.hex()


def build_leg(kind, act, rng, pose, mode, target=None, qval=None, radius=None):
    """``(spec, q)``: a leg of the combination ``(kind, act)`` through ``pose``, its wrench line from
    ``mode``; ``q`` its actuated value at the pose (a double's hex for a slider, ``{"atan2": ...}``
    for an angle). ``target`` (a rational unit ``(c, s)``) asks for that actuated angle where the
    construction can give it; ``qval`` (dyadic) for that slider value; ``radius`` for the circle of
    an RR dyad.

    Raises
    ------
    Incompatible
        The mode fixes the wrench direction and the leg (or ``target``) another one.
    """
    dy = lambda lo=1, hi=4: dyadic(rng, lo, hi, nonzero=True)
    sl = lambda: F(qval) if qval is not None else dyadic(rng, -3, 3)
    rad = lambda: F(radius) if radius is not None else dy()
    ang = lambda cs: atan2_entry(*cs)
    spec = {"type": kind, "actuated": int(act)}
    P0 = pose.cs
    key = (kind, act)
    if key == ("RPR", 1):
        W, d = mode.line(rng)
        rho = F(qval) if qval is not None else rad()
        if rho < 0:
            raise Incompatible("rho must be >= 0")
        spec.update(base=_p(add(W, d, -rho)), platform=_p(pose.local(W)))
        return spec, _qd(rho)
    if key == ("RRR", 0):
        W, d = mode.line(rng)
        l2, l1 = rad(), dy()
        f = target or unit(rng)
        E = add(W, d, -l2)
        spec.update(base=_p(add(E, f, -l1)), platform=_p(pose.local(W)), lengths=[enc(l1), enc(l2)])
        return spec, ang(f)
    if key == ("RRR", 1):
        W, d = mode.line(rng)
        l1, l2, r, cs2 = _heron(rng, radius)
        # |P - A|^2 = l1^2 + l2^2 + 2 l1 l2 cos(theta2) = r^2: the elbow itself is not geometry
        spec.update(base=_p(add(W, d, -r)), platform=_p(pose.local(W)), lengths=[enc(l1), enc(l2)])
        return spec, ang(cs2)
    if key == ("RRR", 2):
        W, d = mode.line(rng)
        l1, l2 = rad(), dy()
        g = div(P0, target) if target else unit(rng)
        P = add(W, g, l2)
        spec.update(base=_p(add(W, d, -l1)), platform=_p(pose.local(P)), lengths=[enc(l1), enc(l2)])
        return spec, ang(div(P0, g))
    if key == ("PRR", 0):
        W, d = mode.line(rng)
        l, u, s = rad(), unit(rng), sl()
        S = add(W, d, -l)
        spec.update(base=_p(add(S, u, -s)), axis=_p(u), platform=_p(pose.local(W)), length=enc(l))
        return spec, _qd(s)
    if key == ("RRP", 2):
        W, d = mode.line(rng)
        l, v, s = rad(), unit(rng), sl()
        b = add(pose.local(W), v, -s)
        spec.update(base=_p(add(W, d, -l)), length=enc(l), platform=_p(b), direction=_p(v))
        return spec, _qd(s)
    # PR dyads: the platform point W on a fixed line of direction h = rot90(d)
    if key == ("RPR", 0):
        W, d = mode.line(rng, d=None if target is None else (target[1], -target[0]))
        h = rot90(d)
        spec.update(base=_p(add(W, h, -dy(-3, 3))), platform=_p(pose.local(W)))
        return spec, ang(h)
    if key == ("PRR", 1):
        W, d = mode.line(rng)
        u = _sign(rng, rot90(d))
        k = mul(target, u) if target else unit(rng)
        l = dy()
        S = add(W, k, -l)
        spec.update(base=_p(add(S, u, -dy(-3, 3))), axis=_p(u), platform=_p(pose.local(W)), length=enc(l))
        return spec, ang(div(k, u))
    if key == ("PRR", 2):
        W, d = mode.line(rng)
        u = _sign(rng, rot90(d))
        k = div(P0, target) if target else unit(rng)
        l = dy()
        P = add(W, k, l)
        spec.update(base=_p(add(W, u, -dy(-3, 3))), axis=_p(u), platform=_p(pose.local(P)), length=enc(l))
        return spec, ang(div(P0, k))
    if key == ("PRP", 2):
        W, d = mode.line(rng)
        u = _sign(rng, rot90(d))
        v, s = unit(rng), sl()
        spec.update(base=_p(add(W, u, -dy(-3, 3))), axis=_p(u), platform=_p(add(pose.local(W), v, -s)),
                    direction=_p(v))
        return spec, _qd(s)
    if key == ("PPR", 0):
        W, d = mode.line(rng)
        w = _sign(rng, rot90(d))
        beta = unit_not_axis(rng)
        u, s = div(w, beta), sl()
        C0 = add(add(W, w, -dy(-3, 3)), u, -s)
        spec.update(base=_p(C0), axis=_p(u), platform=_p(pose.local(W)), angle=ang(beta))
        return spec, _qd(s)
    if key == ("PPR", 1):
        W, d = mode.line(rng)
        u = _sign(rng, rot90(d))
        beta = unit_not_axis(rng)
        w, s = mul(beta, u), sl()
        C0 = add(add(W, u, -dy(-3, 3)), w, -s)
        spec.update(base=_p(C0), axis=_p(u), platform=_p(pose.local(W)), angle=ang(beta))
        return spec, _qd(s)
    # RP dyads: the platform line of direction h = rot90(d) through the fixed point W
    if key == ("RPR", 2):
        W, d = mode.line(rng, d=None if target is None else (lambda h: (h[1], -h[0]))(div(P0, target)))
        h = rot90(d)
        spec.update(base=_p(W), platform=_p(pose.local(add(W, h, dy(-3, 3)))))
        return spec, ang(div(P0, h))
    if key == ("RRP", 0):
        W, d = mode.line(rng)
        h = _sign(rng, rot90(d))
        f, l = target or unit(rng), dy()
        spec.update(base=_p(add(W, f, -l)), length=enc(l), platform=_p(pose.local(add(W, h, dy(-3, 3)))),
                    direction=_p(pose.local_dir(h)))
        return spec, ang(f)
    if key == ("RRP", 1):
        W, d = mode.line(rng)
        h = _sign(rng, rot90(d))
        f = div(h, target) if target else unit(rng)
        l = dy()
        E = add(W, f, l)
        spec.update(base=_p(W), length=enc(l), platform=_p(pose.local(add(E, h, dy(-3, 3)))),
                    direction=_p(pose.local_dir(h)))
        return spec, ang(div(h, f))
    if key == ("RPP", 1):
        W, d = mode.line(rng)
        h = _sign(rng, rot90(d))
        beta = unit_not_axis(rng)
        k, s = div(h, beta), sl()
        Pb = add(add(W, k, s), h, dy(-3, 3))
        spec.update(base=_p(W), platform=_p(pose.local(Pb)), direction=_p(pose.local_dir(h)), angle=ang(beta))
        return spec, _qd(s)
    if key == ("RPP", 2):
        W, d = mode.line(rng)
        k = _sign(rng, rot90(d))
        beta = unit_not_axis(rng)
        h, s = mul(beta, k), sl()
        v = pose.local_dir(h)
        b = add(pose.local(add(W, k, dy(-3, 3))), v, -s)
        spec.update(base=_p(W), platform=_p(b), direction=_p(v), angle=ang(beta))
        return spec, _qd(s)
    if key == ("PRP", 0):
        W, d = mode.line(rng)
        h = _sign(rng, rot90(d))
        u, s = unit(rng), sl()
        spec.update(base=_p(add(W, u, -s)), axis=_p(u), platform=_p(pose.local(add(W, h, dy(-3, 3)))),
                    direction=_p(pose.local_dir(h)))
        return spec, _qd(s)
    # PP dyads: the orientation fixed; the rest of the geometry is free
    if key == ("PPR", 2):
        spec.update(base=_p(point(rng)), axis=_p(unit(rng)), platform=_p(point(rng, 3)), angle=ang(unit_not_axis(rng)))
        return spec, ang(P0)
    if key == ("RPP", 0):
        v, beta = unit(rng), unit_not_axis(rng)
        spec.update(base=_p(point(rng)), platform=_p(point(rng, 3)), direction=_p(v), angle=ang(beta))
        return spec, ang(mul(div(P0, beta), v))
    if key == ("PRP", 1):
        u, v = unit(rng), unit(rng)
        spec.update(base=_p(point(rng)), axis=_p(u), platform=_p(point(rng, 3)), direction=_p(v))
        return spec, ang(mul(div(P0, u), v))
    raise ValueError(f"no construction for {key}")


#: combinations whose construction honours ``target`` (the actuated angle asked for)
TARGETABLE = {("RPR", 0), ("RPR", 2), ("RRR", 0), ("RRR", 2), ("PRR", 1), ("PRR", 2), ("RRP", 0), ("RRP", 1)}
#: combinations whose locked dyad is an RR dyad (honour ``radius``)
RR_COMBOS = [("RPR", 1), ("RRR", 0), ("RRR", 1), ("RRR", 2), ("PRR", 0), ("RRP", 2)]
#: combinations with a PR or RP dyad (a line)
LINE_COMBOS = [("RPR", 0), ("PRR", 1), ("PRR", 2), ("PRP", 2), ("PPR", 0), ("PPR", 1),
               ("RPR", 2), ("RRP", 0), ("RRP", 1), ("RPP", 1), ("RPP", 2), ("PRP", 0)]


def check_through(specs, q, pose):
    """Every leg's constraint (msolve_ref's formulation) vanishes exactly at the pose."""
    from .truth import witness_on

    if not witness_on(specs, q, pose.witness()):
        raise AssertionError(f"construction error: the pose is not a mode of {specs} at {q}")


def design_through(rng, pose, combos, modes, **kw):
    """Three legs through ``pose``: ``(specs, q)``; ``modes`` one :class:`Mode` per leg, ``kw``
    per-leg lists of ``target``/``qval``/``radius`` (None entries allowed). Checked exactly."""
    specs, q = [], []
    for i, ((kind, act), mode) in enumerate(zip(combos, modes)):
        extra = {k: v[i] for k, v in kw.items() if v is not None and v[i] is not None}
        s, e = build_leg(kind, act, rng, pose, mode, **extra)
        specs.append(s)
        q.append(e)
    check_through(specs, q, pose)
    return specs, q


def is_pp(combo):
    return tuple(combo) in PP_COMBOS


def random_pose(rng, cs=None):
    c, s = cs if cs is not None else unit(rng)
    return Pose(dyadic(rng, -2, 2), dyadic(rng, -2, 2), c, s)


def np_rng(seed):
    return np.random.default_rng(seed)
