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
3. :func:`.block_isolate.isolate_block` -- :func:`imagespace.core.isolate.count_real_roots_row`: the Bernstein
   coefficients of both charts and the first :data:`GRID_LEVELS` levels of the subdivision tree
   (every node split at 1/2) are computed for all rows at once (the split grid); each row's
   depth-first search then starts only from the grid's frontier (nodes not split there: one-root
   nodes touching the last root's interval, undecided nodes on the last level; see
   :mod:`.block_isolate`). Rows whose coefficients need scaling (beyond ``2**+-300``) take
   :func:`count_real_roots_row` itself (the slow lane);
4. :func:`modes_block` -- the rest of :func:`.row._solve_row`: each isolated root refined by the
   safeguarded Newton iteration of :func:`.newton._monotone_root`, run for all roots of the block
   at once (:func:`refine_roots`; roots of a row whose form lost its leading coefficients take
   the scalar routine), then back-substitution, the residual test of the point and the checks
   for all roots at once (:func:`.block_modes.backsub_block`), Newton on the 4x4 system for the
   few points it does not prove accurate (the slow lane), and the modes sorted by ``phi``.

A row that any stage cannot decide is flagged exactly as the row kernel flags it (the flag does
not depend on the order in which its checks are met: 1 for any float decision that failed, 2 when
the isolation is undecided and nothing failed before it), so the lockstep kernel's answers are the
row kernel's: the same counts, flags, modes and aspects.

The loops vectorise only where LLVM can see that a block's rows do not overlap in memory: the
quantities a loop reads and writes sit at constant distances (module constants) wherever a loop
touches many of them (the split grid, the Horner step of :func:`refine_roots`); rows at runtime
offsets need runtime overlap checks, of which LLVM allows only a few per loop.
"""

from __future__ import annotations

import math

import numpy as np

from ...core._numba import njit
from ...core.bounded_trig import cos_sin_bounded
from ...core.elimination import (ELIMINATION_ROW_SIZE, ROW_D, ROW_F, ROW_X2, ROW_X3,
                                 ROW_GAMMA, ROW_INFLATE, ROW_TINY, ROW_UNIT_ROUNDOFF)
from ...core.isolate import GRID_FIELDS, ISOLATE_WORK_SIZE, MAX_DEGREE
from .block_isolate import isolate_block
from .block_layout import (GRID_LEVELS, LOCKSTEP_ROWS, S_SIZE, _S_ACC8, _S_BERN, _S_C, _S_CE, _S_CS, _S_DC,  # noqa: F401
                           _S_E, _S_EACC, _S_EE, _S_EL, _S_ELE, _S_FN, _S_LIN, _S_LINE, _S_MONO, _S_Q, _S_TRIG,
                           _M_A, _M_B, _M_FA, _M_FB, _M_H, _M_MAX, _M_P, _M_SIZE, _M_T, _M_W, _M_X, _M_DET,
                           _M_JRES, _MI_CHART, _MI_DEG, _MI_DONE, _MI_LANE, _MI_SIZE, grid_rows)
from .block_modes import backsub_block
from .newton import _BISECT_WIDTH, _HORNER_ZERO, _bracketed_newton, _horner, _monotone_root
from .row import _duplicate_modes, _insert_mode
from .tables import _GAMMA_SUM, _INFLATE, _TINY, _U

__all__ = ["LOCKSTEP_ROWS", "GRID_LEVELS", "LOCKSTEP_NEWTON_STEPS", "S_SIZE", "grid_rows", "coefficients_block",
           "eliminate_block", "isolate_block", "refine_roots", "roots_block", "modes_block", "store_block", "block_workspace",
           "solve_block", "counts_block"]


# --------------------------------------------------------------------------- 1. coefficients

@njit(cache=True)
def coefficients_block(Q, r0, nb, expo, coef, cerr, nmono, trig, bounded, S):
    """:func:`.tables.design_row` for rows ``r0`` to ``r0 + nb - 1`` of ``Q`` at once: the quadric
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
    """The rounding of the sums ``lo`` to ``hi - 1`` added to their bounds (``close`` of
    :func:`~imagespace.core.elimination.eliminate_row`)."""
    if not bounded:
        return
    for k in range(lo, hi):
        o = S[_S_EL + k]
        oe = S[_S_ELE + k]
        oa = S[_S_EACC + k]
        for l in range(nb):
            oe[l] = (oe[l] + ROW_GAMMA * oa[l] + abs(o[l]) * ROW_UNIT_ROUNDOFF) * ROW_INFLATE + ROW_TINY
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
    u = ROW_UNIT_ROUNDOFF
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
                                    + 3 * u * (abs(p1) + abs(p2))) * ROW_INFLATE + ROW_TINY)
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


