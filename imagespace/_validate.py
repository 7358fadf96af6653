"""The one place where user input becomes checked float arrays or sympy objects."""

from __future__ import annotations

import itertools
import numbers

import numpy as np
import sympy as sp

from .exceptions import InputError, InputTypeError, RowIndexError
from .tolerances import TOLERANCES, Tolerances

__all__ = [
    "is_symbolic",
    "as_float_array",
    "as_exact",
    "as_point",
    "check_positive",
    "as_flag",
    "as_count",
    "as_scalar",
    "as_sympy_entry",
    "as_sympy_vector",
    "as_fraction",
    "check_squares",
    "as_joint_vector",
    "as_box",
    "as_index",
    "as_tolerances",
    "warn_angle_units",
    "finite_rows",
]


def finite_rows(Q) -> np.ndarray:
    """Which rows of a 2-d float array ``Q`` (n, k) are finite in every column: ``(n,)`` bool.

    The columns are combined one by one (numpy's reductions along a short last axis take
    several times longer on batches of joint vectors).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace._validate import finite_rows
    >>> finite_rows(np.array([[1.0, 2.0, 3.0], [1.0, np.inf, 3.0], [np.nan, 0.0, 0.0]])).tolist()
    [True, False, False]
    """
    F = np.isfinite(Q)
    ok = np.ones(F.shape[0], dtype=bool)
    for j in range(F.shape[1]):
        ok &= F[:, j]
    return ok


def warn_angle_units(values, is_angle, name: str = "q") -> None:
    """Warn (:class:`~imagespace.exceptions.AngleUnitWarning`, once) when an entry of ``values``
    ``(..., k)`` whose column is an angle (``is_angle[i]``) lies outside ``[-2 pi, 2 pi]``: angles
    are radians, and such a value is most likely in degrees.

    Examples
    --------
    >>> import warnings
    >>> from imagespace._validate import warn_angle_units
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     warn_angle_units([90.0, 4.0, 4.0], [True, False, False])
    >>> "numpy.radians" in str(w[0].message)
    True
    """
    import warnings

    from .exceptions import AngleUnitWarning

    arr = np.asarray(values, dtype=float)
    for i, angle in enumerate(is_angle):
        if not angle:
            continue
        col = arr[..., i]
        bad = np.isfinite(col) & (np.abs(col) > 2 * np.pi)
        if np.any(bad):
            first = float(np.ravel(col)[np.flatnonzero(np.ravel(bad))[0]])
            n = int(bad.sum())
            rows = f" ({n} row{'' if n == 1 else 's'})" if col.ndim else ""
            warnings.warn(f"{name}[{i}] = {first:g}{rows} is outside [-2 pi, 2 pi] for an actuated angle: angles "
                          f"are in radians; for degrees pass numpy.radians of the angle "
                          f"({name}[{i}] = numpy.radians({first:g}) = {np.radians(first):.6g})",
                          AngleUnitWarning, stacklevel=4)
            return


def is_symbolic(value) -> bool:
    """True if ``value`` (or any element of it) is a sympy object."""
    if isinstance(value, sp.Basic):
        return True
    if isinstance(value, sp.MatrixBase):
        return True
    if isinstance(value, (list, tuple)):
        return any(is_symbolic(v) for v in value)
    if isinstance(value, np.ndarray) and value.dtype == object:
        return any(is_symbolic(v) for v in value.ravel())
    return False


def _object_entries(value):
    """The scalar entries of a (nested) sequence, object array or sympy matrix, in order."""
    if isinstance(value, sp.MatrixBase):
        yield from value
    elif isinstance(value, np.ndarray):
        if value.dtype == object:
            for v in value.ravel():
                yield from _object_entries(v)
        else:
            yield from value.ravel()
    elif isinstance(value, (list, tuple)):
        for v in value:
            yield from _object_entries(v)
    else:
        yield value


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


_REFUSED_ENTRY_BASES = (str, bytes, bool, np.bool_, complex)      # numpy's str_, bytes_, complex128 too
_PLAIN_NUMBER_TYPES = frozenset({int, float, np.float64, np.int64})


