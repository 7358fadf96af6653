"""The plane geometry under the leg types (:mod:`imagespace.core.legs`), in one place.

Two families, both used only by the legs: turning user geometry into exact sympy values (points,
numbers, unit directions, exact cosine and sine of an angle, the float copy of that geometry), and
the float plane primitives the legs' inverse kinematics is built from (a platform point in the base
frame, a rotated vector, the meeting point of two lines, a line's intersections with a circle),
with the ``tolerances`` keyword their decisions read (:func:`as_tolerances`).
Nothing here is public API: the names carry no underscore because :mod:`imagespace.core.legs`
imports them, and they are kept out of ``__all__``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from .._validate import as_exact, as_point, as_sympy_entry
from ..exceptions import InputError, InputTypeError

__all__: list[str] = []


# --------------------------------------------------------------------------- exact geometry input

#: Beyond this size an angle is wrapped through ``atan2(sin a, cos a)`` (numpy's sine and cosine
#: reduce the exact binary argument, to within an ulp of the result even at ``1e300``), below it
#: by the remainder of ``2 pi``, whose rounding error grows with the number of turns removed.
_ACCURATE_WRAP_ABOVE = 8 * np.pi


def wrap_angle(a: Any) -> Any:
    """Wrap angles (radians, array or number) to ``(-pi, pi]``, accurately at any size (an angle
    of ``62831853071.79587`` keeps its remainder, not only the ulp of its float). NaN stays NaN.

    Examples
    --------
    >>> round(float(wrap_angle(3 * np.pi / 2)), 6), round(float(wrap_angle(62831853071.79587)), 12)
    (-1.570796, 3.150669e-06)
    """
    out = np.pi - np.remainder(np.pi - a, 2 * np.pi)
    with np.errstate(invalid="ignore"):
        big = np.abs(a) > _ACCURATE_WRAP_ABOVE
    if not np.any(big):
        return out
    far = np.arctan2(np.sin(a), np.cos(a))
    return np.where(big, np.where(far == -np.pi, np.pi, far), out)


def exact_cos_sin(angle: Any, name: str) -> tuple[Any, Any]:
    """Exact (cos, sin) of an angle.

    Symbols stay symbolic; angles whose cosine and sine sympy evaluates in closed form (``pi/2``,
    ``0``, ``atan(3/4)`` ...) stay exact; any other number (a float is the exact binary rational
    it stores) gives the exact transcendental ``cos(r)``, ``sin(r)`` of its rational ``r``, never a
    rounded value: sympy keeps them as atoms, arb encloses them
    (:func:`imagespace.core.certify.to_arb`), and the certified paths decide with them exactly
    (:mod:`imagespace.core.transcendental`).

    Raises
    ------
    InputError
        the angle's float is not finite.

    Examples
    --------
    >>> import sympy as sp
    >>> exact_cos_sin(0.5, "q")
    (cos(1/2), sin(1/2))
    >>> exact_cos_sin(sp.pi / 3, "q")
    (1/2, sqrt(3)/2)
    """
    if isinstance(angle, sp.Basic):
        if angle.free_symbols:
            return sp.cos(angle), sp.sin(angle)
        if not isinstance(angle, sp.Float):
            return sp.cos(angle), sp.sin(angle)
    a = float(as_exact(angle, name))
    if not np.isfinite(a):
        raise InputError(f"{name} must be an angle within the float range, got {short_text(angle)}")
    r = sp.Rational(a)
    return sp.cos(r), sp.sin(r)


def short_text(value: Any) -> str:
    """``str(value)``, cut to 80 characters for an error message."""
    text = str(value)
    return text if len(text) <= 80 else text[:77] + "..."


def in_float_range(values: Any, name: str) -> Any:
    """Geometry is kept exact, but every numeric method works on its floats: refuse numbers whose
    float is infinite (``2**1100``), naming the entry.

    Raises
    ------
    InputError
        an entry's float is infinite (the message names the entry).
    """
    single = not isinstance(values, tuple)
    for i, v in enumerate((values,) if single else values):
        if isinstance(v, sp.Basic) and not v.free_symbols and not np.isfinite(float(v)):
            raise InputError(f"{name if single else f'{name}[{i}]'} must be within the float range, "
                             f"got {short_text(v)}")
    return values


def real_entry(value: Any, name: str) -> Any:
    """A sympy entry of the geometry: a real expression (no booleans, relations, I, nan).

    Raises
    ------
    TypeError
        the entry is not a real sympy expression (a boolean, a relation, or it holds ``I``).
    """
    if isinstance(value, sp.Basic):
        value = as_sympy_entry(value, name)
        if value.has(sp.I):
            raise InputTypeError(f"{name} must be real, got {short_text(value)}")
    return value


def geometry_point(value: Any, name: str) -> tuple[Any, Any]:
    """A 2-vector of the geometry as a pair of exact sympy entries (real, within the float range).

    Raises
    ------
    TypeError
        An entry is not a real number or expression.
    InputError
        ``value`` is not a 2-vector, or an entry's float is infinite.

    Examples
    --------
    >>> geometry_point((1, 0.5), "base")
    (1, 1/2)
    """
    if isinstance(value, (list, tuple)) and len(value) == 2:
        value = tuple(real_entry(v, f"{name}[{i}]") for i, v in enumerate(value))
    elif isinstance(value, sp.MatrixBase) and len(value) == 2:
        value = tuple(real_entry(v, f"{name}[{i}]") for i, v in enumerate(value))
    elif isinstance(value, np.ndarray) and value.dtype == object and value.shape == (2,):
        value = tuple(real_entry(v, f"{name}[{i}]") for i, v in enumerate(value))
    return in_float_range(as_point(value, name), name)


def geometry_number(value: Any, name: str) -> Any:
    """A scalar of the geometry as an exact sympy number or expression (real, within the float
    range); raises like :func:`geometry_point`."""
    return in_float_range(as_exact(real_entry(value, name), name), name)


def unit_direction(value: Any, name: str) -> tuple[Any, Any]:
    """A direction normalised to length 1.

    Exact input (integers, rationals, sympy) is normalised exactly (``(-10, -9)`` becomes
    ``(-10, -9)/sqrt(181)``); float input is normalised in floating point and then taken as exact
    binary rationals, so that no square roots of long rationals enter the symbolic paths.

    Raises
    ------
    InputError
        the vector is zero, or not a finite 2-vector.
    TypeError
        an entry is not a real number.
    """
    vx, vy = geometry_point(value, name)
    n2 = sp.expand(vx**2 + vy**2)
    if n2 == 0 or (n2.is_number and float(n2) == 0.0):
        raise InputError(f"{name} must be a non-zero direction vector, got ({vx}, {vy})")
    if n2 == 1:
        return (vx, vy)
    raw = list(value) if not isinstance(value, np.ndarray) else list(value.ravel())
    if any(isinstance(r, (float, np.floating)) and not isinstance(r, sp.Basic) for r in raw):
        f = np.array([float(vx), float(vy)])
        f = f / np.hypot(*f)
        return (sp.Rational(f[0]), sp.Rational(f[1]))
    n = sp.sqrt(n2)
    return (sp.radsimp(vx / n), sp.radsimp(vy / n))


class Arithmetic:
    """cos/sin and constants for one arithmetic: sympy (exact or symbolic) or numpy (float)."""

    def __init__(self, symbolic: bool) -> None:
        self.symbolic = symbolic

    def cs(self, q: Any) -> tuple[Any, Any]:
        """``(cos q, sin q)`` in this arithmetic (exact through :func:`exact_cos_sin`)."""
        if self.symbolic:
            if isinstance(q, sp.Basic) and q.free_symbols:
                return sp.cos(q), sp.sin(q)
            return exact_cos_sin(q, "q")
        return np.cos(q), np.sin(q)


def floatify(value: Any) -> Any:
    """The float copy of a geometry entry (a tuple entry by entry); None where it holds a symbol."""
    if isinstance(value, tuple):
        return tuple(floatify(v) for v in value)
    if isinstance(value, sp.Basic):
        if value.free_symbols:
            return None
        return float(value)
    return value


# --------------------------------------------------------------------------- float plane primitives





def world_point(x: Any, y: Any, phi: Any, p: Any) -> tuple[Any, Any]:
    """The platform point ``p`` (moving frame) in the base frame at poses ``(x, y, phi)``."""
    c, s = np.cos(phi), np.sin(phi)
    return x + c * p[0] - s * p[1], y + s * p[0] + c * p[1]


def rotate_vector(phi: Any, v: Any) -> tuple[Any, Any]:
    """The vector ``v`` rotated by ``phi``."""
    c, s = np.cos(phi), np.sin(phi)
    return c * v[0] - s * v[1], s * v[0] + c * v[1]


def direction_angle(v: Any) -> Any:
    """The direction angle ``atan2(v_y, v_x)`` of ``v``."""
    return np.arctan2(v[1], v[0])


def lines_meet(p: Any, u: Any, r: Any, v: Any, parallel: float) -> tuple[Any, Any]:
    """Solve p + s u = r + t v for (s, t) (arrays); NaN where parallel (``|u x v| < parallel``,
    :attr:`~imagespace.tolerances.Tolerances.ik_parallel`)."""
    det = -u[0] * v[1] + u[1] * v[0]
    dx, dy = r[0] - p[0], r[1] - p[1]
    with np.errstate(invalid="ignore", divide="ignore"):
        s = (-dx * v[1] + dy * v[0]) / det
        t = (u[0] * dy - u[1] * dx) / det
    bad = np.abs(det) < parallel
    return np.where(bad, np.nan, s), np.where(bad, np.nan, t)


def circle_line(centre: Any, radius: Any, p: Any, v: Any, tangent: float) -> tuple[Any, Any]:
    """Parameters s of p + s v (v unit) on the circle; two branches, NaN if none. A discriminant
    above ``-tangent (1 + radius^2)`` is a tangency (:attr:`~imagespace.tolerances.Tolerances.ik_tangent`)."""
    dx, dy = p[0] - centre[0], p[1] - centre[1]
    b = v[0] * dx + v[1] * dy
    disc = b * b - (dx * dx + dy * dy) + radius * radius
    disc = np.where((disc < 0) & (disc > -tangent * (1 + radius * radius)), 0.0, disc)
    r = np.sqrt(np.where(disc >= 0, disc, np.nan))
    return -b + r, -b - r