# --------------------------------------------------------------------------- 4. modes

#: Steps of the safeguarded Newton iteration all roots of a block take together; roots that need
#: more finish one by one (:func:`.newton._bracketed_newton`). A speed knob, not a decision.
LOCKSTEP_NEWTON_STEPS = 12


@njit(cache=True, error_model="numpy")
def refine_roots(MD, MI, nm, deg):
    """:func:`.newton._monotone_root` for the roots ``0`` to ``nm - 1`` of ``MD``, each in its bracket
    ``[A, B]`` with values ``FA, FB`` of opposite signs: the result in ``MD[_M_T]``. Roots of degree ``deg`` take the first :data:`LOCKSTEP_NEWTON_STEPS` steps together
    (Horner's rule for all of them at once, then each root's decision), operation for operation
    the scalar iteration's; the rest of their steps, and roots of another degree, go through the
    scalar routine itself."""
    A = MD[_M_A]
    B = MD[_M_B]
    FA = MD[_M_FA]
    FB = MD[_M_FB]
    T = MD[_M_T]
    W = MD[_M_W]
    done = MI[_MI_DONE]
    deg_of = MI[_MI_DEG]
    for j in range(nm):
        a = A[j]
        b = B[j]
        fa = FA[j]
        fb = FB[j]
        if deg_of[j] == deg:
            t = a - fa * (b - a) / (fb - fa)
            if not (a < t < b):
                t = 0.5 * (a + b)
            T[j] = t
            W[j] = b - a
            done[j] = 0
        else:
            T[j] = _monotone_root(MD[_M_P:_M_P + MAX_DEGREE + 1, j], deg_of[j], a, b, fa, fb)
            done[j] = 1
    hz = _HORNER_ZERO * deg
    # Horner's rule for every root at once, on the flat columns (the rows at constant distances
    # _M_MAX apart, so the loop over the roots vectorises)
    md = MD.reshape(MD.size)
    toprow = MD[_M_P + deg]
    for it in range(LOCKSTEP_NEWTON_STEPS):
        for j in range(nm):
            top = toprow[j]
            md[_M_H * _M_MAX + j] = top
            md[(_M_H + 1) * _M_MAX + j] = 0.0
            md[(_M_H + 2) * _M_MAX + j] = abs(top)
        for k in range(deg - 1, -1, -1):
            crow = MD[_M_P + k]
            for j in range(nm):
                t = md[_M_T * _M_MAX + j]
                c = crow[j]
                f = md[_M_H * _M_MAX + j]
                md[(_M_H + 1) * _M_MAX + j] = md[(_M_H + 1) * _M_MAX + j] * t + f
                md[_M_H * _M_MAX + j] = f * t + c
                md[(_M_H + 2) * _M_MAX + j] = md[(_M_H + 2) * _M_MAX + j] * abs(t) + abs(c)
        # each root's decision, branch free (selects; the loop vectorises): the scalar
        # iteration's operations on every root still running, the others left as they are
        safeguard = it % 4 == 3
        active = 0
        for j in range(nm):
            run = done[j] == 0
            t = md[_M_T * _M_MAX + j]
            f = md[_M_H * _M_MAX + j]
            a = md[_M_A * _M_MAX + j]
            b = md[_M_B * _M_MAX + j]
            fa = md[_M_FA * _M_MAX + j]
            fb = md[_M_FB * _M_MAX + j]
            w = md[_M_W * _M_MAX + j]
            d = md[(_M_H + 1) * _M_MAX + j]
            zero = abs(f) <= hz * md[(_M_H + 2) * _M_MAX + j]
            left = (f < 0.0) == (fa < 0.0)
            a2 = t if left else a
            fa2 = f if left else fa
            b2 = b if left else t
            fb2 = fb if left else f
            narrow = b2 - a2 <= _BISECT_WIDTH * max(1.0, abs(a2), abs(b2))
            mid = 0.5 * (a2 + b2)
            tn = t - f / d if d != 0.0 else mid
            wn = w
            if safeguard:
                tn = mid if b2 - a2 > 0.5 * w else tn
                wn = b2 - a2
            tn = tn if (a2 < tn) & (tn < b2) else mid
            moved = run & ~zero                 # the bracket takes the new point
            going = moved & ~narrow             # and the iteration goes on from tn
            md[_M_A * _M_MAX + j] = a2 if moved else a
            md[_M_FA * _M_MAX + j] = fa2 if moved else fa
            md[_M_B * _M_MAX + j] = b2 if moved else b
            md[_M_FB * _M_MAX + j] = fb2 if moved else fb
            md[_M_T * _M_MAX + j] = tn if going else t
            md[_M_W * _M_MAX + j] = wn if going else w
            done[j] = 0 if going else 1
            active += 1 if going else 0
        if active == 0:
            return
    for j in range(nm):
        if done[j] == 0:
            T[j] = _bracketed_newton(MD[_M_P:_M_P + MAX_DEGREE + 1, j], deg, A[j], B[j], FA[j], FB[j], T[j], W[j],
                                     LOCKSTEP_NEWTON_STEPS)