def _flat_entries(value, raw):
    """The scalar entries of a Python sequence (rows of scalars chained without an object array:
    ~10x faster for long lists), else of its object array."""
    if raw.ndim == 2 and isinstance(value, (list, tuple)) and all(isinstance(r, (list, tuple)) for r in value):
        return list(itertools.chain.from_iterable(value))
    return np.asarray(value, dtype=object).ravel()


def as_float_array(value, name: str, last: int | None = None, allow_batch: bool = True,
                   finite: bool = True) -> np.ndarray:
    """Convert ``value`` to a float64 array and check its shape and finiteness.

    Parameters
    ----------
    value : array_like
        The user's input.
    name : str
        The parameter name used in error messages.
    last : int, optional
        Required length of the last axis (``None``: a scalar or any 1-d length).
    allow_batch : bool
        Allow a leading batch axis, i.e. shape ``(n, last)`` as well as ``(last,)``.
    finite : bool
        Reject NaN and infinity.
    """
    if isinstance(value, (str, bytes)) or value is None:
        raise InputTypeError(f"{name} must be numeric array_like, got {type(value).__name__} {_short(value)}")
    if is_symbolic(value):
        # a string, bool or complex beside a sympy number would pass through float(): refuse it
        for v in _object_entries(value):
            if isinstance(v, (str, bytes, np.str_, np.bytes_)):
                raise InputTypeError(f"{name} must hold numbers, got the string {_short(v)}; strings are never parsed")
            if v is None or isinstance(v, (bool, np.bool_, complex, np.complexfloating)):
                raise InputTypeError(f"{name} must hold real numbers, got {type(v).__name__} {_short(v)}")
        try:
            value = np.array([float(v) for v in np.ravel(np.array(value, dtype=object))],
                             dtype=float).reshape(np.shape(np.array(value, dtype=object)))
        except (TypeError, ValueError):
            raise InputTypeError(f"{name} must be numeric, got the symbolic value {_short(value)}; "
                                 "substitute numbers first or use the symbolic method") from None
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):
        raise InputTypeError(f"{name} must be numeric array_like, got {_short(value)}") from None
    if raw.dtype.kind == "c":
        raise InputTypeError(f"{name} must be real, got the complex array {_short(value)}")
    if raw.dtype.kind == "b":
        raise InputTypeError(f"{name} must be numeric, got booleans {_short(value)}")
    if raw.dtype.kind in "USV":
        raise InputTypeError(f"{name} must be numeric, got strings {_short(value)}; strings are never parsed")
    if raw.dtype.kind == "O" or not isinstance(value, np.ndarray):
        # python sequences of any length: a bool or a string among numbers would be silently
        # converted (the entries' types are gathered at C speed, ~30 ms per million entries)
        entries = _flat_entries(value, raw)
        if any(issubclass(t, _REFUSED_ENTRY_BASES) for t in set(map(type, entries)) - _PLAIN_NUMBER_TYPES):
            for v in entries:
                if isinstance(v, _REFUSED_ENTRY_BASES):
                    raise InputTypeError(f"{name} must hold real numbers, got {type(v).__name__} {_short(v)}")
    try:
        arr = np.asarray(raw, dtype=float)
    except OverflowError:
        raise InputError(f"{name} must be within the float range, got {_short(value)}") from None
    except (TypeError, ValueError):
        raise InputTypeError(f"{name} must be numeric array_like, got {_short(value)}") from None
    if last is not None:
        ok = arr.ndim >= 1 and arr.shape[-1] == last and (arr.ndim == 1 or (allow_batch and arr.ndim == 2))
        if not ok:
            expected = f"({last},)" + (f" or (n, {last})" if allow_batch else "")
            raise InputError(f"{name} must have shape {expected}, got shape {arr.shape}")
    if finite and not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite, got {_short(value)}")
    return arr


