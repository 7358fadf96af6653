r"""Rows in lockstep: the batch kernel's stages on blocks of :data:`LOCKSTEP_ROWS` rows side by side.

The row kernel (:func:`.row._solve_row`) takes one joint vector through every stage before the
next; its ~300 chained polynomial evaluations a row leave the processor waiting on each result.
Here a block of rows goes through each stage together, in a structure-of-arrays layout (one
column per row: ``S[k, l]`` is quantity ``k`` of row ``l`` of the block), so the innermost loops
run over the rows of the block with the same operations for every row, without branches: loops
numba/LLVM vectorise, or at least overlap.

Stages, each the twin of its row-at-a-time original (same operations in the same order on every
row, so the same floats bit for bit; ``tests/solve/test_lockstep.py`` holds them equal):

1. :func:`coefficients_block` -- :func:`.tables.design_row` (the quadric coefficients, their
   derivatives in the joint values and rigorous bounds);
2. :func:`eliminate_block` -- :func:`imagespace.core.elimination.eliminate_row` (``D, X2, X3, F``
   and bounds);
3. :func:`isolate_block` -- :func:`imagespace.core.isolate.count_real_roots_row`: the Bernstein
   coefficients of both charts and the first :data:`GRID_LEVELS` levels of the subdivision tree
   (every node split at 1/2) are computed for all rows at once (the split grid); each row's
   depth-first search then takes the nodes it visits from the grid and splits only deeper nodes
   itself (:func:`imagespace.core.isolate.count_real_roots_lane`). Rows whose coefficients need
   scaling (beyond ``2**+-300``) take :func:`count_real_roots_row` itself (the slow lane);
4. :func:`modes_block` -- the rest of :func:`.row._solve_row`: each isolated root refined by the
   safeguarded Newton iteration of :func:`.cascade._monotone_root`, run for all roots of the block
   at once (:func:`refine_roots`; roots of a row whose form lost its leading coefficients take
   the scalar routine), then back-substitution, the residual test of the point, Newton on the
   4x4 system for the few points it does not prove accurate (the slow lane), checks, and the
   modes sorted by ``phi``.

A row that any stage cannot decide is flagged exactly as the row kernel flags it (the flag does
not depend on the order in which its checks are met: 1 for any float decision that failed, 2 when
the isolation is undecided and nothing failed before it), so the lockstep kernel's answers are the
row kernel's: the same counts, flags, modes and aspects.
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from ...core._numba import njit
from ...core.bounded_trig import cos_sin_bounded
from ...core.elimination import (ELIMINATION_ROW_SIZE, ROW_D, ROW_F, ROW_X2, ROW_X3,
                                 _ROW_GAMMA, _ROW_INFLATE, _ROW_TINY, _ROW_U)
from ...core.isolate import (BERNSTEIN_MATRIX, GRID_FIELDS, MAX_DEGREE, _BINOM, _GAMMA, _INFL, _NO_SCALING_ABOVE,
                             _NO_SCALING_BELOW, _TINY as _ISO_TINY, _U as _ISO_U, count_real_roots_lane,
                             count_real_roots_row)
from .tables import _GAMMA_SUM, _INFLATE, _TINY, _U

__all__ = ["LOCKSTEP_ROWS", "GRID_LEVELS", "coefficients_block", "eliminate_block", "isolate_block",
           "refine_roots", "modes_block", "S_SIZE", "grid_rows"]

#: Rows per block (a speed knob: the block's workspace, ~40 kB, stays in the level-2 cache).
LOCKSTEP_ROWS = 32
#: Levels of the subdivision tree computed for the whole block before the rows' searches (a speed
#: knob: deeper nodes are split by the row that visits them).
GRID_LEVELS = 3

# the block's workspace S (S_SIZE, LOCKSTEP_ROWS), one named group of rows per quantity
_S_SIZES = (3,      # Q: the block's joint values
            4,      # TRIG: cos q, sin q and their bounds, of the current leg
            2,      # MONO: the current monomial and its bound
            8,      # ACC8: sum |products| per coefficient of the current leg
            24,     # C: the three quadrics (c, a0, a1, b0, b1, k0, k1, k2 each)
            24,     # DC: their derivatives in the joint values (scaled by modes_block)
            24,     # CE: bounds on C
            24,     # E: the elimination's rows E1, E2, E3
            24,     # EE: their bounds
            ELIMINATION_ROW_SIZE,   # EL: D, X2, X3, F (core.elimination layout)
            ELIMINATION_ROW_SIZE,   # ELE: their bounds
            ELIMINATION_ROW_SIZE,   # EACC: sum |products| per output coefficient
            5, 5,   # LIN, LINE: A3 X2 + B3 X3 + K3 D and its bounds
            2 * (MAX_DEGREE + 1),   # SC: F and E as the isolation takes them
            3,      # BERN: accumulators of the Bernstein conversion
            24,     # CS: the quadrics scaled to max |coefficient| 1
            2)      # FN, DN: max |F|, max |D|
(_S_Q, _S_TRIG, _S_MONO, _S_ACC8, _S_C, _S_DC, _S_CE, _S_E, _S_EE, _S_EL, _S_ELE, _S_EACC, _S_LIN, _S_LINE,
 _S_SC, _S_BERN, _S_CS, _S_FN) = (0, *itertools.accumulate(_S_SIZES[:-1]))
#: Rows of the block workspace.
S_SIZE = sum(_S_SIZES)


def grid_rows(levels=GRID_LEVELS):
    """Rows of the split grid of :func:`isolate_block` for ``levels`` levels (two charts, the
    heap-ordered nodes ``1 .. 2**(levels + 1) - 1`` of each, ``GRID_FIELDS`` rows a node).

    Examples
    --------
    >>> from imagespace.solve.kernel.lockstep import grid_rows
    >>> grid_rows(3)
    480
    """
    return 2 * 2 ** (levels + 1) * GRID_FIELDS


# --------------------------------------------------------------------------- 1. coefficients

@njit(cache=True)
def coefficients_block(Q, r0, nb, expo, coef, cerr, nmono, trig, bounded, S):
    """:func:`.tables.design_row` for rows ``r0 .. r0 + nb - 1`` of ``Q`` at once: the quadric
    coefficients into ``S[_S_C + k]``, their derivatives into ``S[_S_DC + k]`` and, with
    ``bounded``, rigorous bounds into ``S[_S_CE + k]`` (zero otherwise).

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import design_row, design_tables
    >>> from imagespace.solve.kernel.lockstep import coefficients_block, S_SIZE, LOCKSTEP_ROWS, _S_C
    >>> m = isp.examples.general_3rpr()
    >>> t = design_tables(m)
    >>> Q = np.array([m.q_example_float] * 3)
    >>> S = np.zeros((S_SIZE, LOCKSTEP_ROWS))
    >>> coefficients_block(Q, 0, 3, t.expo, t.coef, t.cerr, t.nmono, t.trig, True, S)
    >>> buf, Ce, acc = np.zeros(48), np.zeros(24), np.zeros(8)
    >>> design_row(Q[0], t.expo, t.coef, t.cerr, t.nmono, t.trig, True, buf, Ce, acc)
    >>> bool(np.array_equal(S[_S_C:_S_C + 24, 2], buf[:24]))
    True
    """
    for i in range(3):
        qi = S[_S_Q + i]
        for l in range(nb):
            qi[l] = Q[r0 + l, i]
    mv = S[_S_MONO]
    me = S[_S_MONO + 1]
    cq = S[_S_TRIG]
    sq = S[_S_TRIG + 1]
    ec = S[_S_TRIG + 2]
    es = S[_S_TRIG + 3]
    for i in range(3):
        q = S[_S_Q + i]
        for l in range(nb):
            c = 0.0
            s = 0.0
            e1 = 0.0
            e2 = 0.0
            if trig[i] != 0:
                if bounded:
                    c, s, e1, e2 = cos_sin_bounded(q[l])
                else:
                    c = math.cos(q[l])
                    s = math.sin(q[l])
            cq[l] = c
            sq[l] = s
            ec[l] = e1
            es[l] = e2
        for k in range(8):
            row = S[_S_C + 8 * i + k]
            drow = S[_S_DC + 8 * i + k]
            erow = S[_S_CE + 8 * i + k]
            arow = S[_S_ACC8 + k]
            for l in range(nb):
                row[l] = 0.0
                drow[l] = 0.0
                erow[l] = 0.0
                arow[l] = 0.0
        for j in range(nmono[i]):
            for l in range(nb):
                mv[l] = 1.0
                me[l] = 0.0
            for _ in range(expo[i, j, 0]):
                for l in range(nb):
                    nv = mv[l] * q[l]
                    me[l] = me[l] * abs(q[l]) + _U * abs(nv)
                    mv[l] = nv
            for _ in range(expo[i, j, 1]):
                for l in range(nb):
                    nv = mv[l] * cq[l]
                    me[l] = abs(mv[l]) * ec[l] + me[l] * abs(cq[l]) + me[l] * ec[l] + _U * abs(nv)
                    mv[l] = nv
            for _ in range(expo[i, j, 2]):
                for l in range(nb):
                    nv = mv[l] * sq[l]
                    me[l] = abs(mv[l]) * es[l] + me[l] * abs(sq[l]) + me[l] * es[l] + _U * abs(nv)
                    mv[l] = nv
            for k in range(8):
                v = coef[i, j, k]
                vd = coef[i, j, 8 + k]
                ve = cerr[i, j, k]
                row = S[_S_C + 8 * i + k]
                drow = S[_S_DC + 8 * i + k]
                if bounded:
                    erow = S[_S_CE + 8 * i + k]
                    arow = S[_S_ACC8 + k]
                    for l in range(nb):
                        p = mv[l] * v
                        row[l] += p
                        drow[l] += mv[l] * vd
                        erow[l] += abs(mv[l]) * ve + me[l] * abs(v) + me[l] * ve
                        arow[l] += abs(p)
                else:
                    for l in range(nb):
                        row[l] += mv[l] * v
                        drow[l] += mv[l] * vd
        if bounded:
            for k in range(8):
                erow = S[_S_CE + 8 * i + k]
                arow = S[_S_ACC8 + k]
                for l in range(nb):
                    erow[l] = (erow[l] + _GAMMA_SUM * arow[l]) * _INFLATE + _TINY


# --------------------------------------------------------------------------- 2. elimination

@njit(cache=True)
def _mac_block(S, f, fe, nf, g, ge, ng, s, h, nb, bounded):
    """``S[h + k] += s * f[a] * g[b]`` over ``a + b = k`` for every row of the block, with the
    bounds ``S[h - _S_EL + _S_ELE + k]`` and the magnitudes ``S[h - _S_EL + _S_EACC + k]``: the
    ``mac`` of :func:`~imagespace.core.elimination.eliminate_row`."""
    he = h - _S_EL + _S_ELE
    ha = h - _S_EL + _S_EACC
    for a in range(nf):
        x = S[f + a]
        ex = S[fe + a]
        for b in range(ng):
            y = S[g + b]
            ey = S[ge + b]
            o = S[h + a + b]
            if bounded:
                oe = S[he + a + b]
                oa = S[ha + a + b]
                for l in range(nb):
                    xv = x[l]
                    yv = y[l]
                    exv = ex[l]
                    eyv = ey[l]
                    p = xv * yv
                    o[l] += s * p
                    oe[l] += abs(xv) * eyv + exv * abs(yv) + exv * eyv
                    oa[l] += abs(p)
            else:
                for l in range(nb):
                    o[l] += s * (x[l] * y[l])


@njit(cache=True)
def _close_block(S, lo, hi, nb, bounded):
    """The rounding of the sums ``lo .. hi - 1`` added to their bounds (``close`` of
    :func:`~imagespace.core.elimination.eliminate_row`)."""
    if not bounded:
        return
    for k in range(lo, hi):
        o = S[_S_EL + k]
        oe = S[_S_ELE + k]
        oa = S[_S_EACC + k]
        for l in range(nb):
            oe[l] = (oe[l] + _ROW_GAMMA * oa[l] + abs(o[l]) * _ROW_U) * _ROW_INFLATE + _ROW_TINY
            oa[l] = 0.0


@njit(cache=True)
def eliminate_block(S, plan, nb, bounded):
    """:func:`~imagespace.core.elimination.eliminate_row` for every row of the block: ``D, X2, X3,
    F`` into ``S[_S_EL + ROW_*]`` and their bounds into ``S[_S_ELE + ROW_*]``. Returns the degree
    of ``F``.

    Examples
    --------
    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import design_tables
    >>> from imagespace.solve.kernel.lockstep import (coefficients_block, eliminate_block, S_SIZE,
    ...     LOCKSTEP_ROWS, _S_EL)
    >>> m = isp.examples.general_3rpr()
    >>> t = design_tables(m)
    >>> S = np.zeros((S_SIZE, LOCKSTEP_ROWS))
    >>> coefficients_block(np.array([m.q_example_float]), 0, 1, t.expo, t.coef, t.cerr, t.nmono, t.trig, True, S)
    >>> eliminate_block(S, t.plan, 1, True)
    6
    """
    u = _ROW_U
    for r in range(3):
        i = plan[2 * r]
        j = plan[2 * r + 1]
        for k in range(8):
            dst = S[_S_E + 8 * r + k]
            dste = S[_S_EE + 8 * r + k]
            if j < 0:
                src = S[_S_C + 8 * i + k]
                srce = S[_S_CE + 8 * i + k]
                for l in range(nb):
                    dst[l] = src[l]
                    dste[l] = srce[l]
            else:   # c_j Q_i - c_i Q_j: the x2**2 + x3**2 terms cancel exactly
                ra = S[_S_C + 8 * j]
                rea = S[_S_CE + 8 * j]
                rb = S[_S_C + 8 * i + k]
                reb = S[_S_CE + 8 * i + k]
                rc = S[_S_C + 8 * i]
                rec = S[_S_CE + 8 * i]
                rd = S[_S_C + 8 * j + k]
                red = S[_S_CE + 8 * j + k]
                for l in range(nb):
                    a, ea = ra[l], rea[l]
                    b, eb = rb[l], reb[l]
                    c, ec = rc[l], rec[l]
                    d, ed = rd[l], red[l]
                    p1 = a * b
                    p2 = c * d
                    dst[l] = p1 - p2
                    if bounded:
                        dste[l] = ((abs(a) * eb + ea * abs(b) + ea * eb + abs(c) * ed + ec * abs(d) + ec * ed
                                    + 3 * u * (abs(p1) + abs(p2))) * _ROW_INFLATE + _ROW_TINY)
    for k in range(ELIMINATION_ROW_SIZE):
        o = S[_S_EL + k]
        oe = S[_S_ELE + k]
        oa = S[_S_EACC + k]
        for l in range(nb):
            o[l] = 0.0
            oe[l] = 0.0
            oa[l] = 0.0
    E, Ee, O = _S_E, _S_EE, _S_EL
    Oe = _S_ELE
    # D = A1 B2 - A2 B1, X2 = K2 B1 - K1 B2, X3 = A2 K1 - A1 K2 (E rows at 0, 8, 16)
    _mac_block(S, E + 1, Ee + 1, 2, E + 11, Ee + 11, 2, 1.0, O + ROW_D, nb, bounded)
    _mac_block(S, E + 9, Ee + 9, 2, E + 3, Ee + 3, 2, -1.0, O + ROW_D, nb, bounded)
    _mac_block(S, E + 13, Ee + 13, 3, E + 3, Ee + 3, 2, 1.0, O + ROW_X2, nb, bounded)
    _mac_block(S, E + 5, Ee + 5, 3, E + 11, Ee + 11, 2, -1.0, O + ROW_X2, nb, bounded)
    _mac_block(S, E + 9, Ee + 9, 2, E + 5, Ee + 5, 3, 1.0, O + ROW_X3, nb, bounded)
    _mac_block(S, E + 1, Ee + 1, 2, E + 13, Ee + 13, 3, -1.0, O + ROW_X3, nb, bounded)
    _close_block(S, 0, ROW_F, nb, bounded)
    # lin = A3 X2 + B3 X3 + K3 D (E3 at 16), in the F slots; it is F when no quadric is a circle
    _mac_block(S, E + 17, Ee + 17, 2, O + ROW_X2, Oe + ROW_X2, 4, 1.0, O + ROW_F, nb, bounded)
    _mac_block(S, E + 19, Ee + 19, 2, O + ROW_X3, Oe + ROW_X3, 4, 1.0, O + ROW_F, nb, bounded)
    _mac_block(S, E + 21, Ee + 21, 3, O + ROW_D, Oe + ROW_D, 3, 1.0, O + ROW_F, nb, bounded)
    _close_block(S, ROW_F, ROW_F + 5, nb, bounded)
    if plan[6] == 1:
        return 4
    # F = c3 (X2**2 + X3**2) + D lin: lin moved out of the F slots first
    for k in range(5):
        o = S[O + ROW_F + k]
        oe = S[Oe + ROW_F + k]
        lin = S[_S_LIN + k]
        line = S[_S_LINE + k]
        for l in range(nb):
            lin[l] = o[l]
            line[l] = oe[l]
            o[l] = 0.0
            oe[l] = 0.0
    _mac_block(S, O + ROW_X2, Oe + ROW_X2, 4, O + ROW_X2, Oe + ROW_X2, 4, 1.0, O + ROW_F, nb, bounded)
    _mac_block(S, O + ROW_X3, Oe + ROW_X3, 4, O + ROW_X3, Oe + ROW_X3, 4, 1.0, O + ROW_F, nb, bounded)
    _close_block(S, ROW_F, ROW_F + 7, nb, bounded)
    c3 = S[E + 16]
    ec3 = S[Ee + 16]
    for k in range(7):
        o = S[O + ROW_F + k]
        oe = S[Oe + ROW_F + k]
        oa = S[_S_EACC + ROW_F + k]
        for l in range(nb):
            v, ev = o[l], oe[l]
            p = c3[l] * v
            o[l] = p
            if bounded:
                oe[l] = abs(c3[l]) * ev + ec3[l] * abs(v) + ec3[l] * ev
                oa[l] = abs(p)
    _mac_block(S, O + ROW_D, Oe + ROW_D, 3, _S_LIN, _S_LINE, 5, 1.0, O + ROW_F, nb, bounded)
    _close_block(S, ROW_F, ROW_F + 7, nb, bounded)
    return 6


# --------------------------------------------------------------------------- 3. isolation

@njit(cache=True)
def _half_split_block(grid, src, left, right, nb):
    """de Casteljau at 1/2 of the node at grid rows ``src`` for every row of the block: the
    children into rows ``left`` and ``right``, the certain sign of the split point into
    ``src + 14`` (:func:`imagespace.core.isolate._split` with ``lam = 1/2``, operation for
    operation)."""
    u = _ISO_U
    for l in range(nb):
        c0 = grid[src, l]
        c1 = grid[src + 1, l]
        c2 = grid[src + 2, l]
        c3 = grid[src + 3, l]
        c4 = grid[src + 4, l]
        c5 = grid[src + 5, l]
        c6 = grid[src + 6, l]
        e0 = grid[src + 7, l]
        e1 = grid[src + 8, l]
        e2 = grid[src + 9, l]
        e3 = grid[src + 10, l]
        e4 = grid[src + 11, l]
        e5 = grid[src + 12, l]
        e6 = grid[src + 13, l]
        p0 = (c0 + c1) * 0.5
        ep0 = (e0 + e1) * 0.5 + u * abs(p0)
        p1 = (c1 + c2) * 0.5
        ep1 = (e1 + e2) * 0.5 + u * abs(p1)
        p2 = (c2 + c3) * 0.5
        ep2 = (e2 + e3) * 0.5 + u * abs(p2)
        p3 = (c3 + c4) * 0.5
        ep3 = (e3 + e4) * 0.5 + u * abs(p3)
        p4 = (c4 + c5) * 0.5
        ep4 = (e4 + e5) * 0.5 + u * abs(p4)
        p5 = (c5 + c6) * 0.5
        ep5 = (e5 + e6) * 0.5 + u * abs(p5)
        q0 = (p0 + p1) * 0.5
        eq0 = (ep0 + ep1) * 0.5 + u * abs(q0)
        q1 = (p1 + p2) * 0.5
        eq1 = (ep1 + ep2) * 0.5 + u * abs(q1)
        q2 = (p2 + p3) * 0.5
        eq2 = (ep2 + ep3) * 0.5 + u * abs(q2)
        q3 = (p3 + p4) * 0.5
        eq3 = (ep3 + ep4) * 0.5 + u * abs(q3)
        q4 = (p4 + p5) * 0.5
        eq4 = (ep4 + ep5) * 0.5 + u * abs(q4)
        r0 = (q0 + q1) * 0.5
        er0 = (eq0 + eq1) * 0.5 + u * abs(r0)
        r1 = (q1 + q2) * 0.5
        er1 = (eq1 + eq2) * 0.5 + u * abs(r1)
        r2 = (q2 + q3) * 0.5
        er2 = (eq2 + eq3) * 0.5 + u * abs(r2)
        r3 = (q3 + q4) * 0.5
        er3 = (eq3 + eq4) * 0.5 + u * abs(r3)
        s0 = (r0 + r1) * 0.5
        es0 = (er0 + er1) * 0.5 + u * abs(s0)
        s1 = (r1 + r2) * 0.5
        es1 = (er1 + er2) * 0.5 + u * abs(s1)
        s2 = (r2 + r3) * 0.5
        es2 = (er2 + er3) * 0.5 + u * abs(s2)
        v0 = (s0 + s1) * 0.5
        ev0 = (es0 + es1) * 0.5 + u * abs(v0)
        v1 = (s1 + s2) * 0.5
        ev1 = (es1 + es2) * 0.5 + u * abs(v1)
        w0 = (v0 + v1) * 0.5
        ew0 = ((ev0 + ev1) * 0.5 + u * abs(w0)) * _INFL + _ISO_TINY
        grid[left, l] = c0
        grid[left + 1, l] = p0
        grid[left + 2, l] = q0
        grid[left + 3, l] = r0
        grid[left + 4, l] = s0
        grid[left + 5, l] = v0
        grid[left + 6, l] = w0
        grid[left + 7, l] = e0
        grid[left + 8, l] = ep0 * _INFL + _ISO_TINY
        grid[left + 9, l] = eq0 * _INFL + _ISO_TINY
        grid[left + 10, l] = er0 * _INFL + _ISO_TINY
        grid[left + 11, l] = es0 * _INFL + _ISO_TINY
        grid[left + 12, l] = ev0 * _INFL + _ISO_TINY
        grid[left + 13, l] = ew0
        grid[right, l] = w0
        grid[right + 1, l] = v1
        grid[right + 2, l] = s2
        grid[right + 3, l] = r3
        grid[right + 4, l] = q4
        grid[right + 5, l] = p5
        grid[right + 6, l] = c6
        grid[right + 7, l] = ew0
        grid[right + 8, l] = ev1 * _INFL + _ISO_TINY
        grid[right + 9, l] = es2 * _INFL + _ISO_TINY
        grid[right + 10, l] = er3 * _INFL + _ISO_TINY
        grid[right + 11, l] = eq4 * _INFL + _ISO_TINY
        grid[right + 12, l] = ep5 * _INFL + _ISO_TINY
        grid[right + 13, l] = e6
        grid[src + 14, l] = 1.0 if w0 > ew0 else (-1.0 if w0 < -ew0 else 0.0)


@njit(cache=True)
def isolate_block(S, F0, Fe0, d, nb, grid, nleaf, status, counts, lo, hi, chart, work, fl, el):
    """:func:`~imagespace.core.isolate.count_real_roots_row` for every row of the block: the form
    of degree ``d`` in rows ``F0 .. F0 + d`` of ``S``, its bounds in ``Fe0 ..``; counts into
    ``counts[l]``, the isolating intervals into ``lo[l], hi[l], chart[l]``.

    ``grid`` (``grid_rows(levels)``, ``nb``) takes the split grid, ``nleaf = 2**levels``;
    ``status`` (``nb``) int scratch; ``work`` (``ISOLATE_WORK_SIZE``), ``fl``, ``el`` (7) scratch
    of the rows' searches.
    """
    # the rows' inputs as count_real_roots_row checks and scales them: rows whose forms would be
    # scaled take the slow lane (count_real_roots_row itself), non-finite ones are undecided
    for l in range(nb):
        status[l] = 0
    for k in range(d + 1):
        f = S[F0 + k]
        e = S[Fe0 + k]
        for l in range(nb):
            if not (math.isfinite(f[l]) and math.isfinite(e[l])) or not e[l] >= 0.0:
                status[l] = -1
    sc = S[_S_BERN]
    for l in range(nb):
        sc[l] = 0.0
    for k in range(d + 1):
        f = S[F0 + k]
        for l in range(nb):
            if abs(f[l]) > sc[l]:
                sc[l] = abs(f[l])
    for l in range(nb):
        big = sc[l]
        if big == 0.0:
            status[l] = -1
        elif status[l] == 0 and not _NO_SCALING_BELOW <= big <= _NO_SCALING_ABOVE:
            status[l] = 1
    for k in range(d + 1):
        f = S[F0 + k]
        e = S[Fe0 + k]
        g = S[_S_SC + k]
        ge = S[_S_SC + MAX_DEGREE + 1 + k]
        for l in range(nb):
            g[l] = f[l]
            ge[l] = e[l] * (1.0 + 2.0 * _ISO_U) + _ISO_TINY
    for k in range(d + 1):
        ge = S[_S_SC + MAX_DEGREE + 1 + k]
        for l in range(nb):
            if status[l] == 0 and not math.isfinite(ge[l]):
                status[l] = -1
    # the root node of each chart (Bernstein coefficients of degree 6 on [-1, 1]) and the grid
    acc = S[_S_BERN]
    mag = S[_S_BERN + 1]
    box = S[_S_BERN + 2]
    for ch in range(2):
        root = (ch * 2 * nleaf + 1) * GRID_FIELDS
        for i in range(MAX_DEGREE + 1):
            for l in range(nb):
                acc[l] = 0.0
                mag[l] = 0.0
                box[l] = 0.0
            for k in range(d + 1):
                kk = d - k if ch == 1 else k
                w = BERNSTEIN_MATRIX[i, k]
                aw = abs(w)
                g = S[_S_SC + kk]
                ge = S[_S_SC + MAX_DEGREE + 1 + kk]
                for l in range(nb):
                    acc[l] += w * g[l]
                    mag[l] += aw * abs(g[l])
                    box[l] += aw * ge[l]
            binom = _BINOM[i]
            out = grid[root + i]
            oute = grid[root + MAX_DEGREE + 1 + i]
            for l in range(nb):
                b = acc[l] / binom
                out[l] = b
                oute[l] = ((box[l] + _GAMMA * mag[l]) / binom + _ISO_U * abs(b)) * _INFL + _ISO_TINY
        h = 1
        while h < nleaf:
            base = ch * 2 * nleaf
            _half_split_block(grid, (base + h) * GRID_FIELDS, (base + 2 * h) * GRID_FIELDS,
                              (base + 2 * h + 1) * GRID_FIELDS, nb)
            h += 1
    # each row's depth-first search, on the grid where it can
    for l in range(nb):
        if status[l] < 0:
            counts[l] = -1
        elif status[l] == 1:
            for k in range(d + 1):
                fl[k] = S[F0 + k, l]
                el[k] = S[Fe0 + k, l]
            counts[l] = count_real_roots_row(fl, el, d, lo[l], hi[l], chart[l], work)
        else:
            counts[l] = count_real_roots_lane(grid, l, nleaf, d, lo[l], hi[l], chart[l], work)
