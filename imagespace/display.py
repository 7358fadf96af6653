"""Readable forms of the package's objects for notebooks (Jupyter).

Every result object of the public API already displays itself in Jupyter (``_repr_html_``: a
compact table; ``SingularitySurface`` also as LaTeX, ``_repr_latex_``). The symbolic polynomials
(:meth:`PlanarParallel.kinematic_polynomial`, :meth:`PlanarParallel.singularity_polynomial`) are
plain sympy ``Poly`` objects; :func:`latex_form` writes any of them collected by powers of the
chosen variables, e.g. ``IPython.display.Math(latex_form(m.kinematic_polynomial()))``.
"""

from __future__ import annotations

from typing import Any, Sequence

import sympy as sp

from .exceptions import InputTypeError
from ._html import latex_collected
from ._validate import as_count

__all__ = ["latex_form"]


def latex_form(poly: Any, by: Sequence[str] = ("x0", "x1"), digits: int = 6) -> str:
    """LaTeX of a polynomial collected by the monomials in the variables ``by``.

    One term per monomial ``x0**a * x1**b`` (its coefficient, a polynomial in the other
    variables, in parentheses), in order of descending degree. When the LaTeX would be longer
    than 2,000 characters the coefficients are rounded to ``digits`` significant digits
    (``sympy.N``), so a long symbolic kinematic polynomial stays readable.

    Parameters
    ----------
    poly : sympy.Poly or sympy expression
        E.g. :meth:`PlanarParallel.kinematic_polynomial` or :attr:`SingularitySurface.polynomial`.
    by : sequence of str
        Names of the variables to collect by (matched by name; absent ones are ignored).
    digits : int
        Significant digits of the coefficients of a long form (at least 1).

    Returns
    -------
    str
        LaTeX without math delimiters (wrap in ``$...$`` or ``IPython.display.Math``).

    Raises
    ------
    TypeError
        If ``poly`` is not a sympy polynomial or expression, ``by`` is not a sequence of names,
        or ``digits`` is not a whole number.
    InputError
        If ``digits`` is below 1.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.display import latex_form
    >>> m = isp.examples.stigger_husty()
    >>> text = latex_form(m.singularity_polynomial())
    >>> text.startswith("-") and "x_{0}^{3}" in text
    True
    >>> long = latex_form(m.kinematic_polynomial(), digits=3)   # long: coefficients to 3 digits
    >>> long.startswith("x_{0}^{6}"), "1.52" in long
    (True, True)
    """
    if not isinstance(poly, (sp.Poly, sp.Expr)):
        raise InputTypeError(f"poly must be a sympy Poly or expression, got {type(poly).__name__} {repr(poly)[:80]}")
    if isinstance(by, str) or not all(isinstance(b, str) for b in by):
        raise InputTypeError(f"by must be a sequence of variable names such as ('x0', 'x1'), got {repr(by)[:80]}")
    digits = as_count(digits, "digits", 1)
    return latex_collected(poly, by=tuple(by), digits=digits)
