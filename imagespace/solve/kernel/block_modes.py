"""The back-substitution of the lockstep kernel (:mod:`.lockstep`): every refined root of a block
taken to its mode at once, one root column each.

:func:`backsub_block` is the twin of the last loop of :func:`.row._solve_row` (for each root,
:func:`.row._root_point`, :func:`.row._mode_start`, :func:`.row._mode_finish`): the same operations
in the same order on every root, so the same floats bit for bit (``tests/solve/test_lockstep.py``
holds them equal). The roots' rows' forms and quadrics are first gathered into the root columns
of ``MD`` (:func:`_gather_roots`), so that one loop over the roots (:func:`backsub_roots`) reads
and writes rows at constant distances ``_M_MAX`` apart and vectorises: the root's orientation, the
Cramer check, the point, the DK system and its Jacobian, the determinant, Hadamard's bound, the
test that the point is accurate already (``polished``) and, for those, the normalisation, the
residual test and the joint residual, with selects instead of branches. The few roots that are not
polished take the scalar :func:`.row._mode_start` and :func:`.row._mode_finish` (Newton on the 4x4
system) afterwards.
"""

from __future__ import annotations

import math

from ...core._numba import njit
from ...core.elimination import ROW_D, ROW_F, ROW_X2, ROW_X3
from .block_layout import (_M_CH, _M_CS, _M_DET, _M_DN, _M_F, _M_G, _M_JRES, _M_MAX, _M_ST, _M_T, _M_X,
                           _MI_CHART, _MI_LANE, _S_CS, _S_DC, _S_EL, _S_FN)
from .row import (_CONDITIONED, _POLISHED, _T_CRAMER_SMALL, _T_RESIDUAL, _joint_derivative, _mode_finish,
                  _mode_start, _root_point)

__all__ = ["backsub_block", "ST_DONE", "ST_FAILED", "ST_SCALAR"]

#: Status of a root column after :func:`backsub_roots` (``MD[_M_ST]``): mode found and checked,
#: ``ST_DONE``; its row must take the careful path, ``ST_FAILED``; Newton needed (not polished),
#: ``ST_SCALAR``.
ST_DONE, ST_FAILED, ST_SCALAR = 0.0, 1.0, 2.0


@njit(cache=True)
def _gather_roots(S, MD, MI, nm):
    """Each root's row's ``D, X2, X3``, scaled quadrics, scaled derivatives and ``max |D|`` (from
    the block workspace ``S``) and its chart into the root's column of ``MD``."""
    lane = MI[_MI_LANE]
    for k in range(ROW_F - ROW_D):
        src = S[_S_EL + ROW_D + k]
        dst = MD[_M_F + k]
        for j in range(nm):
            dst[j] = src[lane[j]]
    for k in range(24):
        src = S[_S_CS + k]
        dst = MD[_M_CS + k]
        for j in range(nm):
            dst[j] = src[lane[j]]
        src = S[_S_DC + k]
        dst = MD[_M_G + k]
        for j in range(nm):
            dst[j] = src[lane[j]]
    src = S[_S_FN + 1]
    dst = MD[_M_DN]
    ch = MI[_MI_CHART]
    dch = MD[_M_CH]
    for j in range(nm):
        dst[j] = src[lane[j]]
        dch[j] = 1.0 if ch[j] != 0 else 0.0


@njit(cache=True)
def _quadric_lane(c, a0, a1, b0, b1, k0, k1, k2, x0, x1, x2, x3):
    """One quadric (coefficients ``c .. k2``) and its gradient at ``(x0, x1, x2, x3)``: one row of
    :func:`imagespace.core.quadrics.dk_system_row`, operation for operation."""
    v = (c * (x2 * x2 + x3 * x3) + x2 * (a0 * x0 + a1 * x1) + x3 * (b0 * x0 + b1 * x1)
         + k0 * x0 * x0 + k1 * x0 * x1 + k2 * x1 * x1)
    j0 = a0 * x2 + b0 * x3 + 2 * k0 * x0 + k1 * x1
    j1 = a1 * x2 + b1 * x3 + k1 * x0 + 2 * k2 * x1
    j2 = 2 * c * x2 + a0 * x0 + a1 * x1
    j3 = 2 * c * x3 + b0 * x0 + b1 * x1
    return v, j0, j1, j2, j3


