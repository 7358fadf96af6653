"""The type of a conic section from the signs of its invariants, exactly or within a float
tolerance (the fixed-orientation sections of :class:`imagespace.singular.surface.ConicSection`).
Not public API beyond :data:`CONIC_NAMES`.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from .._validate import as_sympy_entry
from ..exceptions import InputError

__all__ = ["CONIC_NAMES"]

#: The types :func:`conic_type` tells apart.
CONIC_NAMES = ("ellipse", "imaginary ellipse", "parabola", "hyperbola", "intersecting lines",
               "parallel lines", "coincident lines", "imaginary parallel lines", "point", "line",
               "empty", "plane")


def exact_sign(a, degree=1):
    """The sign of an exact sympy number (-1, 0, 1), decided exactly (simplification, then 50 digits
    of a nonzero value); ``degree`` is ignored (the signature of :func:`conic_type`'s sign tests).

    Parameters
    ----------
    a : sympy number or int
    degree : int

    Returns
    -------
    int

    Raises
    ------
    InputError
        If the sign cannot be decided.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.singular.conics import exact_sign
    >>> exact_sign(sp.sqrt(2) - sp.Rational(99, 70)), exact_sign(sp.sin(sp.pi) ** 2)
    (-1, 0)
    """
    a = as_sympy_entry(a, "a")
    if a.is_zero:
        return 0
    if a.is_positive:
        return 1
    if a.is_negative:
        return -1
    z = sp.simplify(a)
    if z.is_zero:
        return 0
    v = sp.N(z, 50)
    if v == 0:
        raise InputError(f"could not decide the sign of {a} exactly")
    return 1 if v > 0 else -1


def float_sign_fn(cf, tol):
    """A sign test for float conic coefficients ``cf``: zero within ``tol`` times ``max |cf|`` to the
    power ``degree`` (the number of coefficients multiplied in the tested value).

    Parameters
    ----------
    cf : (6,) float
    tol : float

    Returns
    -------
    callable
        ``sign(value, degree=1)`` returning -1, 0 or 1.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.singular.conics import float_sign_fn
    >>> sign = float_sign_fn(np.array([1.0, 0, 1, 0, 0, -1]), 1e-9)
    >>> sign(1e-12), sign(-0.5), sign(1e-12, 2)
    (0, -1, 0)
    """
    scale = float(np.max(np.abs(cf))) if np.any(cf) else 0.0

    def sign(a, degree=1):
        a = float(a)
        return 0 if abs(a) <= tol * scale ** degree else (1 if a > 0 else -1)
    return sign


def conic_type(co, sign):
    """Classify a conic ``A x² + B xy + C y² + D x + E y + F`` from the signs of its invariants.

    Parameters
    ----------
    co : sequence of six numbers
        ``(A, B, C, D, E, F)``, exact sympy numbers or floats.
    sign : callable
        ``sign(value, degree)`` decides a sign (``degree``: how many coefficients multiply in
        ``value``, for a float tolerance): :func:`exact_sign` or :func:`float_sign_fn`.

    Returns
    -------
    str
        One of :data:`CONIC_NAMES`.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.singular.conics import conic_type, exact_sign
    >>> conic_type([sp.Integer(c) for c in (1, 0, 2, 0, 0, -1)], exact_sign)
    'ellipse'
    """
    A, B, C, D, E, F = co
    if all(sign(c, 1) == 0 for c in (A, B, C)):
        if sign(D, 1) == 0 and sign(E, 1) == 0:
            return "plane" if sign(F, 1) == 0 else "empty"
        return "line"
    delta = sign(4 * A * C - B * B, 2)
    Delta = sign(4 * A * C * F - A * E * E - B * B * F + B * D * E - C * D * D, 3)   # 4 det M
    if Delta != 0:
        if delta > 0:
            return "imaginary ellipse" if sign(A + C, 1) * Delta > 0 else "ellipse"
        return "parabola" if delta == 0 else "hyperbola"
    if delta < 0:
        return "intersecting lines"
    if delta > 0:
        return "point"
    # the quadratic part is a square: parallel, coincident or imaginary parallel lines
    cof = sign((4 * A * F - D * D) + (4 * C * F - E * E), 2)
    if cof < 0:
        return "parallel lines"
    return "coincident lines" if cof == 0 else "imaginary parallel lines"

