"""An independent exact referee for the Gough-Stewart (6-SPS) direct kinematics.

Formulation (owes nothing to Study coordinates or to imagespace): the unknowns are a quaternion
``q = (q0, q1, q2, q3)`` with ``q.q = 1`` and a translation ``t = (t1, t2, t3)``; the rotation
matrix of ``q`` is written out in :func:`rotation_polys` (the classical Euler-Rodrigues form,
homogeneous of degree 2 in ``q``, a rotation matrix when ``q.q = 1``). A platform point ``b``
(moving frame) lands at ``R(q) b + t``; leg ``i`` joins base point ``a_i`` to platform point
``b_i`` and has length ``L_i``. The system is the seven equations in seven unknowns

    q0^2 + q1^2 + q2^2 + q3^2 - 1 = 0,
    |R(q) b_i + t - a_i|^2 - L_i^2 = 0        (i = 1..6),

written literally (degree 4 in ``q``, no simplification by ``q.q = 1``), with exact rational
coefficients, and solved by msolve through :mod:`msolve_ref` (``real_solutions`` and
``solution_degrees``).

Exactness. Design points enter as exact rationals (floats as ``Fraction(float)``, i.e. their exact
binary value). Lengths: the public API takes leg LENGTHS as floats, so the referee is given either
``lengths`` -- and then solves for ``Fraction(float(L_i)) ** 2`` exactly, the square of the exact
binary value of the float the API receives -- or ``squared_lengths`` (exact rationals, for
self-tests where ``L_i^2`` is rational but ``L_i`` is not).

Sign of the quaternion. ``q`` and ``-q`` give the same rotation, so every real pose is two real
solutions of the system (and every complex pose two complex solutions: ``q -> -q`` is a free
involution because ``q.q = 1`` excludes ``q = 0``). De-duplication is exact, on msolve's isolating
boxes, by the normalisation "the first non-zero of ``(q0, q1, q2, q3)`` is positive":

* a box whose ``q0`` interval excludes 0 is kept iff ``q0 > 0`` on it;
* the boxes whose ``q0`` interval contains 0 may be half-turns (``q0 = 0``, ordinary poses that a
  chart ``q0 = 1`` would lose) or poses with a tiny non-zero ``q0``. msolve is run again on the
  system with ``q0 = 0`` added: it isolates exactly the real half-turn solutions. If their number
  equals the number of such boxes, each of those boxes holds a half-turn (every half-turn solution
  lies in its own box, and its box has 0 in the ``q0`` interval) and the decision passes to
  ``q1`` the same way (system with ``q0 = q1 = 0`` added for the boxes with 0 in both intervals,
  and so on; ``q0 = .. = q3 = 0`` is impossible). Otherwise some box holds a tiny non-zero ``q0``:
  the solve is repeated with twice the precision (a few times, then :class:`RefereeError`).

Finally the kept boxes are checked to be exactly half of all boxes, and every kept box to have
its mirror ``(-q, t)`` among the discarded ones (interval overlap): a second, independent check
of the pairing.
"""

from __future__ import annotations

import sys
from contextlib import contextmanager
from fractions import Fraction
from typing import List, NamedTuple, Tuple

import numpy as np

from msolve_ref import (DEFAULT_TIMEOUT, POSITIVE_DIMENSIONAL, MsolveError, Poly, real_solutions,
                        solution_degrees)

__all__ = ["VARIABLES", "RefereeError", "SpatialDKReference", "rotation_polys",
           "rotation_matrix_of_quaternion", "gs_system", "gough_stewart_reference",
           "gough_stewart_complex_count", "exact_squared_lengths"]

NV = 7
Q0, Q1, Q2, Q3, T1, T2, T3 = (Poly.var(i, NV) for i in range(NV))
Q = (Q0, Q1, Q2, Q3)
T = (T1, T2, T3)
VARIABLES = ("q0", "q1", "q2", "q3", "t1", "t2", "t3")

# the precision of msolve's isolating boxes (bits) at the first attempt, and how many times it
# is doubled when a box with 0 in a quaternion interval is not a half-turn (numerical knobs)
START_PRECISION = 128
MAX_PRECISION_DOUBLINGS = 4


@contextmanager
def _long_integers():
    """Lift Python's limit on int <-> str conversion (4300 digits) while msolve's output is parsed:
    the rational parametrisation of a design with float (binary) data has longer integers."""
    get = getattr(sys, "get_int_max_str_digits", None)
    if get is None:                                    # pragma: no cover (Python < 3.11)
        yield
        return
    old = get()
    sys.set_int_max_str_digits(0)
    try:
        yield
    finally:
        sys.set_int_max_str_digits(old)


class RefereeError(RuntimeError):
    """The referee could not decide the sign pairing of its boxes."""


