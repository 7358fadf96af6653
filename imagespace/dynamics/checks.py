"""Input checks shared by the modules of the dynamics subpackage (issue [14]): clear errors naming
the parameter. Internal helpers (not part of the public API, hence no ``__all__`` re-export from
:mod:`imagespace.dynamics`)."""

from __future__ import annotations

import numbers

import numpy as np
import sympy as sp

from .._validate import _short, as_count, as_float_array
from .._validate import as_tolerances as tolerances  # noqa: F401  (checks.tolerances for the dynamics modules)
from ..exceptions import InputError, InputTypeError

MAX_SAMPLES = 1_000_000
"""The largest sample count (``samples``, ``n``) the dynamics functions accept."""





def instance(value, cls, name, hint=""):
    """``value`` if it is an instance of ``cls``.

    Raises
    ------
    TypeError
        If it is not.

    Examples
    --------
    >>> from imagespace.dynamics.checks import instance
    >>> instance(2, int, "n")
    2
    """
    if not isinstance(value, cls):
        what = cls.__name__ if isinstance(cls, type) else " or ".join(c.__name__ for c in cls)
        article = "an" if what[0] in "AEIOU" else "a"
        raise InputTypeError(f"{name} must be {article} {what}{hint}, got {type(value).__name__} {_short(value)}")
    return value


def scalar(value, name, positive=False):
    """One real number as a float (positive if ``positive``).

    Raises
    ------
    TypeError
        For non-numeric input.
    InputError
        For several numbers, a non-finite one, or a non-positive one when ``positive``.

    Examples
    --------
    >>> from imagespace.dynamics.checks import scalar
    >>> scalar(2, "T", positive=True)
    2.0
    """
    v = as_float_array(value, name)
    if v.ndim != 0:
        raise InputError(f"{name} must be a single number, got shape {v.shape}")
    v = float(v)
    if positive and not v > 0:
        raise InputError(f"{name} must be positive, got {value!r}")
    return v


def vector(value, name, n=None):
    """A finite float vector, of length ``n`` if given.

    Raises
    ------
    TypeError
        For non-numeric input.
    InputError
        For a wrong shape or a non-finite entry.

    Examples
    --------
    >>> from imagespace.dynamics.checks import vector
    >>> vector([1, 2], "gravity", 2).tolist()
    [1.0, 2.0]
    """
    v = as_float_array(value, name)
    if v.ndim != 1 or (n is not None and len(v) != n):
        expected = f"({n},)" if n is not None else "(k,)"
        raise InputError(f"{name} must have shape {expected}, got shape {v.shape}")
    return v


def count(value, name, minimum=1):
    """A whole number between ``minimum`` and :data:`MAX_SAMPLES`.

    Raises
    ------
    TypeError
        For a non-integer.
    InputError
        Below ``minimum`` or above ``MAX_SAMPLES``.

    Examples
    --------
    >>> from imagespace.dynamics.checks import count
    >>> count(400, "samples", 2)
    400
    """
    v = as_count(value, name, minimum)
    if v > MAX_SAMPLES:
        raise InputError(f"{name} must be at most {MAX_SAMPLES}, got {v}")
    return v


def not_text(value, name):
    """Refuse strings anywhere in a (nested) symbolic input: sympify would evaluate them.

    Raises
    ------
    TypeError
        For a string, bytes, None, a complex number or an object that is neither a number nor a
        sympy object, anywhere in ``value``.

    Examples
    --------
    >>> from imagespace.dynamics.checks import not_text
    >>> not_text([1, 2.5], "centre")
    [1, 2.5]
    """
    if isinstance(value, (str, bytes)):
        raise InputTypeError(f"{name} must be a number or sympy expression, got the string {_short(value)}; "
                             "strings are never parsed")
    if isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            not_text(v, f"{name}[{i}]")
    elif isinstance(value, np.ndarray) and value.dtype.kind in "OUSV":
        for i, v in enumerate(value.ravel()):
            not_text(v, f"{name}[{i}]")
    elif value is None or isinstance(value, (complex, np.complexfloating)):
        raise InputTypeError(f"{name} must be a real number or sympy expression, got {_short(value)}")
    elif not isinstance(value, (numbers.Real, sp.Basic, sp.MatrixBase, np.ndarray)):
        raise InputTypeError(f"{name} must be a number or sympy expression, got {type(value).__name__} {_short(value)}")
    return value
