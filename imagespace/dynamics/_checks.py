"""Private input checks of the dynamics subpackage (issue [14]): clear errors naming the parameter."""

from __future__ import annotations

import numbers

import numpy as np
import sympy as sp

from .._validate import _short, as_count, as_float_array
from ..exceptions import InputError

MAX_SAMPLES = 1_000_000
"""The largest sample count (``samples``, ``n``) the dynamics functions accept."""


def instance(value, cls, name, hint=""):
    if not isinstance(value, cls):
        what = cls.__name__ if isinstance(cls, type) else " or ".join(c.__name__ for c in cls)
        article = "an" if what[0] in "AEIOU" else "a"
        raise TypeError(f"{name} must be {article} {what}{hint}, got {type(value).__name__} {_short(value)}")
    return value


def scalar(value, name, positive=False):
    v = as_float_array(value, name)
    if v.ndim != 0:
        raise InputError(f"{name} must be a single number, got shape {v.shape}")
    v = float(v)
    if positive and not v > 0:
        raise InputError(f"{name} must be positive, got {value!r}")
    return v


def vector(value, name, n=None):
    v = as_float_array(value, name)
    if v.ndim != 1 or (n is not None and len(v) != n):
        expected = f"({n},)" if n is not None else "(k,)"
        raise InputError(f"{name} must have shape {expected}, got shape {v.shape}")
    return v


def count(value, name, minimum=1):
    v = as_count(value, name, minimum)
    if v > MAX_SAMPLES:
        raise InputError(f"{name} must be at most {MAX_SAMPLES}, got {v}")
    return v


def not_text(value, name):
    """Refuse strings anywhere in a (nested) symbolic input: sympify would evaluate them."""
    if isinstance(value, (str, bytes)):
        raise TypeError(f"{name} must be a number or sympy expression, got the string {_short(value)}; "
                        "strings are never parsed")
    if isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            not_text(v, f"{name}[{i}]")
    elif isinstance(value, np.ndarray) and value.dtype.kind in "OUSV":
        for i, v in enumerate(value.ravel()):
            not_text(v, f"{name}[{i}]")
    elif value is None or isinstance(value, (complex, np.complexfloating)):
        raise TypeError(f"{name} must be a real number or sympy expression, got {_short(value)}")
    elif not isinstance(value, (numbers.Real, sp.Basic, sp.MatrixBase, np.ndarray)):
        raise TypeError(f"{name} must be a number or sympy expression, got {type(value).__name__} {_short(value)}")
    return value