@njit(cache=True)
def _bf2_lane(f0, f1, f2, x0, x1):
    """:func:`.row._bf` of degree 2, operation for operation."""
    v = 0.0 * x0 + f0 * 1.0
    p1 = 1.0 * x1
    v = v * x0 + f1 * p1
    p1 *= x1
    return v * x0 + f2 * p1


@njit(cache=True)
def _bf3_lane(f0, f1, f2, f3, x0, x1):
    """:func:`.row._bf` of degree 3, operation for operation."""
    v = 0.0 * x0 + f0 * 1.0
    p1 = 1.0 * x1
    v = v * x0 + f1 * p1
    p1 *= x1
    v = v * x0 + f2 * p1
    p1 *= x1
    return v * x0 + f3 * p1


@njit(cache=True, error_model="numpy")
def backsub_roots(MD, nm, tol):
    """The roots ``0`` to ``nm - 1`` of ``MD`` (refined ``MD[_M_T]``, gathered columns of
    :func:`_gather_roots`) to their modes, all at once.

    Parameters
    ----------
    MD : (_M_SIZE, _M_MAX) float array
        The root columns; reads ``T``, ``F``, ``CS``, ``G``, ``DN``, ``CH``, writes ``X``,
        ``DET``, ``JRES`` and ``ST``.
    nm : int
        Number of roots.
    tol : float array
        The kernel's thresholds (:func:`.row.kernel_tolerances`).

    Notes
    -----
    Operation for operation :func:`.row._root_point` and :func:`.row._mode_start` on every root,
    then the ``polished`` branch of :func:`.row._mode_finish`: a root whose Cramer denominator
    nearly vanishes or whose polished point fails the residual test gets the status
    :data:`ST_FAILED`, a root that is not polished :data:`ST_SCALAR` (its outputs are then
    meaningless), the others :data:`ST_DONE` with the normalised point, ``det`` and the joint
    residual.
    """
    md = MD.reshape(MD.size)
    M = _M_MAX
    small = tol[_T_CRAMER_SMALL]
    rtol = tol[_T_RESIDUAL]
    for j in range(nm):
        # _root_point
        t = md[_M_T * M + j]
        ch0 = md[_M_CH * M + j] == 0.0
        h = 1.0 / math.sqrt(1.0 + t * t)
        th = t * h
        x0 = h if ch0 else th
        x1 = th if ch0 else h
        flip = (x0 < 0.0) | ((x0 == 0.0) & (x1 < 0.0))
        x0 = -x0 if flip else x0
        x1 = -x1 if flip else x1
        # _mode_start: the Cramer check and the back-substituted point
        o = (_M_F + ROW_D) * M + j
        Dv = _bf2_lane(md[o], md[o + M], md[o + 2 * M], x0, x1)
        cramer = abs(Dv) <= small * md[_M_DN * M + j]
        o = (_M_F + ROW_X2) * M + j
        x2 = _bf3_lane(md[o], md[o + M], md[o + 2 * M], md[o + 3 * M], x0, x1) / Dv
        o = (_M_F + ROW_X3) * M + j
        x3 = _bf3_lane(md[o], md[o + M], md[o + 2 * M], md[o + 3 * M], x0, x1) / Dv
        # the system and its Jacobian (rows 0-2; row 3 is 2 x0, 2 x1, 0, 0)
        o = _M_CS * M + j
        v0, j00, j01, j02, j03 = _quadric_lane(md[o], md[o + M], md[o + 2 * M], md[o + 3 * M], md[o + 4 * M],
                                               md[o + 5 * M], md[o + 6 * M], md[o + 7 * M], x0, x1, x2, x3)
        o = (_M_CS + 8) * M + j
        v1, j10, j11, j12, j13 = _quadric_lane(md[o], md[o + M], md[o + 2 * M], md[o + 3 * M], md[o + 4 * M],
                                               md[o + 5 * M], md[o + 6 * M], md[o + 7 * M], x0, x1, x2, x3)
        o = (_M_CS + 16) * M + j
        v2, j20, j21, j22, j23 = _quadric_lane(md[o], md[o + M], md[o + 2 * M], md[o + 3 * M], md[o + 4 * M],
                                               md[o + 5 * M], md[o + 6 * M], md[o + 7 * M], x0, x1, x2, x3)
        j30 = 2 * x0
        j31 = 2 * x1
        j32 = 0.0
        j33 = 0.0
        # _det4
        m30 = (j01 * (j12 * j23 - j13 * j22)
               - j02 * (j11 * j23 - j13 * j21)
               + j03 * (j11 * j22 - j12 * j21))
        m31 = (j00 * (j12 * j23 - j13 * j22)
               - j02 * (j10 * j23 - j13 * j20)
               + j03 * (j10 * j22 - j12 * j20))
        det = -2.0 * x0 * m30 + 2.0 * x1 * m31
        size = 1.0 + x2 * x2 + x3 * x3
        hadamard = 1.0
        hadamard *= math.sqrt(j00 * j00 + j01 * j01 + j02 * j02 + j03 * j03)
        hadamard *= math.sqrt(j10 * j10 + j11 * j11 + j12 * j12 + j13 * j13)
        hadamard *= math.sqrt(j20 * j20 + j21 * j21 + j22 * j22 + j23 * j23)
        hadamard *= math.sqrt(j30 * j30 + j31 * j31 + j32 * j32 + j33 * j33)
        polished = ((max(abs(v0), abs(v1), abs(v2)) <= _POLISHED * size)
                    & (abs(det) >= _CONDITIONED * hadamard))
        # _mode_finish, polished: normalised, residual test, joint residual
        sg = -1.0 if ((x0 < 0.0) | ((x0 == 0.0) & (x1 < 0.0))) else 1.0
        nrm = sg / math.sqrt(x0 * x0 + x1 * x1)
        x0 = x0 * nrm
        x1 = x1 * nrm
        x2 = x2 * nrm
        x3 = x3 * nrm
        v0 = v0 * (nrm * nrm)
        v1 = v1 * (nrm * nrm)
        v2 = v2 * (nrm * nrm)
        size = 1.0 + x2 * x2 + x3 * x3
        rel = max(abs(v0), abs(v1), abs(v2)) / size
        good = rel <= rtol
        jres = 0.0
        o = _M_G * M + j
        dq = _joint_derivative(md[o], md[o + M], md[o + 2 * M], md[o + 3 * M], md[o + 4 * M], md[o + 5 * M],
                               md[o + 6 * M], md[o + 7 * M], x0, x1, x2, x3)
        jres = max(jres, abs(v0) / abs(dq) if dq != 0.0 else math.inf)
        o = (_M_G + 8) * M + j
        dq = _joint_derivative(md[o], md[o + M], md[o + 2 * M], md[o + 3 * M], md[o + 4 * M], md[o + 5 * M],
                               md[o + 6 * M], md[o + 7 * M], x0, x1, x2, x3)
        jres = max(jres, abs(v1) / abs(dq) if dq != 0.0 else math.inf)
        o = (_M_G + 16) * M + j
        dq = _joint_derivative(md[o], md[o + M], md[o + 2 * M], md[o + 3 * M], md[o + 4 * M], md[o + 5 * M],
                               md[o + 6 * M], md[o + 7 * M], x0, x1, x2, x3)
        jres = max(jres, abs(v2) / abs(dq) if dq != 0.0 else math.inf)
        md[_M_X * M + j] = x0
        md[(_M_X + 1) * M + j] = x1
        md[(_M_X + 2) * M + j] = x2
        md[(_M_X + 3) * M + j] = x3
        md[_M_DET * M + j] = det
        md[_M_JRES * M + j] = jres
        st = ST_DONE if good else ST_FAILED
        st = st if polished else ST_SCALAR
        md[_M_ST * M + j] = ST_FAILED if cramer else st