class SpatialDKReference(NamedTuple):
    """Real poses of a 6-SPS found by msolve (one per pose, ``q ~ -q`` identified).

    ``rotations`` ``(k, 3, 3)`` float, ``translations`` ``(k, 3)`` float, ``quaternions``
    ``(k, 4)`` float (first non-zero entry positive), ``boxes``: the kept isolating boxes, each a
    list of seven ``(lo, hi)`` Fractions for ``q0, q1, q2, q3, t1, t2, t3``, and ``half_turns``
    ``(k,)`` bool: ``q0 = 0`` exactly (certified by the ``q0 = 0`` stratum).
    """

    rotations: np.ndarray
    translations: np.ndarray
    quaternions: np.ndarray
    boxes: List[List[Tuple[Fraction, Fraction]]]
    half_turns: np.ndarray

    def __len__(self):
        return len(self.boxes)

    @property
    def count(self):
        return len(self.boxes)


# --------------------------------------------------------------------------- the formulation

def rotation_polys(q=Q):
    """The rotation matrix of a quaternion, written out (Euler-Rodrigues), degree 2 in ``q``.

    ``R = [[q0^2+q1^2-q2^2-q3^2, 2(q1 q2 - q0 q3), 2(q1 q3 + q0 q2)],
    [2(q1 q2 + q0 q3), q0^2-q1^2+q2^2-q3^2, 2(q2 q3 - q0 q1)],
    [2(q1 q3 - q0 q2), 2(q2 q3 + q0 q1), q0^2-q1^2-q2^2+q3^2]]``: the rotation by the angle
    ``2 acos(q0)`` about ``(q1, q2, q3)`` when ``q.q = 1`` (works on Polys, Fractions or floats).
    """
    q0, q1, q2, q3 = q
    return [[q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
            [2 * (q1 * q2 + q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2 * (q2 * q3 - q0 * q1)],
            [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3]]


def rotation_matrix_of_quaternion(q):
    """``(3, 3)`` float rotation matrix of a (not necessarily unit) quaternion ``(4,)``: ``R(q) / q.q``."""
    q = np.asarray(q, dtype=float)
    return np.array(rotation_polys(tuple(q)), dtype=float) / float(q @ q)


def _exact(v):
    """An exact Fraction: floats as their binary value, ints, Fractions, decimal strings
    (``"0.645275"``), sympy rationals; anything else raises TypeError."""
    if isinstance(v, Fraction):
        return v
    if isinstance(v, (bool, np.bool_)):
        raise TypeError(f"expected a number, got the boolean {v}")
    if isinstance(v, (int, np.integer)):
        return Fraction(int(v))
    if isinstance(v, (float, np.floating)):
        if not np.isfinite(v):
            raise ValueError(f"expected a finite number, got {v}")
        return Fraction(float(v))
    if isinstance(v, str):
        return Fraction(v)
    p, q = getattr(v, "p", None), getattr(v, "q", None)      # a sympy Rational
    if getattr(v, "is_Rational", False) and p is not None and q is not None:
        return Fraction(int(p), int(q))
    raise TypeError(f"expected an exact rational or a float, got {type(v).__name__} {v!r}")


def _points(p, name):
    rows = [list(r) for r in (p.tolist() if isinstance(p, np.ndarray) else p)]
    if len(rows) != 6 or any(len(r) != 3 for r in rows):
        raise ValueError(f"{name} must be six 3D points, got {np.shape(np.asarray(p, dtype=object))}")
    return [[_exact(v) for v in r] for r in rows]


def exact_squared_lengths(lengths=None, squared_lengths=None):
    """The six exact ``L_i^2``: ``Fraction(float(L_i)) ** 2`` from lengths, or the given squares."""
    if (lengths is None) == (squared_lengths is None):
        raise ValueError("give exactly one of lengths and squared_lengths")
    if squared_lengths is not None:
        out = [_exact(v) for v in list(np.asarray(squared_lengths, dtype=object).ravel())]
    else:
        out = [Fraction(float(v)) ** 2 for v in list(np.asarray(lengths, dtype=float).ravel())]
    if len(out) != 6:
        raise ValueError(f"six leg lengths are needed, got {len(out)}")
    return out


def gs_system(base, platform, lengths=None, squared_lengths=None):
    """The seven exact polynomials (Poly in ``VARIABLES``): ``q.q - 1`` and the six legs."""
    A, B = _points(base, "base"), _points(platform, "platform")
    L2 = exact_squared_lengths(lengths, squared_lengths)
    R = rotation_polys()
    polys = [Q0 * Q0 + Q1 * Q1 + Q2 * Q2 + Q3 * Q3 - 1]
    for a, b, l2 in zip(A, B, L2):
        d = [R[r][0] * b[0] + R[r][1] * b[1] + R[r][2] * b[2] + T[r] - a[r] for r in range(3)]
        polys.append(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - l2)
    return polys


# --------------------------------------------------------------------------- sign de-duplication

def _has_zero(iv):
    return iv[0] <= 0 <= iv[1]


def _overlap(iv, jv):
    return iv[0] <= jv[1] and jv[0] <= iv[1]


def _is_mirror(box, other):
    """``other`` overlaps ``(-q, t)`` of ``box``."""
    for k in range(4):
        lo, hi = box[k]
        if not _overlap((-hi, -lo), other[k]):
            return False
    return all(_overlap(box[k], other[k]) for k in range(4, 7))


def _dedupe(polys, boxes, timeout, precision):
    """Keep one box per pose (first non-zero quaternion entry positive); None if undecided."""
    keep = [None] * len(boxes)
    undecided = list(range(len(boxes)))
    zeros = []                                         # the coordinates known to vanish
    for k in range(4):
        rest = []
        for i in undecided:
            if _has_zero(boxes[i][k]):
                rest.append(i)
            else:
                keep[i] = boxes[i][k][0] > 0
        if not rest:
            break
        zeros.append(Q[k])
        stratum = real_solutions(polys + zeros, VARIABLES, timeout=timeout, precision=precision)
        if stratum == POSITIVE_DIMENSIONAL:
            raise RefereeError(f"the stratum q0..q{k} = 0 is positive-dimensional")
        if len(stratum) != len(rest):
            return None                                # a tiny non-zero entry: refine
        undecided = rest
    if any(v is None for v in keep):
        raise RefereeError("a box with 0 in every quaternion interval")
    return keep


def _solve(polys, timeout):
    precision = START_PRECISION
    for _ in range(MAX_PRECISION_DOUBLINGS + 1):
        boxes = real_solutions(polys, VARIABLES, timeout=timeout, precision=precision)
        if boxes == POSITIVE_DIMENSIONAL:
            return POSITIVE_DIMENSIONAL, None
        keep = _dedupe(polys, boxes, timeout, precision)
        if keep is not None:
            return boxes, keep
        precision *= 2
    raise RefereeError(f"could not separate q0 = 0 from q0 != 0 up to {precision // 2} bits")


def _mid(iv):
    return (iv[0] + iv[1]) / 2


def gough_stewart_reference(base, platform, lengths=None, squared_lengths=None,
                            timeout=DEFAULT_TIMEOUT):
    """Every real pose of the 6-SPS, exactly isolated by msolve on the quaternion formulation.

    Parameters
    ----------
    base, platform : (6, 3) numbers (floats exactly, ints, Fractions, sympy rationals)
    lengths : (6,) float, optional
        Leg lengths as the API gets them; the referee solves for ``Fraction(float(L)) ** 2``.
    squared_lengths : (6,) exact rationals, optional
        Alternative to ``lengths``: the exact ``L^2``.
    timeout : float
        Seconds per msolve run.

    Returns
    -------
    SpatialDKReference (sorted by translation, then quaternion), or ``"positive-dimensional"``.
    """
    polys = gs_system(base, platform, lengths, squared_lengths)
    with _long_integers():
        boxes, keep = _solve(polys, timeout)
    if boxes == POSITIVE_DIMENSIONAL:
        return POSITIVE_DIMENSIONAL
    kept = [b for b, k in zip(boxes, keep) if k]
    dropped = [b for b, k in zip(boxes, keep) if not k]
    if 2 * len(kept) != len(boxes):
        raise RefereeError(f"{len(boxes)} boxes but {len(kept)} kept: the pairing q ~ -q failed")
    for b in kept:
        if sum(_is_mirror(b, o) for o in dropped) != 1:
            raise RefereeError("a kept box has no unique mirror (-q, t) among the others")
    half = []
    for b in kept:
        half.append(_has_zero(b[0]))
    # a box with 0 in its q0 interval survived the stratum count only if q0 = 0 there exactly
    qs = np.array([[float(_mid(b[k])) for k in range(4)] for b in kept], dtype=float).reshape(-1, 4)
    ts = np.array([[float(_mid(b[k])) for k in range(4, 7)] for b in kept], dtype=float).reshape(-1, 3)
    Rs = np.array([rotation_matrix_of_quaternion(q) for q in qs], dtype=float).reshape(-1, 3, 3)
    order = sorted(range(len(kept)), key=lambda i: (tuple(ts[i]), tuple(qs[i])))
    return SpatialDKReference(Rs[order], ts[order], qs[order], [kept[i] for i in order],
                              np.array([half[i] for i in order], dtype=bool))


def gough_stewart_complex_count(base, platform, lengths=None, squared_lengths=None,
                                timeout=DEFAULT_TIMEOUT):
    """``(poses, with_multiplicity)``: complex poses of the 6-SPS (40 for a general design).

    From :func:`msolve_ref.solution_degrees` of the quaternion system: ``q -> -q`` is a free
    involution on its complex solutions (``q.q = 1`` excludes ``q = 0``), so the number of distinct
    complex poses is exactly half the number of distinct complex solutions, and likewise with
    multiplicity. Returns ``"positive-dimensional"`` for a continuum.
    """
    polys = gs_system(base, platform, lengths, squared_lengths)
    with _long_integers():
        deg = solution_degrees(polys, VARIABLES, timeout=timeout)
    if deg == POSITIVE_DIMENSIONAL:
        return POSITIVE_DIMENSIONAL
    degree, distinct = deg
    if degree % 2 or distinct % 2:
        raise MsolveError(f"odd solution count {deg} of a system symmetric under q -> -q")
    return distinct // 2, degree // 2