@njit(cache=True, error_model="numpy")
def roots_block(S, d, nb, counts, lo, hi, chart, lflag, MD, MI, p):
    """The first part of :func:`modes_block`: the scaled quadrics, the checks of ``F`` and ``D``
    (each row's flag into ``lflag[l]``), each isolated root refined into a column of ``MD`` and
    ``MI`` (:func:`refine_roots`). Returns the number of roots."""
    F0 = _S_EL + ROW_F
    for l in range(nb):
        lflag[l] = 0
    # scaled quadrics (zero set unchanged) and their q-derivatives with the same scale
    sc = S[_S_BERN]
    for i in range(3):
        for l in range(nb):
            sc[l] = 0.0
        for k in range(8):
            c = S[_S_C + 8 * i + k]
            for l in range(nb):
                sc[l] = max(sc[l], abs(c[l]))
        for l in range(nb):
            if not (sc[l] > 0.0) or not np.isfinite(sc[l]):
                lflag[l] = 1
        for k in range(8):
            c = S[_S_C + 8 * i + k]
            cs = S[_S_CS + 8 * i + k]
            dc = S[_S_DC + 8 * i + k]
            for l in range(nb):
                cs[l] = c[l] / sc[l]
                dc[l] = dc[l] / sc[l]
    fn = S[_S_FN]
    dn = S[_S_FN + 1]
    for l in range(nb):
        fn[l] = 0.0
        dn[l] = 0.0
    for k in range(d + 1):
        f = S[F0 + k]
        for l in range(nb):
            if not np.isfinite(f[l]):
                lflag[l] = 1
            fn[l] = max(fn[l], abs(f[l]))
    for k in range(3):
        f = S[_S_EL + ROW_D + k]
        for l in range(nb):
            dn[l] = max(dn[l], abs(f[l]))
    for l in range(nb):
        if fn[l] == 0.0 or dn[l] == 0.0:
            lflag[l] = 1
        elif lflag[l] == 0 and counts[l] < 0:
            lflag[l] = 2
    # the roots of the block, one column each
    nm = 0
    for l in range(nb):
        if lflag[l] != 0:
            continue
        first = nm
        for m in range(counts[l]):
            ch = 0 if chart[l, m] == 0 else 1
            for k in range(d + 1):
                p[k] = S[F0 + k, l] / fn[l] if ch == 0 else S[F0 + d - k, l] / fn[l]
            deg = d
            while deg > 0 and p[deg] == 0.0:
                deg -= 1
            a = lo[l, m]
            b = hi[l, m]
            fa = _horner(p, deg, a)
            fb = _horner(p, deg, b)
            if deg == 0 or not (fa * fb < 0.0):
                lflag[l] = 1         # rounding hid the sign change the isolation proved: careful path
                nm = first
                break
            for k in range(d + 1):
                MD[_M_P + k, nm] = p[k]
            MD[_M_A, nm] = a
            MD[_M_B, nm] = b
            MD[_M_FA, nm] = fa
            MD[_M_FB, nm] = fb
            MI[_MI_LANE, nm] = l
            MI[_MI_CHART, nm] = ch
            MI[_MI_DEG, nm] = deg
            nm += 1
    refine_roots(MD, MI, nm, d)
    return nm


@njit(cache=True, error_model="numpy")
def modes_block(S, d, nb, tol, counts, lo, hi, chart, lflag, MD, MI, p):
    """The rest of :func:`.row._solve_row` for every row of the block, up to the modes: the scaled
    quadrics, the checks of ``F`` and ``D``, each isolated root (``counts``, ``lo``, ``hi``,
    ``chart`` of :func:`isolate_block`) refined (:func:`refine_roots`), back-substituted and
    polished (:func:`.block_modes.backsub_block`). Each row's flag goes to ``lflag[l]`` (0, 1 or 2,
    as the row kernel's), its modes to the columns of ``MD`` (image point, ``det``, joint
    residual), in the order of its roots. Returns the number of roots."""
    nm = roots_block(S, d, nb, counts, lo, hi, chart, lflag, MD, MI, p)
    backsub_block(S, nm, tol, lflag, MD, MI)
    return nm