def as_exact(value, name: str):
    """Convert a number to an exact sympy number (floats become exact binary rationals).

    Sympy expressions (including symbols) pass through unchanged.
    """
    if isinstance(value, sp.Basic):
        if not isinstance(value, sp.Expr):
            raise InputTypeError(f"{name} must be a real number or sympy expression, got the sympy "
                                 f"{type(value).__name__} {_short(value)}")
        if isinstance(value, sp.Float):
            return sp.Rational(value)
        if value.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
            raise InputError(f"{name} must be finite, got {value}")
        if value.has(sp.I) and not value.free_symbols:
            raise InputTypeError(f"{name} must be real, got the complex number {_short(value)}")
        return value
    if isinstance(value, (bool, np.bool_)):
        raise InputTypeError(f"{name} must be a number, got the boolean {value}")
    if isinstance(value, numbers.Integral):
        return sp.Integer(int(value))
    if isinstance(value, numbers.Rational):
        return sp.Rational(value.numerator, value.denominator)
    if isinstance(value, numbers.Real):
        v = float(value)
        if not np.isfinite(v):
            raise InputError(f"{name} must be finite, got {v}")
        return sp.Rational(v)
    raise InputTypeError(f"{name} must be a real number or sympy expression, got {type(value).__name__} {_short(value)}")


def as_point(value, name: str):
    """A planar point ``(2,)`` as a tuple of two exact sympy numbers or expressions."""
    if isinstance(value, (str, bytes)) or value is None:
        raise InputTypeError(f"{name} must be a 2-vector, got {_short(value)}")
    try:
        items = list(value)
    except TypeError:
        raise InputTypeError(f"{name} must be a 2-vector (x, y), got {_short(value)}") from None
    if len(items) != 2:
        raise InputError(f"{name} must have shape (2,), got {len(items)} entries: {_short(value)}")
    return tuple(as_exact(v, f"{name}[{i}]") for i, v in enumerate(items))


def as_flag(value, name: str) -> bool:
    """A boolean option (``True``/``False``, numpy bools), refusing anything else ('yes', 1.0 ...).

    Examples
    --------
    >>> from imagespace._validate import as_flag
    >>> as_flag(True, "certify")
    True
    """
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise InputTypeError(f"{name} must be True or False, got {type(value).__name__} {_short(value)}")


