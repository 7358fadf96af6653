"""Compact summaries of result objects for the terminal and for Jupyter (a private utility module).

The results' ``__repr__`` and ``_repr_html_`` are built here: no array is dumped (an array shows
its shape and dtype, a boolean mask how many entries are set), numbers are printed to 6
significant digits, every value in HTML is escaped with :func:`html.escape`, and a text summary
is wrapped into lines of at most :data:`WIDTH` characters, so no result prints more than a few
lines however many rows it holds.
"""

from __future__ import annotations

import dataclasses
import html
import numbers
from collections import Counter
from typing import Any, Iterable, Optional, Sequence

import numpy as np
from ._validate import as_sympy

WIDTH = 100
"""Line width of a wrapped text summary (layout only, decides nothing)."""

INLINE = 80
"""Longest text of a value or a short container shown inline; longer ones are summarised."""


def fmt(value: Any, digits: int = 6) -> str:
    """Compact text of one value: numbers to ``digits`` significant digits, arrays as shape and dtype.

    Small numeric vectors (at most 6 entries) and short containers are shown inline, string
    arrays as the count of each value, longer containers as their length and item type; other
    objects by their own ``repr`` when it is a single short line, else by their type name.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace._html import fmt
    >>> fmt(np.pi), fmt(np.zeros((1000, 6, 4))), fmt(np.array([True, False, True]))
    ('3.14159', 'array(1000, 6, 4) float64', '[True, False, True]')
    >>> fmt(np.ones(10, dtype=bool)), fmt([1.0, 2.5]), fmt(tuple(range(30)))
    ('bool array(10), 10 True', '[1, 2.5]', '(30 × int)')
    >>> fmt(np.array(["regular"] * 9 + ["both"]))
    'str array(10) {both: 1, regular: 9}'
    """
    if value is None or isinstance(value, (bool, np.bool_)):
        return str(bool(value)) if value is not None else "None"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.{digits}g}"
    if isinstance(value, (complex, np.complexfloating)):
        return f"{complex(value):.{digits}g}"
    if isinstance(value, str):
        return repr(value) if len(value) <= INLINE else repr(value[: INLINE - 3] + "...")
    if isinstance(value, np.ndarray):
        return _fmt_array(value, digits)
    if isinstance(value, dict):
        return _fmt_dict(value, digits)
    if isinstance(value, (list, tuple)):
        return _fmt_sequence(value, digits)
    text = repr(value)
    if "\n" in text or len(text) > INLINE:
        return f"<{type(value).__name__}>"
    return text


def _fmt_array(a: np.ndarray, digits: int) -> str:
    shape = ", ".join(str(s) for s in a.shape)
    if a.ndim <= 1 and a.size <= 6 and a.dtype.kind in "biufc":
        text = "[" + ", ".join(fmt(v, digits) for v in a.tolist()) + "]"
        if len(text) <= INLINE:
            return text
    if a.dtype.kind == "b":
        return f"bool array({shape}), {int(np.count_nonzero(a))} True"
    if a.dtype.kind in "US" and a.size:
        hist = counts_text(a.ravel().tolist())
        if len(hist) <= INLINE:
            return f"str array({shape}) {{{hist}}}"
    return f"array({shape}) {a.dtype}"


def _fmt_dict(d: dict, digits: int) -> str:
    text = "{" + ", ".join(f"{k!r}: {fmt(v, digits)}" for k, v in d.items()) + "}"
    if len(d) <= 4 and len(text) <= INLINE:
        return text
    keys = ", ".join(repr(k) for k in list(d)[:4]) + (", ..." if len(d) > 4 else "")
    return f"{{{len(d)} keys: {keys}}}"


def _fmt_sequence(s: Sequence, digits: int) -> str:
    opening, closing = ("(", ")") if isinstance(s, tuple) else ("[", "]")
    if len(s) <= 4:
        text = opening + ", ".join(fmt(v, digits) for v in s) + ("," if len(s) == 1 and opening == "(" else "") + closing
        if len(text) <= INLINE and "<" not in text:
            return text
    kinds = {type(v).__name__ for v in s}
    kind = kinds.pop() if len(kinds) == 1 else "items"
    return f"{opening}{len(s)} × {kind}{closing}"


def counts_text(values: Iterable[Any]) -> str:
    """A histogram as text, ``value: how many`` in ascending order of the values.

    Examples
    --------
    >>> from imagespace._html import counts_text
    >>> counts_text([4, 2, 4, 6, 4])
    '2: 1, 4: 3, 6: 1'
    """
    hist = Counter(v.item() if isinstance(v, np.generic) else v for v in values)
    return ", ".join(f"{k}: {n}" for k, n in sorted(hist.items(), key=lambda kv: (str(type(kv[0])), kv[0])))