@njit(cache=True)
def store_block(r0, nb, counts, lflag, MD, MI, nm, tol, X, out_X, out_P, out_R, out_A, cnt, flag):
    """Each row's modes sorted by ``phi`` into the kernel's outputs (:func:`.row._insert_mode`),
    two coinciding modes flagged (:func:`.row._duplicate_modes`), unused slots NaN, a flagged
    row's count 0."""
    j = 0
    for l in range(nb):
        r = r0 + l
        k = 0
        f = lflag[l]
        if f == 0:
            while j < nm and MI[_MI_LANE, j] < l:
                j += 1
            for m in range(counts[l]):
                for i in range(4):
                    X[i] = MD[_M_X + i, j + m]
                _insert_mode(out_X[r], out_P[r], out_R[r], out_A[r], k, X, MD[_M_JRES, j + m], MD[_M_DET, j + m])
                k += 1
            if _duplicate_modes(out_X[r], k, tol):
                f = 1
        if f != 0:
            k = 0
        for s in range(k, out_X.shape[1]):
            for i in range(4):
                out_X[r, s, i] = np.nan
            for i in range(3):
                out_P[r, s, i] = np.nan
            out_R[r, s] = np.nan
            out_A[r, s] = 0
        cnt[r] = k
        flag[r] = f


@njit(cache=True)
def block_workspace():
    """The scratch arrays of one block (one set per parallel chunk of blocks): ``S``, the split
    grid, per-row ints, intervals, the root columns and small per-mode arrays."""
    B = LOCKSTEP_ROWS
    M = _M_MAX
    S = np.zeros((S_SIZE, B))
    grid = np.zeros((2 * 2 ** (GRID_LEVELS + 1), GRID_FIELDS * B))
    ints = np.zeros((3, B), dtype=np.int64)          # isolation status, counts, row flags
    kinds = np.zeros((4, 2 ** (GRID_LEVELS + 1), B), dtype=np.int64)
    lo = np.full((B, MAX_DEGREE), np.nan)
    hi = np.full((B, MAX_DEGREE), np.nan)
    chart = np.full((B, MAX_DEGREE), -1, dtype=np.int8)
    work = np.zeros(ISOLATE_WORK_SIZE)
    small = np.zeros((2, MAX_DEGREE + 1))           # one row's F and E for the slow lane
    MD = np.zeros((_M_SIZE, M))
    MI = np.zeros((_MI_SIZE, M), dtype=np.int64)
    X = np.zeros(4)
    p = np.zeros(MAX_DEGREE + 1)
    return S, grid, ints, kinds, lo, hi, chart, work, small, MD, MI, X, p


@njit(cache=True)
def solve_block(Q, r0, nb, expo, coef, cerr, nmono, trig, plan, tol, proof, out_X, out_P, out_R, out_A, cnt, flag,
                S, grid, ints, kinds, lo, hi, chart, work, small, MD, MI, X, p):
    """The rows ``r0`` to ``r0 + nb - 1`` of ``Q`` through every stage in lockstep, into the kernel's
    outputs (the row kernel's ``run``, block by block)."""
    coefficients_block(Q, r0, nb, expo, coef, cerr, nmono, trig, proof, S)
    d = eliminate_block(S, plan, nb, proof)
    status, counts, lflag = ints[0], ints[1], ints[2]
    isolate_block(S, _S_EL + ROW_F, _S_ELE + ROW_F, d, nb, grid, 2 ** GRID_LEVELS, status, counts, lo, hi, chart,
                  work, small[0], small[1], kinds)
    nm = modes_block(S, d, nb, tol, counts, lo, hi, chart, lflag, MD, MI, p)
    store_block(r0, nb, counts, lflag, MD, MI, nm, tol, X, out_X, out_P, out_R, out_A, cnt, flag)


@njit(cache=True)
def counts_block(Q, r0, nb, expo, coef, cerr, nmono, trig, plan, out_counts, out_lo, out_hi, out_chart,
                 S, grid, ints, kinds, lo, hi, chart, work, small):
    """The certified counts of the rows ``r0`` to ``r0 + nb - 1`` (the row kernel's ``run_counts``):
    bounded coefficients and elimination, isolation; intervals of undecided rows left NaN / -1."""
    coefficients_block(Q, r0, nb, expo, coef, cerr, nmono, trig, True, S)
    d = eliminate_block(S, plan, nb, True)
    status, counts = ints[0], ints[1]
    isolate_block(S, _S_EL + ROW_F, _S_ELE + ROW_F, d, nb, grid, 2 ** GRID_LEVELS, status, counts, lo, hi, chart,
                  work, small[0], small[1], kinds)
    for l in range(nb):
        r = r0 + l
        k = counts[l]
        out_counts[r] = k
        for m in range(max(k, 0)):
            out_lo[r, m] = lo[l, m]
            out_hi[r, m] = hi[l, m]
            out_chart[r, m] = chart[l, m]