@njit(cache=True, error_model="numpy")
def backsub_block(S, nm, tol, lflag, MD, MI, rows, X, val, J, dx):
    """The modes of the roots ``0`` to ``nm - 1`` of a block (the last loop of
    :func:`.row._solve_row` for every row of the block).

    Parameters
    ----------
    S : (S_SIZE, LOCKSTEP_ROWS) float array
        The block workspace after :func:`.lockstep.modes_block`'s checks (scaled quadrics and
        derivatives, ``D, X2, X3``, ``max |D|``).
    nm : int
        Number of roots (columns of ``MD`` and ``MI``, refined by :func:`.lockstep.refine_roots`).
    tol : float array
        The kernel's thresholds.
    lflag : (LOCKSTEP_ROWS,) int array
        The rows' flags: set to 1 for a row any of whose roots fails.
    MD, MI : root columns
        Each root's mode goes to ``MD[_M_X]``, ``MD[_M_DET]``, ``MD[_M_JRES]`` (meaningless for a
        flagged row's roots).
    rows : (LOCKSTEP_ROWS, _R_SIZE) float array
        Each row's quadrics and forms in the row kernel's layout, for the roots taking the
        scalar path.
    X, val, J, dx : scratch of :func:`.row._mode_start` and :func:`.row._mode_finish`.

    Notes
    -----
    A root failing flags its row; the row kernel stops at a row's first failing root, but the
    modes of a flagged row are discarded, so the outputs are the same.

    Examples
    --------
    The six modes of the general 3-RPR example, one row through the block's stages:

    >>> import numpy as np
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import design_tables, kernel_tolerances
    >>> from imagespace.solve.kernel.lockstep import (block_workspace, coefficients_block, eliminate_block,
    ...     isolate_block, roots_block, GRID_LEVELS, _S_EL, _S_ELE)
    >>> from imagespace.solve.kernel.block_layout import _M_X
    >>> from imagespace.core.elimination import ROW_F
    >>> m = isp.examples.general_3rpr()
    >>> t = design_tables(m)
    >>> S, grid, ints, kinds, lo, hi, chart, work, small, MD, MI, rows, X, val, J, dx, p = block_workspace()
    >>> coefficients_block(np.array([m.q_example_float]), 0, 1, t.expo, t.coef, t.cerr, t.nmono, t.trig, True, S)
    >>> d = eliminate_block(S, t.plan, 1, True)
    >>> isolate_block(S, _S_EL + ROW_F, _S_ELE + ROW_F, d, 1, grid, 2 ** GRID_LEVELS, ints[0], ints[1], lo, hi,
    ...               chart, work, small[0], small[1], kinds)
    >>> nm = roots_block(S, d, 1, ints[1], lo, hi, chart, ints[2], MD, MI, rows, p)
    >>> backsub_block(S, nm, kernel_tolerances(m.tolerances), ints[2], MD, MI, rows, X, val, J, dx)
    >>> nm, int(ints[2][0])
    (6, 0)
    >>> bool(np.allclose(MD[_M_X, :6] ** 2 + MD[_M_X + 1, :6] ** 2, 1.0))
    True
    """
    _gather_roots(S, MD, MI, nm)
    backsub_roots(MD, nm, tol)
    st = MD[_M_ST]
    for j in range(nm):
        if st[j] == ST_FAILED:
            lflag[MI[_MI_LANE, j]] = 1
    for j in range(nm):
        l = MI[_MI_LANE, j]
        if st[j] != ST_SCALAR or lflag[l] != 0:
            continue
        x0, x1 = _root_point(MD[_M_T, j], MI[_MI_CHART, j])
        buf = rows[l]
        Cs = buf[0:24]
        ok, det, polished = _mode_start(buf, 48 + ROW_D, 48 + ROW_X2, 48 + ROW_X3, 2, 3, Cs, x0, x1, MD[_M_DN, j],
                                        tol, X, val, J)
        if ok:
            ok, det, jres = _mode_finish(Cs, buf[24:48], X, val, J, dx, det, polished, tol)
        if not ok:
            lflag[l] = 1
            continue
        for i in range(4):
            MD[_M_X + i, j] = X[i]
        MD[_M_DET, j] = det
        MD[_M_JRES, j] = jres