def summary(name: str, items: Iterable[tuple[Optional[str], str]], width: int = WIDTH) -> str:
    """``name(label=text, ...)`` wrapped at the commas into lines of at most ``width`` characters.

    ``items`` are ``(label, text)`` pairs with the text already formatted (:func:`fmt`); a
    ``None`` label shows the text alone.

    Examples
    --------
    >>> from imagespace._html import summary
    >>> summary("Result", [(None, "3 rows"), ("found", "True")])
    'Result(3 rows, found=True)'
    >>> print(summary("R", [("a", "1" * 30), ("b", "2" * 30)], width=40))
    R(a=111111111111111111111111111111,
      b=222222222222222222222222222222)
    """
    parts = [text if label is None else f"{label}={text}" for label, text in items]
    indent = " " * (len(name) + 1)
    lines: list[str] = []
    line = name + "("
    for k, part in enumerate(parts):
        piece = part + ("," if k < len(parts) - 1 else ")")
        if line.strip() and line not in (name + "(",) and len(line) + 1 + len(piece) > width:
            lines.append(line.rstrip())
            line = indent + piece
        else:
            line += ("" if line.endswith("(") else " ") + piece
    if not parts:
        line += ")"
    lines.append(line)
    return "\n".join(lines)


def dataclass_items(obj: Any, skip: Iterable[str] = (), quote: bool = True) -> list[tuple[Optional[str], str]]:
    """``(field name, formatted value)`` of every field of a dataclass shown by its repr.

    ``quote=False`` leaves string values as they are (for HTML) instead of their ``repr``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace._html import dataclass_items
    >>> from imagespace.paths.check import Crossing
    >>> dataclass_items(Crossing(0, (0.25, 0.25), 1))
    [('piece', '0'), ('t', '(0.25, 0.25)'), ('multiplicity', '1')]
    """
    skip = set(skip)
    values = [(f.name, getattr(obj, f.name)) for f in dataclasses.fields(obj) if f.repr and f.name not in skip]
    return [(k, v if isinstance(v, str) and not quote else fmt(v)) for k, v in values]


def dataclass_repr(obj: Any, skip: Iterable[str] = ()) -> str:
    """The short text summary of a dataclass: its fields, arrays as shape and dtype.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace._html import dataclass_repr
    >>> from imagespace.singular.cusps import ModeCountMap
    >>> print(dataclass_repr(ModeCountMap(0, 1.0, (1, 2), (np.zeros(50), np.zeros(60)), np.zeros((50, 60), int))))
    ModeCountMap(fixed=0, value=1, free=(1, 2), axes=(array(50) float64, array(60) float64),
                 counts=array(50, 60) int64)
    """
    return summary(type(obj).__name__, dataclass_items(obj, skip))


def dataclass_html(obj: Any, skip: Iterable[str] = ()) -> str:
    """The HTML table of :func:`dataclass_items` (one row per field), titled by the class name.

    Examples
    --------
    >>> from imagespace._html import dataclass_html
    >>> from imagespace.paths.check import Crossing
    >>> print(dataclass_html(Crossing(0, (0.25, 0.25), 1)))  # doctest: +ELLIPSIS
    <table class="imagespace-summary"><caption>Crossing</caption>
    <tr><th ...>piece</th><td ...>0</td></tr>
    ...
    </table>
    """
    return html_table(dataclass_items(obj, skip, quote=False), title=type(obj).__name__)


_CELL = ' style="text-align:left"'


def _cell(value: Any) -> str:
    text = value if isinstance(value, str) else fmt(value)
    return html.escape(text)


def html_table(rows: Iterable[Sequence[Any]], title: Optional[str] = None,
               header: Optional[Sequence[Any]] = None) -> str:
    """A compact HTML table; every value is escaped (strings as they are, others through :func:`fmt`).

    Without ``header`` the rows are ``(label, value)`` pairs and the label is a row header;
    with it, the table has a header row and plain rows.

    Examples
    --------
    >>> from imagespace._html import html_table
    >>> print(html_table([("rows", 3), ("label", "a<b")], title="T"))
    <table class="imagespace-summary"><caption>T</caption>
    <tr><th style="text-align:left">rows</th><td style="text-align:left">3</td></tr>
    <tr><th style="text-align:left">label</th><td style="text-align:left">a&lt;b</td></tr>
    </table>
    >>> html_table([(2, 10)], header=("modes", "rows")).count("<th")
    2
    """
    out = ['<table class="imagespace-summary">' + (f"<caption>{html.escape(title)}</caption>" if title else "")]
    if header is not None:
        out.append("<tr>" + "".join(f"<th{_CELL}>{_cell(h)}</th>" for h in header) + "</tr>")
        for row in rows:
            out.append("<tr>" + "".join(f"<td{_CELL}>{_cell(v)}</td>" for v in row) + "</tr>")
    else:
        for label, value in rows:
            out.append(f"<tr><th{_CELL}>{_cell(label)}</th><td{_CELL}>{_cell(value)}</td></tr>")
    out.append("</table>")
    return "\n".join(out)


