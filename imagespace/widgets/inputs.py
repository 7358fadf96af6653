"""The explorers' inputs: exact joint values typed as text, slider ranges from a design."""

from __future__ import annotations

import re
from fractions import Fraction

import numpy as np

from .._validate import as_joint_vector
from ..core.mechanism import check_mechanism
from ..exceptions import InputError, InputTypeError

__all__ = ["parse_joint_value", "joint_ranges"]

_PI_FORM = re.compile(r"^\s*([-+]?)\s*([0-9]*\.?[0-9]*(?:[eE][-+]?[0-9]+)?)\s*\*?\s*pi\s*(?:/\s*([0-9]+))?\s*$")


def parse_joint_value(text, name="q"):
    """An exact joint value from text: a decimal or fraction (``13.25``, ``27/2``) or a rational
    multiple of pi (``pi/2``, ``-3/4*pi`` is not accepted; write ``-0.75*pi`` or ``-3*pi/4``).

    The text is parsed with :class:`fractions.Fraction` (never evaluated as Python).

    Parameters
    ----------
    text : str
    name : str
        The parameter name used in error messages.

    Returns
    -------
    sympy.Rational or sympy expression
        The exact value (``sympy.pi`` times a rational for the pi forms).

    Raises
    ------
    TypeError
        ``text`` is not a string.
    InputError
        The text is not a number, a fraction or a rational multiple of pi.

    Examples
    --------
    >>> from imagespace.widgets import parse_joint_value
    >>> parse_joint_value("27/2"), parse_joint_value("-3*pi/4")
    (27/2, -3*pi/4)
    """
    import sympy as sp

    if not isinstance(text, str):
        raise InputTypeError(f"{name} must be text such as '27/2' or 'pi/3', got {type(text).__name__}")
    if len(text) > 100 or re.search(r"[eE][-+]?[0-9]{4,}", text):
        raise InputError(f"{name} must be a number of float size (at most 100 characters, exponent "
                         f"below 1000), got {text[:40]!r}")
    m = _PI_FORM.match(text)
    try:
        if m:
            sign, coef, den = m.groups()
            c = Fraction(coef) if coef else Fraction(1)
            c = c / int(den) if den else c
            c = -c if sign == "-" else c
            return sp.Rational(c.numerator, c.denominator) * sp.pi
        f = Fraction(text.strip())
    except (ValueError, ZeroDivisionError):
        raise InputError(f"{name} must be a number, a fraction such as 27/2 or a rational multiple of pi "
                         f"such as 3*pi/4; got {text!r}") from None
    if not abs(f) < Fraction(10) ** 300:
        raise InputError(f"{name} must be within the float range (|value| < 1e300), got {text!r}")
    return sp.Rational(f.numerator, f.denominator)


def joint_ranges(manipulator, q):
    """Slider ranges ``(3, 2)`` for the actuated joints, from the design and the joint values ``q``.

    Angles get ``[-pi, pi]``. An RPR leg length gets ``[0, L]`` and a slider travel
    ``[q - L/2, q + L/2]``, where ``L`` is twice the larger of ``|q_i|`` and the design's size (the
    spread of its base anchors plus that of its platform anchors).

    Parameters
    ----------
    manipulator : PlanarParallel
    q : (3,) float

    Returns
    -------
    (3, 2) float

    Raises
    ------
    InputError
        ``q`` is not three finite numbers.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.widgets import joint_ranges
    >>> m = isp.examples.stigger_husty()
    >>> joint_ranges(m, m.q_example_float).round(3).tolist()
    [[0.0, 40.0], [0.0, 40.0], [-6.75, 33.25]]
    """
    check_mechanism(manipulator)
    qv = as_joint_vector(q)
    geo = [leg.geometry(exact=False) for leg in manipulator.legs]
    base = np.array([g["base"] for g in geo], dtype=float)
    plat = np.array([g["platform"] for g in geo], dtype=float)
    size = float(np.max(np.ptp(base, axis=0)) + np.max(np.ptp(plat, axis=0)))
    out = np.empty((3, 2))
    for i, leg in enumerate(manipulator.legs):
        L = 2 * max(abs(qv[i]), size, 1.0)
        if leg.actuated_is_angle:
            out[i] = (-np.pi, np.pi)
        elif leg.joints == "RPR":
            out[i] = (0.0, L)
        else:
            out[i] = (qv[i] - L / 2, qv[i] + L / 2)
    return out
