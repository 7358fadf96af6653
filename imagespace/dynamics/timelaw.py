"""Polynomial time laws ``s(t)`` for a path parameter (seed 000, eq. 21)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..exceptions import InputError
from .._validate import as_count, as_float_array
from . import checks

__all__ = ["TimeLaw", "cubic_rest_to_rest", "sextic_through"]

SIGN_PROBE = 1e-7
"""Relative to ``T``: how far either side of an interior root of ``s'`` its sign is compared (a
probe step, not a threshold)."""


@dataclass(frozen=True)
class TimeLaw:
    """``s(t) = sum_k c_k t**k`` on ``[0, T]``.

    Attributes
    ----------
    coefficients : (k + 1,) float
        ``c_0 .. c_k``.
    T : float

    Raises
    ------
    TypeError
        For non-numeric coefficients or ``T``.
    InputError
        For no coefficients, a non-finite one, or a non-positive ``T``.

    Examples
    --------
    >>> from imagespace.dynamics.timelaw import TimeLaw
    >>> float(TimeLaw([0.0, 1.0], 2.0)(2.0))
    2.0
    """

    coefficients: np.ndarray
    T: float

    def __post_init__(self):
        c = checks.vector(self.coefficients, "coefficients")
        if len(c) == 0:
            raise InputError("coefficients must hold at least one coefficient, got none")
        object.__setattr__(self, "coefficients", c)
        object.__setattr__(self, "T", checks.scalar(self.T, "T", positive=True))

    def __call__(self, t, order=0):
        """``s``, or its ``order``-th time derivative, at ``t``.

        Raises
        ------
        TypeError
            For a non-integer ``order`` or non-numeric ``t``.
        InputError
            For a negative ``order``.

        Examples
        --------
        >>> from imagespace.dynamics.timelaw import cubic_rest_to_rest
        >>> law = cubic_rest_to_rest(1.5, 1.0)
        >>> float(law(1.0)), float(law(1.0, 1))
        (1.5, 0.0)
        """
        order = as_count(order, "order", 0)
        t = as_float_array(t, "t", finite=False)
        c = np.polynomial.polynomial.Polynomial(self.coefficients)
        for _ in range(order):
            c = c.deriv()
        return c(t)

    def is_monotone(self, n=2001, tolerances=None):
        """True if ``s`` never decreases on ``[0, T]`` (sampled with ``n`` points, plus the
        derivative's real roots inside).

        Parameters
        ----------
        n : int
            Samples of ``s'`` over ``[0, T]``.
        tolerances : Tolerances, optional
            ``timelaw_root`` (which roots of ``s'`` are real and interior) and ``timelaw_monotone``
            (the slack of ``s' >= 0``); ``None``: the defaults.

        Raises
        ------
        TypeError
            For a non-integer ``n`` or a ``tolerances`` that is not a Tolerances.
        InputError
            For ``n < 2`` or above ``MAX_SAMPLES``.

        Examples
        --------
        >>> from imagespace.dynamics.timelaw import cubic_rest_to_rest
        >>> cubic_rest_to_rest(1.5, 1.0).is_monotone()
        True
        """
        n = checks.count(n, "n", 2)
        tol = checks.tolerances(tolerances)
        d = np.polynomial.polynomial.Polynomial(self.coefficients).deriv()
        r = d.roots()
        edge = tol.timelaw_root
        r = r[(np.abs(r.imag) < edge) & (r.real > edge) & (r.real < self.T - edge)].real
        ts = np.concatenate([np.linspace(0, self.T, n), r])
        vals = d(ts)
        scale = max(1.0, float(np.max(np.abs(vals))))
        # a root strictly inside where the derivative changes sign means a local extremum
        for x in r:
            h = SIGN_PROBE * self.T
            if d(x - h) * d(x + h) < 0:
                return False
        return bool(np.all(vals >= -tol.timelaw_monotone * scale))


def cubic_rest_to_rest(L, T):
    """``s(t) = 3 L t^2/T^2 - 2 L t^3/T^3`` (zero speed at both ends).

    Raises
    ------
    TypeError
        For non-numeric ``L`` or ``T``.
    InputError
        For a non-finite value or a non-positive ``T``.

    Examples
    --------
    >>> from imagespace.dynamics.timelaw import cubic_rest_to_rest
    >>> cubic_rest_to_rest(1.5, 1.0).coefficients.tolist()
    [0.0, 0.0, 4.5, -3.0]
    """
    L, T = checks.scalar(L, "L"), checks.scalar(T, "T")
    if not T > 0:
        raise InputError(f"T must be positive, got {T}")
    return TimeLaw(np.array([0.0, 0.0, 3 * L / T**2, -2 * L / T**3]), T)


def sextic_through(T, L, Td, Ld, v, a):
    """The sixth-degree law with ``s(0) = s'(0) = 0``, ``s(T) = L``, ``s'(T) = 0``,
    ``s(Td) = Ld``, ``s'(Td) = v``, ``s''(Td) = a`` (seed 000, eq. 21).

    Parameters
    ----------
    T, L, Td, Ld, v, a : float

    Returns
    -------
    TimeLaw

    Raises
    ------
    TypeError
        For a non-numeric argument.
    InputError
        ``Td`` not inside ``(0, T)``, or a non-finite argument.

    Examples
    --------
    >>> from imagespace.dynamics.timelaw import sextic_through
    >>> law = sextic_through(1.0, 1.5, 0.62, 0.662, 1.7, 10.6)
    >>> [round(float(c), 1) for c in law.coefficients[2:]]
    [20.8, -88.0, 147.0, -104.0, 25.8]
    """
    T, L, Td, Ld, v, a = (checks.scalar(x, name) for x, name in
                          zip((T, L, Td, Ld, v, a), ("T", "L", "Td", "Ld", "v", "a")))
    if not 0 < Td < T:
        raise InputError(f"Td must be inside (0, T) = (0, {T}), got {Td}")
    rows, rhs = [], []

    def row(t, order):
        out = np.zeros(7)
        for k in range(order, 7):
            out[k] = np.prod(np.arange(k, k - order, -1)) * t ** (k - order)
        return out
    for t, order, val in ((0.0, 0, 0.0), (0.0, 1, 0.0), (T, 0, L), (T, 1, 0.0), (Td, 0, Ld), (Td, 1, v), (Td, 2, a)):
        rows.append(row(t, order))
        rhs.append(val)
    c = np.linalg.solve(np.array(rows), np.array(rhs))
    return TimeLaw(c, T)
