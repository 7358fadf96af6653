"""Exact real solutions of polynomial systems in Study coordinates (the msolve backend).

A displacement is a point ``s = (x0, x1, x2, x3, y0, y1, y2, y3)`` of P^7 with ``x != 0`` (the
rotation quaternion); constraint equations are homogeneous polynomials in ``s``. To hand such a
projective system to an affine solver, every point is written in exactly one of four strata

* ``x0 = 1``;
* ``x0 = 0, x1 = 1``;
* ``x0 = x1 = 0, x2 = 1``;
* ``x0 = x1 = x2 = 0, x3 = 1``,

the representative whose first non-zero rotation coordinate is 1. Together they cover every point
with ``x != 0`` once, half-turns (``x0 = 0``) included, which a single chart ``x0 = 1`` would
lose. The points with ``x = 0`` are not displacements and are not looked for (for the sphere
constraints of a Gough-Stewart leg a real one would need ``y . y = 0``, so there is none).

Each stratum is solved by msolve (:func:`imagespace.core.msolve.solve_real`), exactly: isolating
boxes with rational end points, certified to contain one real solution each, and the number of
complex solutions counted with multiplicity. A stratum with infinitely many complex solutions (an
architecture singularity, a self-motion, too few equations) raises :class:`DegenerateDesignError`.

The examples run msolve; when the binary is missing they are skipped (first lines).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from imagespace._validate import as_flag, as_scalar
from imagespace.core.msolve import DEFAULT_TIMEOUT, MsolveTimeoutError, solve_real
from imagespace.exceptions import DegenerateDesignError, InputError
from .._validate import as_sympy
from ..exceptions import InputTypeError

__all__ = ["STUDY_STRATA", "ExactStudyResult", "exact_real_study_points"]

#: The four strata, in the order they are solved; ``ExactStudyResult.strata`` indexes this.
STUDY_STRATA = ("x0 = 1", "x0 = 0, x1 = 1", "x0 = x1 = 0, x2 = 1", "x0 = x1 = x2 = 0, x3 = 1")

_NAMES = ("x0", "x1", "x2", "x3", "y0", "y1", "y2", "y3")


def _symbols():
    """The eight Study symbols x0..x3, y0..y3 (plain sympy symbols, no assumptions)."""
    import sympy as sp
    return sp.symbols("x0:4") + sp.symbols("y0:4")


@dataclass(frozen=True, repr=False)
class ExactStudyResult:
    """The real solutions of a system in Study coordinates, found exactly stratum by stratum.

    Attributes
    ----------
    study_points : (k, 8) float
        The real solutions, normalised (``x . x = 1``, first non-zero of ``x`` positive), sorted
        by stratum, then lexicographically.
    boxes : list of tuple of (Fraction, Fraction)
        Row ``i``'s isolating box: eight ``(lo, hi)`` pairs for ``(x0, ..., y3)`` of the stratum
        representative (first non-zero of ``x`` equal to 1; fixed coordinates as ``(c, c)``).
    strata : (k,) int
        Index into :data:`STUDY_STRATA` of each row's stratum (``strata > 0``: a half-turn).
    complex_count : int
        Complex solutions in the chart ``x0 = 1``, counted with multiplicity (40 for a general
        Gough-Stewart platform).
    stratum_complex_counts : tuple of int
        The same count for each of the four strata.
    seconds : tuple of float
        msolve's wall-clock time on each stratum.

    Examples
    --------
    Rotations about the z axis by the quaternion ``(x0, 0, 0, x3)`` with ``x3^2 = 3 x0^2``
    (+-120 degrees), no translation:

    >>> import sympy as sp
    >>> from imagespace.core.msolve import msolve_available
    >>> from imagespace.spatial.exact import exact_real_study_points
    >>> if not msolve_available():
    ...     import pytest; pytest.skip("msolve is not installed")
    >>> x0, x1, x2, x3, y0, y1, y2, y3 = sp.symbols("x0:4") + sp.symbols("y0:4")
    >>> res = exact_real_study_points([x1, x2, x3**2 - 3 * x0**2, y1, y2, y3])
    >>> res.count, res.strata, res.complex_count
    (2, array([0, 0]), 2)
    >>> res.study_points[:, :4].round(6)
    array([[ 0.5     ,  0.      ,  0.      , -0.866025],
           [ 0.5     ,  0.      ,  0.      ,  0.866025]])
    """

    study_points: np.ndarray
    boxes: list
    strata: np.ndarray
    complex_count: int
    stratum_complex_counts: tuple
    seconds: tuple

    def __repr__(self):
        per = ", ".join(f"{int(np.sum(self.strata == k))}" for k in range(len(STUDY_STRATA)))
        return (f"ExactStudyResult({self.count} real Study points (per stratum: {per}); "
                f"{self.complex_count} complex in the chart x0 = 1; "
                f"msolve {sum(self.seconds):.2f} s)")

    @property
    def count(self) -> int:
        """Number of real solutions."""
        return len(self.boxes)


def _checked_system(polys, symbols):
    """The polynomials as exact ``sympy.Poly`` over QQ in ``symbols``, each homogeneous."""
    import sympy as sp
    if isinstance(polys, (str, bytes, sp.Basic, sp.Poly)) or not hasattr(polys, "__iter__"):
        raise InputTypeError(f"polys must be a sequence of polynomials in the Study coordinates, got "
                             f"{type(polys).__name__}")
    by_name = dict(zip(_NAMES, symbols))
    out = []
    for i, p in enumerate(polys):
        name = f"polys[{i}]"
        if isinstance(p, sp.Poly):
            p = p.as_expr()
        if isinstance(p, (bool, np.bool_, str, bytes)) or \
                not isinstance(p, (sp.Basic, int, float, Fraction)):
            raise InputTypeError(f"{name} must be a sympy polynomial in x0..x3, y0..y3, got "
                                 f"{type(p).__name__}")
        p = as_sympy(p)
        if p.has(sp.nan, sp.oo, -sp.oo, sp.zoo):
            raise InputError(f"{name} has a non-finite coefficient (nan or infinity): {p}")
        # symbols of the same name but other assumptions (real=True ...) are the same unknowns;
        # floats are their exact binary rationals
        rename = {}
        for s in p.free_symbols:
            if s.name not in by_name:
                raise InputError(f"{name} contains the symbol {s}; expected polynomials in the "
                                 f"Study coordinates {', '.join(_NAMES)} only")
            rename[s] = by_name[s.name]
        rename.update({f: sp.Rational(f) for f in p.atoms(sp.Float)})
        p = p.xreplace(rename)
        try:
            poly = sp.Poly(p, *symbols)
        except sp.PolynomialError as exc:
            raise InputError(f"{name} must be a polynomial in the Study coordinates, got "
                             f"{p}") from exc
        domain = poly.get_domain()
        if not (domain.is_ZZ or domain.is_QQ):
            raise InputError(f"{name} has coefficients in {domain}; expected rational numbers "
                             f"(floats are taken exactly; irrational numbers are refused)")
        if not poly.is_zero and not poly.is_homogeneous:
            raise InputError(f"{name} must be homogeneous in (x0, ..., y3) (Study coordinates "
                             f"are projective), got {p}")
        out.append(poly.set_domain("QQ"))
    return out


def _on_stratum(poly, k, unknowns):
    """``poly`` at ``x_j = 0`` (``j < k``), ``x_k = 1``: a Poly in ``unknowns``, None if zero."""
    import sympy as sp
    terms = {}
    for exps, c in poly.terms():
        if any(exps[:k]):
            continue
        rest = exps[k + 1:]
        terms[rest] = terms.get(rest, 0) + c
    terms = {e: c for e, c in terms.items() if c != 0}
    if not terms:
        return None
    return sp.Poly.from_dict(terms, *unknowns, domain="QQ")


def exact_real_study_points(polys, *, study_quadric=True, timeout=DEFAULT_TIMEOUT,
                            threads=1, exclude_null_rotations=None) -> ExactStudyResult:
    """Every real displacement satisfying homogeneous equations in Study coordinates, exactly.

    Parameters
    ----------
    polys : sequence of sympy expressions or sympy.Poly
        Homogeneous polynomials with rational coefficients in the symbols ``x0, x1, x2, x3, y0,
        y1, y2, y3`` (``sympy.symbols('x0:4') + sympy.symbols('y0:4')``; symbols are matched by
        name). Floats enter as their exact binary rationals. Any number of equations.
    study_quadric : bool, optional
        Add Study's quadric ``x0 y0 + x1 y1 + x2 y2 + x3 y3`` to ``polys`` (default True;
        harmless when it is already there).
    timeout : float, optional
        Seconds for all four msolve runs together.
    threads : int, optional
        Threads per msolve run.
    exclude_null_rotations : bool or None, optional
        Solve with the extra unknown ``w`` and equation ``w (x . x) = 1``: complex points with
        ``x . x = 0`` are not displacements, and for special designs (6-3 and 3-3 Gough-Stewart
        platforms) they form a continuum that would make a stratum look positive-dimensional.
        Real solutions have ``x . x > 0`` and are unaffected; the complex counts then count
        displacements only. ``None`` (default): only for a stratum that is positive-dimensional
        without it (the extra unknown costs 5-7x in msolve on a general 6-6 design).

    Returns
    -------
    ExactStudyResult
        ``study_points (k, 8)``, ``boxes``, ``strata``, ``complex_count`` (chart ``x0 = 1``).

    Raises
    ------
    TypeError
        ``polys`` is not a sequence of polynomials.
    InputError
        A polynomial that is not homogeneous, has a symbol other than the eight Study
        coordinates, or irrational coefficients.
    DegenerateDesignError
        A stratum has infinitely many complex solutions (the message names it): an architecture
        singularity, a continuum of poses, or too few equations.
    MsolveUnavailableError
        No msolve binary (``pip install imagespace[exact]``).
    MsolveTimeoutError
        The strata took longer than ``timeout`` seconds in total.

    Examples
    --------
    A half-turn about the x axis (``x = (0, 1, 0, 0)``) translated by ``t = (0, 4, 6)``:
    ``y = t x / 2 = (0, 0, 3, -2)``. Pin it down by the rotation and two translation equations:

    >>> import sympy as sp
    >>> from imagespace.core.msolve import msolve_available
    >>> from imagespace.spatial.exact import exact_real_study_points
    >>> if not msolve_available():
    ...     import pytest; pytest.skip("msolve is not installed")
    >>> x0, x1, x2, x3, y0, y1, y2, y3 = sp.symbols("x0:4") + sp.symbols("y0:4")
    >>> res = exact_real_study_points([x0, x2, x3, y2 - 3 * x1, y3 + 2 * x1, y0])
    >>> res.study_points
    array([[ 0.,  1.,  0.,  0.,  0.,  0.,  3., -2.]])
    >>> res.strata, res.complex_count
    (array([1]), 0)
    """
    import sympy as sp
    study_quadric = as_flag(study_quadric, "study_quadric")
    timeout = as_scalar(timeout, "timeout")
    if not timeout > 0:
        raise InputError(f"timeout must be a positive number of seconds, got {timeout}")
    symbols = _symbols()
    system = _checked_system(polys, symbols)
    x, y = symbols[:4], symbols[4:]
    if study_quadric:
        system.append(sp.Poly(sum(a * b for a, b in zip(x, y)), *symbols, domain="QQ"))
    deadline = time.monotonic() + timeout
    rows: list[np.ndarray] = []
    boxes: list[tuple] = []
    strata: list[int] = []
    counts: list[int] = []
    seconds: list[float] = []
    for k, label in enumerate(STUDY_STRATA):
        fixed = {x[j]: 0 for j in range(k)}
        fixed[x[k]] = 1
        unknowns = symbols[k + 1:]
        chart = [c for c in (_on_stratum(p, k, unknowns) for p in system) if c is not None]
        tries = [True] if exclude_null_rotations else ([False] if exclude_null_rotations is False
                                                        else [False, True])
        for saturate in tries:
            eqs, unk = chart, tuple(unknowns)
            if saturate:
                w = sp.Symbol("w_null")
                xx = 1 + sum(v ** 2 for v in x[k + 1:])
                eqs = [sp.Poly(c.as_expr(), *unk, w, domain="QQ") for c in chart]
                eqs.append(sp.Poly(w * xx - 1, *unk, w, domain="QQ"))
                unk = unk + (w,)
            left = deadline - time.monotonic()
            if left <= 0:
                raise MsolveTimeoutError(f"timeout={timeout} s spent before the stratum {label}")
            res = solve_real(eqs, unk, timeout=left, threads=threads)
            if not res.positive_dimensional:
                break
        if res.positive_dimensional:
            raise DegenerateDesignError(
                f"the stratum {label} has infinitely many complex solutions (an architecture "
                f"singularity, a continuum of poses, or too few equations); no finite answer")
        assert res.complex_count is not None  # a finite (zero-dimensional) answer carries its count
        counts.append(res.complex_count)
        seconds.append(res.seconds)
        found = []
        for box in res.boxes:
            it = iter(box)
            full = tuple((Fraction(fixed[s]),) * 2 if s in fixed else next(it) for s in symbols)
            # (a trailing box of the auxiliary unknown w is not part of the Study point)
            mid = np.array([float((lo + hi) / 2) for lo, hi in full])
            found.append((tuple(mid), full, mid / np.linalg.norm(mid[:4])))
        found.sort(key=lambda item: item[0])
        for _, full, point in found:
            rows.append(point)
            boxes.append(full)
            strata.append(k)
    return ExactStudyResult(
        study_points=np.array(rows, dtype=float).reshape(-1, 8),
        boxes=boxes,
        strata=np.array(strata, dtype=int),
        complex_count=counts[0],
        stratum_complex_counts=tuple(counts),
        seconds=tuple(seconds))