def as_count(value, name: str, minimum: int = 1) -> int:
    """A whole number ``>= minimum`` (ints, integral numpy ints); floats such as 2.5 are refused.

    Examples
    --------
    >>> from imagespace._validate import as_count
    >>> as_count(65536, "chunk_size")
    65536
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
        raise InputTypeError(f"{name} must be a whole number, got {type(value).__name__} {_short(value)}")
    if int(value) < minimum:
        raise InputError(f"{name} must be at least {minimum}, got {value}")
    return int(value)


def check_positive(value, name: str, allow_zero: bool = False):
    """Reject a non-positive (or negative) exact or float number; symbols pass."""
    if isinstance(value, sp.Basic) and value.free_symbols:
        return value
    v = float(value)
    if v < 0 or (v == 0 and not allow_zero):
        expected = "a non-negative number" if allow_zero else "a positive number"
        raise InputError(f"{name} must be {expected}, got {value}")
    return value


_STRINGS = (str, bytes, np.str_, np.bytes_)


def _holds_string(value) -> bool:
    if isinstance(value, _STRINGS):
        return True
    if isinstance(value, np.ndarray):
        return value.dtype.kind in "USV" or (value.dtype.kind == "O" and any(map(_holds_string, value.ravel())))
    if isinstance(value, (list, tuple, set, frozenset)):
        return any(map(_holds_string, value))
    if isinstance(value, dict):
        return any(map(_holds_string, value.keys())) or any(map(_holds_string, value.values()))
    return False


def as_sympy(value, name: str = "value"):
    """``sympy.sympify`` that never parses: the library's one call of it. A string, or a container
    holding one, is refused (sympify would evaluate it as Python code); sympy objects pass as
    they are.

    Examples
    --------
    >>> from imagespace._validate import as_sympy
    >>> as_sympy(0.5), as_sympy([1, 2])
    (0.500000000000000, [1, 2])
    """
    if isinstance(value, sp.Basic):
        return value
    if _holds_string(value):
        raise InputTypeError(f"{name} must be numbers or sympy expressions, got the string "
                             f"{_short(value)}; strings are never parsed")
    return sp.sympify(value)


def as_sympy_entry(value, name: str):
    """One scalar entry of a symbolic input as a sympy object, without ever parsing a string.

    Sympy expressions pass unchanged (sympy booleans, ``nan``, ``zoo``, infinities and
    non-real numbers such as ``I`` are refused); python and numpy integers become
    :class:`sympy.Integer`, fractions :class:`sympy.Rational` and floats :class:`sympy.Float`
    (as :func:`sympy.sympify` would make them). Strings, bytes, ``None``, bools, complex numbers,
    sequences and non-finite floats are refused: a string handed to ``sympify`` is evaluated as
    Python code.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace._validate import as_sympy_entry
    >>> as_sympy_entry(2, "x"), as_sympy_entry(0.5, "x"), as_sympy_entry(sp.Symbol("a"), "x")
    (2, 0.500000000000000, a)
    """
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, (str, bytes, np.str_, np.bytes_)):
        raise InputTypeError(f"{name} must be a number or sympy expression, got the string {_short(value)}; "
                             "strings are never parsed")
    if isinstance(value, sp.Basic):
        if not isinstance(value, sp.Expr):
            raise InputTypeError(f"{name} must be a number or sympy expression, got the sympy "
                                 f"{type(value).__name__} {_short(value)}")
        if value.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
            raise InputError(f"{name} must be finite, got {_short(value)}")
        if value.has(sp.I) and not value.free_symbols:
            raise InputTypeError(f"{name} must be real, got the complex number {_short(value)}")
        return value
    if value is None or isinstance(value, (bool, np.bool_)):
        raise InputTypeError(f"{name} must be a number or sympy expression, got {type(value).__name__} {_short(value)}")
    if isinstance(value, (complex, np.complexfloating)):
        raise InputTypeError(f"{name} must be real, got the complex number {_short(value)}")
    if isinstance(value, (numbers.Integral, np.integer)):
        return sp.Integer(int(value))
    if isinstance(value, numbers.Rational):
        return sp.Rational(value.numerator, value.denominator)
    if isinstance(value, (numbers.Real, np.floating)):
        v = float(value)
        if not np.isfinite(v):
            raise InputError(f"{name} must be finite, got {v}")
        return sp.Float(v)
    raise InputTypeError(f"{name} must be a number or sympy expression, got {type(value).__name__} {_short(value)}")


def as_sympy_vector(value, name: str, n: int) -> list:
    """The ``n`` entries of a vector on a symbolic face as sympy objects; strings are never parsed.

    ``value`` is a list, tuple, 1-d numpy array or a sympy row or column vector; each entry goes
    through :func:`as_sympy_entry` (numbers become sympy numbers, sympy expressions pass, strings,
    bytes, ``None``, bools, complex numbers, nested sequences and non-finite numbers are refused
    with the entry's index in the message). This is the one way user input reaches sympy on the
    symbolic faces: :func:`sympy.sympify` on a string evaluates it as Python code.

    Parameters
    ----------
    value : sequence or sympy.Matrix
        The user's vector.
    name : str
        The parameter name used in error messages.
    n : int
        The required number of entries.

    Returns
    -------
    list of sympy.Expr

    Raises
    ------
    TypeError
        ``value`` is not a sequence (a string, a number, ``None``, a dict ...), or an entry is not a
        real number or sympy expression.
    InputError
        A wrong number of entries, a matrix that is not a vector, a numpy array that is not 1-d,
        or a non-finite entry.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace._validate import as_sympy_vector
    >>> as_sympy_vector([sp.Symbol("a"), 0, 0.5], "t", 3)
    [a, 0, 0.500000000000000]
    >>> as_sympy_vector([sp.Symbol("a"), "1", 0], "t", 3)
    Traceback (most recent call last):
    ...
    imagespace.exceptions.InputTypeError: t[1] must be a number or sympy expression, got the string '1'; strings are never parsed
    """
    if isinstance(value, sp.MatrixBase):
        if 1 not in value.shape:
            raise InputError(f"{name} must be a vector of {n} entries, got a {value.shape} matrix")
        items = list(value)
    elif isinstance(value, np.ndarray):
        if value.ndim != 1:
            raise InputError(f"{name} must have shape ({n},) on the symbolic face, got shape {value.shape}")
        items = list(value)
    elif isinstance(value, (list, tuple)):
        items = list(value)
    else:
        raise InputTypeError(f"{name} must be a sequence of {n} numbers or sympy expressions, got "
                             f"{type(value).__name__} {_short(value)}")
    if len(items) != n:
        raise InputError(f"{name} must have {n} entries, got {len(items)}: {_short(value)}")
    return [as_sympy_entry(v, f"{name}[{i}]") for i, v in enumerate(items)]


def as_fraction(value, name: str):
    """One real number as an exact :class:`fractions.Fraction` (a float is its binary rational).

    Integers (python and numpy), fractions, sympy rationals and finite floats are accepted; strings
    (``Fraction("1/3")`` would parse them), bytes, ``None``, bools, complex numbers, sequences and
    non-finite floats are refused.

    Parameters
    ----------
    value : int, float, Fraction or sympy.Rational
    name : str
        The parameter name used in error messages.

    Returns
    -------
    fractions.Fraction

    Raises
    ------
    TypeError
        Not a real number.
    InputError
        NaN or infinity.

    Examples
    --------
    >>> from imagespace._validate import as_fraction
    >>> as_fraction(0.1, "length") == 3602879701896397 / 36028797018963968, as_fraction(3, "length")
    (True, Fraction(3, 1))
    """
    from fractions import Fraction

    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, (str, bytes, np.str_, np.bytes_)):
        raise InputTypeError(f"{name} must be a number, got the string {_short(value)}; strings are never parsed")
    if value is None or isinstance(value, (bool, np.bool_)):
        raise InputTypeError(f"{name} must be a number, got {type(value).__name__} {_short(value)}")
    if isinstance(value, sp.Rational):
        return Fraction(int(value.p), int(value.q))
    if isinstance(value, (numbers.Integral, np.integer)):
        return Fraction(int(value))
    if isinstance(value, numbers.Rational):
        return Fraction(int(value.numerator), int(value.denominator))
    if isinstance(value, (numbers.Real, np.floating)) and not isinstance(value, sp.Basic):
        v = float(value)
        if not np.isfinite(v):
            raise InputError(f"{name} must be finite, got {v}")
        return Fraction(v)
    raise InputTypeError(f"{name} must be a real number (int, float, Fraction), got {type(value).__name__} "
                         f"{_short(value)}")


def check_squares(values, name: str) -> None:
    """Refuse checked finite floats whose squares leave the float range: ``v * v`` overflows
    (``|v|`` above about 1.3e154) or a non-zero ``v`` squares to zero (``|v|`` below about 1e-162).
    Lengths enter the constraint quadrics squared; beyond these bounds the quadric would hold
    infinity or lose the length without a trace.

    Parameters
    ----------
    values : numpy.ndarray
        Finite floats (already checked, e.g. by :func:`as_float_array`).
    name : str
        The parameter name used in error messages.

    Raises
    ------
    InputError
        Naming the parameter, the first offending value and the bounds.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace._validate import check_squares
    >>> check_squares(np.array([1.0, 2.0, 1e150]), "lengths")
    >>> check_squares(np.array([1.0, 1e200]), "lengths")
    Traceback (most recent call last):
    ...
    imagespace.exceptions.InputError: lengths must have squares within the float range (|value| between about 1e-162 and 1.3e154), got 1e+200
    """
    v = np.asarray(values, dtype=float)
    with np.errstate(over="ignore", under="ignore"):
        sq = v * v
    bad = ~np.isfinite(sq) | ((sq == 0) & (v != 0))
    if np.any(bad):
        first = float(v[bad].ravel()[0])
        raise InputError(f"{name} must have squares within the float range (|value| between about 1e-162 "
                         f"and 1.3e154), got {first:g}")


def as_scalar(value, name: str, finite: bool = True) -> float:
    """One real number as a float (no bools, strings, complex, or arrays of several entries).

    Examples
    --------
    >>> from imagespace._validate import as_scalar
    >>> as_scalar(0.25, "radius")
    0.25
    """
    v = as_float_array(value, name, finite=finite)
    if v.ndim != 0:
        raise InputError(f"{name} must be a single number, got shape {v.shape}")
    return float(v)


def as_seconds(value, name: str = "timeout") -> float:
    """A wait in seconds: one finite number, zero or more.

    Examples
    --------
    >>> from imagespace._validate import as_seconds
    >>> as_seconds(2)
    2.0
    """
    v = as_scalar(value, name)
    if v < 0:
        raise InputError(f"{name} must be a number of seconds (0 or more), got {v!r}")
    return v


def as_joint_vector(value, name: str = "q", count: int = 3, allow_batch: bool = False) -> np.ndarray:
    """Joint values as a finite float array of shape ``(count,)`` (or ``(n, count)`` for a batch).

    Parameters
    ----------
    value : array_like
        The user's joint values (radians for revolute joints, lengths for prismatic ones).
    name : str
        The parameter name used in error messages.
    count : int
        Number of joints (3 for the planar 3-legged manipulators).
    allow_batch : bool
        Also accept a batch of shape ``(n, count)``.

    Returns
    -------
    numpy.ndarray
        float64, shape ``(count,)`` or ``(n, count)``.

    Raises
    ------
    TypeError
        For strings, booleans, complex or non-numeric input.
    InputError
        For a wrong shape or a non-finite entry.

    Examples
    --------
    >>> from imagespace._validate import as_joint_vector
    >>> as_joint_vector([1, 2, 3.5])
    array([1. , 2. , 3.5])
    """
    return as_float_array(value, name, last=count, allow_batch=allow_batch)


def as_box(value, name: str = "box", dim: int = 3, required: bool = True):
    """An axis-aligned box ``((min_0, max_0), ..., (min_{dim-1}, max_{dim-1}))`` as a ``(dim, 2)`` array.

    Every side must have ``min < max`` and a length within the float range.

    Parameters
    ----------
    value : array_like or None
        The user's box.
    name : str
        The parameter name used in error messages.
    dim : int
        Number of axes (3 for image-space boxes, 2 for planar workspace boxes).
    required : bool
        If False, ``None`` is passed through (returned as ``None``).

    Returns
    -------
    numpy.ndarray or None
        float64, shape ``(dim, 2)``.

    Raises
    ------
    TypeError
        For non-numeric input.
    InputError
        For a missing box, a wrong shape, an empty side, a non-finite entry or a side whose length
        overflows.

    Examples
    --------
    >>> from imagespace._validate import as_box
    >>> as_box([[-1, 1], [0, 2]], dim=2)
    array([[-1.,  1.],
           [ 0.,  2.]])
    """
    axes = ", ".join(f"(min_{i}, max_{i})" for i in range(dim))
    if value is None:
        if required:
            raise InputError(f"{name} ({axes}) is needed here, got None")
        return None
    b = as_float_array(value, name, allow_batch=True)
    if b.shape != (dim, 2):
        raise InputError(f"{name} must be ({axes}), shape ({dim}, 2); got shape {b.shape}")
    if np.any(b[:, 1] <= b[:, 0]):
        bad = [i for i in range(dim) if b[i, 1] <= b[i, 0]]
        raise InputError(f"{name} is empty along axis {bad}: need min < max, got {b.tolist()}")
    with np.errstate(over="ignore"):
        sides = b[:, 1] - b[:, 0]
    if not np.all(np.isfinite(sides)):
        raise InputError(f"{name} sides must be within the float range (max - min overflows), got {b.tolist()}")
    return b


def as_row_index(value, size: int, name: str = "i") -> int:
    """A row index of a batch of ``size`` rows, negative ones counted from the end (as a list's).

    Raises
    ------
    InputTypeError
        For a non-integer (floats, bools, strings).
    RowIndexError
        Outside ``-size .. size - 1`` (an :class:`InputError` and an :class:`IndexError`).

    Examples
    --------
    >>> from imagespace._validate import as_row_index
    >>> as_row_index(-1, 3)
    2
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise InputTypeError(f"{name} must be a row index (an integer), got {type(value).__name__} {_short(value)}")
    if not -size <= int(value) < size:
        raise RowIndexError(f"{name} = {int(value)} is out of range for a batch of {size} rows "
                            f"(valid: {-size}..{size - 1})")
    return int(value) % size


def as_row_indices(rows, n: int, name: str = "rows") -> np.ndarray:
    """Distinct row indices (int64) from 0 to n - 1, given as integers (negative ones wrap) or as
    a boolean mask of shape ``(n,)``.

    Examples
    --------
    >>> from imagespace._validate import as_row_indices
    >>> as_row_indices([-1, 0], 3).tolist(), as_row_indices([True, False, True], 3).tolist()
    ([2, 0], [0, 2])
    """
    if isinstance(rows, (str, bytes)) or rows is None:
        raise InputTypeError(f"{name} must be integer indices or a boolean mask, got {type(rows).__name__}")
    try:
        r = np.atleast_1d(np.asarray(rows))
    except (TypeError, ValueError):
        raise InputTypeError(f"{name} must be integer indices or a boolean mask, got {_short(rows)}") from None
    if r.dtype == bool:
        if r.shape != (n,):
            raise InputError(f"a boolean {name} mask must have shape ({n},), got {r.shape}")
        return np.flatnonzero(r)
    if r.size and r.dtype.kind not in "iu":
        raise InputTypeError(f"{name} must be integer indices, got dtype {r.dtype}")
    r = r.astype(np.int64).ravel()
    if r.size and (r.min() < -n or r.max() >= n):
        raise RowIndexError(f"{name} must lie in -{n} .. {n - 1}, got {r.min()} .. {r.max()}")
    r = np.where(r < 0, r + n, r)
    if np.unique(r).size != r.size:
        raise InputError(f"{name} must be distinct")
    return r


def as_index(value, name: str, size: int) -> int:
    """A whole number in ``range(size)`` (negative indices are refused, not wrapped).

    Raises
    ------
    TypeError
        For a non-integer (floats, bools, strings).
    InputError
        For an index outside ``0 .. size - 1``.

    Examples
    --------
    >>> from imagespace._validate import as_index
    >>> as_index(2, "mode", 3)
    2
    """
    i = as_count(value, name, minimum=0)
    if i >= size:
        raise InputError(f"{name} must be in 0..{size - 1}, got {i}")
    return i


def as_tolerances(value, name: str = "tolerances") -> Tolerances:
    """A ``tolerances=None`` keyword at a public boundary: ``None`` gives the defaults
    (:data:`~imagespace.tolerances.TOLERANCES`), a :class:`~imagespace.tolerances.Tolerances`
    passes, anything else is refused.

    Raises
    ------
    TypeError
        If ``value`` is neither None nor a :class:`~imagespace.tolerances.Tolerances`.

    Examples
    --------
    >>> from imagespace._validate import as_tolerances
    >>> as_tolerances(None).duplicate
    1e-07
    """
    if value is None:
        return TOLERANCES
    if not isinstance(value, Tolerances):
        raise InputTypeError(f"{name} must be an imagespace.Tolerances or None (the defaults), got "
                             f"{type(value).__name__} {_short(value)}")
    return value
