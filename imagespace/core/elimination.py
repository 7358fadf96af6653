r"""Elimination: three dyad quadrics -> a binary form in ``(x0 : x1)`` and back-substitution.

The quadrics are ``Q_i = c_i S + x2 A_i + x3 B_i + K_i`` with ``S = x2**2 + x3**2``, ``A_i, B_i``
linear and ``K_i`` quadratic binary forms in ``(x0, x1)`` (:mod:`imagespace.core.quadrics`).
Combinations with ``sum(w_i c_i) = 0`` are linear in ``(x2, x3)``; two of them, ``E1, E2``, are
solved by Cramer's rule

.. math::

    D = A_1 B_2 - A_2 B_1,\quad X_2 = -(K_1 B_2 - K_2 B_1),\quad X_3 = -(A_1 K_2 - A_2 K_1),
    \quad x_2 = X_2 / D,\quad x_3 = X_3 / D,

and substituted into a third equation ``E3`` (a circle, ``c_3 != 0``) with the denominator
cleared:

.. math::

    F = c_3 (X_2^2 + X_3^2) + D (A_3 X_2 + B_3 X_3) + K_3 D^2 \quad (\text{degree } 6).

When all three quadrics are linear in ``(x2, x3)`` (no RR dyad) the determinant
``A_3 X_2 + B_3 X_3 + K_3 D`` (degree 4) takes its place. ``F`` is homogeneous in ``(x0, x1)``, so
roots with ``x0 = 0`` (half-turns) are ordinary roots.

Two cases lose nothing but need their own treatment (``docs/conventions.md``):

(a) ``D`` vanishes identically (e.g. collinear base and platform anchors of a 3-RPR, seed 003,
    or a PP dyad among ``E1, E2``): a combination of ``E1, E2`` is free of ``(x2, x3)``, a binary
    quadratic ``G`` that fixes the orientations directly; each orientation is solved on its own.
(b) ``D`` vanishes at a root of ``F``: that orientation is solved on its own.

The arithmetic below is written once on coefficient lists and serves both faces: sympy
expressions (exact or symbolic) and numpy arrays (a batch of designs or joint values, one per
row).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, List

import sympy as sp

from .._validate import as_sympy
from .quadrics import image_symbols
from ..exceptions import DegenerateDesignError

__all__ = [
    "form_coefficients",
    "bf_mul",
    "bf_add",
    "bf_scale",
    "bf_eval",
    "LinearRow",
    "EliminationPlan",
    "plan_elimination",
    "eliminate",
    "combine_rows",
    "binary_form_poly",
    "plan_array",
    "eliminate_row",
]


# --------------------------------------------------------------------------- binary forms
# A binary form of degree d is a list [f_0, ..., f_d]: f_k is the coefficient of x0^(d-k) x1^k.

def bf_mul(f, g):
    """Product of two binary forms (coefficient lists).

    Examples
    --------
    >>> from imagespace.core.elimination import bf_mul
    >>> bf_mul([1, 1], [1, -1])       # (x0 + x1)(x0 - x1)
    [1, 0, -1]
    """
    h = [0] * (len(f) + len(g) - 1)
    for i, fi in enumerate(f):
        for j, gj in enumerate(g):
            h[i + j] = h[i + j] + fi * gj
    return h


def bf_add(f, g):
    """Sum of two binary forms of the same degree.

    Raises
    ------
    ValueError
        the two forms have different degrees.

    Examples
    --------
    >>> from imagespace.core.elimination import bf_add
    >>> bf_add([1, 2, 3], [1, 0, -3])
    [2, 2, 0]
    """
    if len(f) != len(g):
        raise ValueError(f"binary forms of different degree cannot be added: {len(f) - 1} and {len(g) - 1}")
    return [a + b for a, b in zip(f, g)]


def bf_scale(f, s):
    """A binary form times a scalar (or an array of scalars).

    Examples
    --------
    >>> from imagespace.core.elimination import bf_scale
    >>> bf_scale([1, 2], 3)
    [3, 6]
    """
    return [s * a for a in f]


def bf_eval(f, x0, x1):
    """Value of a binary form at ``(x0, x1)`` (broadcasting over arrays).

    Examples
    --------
    >>> from imagespace.core.elimination import bf_eval
    >>> bf_eval([1, 0, -1], 2.0, 1.0)
    3.0
    """
    d = len(f) - 1
    return sum(fk * x0 ** (d - k) * x1**k for k, fk in enumerate(f))


def binary_form_poly(f, x=None):
    """A coefficient list as a ``sympy.Poly`` in ``(x0, x1)``.

    Examples
    --------
    >>> from imagespace.core.elimination import binary_form_poly
    >>> binary_form_poly([1, 0, 1]).as_expr()
    x0**2 + x1**2
    """
    x0, x1 = (image_symbols()[:2] if x is None else x)
    d = len(f) - 1
    expr = sum(sp.expand(as_sympy(fk)) * x0 ** (d - k) * x1**k for k, fk in enumerate(f))
    return sp.Poly(expr, x0, x1)


# --------------------------------------------------------------------------- the plan

@dataclass(frozen=True)
class LinearRow:
    """A combination of the quadrics: weights and its parts ``c S + x2 A + x3 B + K``."""

    c: Any
    A: List[Any]
    B: List[Any]
    K: List[Any]


@dataclass(frozen=True)
class EliminationPlan:
    """Which combinations of the three quadrics form ``E1, E2`` (linear) and ``E3``.

    Attributes
    ----------
    w1, w2, w3 : tuple of three numbers
        Which quadrics form E1, E2 and E3: one entry 1 (that quadric), or entries 1 and -1 (the
        difference ``c_j Q_i - c_i Q_j`` of two circle quadrics, free of ``x2**2 + x3**2``).
    linear_only : bool
        No quadric has an ``x2**2 + x3**2`` term (no RR dyad): ``F`` is the 3x3 determinant.
    """

    w1: tuple
    w2: tuple
    w3: tuple
    linear_only: bool


def plan_elimination(kinds):
    """The elimination plan for three dyad kinds (``"RR"``, ``"PR"``, ``"RP"``, ``"PP"``).

    RR quadrics have ``c = 4``, the others ``c = 0``; differences of RR quadrics and all
    the others are linear in ``(x2, x3)``.

    Examples
    --------
    >>> from imagespace.core.elimination import plan_elimination
    >>> plan_elimination(["RR", "RR", "PR"])
    EliminationPlan(w1=(0, 0, 1), w2=(1, -1, 0), w3=(1, 0, 0), linear_only=False)
    """
    circles = [i for i, k in enumerate(kinds) if k == "RR"]
    lines = [i for i, k in enumerate(kinds) if k != "RR"]

    def e(i):
        return tuple(1 if j == i else 0 for j in range(3))

    def diff(i, j):
        return tuple(1 if k == i else (-1 if k == j else 0) for k in range(3))

    if len(circles) == 3:
        return EliminationPlan(diff(0, 1), diff(0, 2), e(0), False)
    if len(circles) == 2:
        i, j = circles
        return EliminationPlan(e(lines[0]), diff(i, j), e(i), False)
    if len(circles) == 1:
        return EliminationPlan(e(lines[0]), e(lines[1]), e(circles[0]), False)
    return EliminationPlan(e(0), e(1), e(2), True)


def _combine(quadrics, w):
    parts = [q.coefficients() for q in quadrics]
    idx = [i for i, wi in enumerate(w) if wi]
    if len(idx) == 2:
        # a difference of two circle quadrics: c_j Q_i - c_i Q_j, so that S cancels whatever
        # scaling the quadrics carry
        i, j = idx
        weights = {i: parts[j][0], j: -parts[i][0]}
    else:
        weights = {idx[0]: 1}
    out = []
    for k in range(8):
        acc = 0
        for i, wi in weights.items():
            acc = acc + wi * parts[i][k]
        out.append(acc)
    c, a0, a1, b0, b1, k0, k1, k2 = out
    return LinearRow(c, [a0, a1], [b0, b1], [k0, k1, k2])


@dataclass
class Elimination:
    """The forms of the elimination (coefficient lists, sympy or numpy entries).

    Attributes
    ----------
    plan : EliminationPlan
    rows : (LinearRow, LinearRow, LinearRow)
        ``E1, E2, E3``.
    D : list, degree 2
        The Cramer denominator ``A1 B2 - A2 B1``.
    X2, X3 : list, degree 3
        Cramer numerators: ``x2 = X2 / D``, ``x3 = X3 / D``.
    F : list, degree 6 (4 when ``plan.linear_only``)
        The binary form whose roots are the orientations of the assembly modes.
    """

    plan: EliminationPlan
    rows: tuple
    D: list
    X2: list
    X3: list
    F: list


def combine_rows(quadrics, plan):
    """The three combinations ``E1, E2, E3`` of the quadrics that ``plan`` names (see
    :class:`EliminationPlan`), as :class:`LinearRow` s.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.core.elimination import combine_rows, plan_elimination
    >>> m = isp.examples.general_3rpr()
    >>> quads = m.quadrics(m.q_example)
    >>> [row.c for row in combine_rows(quads, plan_elimination([q.kind for q in quads]))]
    [0, 0, 4]
    """
    return tuple(_combine(quadrics, w) for w in (plan.w1, plan.w2, plan.w3))


def eliminate(quadrics, plan=None):
    """Eliminate ``(x2, x3)`` from three quadrics.

    Parameters
    ----------
    quadrics : sequence of three Quadric
        Coefficients sympy expressions or numpy arrays (broadcast together).
    plan : EliminationPlan, optional
        Defaults to :func:`plan_elimination` of the quadrics' kinds.

    Returns
    -------
    Elimination

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.core.elimination import eliminate
    >>> m = isp.examples.stigger_husty()
    >>> len(eliminate(m.quadrics(m.q_example)).F) - 1     # a sextic
    6
    """
    if plan is None:
        plan = plan_elimination([q.kind for q in quadrics])
    E1, E2, E3 = combine_rows(quadrics, plan)
    symbolic = any(isinstance(v, sp.Basic) for q in quadrics for v in q.coefficients())
    # sympy entries are expanded after every stage: nested unexpanded products would make the
    # final expansion exponentially expensive
    ex = (lambda f: [sp.expand(v) for v in f]) if symbolic else (lambda f: f)
    if symbolic:
        E1, E2, E3 = (LinearRow(sp.expand(E.c), ex(E.A), ex(E.B), ex(E.K)) for E in (E1, E2, E3))
    D = ex(bf_add(bf_mul(E1.A, E2.B), bf_scale(bf_mul(E2.A, E1.B), -1)))
    X2 = ex(bf_scale(bf_add(bf_mul(E1.K, E2.B), bf_scale(bf_mul(E2.K, E1.B), -1)), -1))
    X3 = ex(bf_scale(bf_add(bf_mul(E1.A, E2.K), bf_scale(bf_mul(E2.A, E1.K), -1)), -1))
    lin = ex(bf_add(bf_add(bf_mul(E3.A, X2), bf_mul(E3.B, X3)), bf_mul(E3.K, D)))
    if plan.linear_only:
        F = lin
    else:
        F = ex(bf_add(bf_scale(ex(bf_add(bf_mul(X2, X2), bf_mul(X3, X3))), E3.c), bf_mul(D, lin)))
    return Elimination(plan, (E1, E2, E3), D, X2, X3, F)


def orientation_form(rows):
    """Case (a): a combination of ``E1, E2`` free of ``(x2, x3)`` (exact/symbolic rows).

    Returns the binary quadratic ``G`` as a coefficient list, or raises DegenerateDesignError when
    every such combination vanishes identically.

    Raises
    ------
    DegenerateDesignError
        the ``x2, x3``-free combination of the linear constraints vanishes identically (a
        continuum of assembly modes, an architecture singularity).

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.core.elimination import eliminate, orientation_form
    >>> m = isp.examples.collinear_3rpr(2, 1)
    >>> orientation_form(eliminate(m.quadrics(m.q_example)).rows)
    [-576, 0, 2496]
    """
    E1, E2 = rows[0], rows[1]
    v1 = [sp.expand(v) for v in (*E1.A, *E1.B)]
    v2 = [sp.expand(v) for v in (*E2.A, *E2.B)]
    if all(v == 0 for v in v1):
        G = E1.K
    else:
        j = next(k for k, v in enumerate(v1) if v != 0)
        G = bf_add(bf_scale(E1.K, v2[j]), bf_scale(E2.K, -v1[j]))
    G = [sp.expand(g) for g in G]
    if all(g == 0 for g in G):
        if all(v == 0 for v in v1) and any(sp.expand(k) != 0 for k in E2.K):
            return [sp.expand(k) for k in E2.K]
        raise DegenerateDesignError(
            "the constraint equations leave a continuum of assembly modes (the x2, x3-free "
            "combination of the linear constraints vanishes identically): architecture singularity")
    return G


def form_coefficients(poly):
    """Coefficients ``[f_0, ..., f_d]`` (of ``x0^(d-k) x1^k``) of a homogeneous Poly in ``(x0, x1)``.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.core.elimination import form_coefficients
    >>> x0, x1 = sp.symbols("x0 x1")
    >>> form_coefficients(sp.Poly(x0**2 - 3 * x1**2, x0, x1))
    [1, 0, -3]
    """
    d = poly.total_degree()
    return [poly.coeff_monomial((d - k, k)) for k in range(d + 1)]


# --------------------------------------------------------------------------- the numeric twin
# ``eliminate_row`` is the compiled kernel's copy of :func:`eliminate` for ONE row of float
# coefficients, with a rigorous bound on the error of every output coefficient. It is plain
# Python written for numba (``imagespace.solve.kernel`` compiles this very function) and
# self-contained (numba compiles only the functions it is handed); ``tests/core`` hold it equal
# to :func:`eliminate` on random rows and its bounds against exact rational arithmetic.

#: Layout of :func:`eliminate_row`'s output: ``D`` (3), ``X2`` (4), ``X3`` (4), then ``F`` (7, or 5
#: when no quadric has an ``x2**2 + x3**2`` term).
ELIMINATION_ROW_SIZE = 18
#: Offsets of ``D, X2, X3, F`` in that layout.
ROW_D, ROW_X2, ROW_X3, ROW_F = 0, 3, 7, 11
#: Scratch floats :func:`eliminate_row` needs.
ELIMINATION_WORK_SIZE = 76

ROW_UNIT_ROUNDOFF = 2.0**-53                        # unit roundoff of double precision
ROW_GAMMA = 40 * ROW_UNIT_ROUNDOFF / (1 - 40 * ROW_UNIT_ROUNDOFF)   # gamma_40: any sum of up to 39 rounded products
ROW_INFLATE = 1.0 + 2.0**-40            # covers the rounding of the bound arithmetic itself
ROW_TINY = 2.0**-500                    # covers every underflow (each below 2**-1074 per operation); not
                                         # smaller: a product of two such floors must not underflow (slow)


def plan_array(plan):
    """An :class:`EliminationPlan` as the integer array :func:`eliminate_row` reads: for ``E1, E2,
    E3`` the quadric ``i`` and ``j`` (``-1`` for a single quadric; ``c_j Q_i - c_i Q_j`` for a
    difference), then ``1`` if ``plan.linear_only``.

    Examples
    --------
    >>> from imagespace.core.elimination import plan_array, plan_elimination
    >>> plan_array(plan_elimination(["RR", "RR", "PR"])).tolist()
    [2, -1, 0, 1, 0, -1, 0]
    """
    import numpy as np

    out = []
    for w in (plan.w1, plan.w2, plan.w3):
        idx = [i for i, wi in enumerate(w) if wi]
        out += [idx[0], idx[1] if len(idx) == 2 else -1]
    return np.array(out + [1 if plan.linear_only else 0], dtype=np.int64)


def eliminate_row(C, Ce, plan, out, eout, work, bounded):
    """:func:`eliminate` for one row of float quadric coefficients, with error bounds.

    Parameters
    ----------
    C : (24,) float
        The three quadrics' coefficients ``c, a0, a1, b0, b1, k0, k1, k2``, quadric ``i`` at
        ``8 i .. 8 i + 7``.
    Ce : (24,) float
        Rigorous bounds on the error of ``C`` (zeros: ``C`` is exact).
    plan : (7,) int
        :func:`plan_array` of the elimination plan.
    out, eout : (ELIMINATION_ROW_SIZE,) float
        Filled with ``D, X2, X3, F`` (offsets ``ROW_*``) and bounds such that the forms of the
        exact coefficients lie in ``out +- eout`` (rounding of every operation included).
    work : (ELIMINATION_WORK_SIZE,) float
        Scratch (no allocation inside: the kernel calls this once per row).
    bounded : bool
        Compute the bounds (else ``eout`` is left at zero and only the values are computed).

    Returns
    -------
    int
        The degree of ``F`` (6, or 4 when ``plan`` is linear only).

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.core.elimination import (eliminate, eliminate_row, plan_array,
    ...     plan_elimination, ROW_F, ELIMINATION_WORK_SIZE)
    >>> m = isp.examples.general_3rpr()
    >>> quads = m.quadrics(m.q_example_float)
    >>> C = np.array([float(v) for qd in quads for v in qd.coefficients()])
    >>> out, err, work = np.zeros(18), np.zeros(18), np.zeros(ELIMINATION_WORK_SIZE)
    >>> d = eliminate_row(C, np.zeros(24), plan_array(plan_elimination([q.kind for q in quads])),
    ...                   out, err, work, True)
    >>> F = eliminate(quads).F
    >>> d, bool(np.allclose(out[ROW_F:ROW_F + 7], np.array(F, dtype=float), rtol=1e-12))
    (6, True)
    """
    u = ROW_UNIT_ROUNDOFF
    # E rows (c, A0, A1, B0, B1, K0, K1, K2) with bounds, three of them side by side
    E = work[0:24]
    Ee = work[24:48]
    for r in range(3):
        i = plan[2 * r]
        j = plan[2 * r + 1]
        for k in range(8):
            if j < 0:
                E[8 * r + k] = C[8 * i + k]
                Ee[8 * r + k] = Ce[8 * i + k]
            else:   # c_j Q_i - c_i Q_j: the x2**2 + x3**2 terms cancel exactly
                a, ea = C[8 * j], Ce[8 * j]
                b, eb = C[8 * i + k], Ce[8 * i + k]
                c, ec = C[8 * i], Ce[8 * i]
                d, ed = C[8 * j + k], Ce[8 * j + k]
                p1 = a * b
                p2 = c * d
                v = p1 - p2
                E[8 * r + k] = v
                if bounded:
                    Ee[8 * r + k] = ((abs(a) * eb + ea * abs(b) + ea * eb + abs(c) * ed + ec * abs(d) + ec * ed
                                      + 3 * u * (abs(p1) + abs(p2))) * ROW_INFLATE + ROW_TINY)
    for k in range(ELIMINATION_ROW_SIZE):
        out[k] = 0.0
        eout[k] = 0.0
    acc = work[48:66]              # sum |products| per output coefficient, for rounding
    for k in range(ELIMINATION_ROW_SIZE):
        acc[k] = 0.0

    # h[oh + k] += s * f[of + i] * g[og + j] over i + j = k, propagating the input bounds
    def mac(fv, fe, of, nf, gv, ge, og, ng, s, oh, out, eout, acc, bounded):
        for a in range(nf):
            for b in range(ng):
                x, ex = fv[of + a], fe[of + a]
                y, ey = gv[og + b], ge[og + b]
                p = x * y
                out[oh + a + b] += s * p
                if bounded:
                    eout[oh + a + b] += abs(x) * ey + ex * abs(y) + ex * ey
                    acc[oh + a + b] += abs(p)

    def close(lo, hi, out, eout, acc, bounded):
        if not bounded:
            return
        for k in range(lo, hi):
            eout[k] = (eout[k] + ROW_GAMMA * acc[k] + abs(out[k]) * u) * ROW_INFLATE + ROW_TINY
            acc[k] = 0.0

    # D = A1 B2 - A2 B1, X2 = K2 B1 - K1 B2, X3 = A2 K1 - A1 K2 (E rows at 0, 8, 16)
    mac(E, Ee, 1, 2, E, Ee, 11, 2, 1.0, ROW_D, out, eout, acc, bounded)
    mac(E, Ee, 9, 2, E, Ee, 3, 2, -1.0, ROW_D, out, eout, acc, bounded)
    mac(E, Ee, 13, 3, E, Ee, 3, 2, 1.0, ROW_X2, out, eout, acc, bounded)
    mac(E, Ee, 5, 3, E, Ee, 11, 2, -1.0, ROW_X2, out, eout, acc, bounded)
    mac(E, Ee, 9, 2, E, Ee, 5, 3, 1.0, ROW_X3, out, eout, acc, bounded)
    mac(E, Ee, 1, 2, E, Ee, 13, 3, -1.0, ROW_X3, out, eout, acc, bounded)
    close(0, ROW_F, out, eout, acc, bounded)
    # lin = A3 X2 + B3 X3 + K3 D (E3 at 16), in the F slots; it is F when no quadric is a circle
    mac(E, Ee, 17, 2, out, eout, ROW_X2, 4, 1.0, ROW_F, out, eout, acc, bounded)
    mac(E, Ee, 19, 2, out, eout, ROW_X3, 4, 1.0, ROW_F, out, eout, acc, bounded)
    mac(E, Ee, 21, 3, out, eout, ROW_D, 3, 1.0, ROW_F, out, eout, acc, bounded)
    close(ROW_F, ROW_F + 5, out, eout, acc, bounded)
    if plan[6] == 1:
        return 4
    # F = c3 (X2**2 + X3**2) + D lin: lin moved out of the F slots first
    lin = work[66:71]
    line = work[71:76]
    for k in range(5):
        lin[k] = out[ROW_F + k]
        line[k] = eout[ROW_F + k]
        out[ROW_F + k] = 0.0
        eout[ROW_F + k] = 0.0
    mac(out, eout, ROW_X2, 4, out, eout, ROW_X2, 4, 1.0, ROW_F, out, eout, acc, bounded)
    mac(out, eout, ROW_X3, 4, out, eout, ROW_X3, 4, 1.0, ROW_F, out, eout, acc, bounded)
    close(ROW_F, ROW_F + 7, out, eout, acc, bounded)
    c3, ec3 = E[16], Ee[16]
    for k in range(7):
        v, ev = out[ROW_F + k], eout[ROW_F + k]
        p = c3 * v
        out[ROW_F + k] = p
        if bounded:
            eout[ROW_F + k] = abs(c3) * ev + ec3 * abs(v) + ec3 * ev
            acc[ROW_F + k] = abs(p)
    mac(out, eout, ROW_D, 3, lin, line, 0, 5, 1.0, ROW_F, out, eout, acc, bounded)
    close(ROW_F, ROW_F + 7, out, eout, acc, bounded)
    return 6
