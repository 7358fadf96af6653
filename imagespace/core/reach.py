r"""Reach bounds: exact proofs that no assembly mode exists because legs cannot meet.

Locking the actuated joint of a leg confines one point of the platform (or one line of it). Two
legs then constrain the platform's rigid distance between their points, and a triangle inequality
that fails proves, without solving anything, that no real pose satisfies the constraints. That is
how an absurd input (a leg ``1e300`` long on a design of size 10, or ``1e-300`` on a design whose
anchors are 1 apart) is answered at once, and exactly, instead of sending thousands of digits to
an exact root finder.

The constraints used (``p`` a platform point in the moving frame, ``C`` a base point; ``p^w`` the
platform point in the base frame at the unknown pose):

* **annulus** -- ``|p^w - C|`` lies in ``[lo, hi]``: an RR dyad (RPR with the length actuated,
  PRR with the slider actuated, RRP with the platform slider actuated: a circle, ``lo = hi``) or
  any RRR leg (the elbow turns: ``[|l1 - l2|, l1 + l2]`` whatever joint is actuated);
* **base strip** -- ``p^w`` lies within ``h`` of a base line: PRR with an angle actuated (``h =
  l``), PRP with the platform slider actuated and PPR with a slider actuated (``h = 0``);
* **platform strip** -- the base point ``C`` lies within ``h`` of a platform line: RRP with an
  angle actuated (``h = l``), PRP with the base slider actuated and RPP with a slider actuated
  (``h = 0``).

Legs whose locked dyad fixes only the orientation (PP dyads) or only a line through a base pivot
(RPR with an angle actuated) give no constraint. Prismatic guides reach arbitrarily far, so their
constraints are lines, never bounded regions.

For two constraints the necessary conditions checked are (``d = |p_i - p_j|`` in the moving frame,
``D = |C_i - C_j|`` in the base frame, both fixed by the design):

* annulus / annulus: no side of the quadrilateral ``C_i, p_i^w, p_j^w, C_j`` is longer than the
  other three together: ``d <= D + hi_i + hi_j``, ``D <= d + hi_i + hi_j``,
  ``lo_i <= d + D + hi_j`` and ``lo_j <= d + D + hi_i``;
* annulus / base strip: ``dist(C_i, line_j) <= hi_i + d + h_j``;
* annulus / platform strip: ``dist(p_i, line_j) <= hi_i + D + h_j`` (the distance taken in the
  moving frame).

Every quantity is enclosed in an arb ball computed from the exact input (floats are the binary
rationals they store, sympy numbers are enclosed by :func:`~imagespace.core.certify.to_arb`); a
condition counts as violated only when the ball of ``left - right`` lies entirely above zero, so
the answer "no real mode" is a theorem and a tie is never decided. Cosine and sine of an angle
never enter as rounded numbers: the annuli and strips of angle-actuated legs do not depend on the
angle, and the design angle of an RPP or PPR leg is enclosed as the union of its true cosine and
sine and the rounded pair the float paths use, so the proof holds for both.

The spatial analogue (:func:`point_pairs_obstruction`) serves the Gough-Stewart platform and the
3-RPS manipulator: leg ``i`` keeps platform point ``b_i`` at distance ``L_i`` from base point
``a_i``, and the same quadrilateral inequalities hold in space.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Optional, Sequence

import numpy as np

from .._validate import as_sympy
from ..exceptions import InputError, InputTypeError

__all__ = ["REACH_BITS", "ReachObstruction", "planar_reach_obstruction", "point_pairs_obstruction",
           "planar_design_scale", "prismatic_magnitude"]

#: Working precision (bits) of the arb balls of the reach bounds. A numerical knob: a tighter
#: ball only settles more near-ties; a decision is never taken on a ball that straddles zero.
REACH_BITS = 128

# A (cos, sin) pair that the float paths rounded to doubles has a norm within this of 1 (a few
# units of the last place, generously); the constraints of angle-actuated legs are widened by it
# so that they hold for the rounded model as well as for the true one. Not a decision threshold.
_ROUNDED_UNIT_NORM = 2.0 ** -48


@dataclass(frozen=True)
class ReachObstruction:
    """A proof that no real pose satisfies the legs' constraints.

    Attributes
    ----------
    legs : tuple of int
        The two legs whose constraints cannot hold together.
    reason : str
        The violated inequality, in words and numbers (rounded for display only; the decision
        was taken on exact enclosures).

    Examples
    --------
    >>> from imagespace.core.reach import point_pairs_obstruction
    >>> ob = point_pairs_obstruction([[0, 0], [3, 0]], [[0, 0], [1, 0]], [10.0, 1.0])
    >>> ob.legs
    (0, 1)
    """

    legs: tuple
    reason: str

    def __str__(self):
        return f"no real assembly mode: {self.reason}"


# --------------------------------------------------------------------------- enclosures

def _arb(value):
    """A rigorous arb ball of an exact number: python float / int / Fraction / numpy number or a
    real sympy number (closed form, enclosed by :func:`~imagespace.core.certify.to_arb`)."""
    import flint
    from fractions import Fraction
    from numbers import Integral

    if isinstance(value, (bool, np.bool_)):
        raise InputTypeError(f"expected a number, got the boolean {value!r}")
    if isinstance(value, (float, np.floating)):
        v = float(value)
        if not math.isfinite(v):
            raise InputError(f"expected a finite number, got {v}")
        return flint.arb(v)                     # exact: a double is a binary rational
    if isinstance(value, (Integral, np.integer)):
        return flint.arb(int(value))
    if isinstance(value, Fraction):
        return flint.arb(flint.fmpq(value.numerator, value.denominator))
    import sympy as sp

    from .certify import to_arb

    v = as_sympy(value)
    if v.free_symbols:
        raise InputError(f"expected a number, got the symbolic {v}")
    ball = to_arb(v, REACH_BITS)
    if not ball.is_finite():
        raise InputError(f"expected a finite real number, got {v}")
    return ball


def _vec(values):
    return tuple(_arb(v) for v in values)


def _sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def _norm(v):
    """Euclidean length of an arb vector (the square root of a ball that may reach below 0 is
    taken of its non-negative part)."""
    import flint

    s = flint.arb(0)
    for x in v:
        s = s + x * x
    return _sqrt(s)


def _sqrt(s):
    import flint

    if s > 0:
        return s.sqrt()
    # a ball around 0: |x| <= sqrt(upper bound), and >= 0
    up = s.upper()
    if up <= 0:
        return flint.arb(0)
    return flint.arb(0).union(up.sqrt())


def _cross2(u, v):
    return u[0] * v[1] - u[1] * v[0]


def _line_distance(point, through, direction):
    """Distance from ``point`` to the line through ``through`` along ``direction`` (2-d, any
    non-zero length of ``direction``)."""
    return abs(_cross2(direction, _sub(point, through))) / _norm(direction)


def _proven_positive(ball):
    """True only when every number in the ball is > 0."""
    return bool(ball > 0)


def _show(ball):
    return f"{float(ball.mid()):.6g}"


# --------------------------------------------------------------------------- the planar legs

@dataclass(frozen=True)
class _Annulus:
    leg: int
    point: tuple        # platform point (moving frame)
    centre: tuple       # base point
    lo: Any
    hi: Any


@dataclass(frozen=True)
class _BaseStrip:
    leg: int
    point: tuple        # platform point (moving frame)
    through: tuple      # base line: point and direction (base frame)
    direction: tuple
    width: Any


@dataclass(frozen=True)
class _PlatformStrip:
    leg: int
    centre: tuple       # base point
    through: tuple      # platform line: point and direction (moving frame)
    direction: tuple
    width: Any


def _unit_slack():
    """The ball ``[1 - e, 1 + e]`` holding the norm of a true or rounded (cos, sin) pair."""
    import flint

    return flint.arb(1, _ROUNDED_UNIT_NORM)


def _angle_cs(leg):
    """Enclosures of (cos, sin) of the design angle of an RPP or PPR leg: the union of the true
    values at the exact angle and the pair the float paths use."""
    import sympy as sp

    from .leg_geometry import exact_cos_sin

    angle = leg.angle
    true = (_arb(sp.cos(angle)), _arb(sp.sin(angle)))
    used = exact_cos_sin(angle, "angle")
    used = (_arb(used[0]), _arb(used[1]))
    return tuple(t.union(u) for t, u in zip(true, used))


def _leg_constraint(j, leg, q):
    """The reach constraint of leg ``j`` at its actuated value ``q`` (an arb ball), or None."""
    g = leg.geometry()
    kind, act = leg.joints, leg.actuated
    if kind == "RPR":
        if act != 1:
            return None                 # a line through the base pivot: no bound
        A, a = _vec(g["base"]), _vec(g["platform"])
        r = abs(q)
        return _Annulus(j, a, A, r, r)
    if kind == "RRR":
        A, a = _vec(g["base"]), _vec(g["platform"])
        l1, l2 = _vec(g["lengths"])
        l1 = l1 * _unit_slack()         # the elbow's circle, true or rounded cos/sin
        lo = abs(l1 - l2)
        return _Annulus(j, a, A, lo, l1 + l2)
    if kind == "PRR":
        A, u, a = _vec(g["base"]), _vec(g["axis"]), _vec(g["platform"])
        length = _arb(g["length"])
        if act == 0:
            return _Annulus(j, a, (A[0] + q * u[0], A[1] + q * u[1]), length, length)
        return _BaseStrip(j, a, A, u, length * _unit_slack())
    if kind == "RRP":
        A, b, v = _vec(g["base"]), _vec(g["platform"]), _vec(g["direction"])
        length = _arb(g["length"])
        if act == 2:
            return _Annulus(j, (b[0] + q * v[0], b[1] + q * v[1]), A, length, length)
        return _PlatformStrip(j, A, b, v, length * _unit_slack())
    if kind == "PRP":
        A, u, b, v = _vec(g["base"]), _vec(g["axis"]), _vec(g["platform"]), _vec(g["direction"])
        if act == 0:
            return _PlatformStrip(j, (A[0] + q * u[0], A[1] + q * u[1]), b, v, _arb(0))
        if act == 2:
            return _BaseStrip(j, (b[0] + q * v[0], b[1] + q * v[1]), A, u, _arb(0))
        return None                     # a PP dyad: the orientation only
    if kind == "RPP":
        if act == 0:
            return None
        A, b, v = _vec(g["base"]), _vec(g["platform"]), _vec(g["direction"])
        cb, sb = _angle_cs(leg)
        w = (v[0] * cb + v[1] * sb, v[1] * cb - v[0] * sb)
        if act == 1:
            return _PlatformStrip(j, A, (b[0] - q * w[0], b[1] - q * w[1]), v, _arb(0))
        return _PlatformStrip(j, A, (b[0] + q * v[0], b[1] + q * v[1]), w, _arb(0))
    if kind == "PPR":
        if act == 2:
            return None
        C, u, c = _vec(g["base"]), _vec(g["axis"]), _vec(g["platform"])
        cb, sb = _angle_cs(leg)
        w = (u[0] * cb - u[1] * sb, u[1] * cb + u[0] * sb)
        if act == 0:
            return _BaseStrip(j, c, (C[0] + q * u[0], C[1] + q * u[1]), w, _arb(0))
        return _BaseStrip(j, c, (C[0] + q * w[0], C[1] + q * w[1]), u, _arb(0))
    return None


def _pair(ci, cj):
    """The obstruction between two constraints (either order), or None."""
    if isinstance(cj, _Annulus) and not isinstance(ci, _Annulus):
        ci, cj = cj, ci
    if not isinstance(ci, _Annulus):
        return None                     # two lines: unbounded, no claim
    legs = tuple(sorted((ci.leg, cj.leg)))
    if isinstance(cj, _Annulus):
        return _annuli(ci.point, cj.point, ci.centre, cj.centre, ci.lo, ci.hi, cj.lo, cj.hi,
                       ci.leg, cj.leg)
    if isinstance(cj, _BaseStrip):
        d = _norm(_sub(ci.point, cj.point))
        gap = _line_distance(ci.centre, cj.through, cj.direction) - (ci.hi + d + cj.width)
        if _proven_positive(gap):
            return ReachObstruction(legs, (
                f"leg {ci.leg} keeps its platform point within {_show(ci.hi)} of a base point "
                f"that lies {_show(gap + ci.hi + d + cj.width)} from the line of leg {cj.leg}, "
                f"farther than that reach plus the platform distance {_show(d)} and the line's "
                f"slack {_show(cj.width)}"))
        return None
    D = _norm(_sub(ci.centre, cj.centre))
    gap = _line_distance(ci.point, cj.through, cj.direction) - (ci.hi + D + cj.width)
    if _proven_positive(gap):
        return ReachObstruction(legs, (
            f"the platform line of leg {cj.leg} lies {_show(gap + ci.hi + D + cj.width)} from the "
            f"platform point of leg {ci.leg}, farther than that leg's reach {_show(ci.hi)} plus "
            f"the base distance {_show(D)} and the slack {_show(cj.width)}"))
    return None


def _annuli(pi, pj, Ci, Cj, lo_i, hi_i, lo_j, hi_j, i, j):
    d = _norm(_sub(pi, pj))
    D = _norm(_sub(Ci, Cj))
    legs = (min(i, j), max(i, j))
    checks = (
        (d - (D + hi_i + hi_j), f"the platform distance {_show(d)} between the points of legs {i} "
                                f"and {j} exceeds the base distance {_show(D)} plus their reaches "
                                f"{_show(hi_i)} and {_show(hi_j)}"),
        (D - (d + hi_i + hi_j), f"the base distance {_show(D)} between legs {i} and {j} exceeds "
                                f"the platform distance {_show(d)} plus their reaches "
                                f"{_show(hi_i)} and {_show(hi_j)}"),
        (lo_i - (d + D + hi_j), f"leg {i} holds its platform point at least {_show(lo_i)} from its "
                                f"base point, more than leg {j}'s reach {_show(hi_j)} plus the "
                                f"base distance {_show(D)} and the platform distance {_show(d)}"),
        (lo_j - (d + D + hi_i), f"leg {j} holds its platform point at least {_show(lo_j)} from its "
                                f"base point, more than leg {i}'s reach {_show(hi_i)} plus the "
                                f"base distance {_show(D)} and the platform distance {_show(d)}"),
    )
    for gap, text in checks:
        if _proven_positive(gap):
            return ReachObstruction(legs, text)
    return None


def planar_reach_obstruction(legs: Sequence[Any], q: Sequence[Any]) -> Optional[ReachObstruction]:
    """Prove, if a reach bound can, that no real pose of a planar design meets the joint values.

    Parameters
    ----------
    legs : sequence of :class:`~imagespace.core.legs.Leg`
        The design's legs (numeric geometry; a leg with symbolic geometry is skipped).
    q : sequence of numbers
        One actuated joint value per leg: floats (taken as the binary rationals they are),
        integers, Fractions or real sympy numbers. Values outside a joint's domain are not
        checked here (the callers validate ``q`` first).

    Returns
    -------
    ReachObstruction or None
        An obstruction proves that the direct kinematics has no real solution (no real assembly
        mode); None proves nothing (modes may or may not exist).

    Raises
    ------
    InputError
        ``q`` does not hold one finite real number per leg.

    Examples
    --------
    A 3-RPR whose first leg is ``1e300`` long while the others are 5 and 10:

    >>> import imagespace as isp
    >>> from imagespace.core.reach import planar_reach_obstruction
    >>> m = isp.examples.general_3rpr()
    >>> planar_reach_obstruction(m.legs, [1e300, 5, 10]).legs
    (0, 1)
    >>> planar_reach_obstruction(m.legs, m.q_example_float) is None
    True
    """
    from .certify import flint_precision

    legs = list(legs)
    if isinstance(q, (str, bytes)):
        raise InputTypeError(f"q must be a sequence of numbers, got {q!r:.60}")
    q = list(np.ravel(np.asarray(q, dtype=object))) if not hasattr(q, "free_symbols") else [q]
    if len(q) != len(legs):
        raise InputError(f"q must hold one value per leg ({len(legs)}), got {len(q)}")
    with flint_precision(REACH_BITS):
        cons = []
        for j, (leg, v) in enumerate(zip(legs, q)):
            if leg.free_symbols:
                continue
            try:
                qa = _arb(v)
            except TypeError as exc:
                raise InputTypeError(f"q[{j}] must be a number, got {type(v).__name__}") from exc
            except InputError as exc:
                raise type(exc)(f"q[{j}]: {exc}") from None
            c = _leg_constraint(j, leg, qa)
            if c is not None:
                cons.append(c)
        for a in range(len(cons)):
            for b in range(a + 1, len(cons)):
                ob = _pair(cons[a], cons[b])
                if ob is not None:
                    return ob
    return None


def point_pairs_obstruction(centres: Any, points: Any, lengths: Any,
                            lower: Any = None) -> Optional[ReachObstruction]:
    """Prove, if a triangle inequality can, that platform points cannot reach their annuli.

    Leg ``i`` holds the platform point ``points[i]`` (moving frame) at a distance between
    ``lower[i]`` and ``lengths[i]`` from the base point ``centres[i]`` (base frame), in any
    dimension; the platform is rigid. Used by the spatial platforms (a Gough-Stewart or 3-RPS
    leg: ``lower = lengths``, a sphere) and by the planar bound.

    Parameters
    ----------
    centres : (k, n) float
        Base points.
    points : (k, n) float
        Platform points, in the moving frame.
    lengths : (k,) float
        Largest distance of each leg (its length); finite, non-negative.
    lower : (k,) float, optional
        Smallest distance (default ``lengths``: each leg exactly that long).

    Returns
    -------
    ReachObstruction or None
        An obstruction proves that no real pose exists; None proves nothing.

    Raises
    ------
    InputError
        Mismatched shapes, non-finite or negative values.

    Examples
    --------
    Two legs 1 apart on the base and on the platform, lengths ``1e300`` and ``2``:

    >>> from imagespace.core.reach import point_pairs_obstruction
    >>> point_pairs_obstruction([[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1, 0, 0]], [1e300, 2.0]).legs
    (0, 1)
    >>> point_pairs_obstruction([[0, 0, 0], [1, 0, 0]], [[0, 0, 0], [1, 0, 0]], [5.0, 5.5]) is None
    True
    """
    from .certify import flint_precision

    C = np.asarray(centres, dtype=float)
    P = np.asarray(points, dtype=float)
    hi = np.asarray(lengths, dtype=float)
    lo = hi if lower is None else np.asarray(lower, dtype=float)
    if C.ndim != 2 or C.shape != P.shape or hi.shape != (C.shape[0],) or lo.shape != hi.shape:
        raise InputError(f"centres and points must be (k, n) and lengths (k,), got shapes "
                         f"{C.shape}, {P.shape}, {hi.shape}" + ("" if lower is None else f", {lo.shape}"))
    for name, arr in (("centres", C), ("points", P), ("lengths", hi), ("lower", lo)):
        if not np.all(np.isfinite(arr)):
            raise InputError(f"{name} must be finite, got {arr.tolist()}")
    if np.any(hi < 0) or np.any(lo < 0) or np.any(lo > hi):
        raise InputError(f"lengths must be non-negative (and not below lower), got {hi.tolist()}")
    k = C.shape[0]
    with flint_precision(REACH_BITS):
        Ca = [_vec(c) for c in C]
        Pa = [_vec(p) for p in P]
        H = [_arb(v) for v in hi]
        L = [_arb(v) for v in lo]
        for i in range(k):
            for j in range(i + 1, k):
                ob = _annuli(Pa[i], Pa[j], Ca[i], Ca[j], L[i], H[i], L[j], H[j], i, j)
                if ob is not None:
                    return ob
    return None


# --------------------------------------------------------------------------- magnitudes

def planar_design_scale(legs: Sequence[Any]) -> float:
    """The size of a planar design: the largest magnitude among its numeric geometry.

    Base and platform coordinates, link lengths (directions and angles excluded); at least the
    smallest positive double, 1 when there is none.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.core.reach import planar_design_scale
    >>> planar_design_scale(isp.examples.general_3rpr().legs)
    8.0
    """
    size = 0.0
    for leg in legs:
        for key, value in leg.geometry().items():
            if key in ("axis", "direction", "angle_cs", "second_axis"):
                continue
            for v in (value if isinstance(value, tuple) else (value,)):
                try:
                    f = abs(float(v))
                except (TypeError, ValueError):
                    continue            # symbolic
                if math.isfinite(f):
                    size = max(size, f)
    return size if size > 0 else 1.0


def prismatic_magnitude(legs: Sequence[Any], Q: Any) -> np.ndarray:
    """Per row, the largest ``|q_j|`` over the legs whose actuated joint is prismatic (0 when
    none is); non-finite values give ``inf``.

    Parameters
    ----------
    legs : sequence of Leg
    Q : (n, k) or (k,) float

    Returns
    -------
    (n,) float

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.core.reach import prismatic_magnitude
    >>> prismatic_magnitude(isp.examples.general_3rpr().legs, np.array([[1e300, 5, 10]]))
    array([1.e+300])
    """
    Q = np.atleast_2d(np.asarray(Q, dtype=float))
    if Q.ndim != 2 or Q.shape[1] != len(legs):
        raise InputError(f"Q must have shape (n, {len(legs)}), got {Q.shape}")
    out = np.zeros(Q.shape[0])
    for j, leg in enumerate(legs):          # column by column: a short-axis reduction is slow
        if not leg.actuated_is_angle:
            col = np.abs(Q[:, j])
            col[~np.isfinite(col)] = np.inf
            np.maximum(out, col, out=out)
    return out