LONG_LATEX = 2000
"""LaTeX longer than this (characters) has its coefficients shortened to ``digits`` significant
digits by :func:`latex_collected` (readability only, decides nothing about the mathematics)."""


def collected_terms(poly: Any, by: Sequence[str] = ("x0", "x1")) -> dict:
    """The polynomial collected by the monomials in the variables named ``by``: ``{monomial: coefficient}``.

    One group per monomial ``x0**a * x1**b`` (every power of every variable in ``by`` together,
    the other variables in the coefficients), in order of descending total degree, then of
    descending powers (``x0`` first). ``poly`` is a sympy ``Poly`` or expression; variables are
    matched by name.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace._html import collected_terms
    >>> x0, x1, x2 = sp.symbols("x0 x1 x2")
    >>> collected_terms(x0**2*x2 + 3*x0**2 + x0*x1*x2 + x1*x2 - 1)
    {x0**2: x2 + 3, x0*x1: x2, x1: x2, 1: -1}
    """
    import sympy as sp

    expr = poly.as_expr() if isinstance(poly, sp.Poly) else as_sympy(poly)
    named = {s.name: s for s in expr.free_symbols if isinstance(s, sp.Symbol)}
    syms = [named.get(str(b), sp.Symbol(str(b))) for b in by]
    groups = sp.Poly(expr, *syms).as_dict()
    order = sorted(groups, key=lambda powers: (-sum(powers), [-p for p in powers]))
    return {sp.Mul(*(s**p for s, p in zip(syms, powers))): groups[powers] for powers in order}


def latex_collected(poly: Any, by: Sequence[str] = ("x0", "x1"), digits: int = 6,
                    long: int = LONG_LATEX) -> str:
    """Readable LaTeX of a polynomial collected by powers of the variables ``by`` (no ``$``).

    One term per monomial in ``by``, its coefficient in parentheses when it is a sum. When the
    result is longer than ``long`` characters, the coefficients are rounded to ``digits``
    significant digits (``sympy.N``).

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace._html import latex_collected
    >>> x0, x1, x2 = sp.symbols("x0 x1 x2")
    >>> print(latex_collected(x0**2*x2 + 3*x0**2 - x1*x2 - 1))
    x_{0}^{2} \\left(x_{2} + 3\\right) - x_{1} x_{2} - 1
    """
    import sympy as sp

    groups = collected_terms(poly, by)

    def render(shorten):
        out = []
        for mono, coeff in groups.items():
            c = sp.N(coeff, digits) if shorten else coeff
            if shorten:         # whole numbers that fit the digits stay whole (256, not 256.0)
                c = c.xreplace({f: sp.Integer(int(f)) for f in c.atoms(sp.Float)
                                if float(f).is_integer() and abs(float(f)) < 10**digits})
            negative = c.could_extract_minus_sign()
            c = -c if negative else c
            m = "" if mono == 1 else sp.latex(mono)
            if isinstance(c, sp.Add):
                term = (m + rf" \left({sp.latex(c)}\right)").lstrip()
            else:
                term = sp.latex(c * mono)
            if not out:
                out.append(("-" if negative else "") + term)
            else:
                out.append(("- " if negative else "+ ") + term)
        return " ".join(out) or "0"

    text = render(False)
    return render(True) if len(text) > long else text


def modes_table(modes: Sequence[Any], title: Optional[str] = None, roots: Sequence[int] = ()) -> str:
    """An HTML table of assembly modes, one row each (pose, aspect, residual, multiplicity).

    Works on any sequence of :class:`imagespace.AssemblyMode` (the plain list that
    ``direct_kinematics`` returns included); ``roots`` adds the certificate's root of each mode.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace._html import modes_table
    >>> m = isp.examples.general_3rpr()
    >>> modes_table(m.direct_kinematics(m.q_example)).count("<tr>")
    7
    """
    header = ["#", "x", "y", "phi", "aspect", "residual", "multiplicity"] + (["root"] if roots else [])
    rows = []
    for k, mode in enumerate(modes):
        if mode.is_real:
            x, y, phi = (fmt(v) for v in mode.pose)
        else:
            x, y, phi = "complex", "", ""
        row = [k, x, y, phi, f"{int(mode.aspect):+d}", f"{float(mode.residual):.1e}", int(mode.multiplicity)]
        rows.append(row + ([roots[k]] if k < len(roots) else []))
    return html_table(rows, title=title, header=header)
