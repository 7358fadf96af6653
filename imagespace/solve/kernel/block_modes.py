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
residual test and the joint residual, with selects instead of branches. The roots that are not
polished (about a fifth) then take Newton's method on the 4x4 system together
(:func:`newton_roots`: the iteration of :func:`.row._mode_finish`, its 4x4 solve's row exchanges as
selects), compacted into consecutive columns.
"""

from __future__ import annotations

import math

from ...core._numba import njit
from ...core.elimination import ROW_D, ROW_F, ROW_X2, ROW_X3
from .block_layout import (_M_CH, _M_CS, _M_DET, _M_DN, _M_F, _M_G, _M_H, _M_JRES, _M_MAX, _M_ST, _M_T, _M_X,
                           _MI_CHART, _MI_LANE, _S_CS, _S_DC, _S_EL, _S_FN)
from .row import (_CONDITIONED, _NEWTON_ITERATIONS, _POLISHED, _T_CRAMER_SMALL, _T_NEWTON_STOP, _T_PIVOT,
                  _T_RESIDUAL, _joint_derivative)

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
        det = _det_lane(j00, j01, j02, j03, j10, j11, j12, j13, j20, j21, j22, j23, x0, x1)
        size = 1.0 + x2 * x2 + x3 * x3
        hadamard = 1.0
        hadamard *= math.sqrt(j00 * j00 + j01 * j01 + j02 * j02 + j03 * j03)
        hadamard *= math.sqrt(j10 * j10 + j11 * j11 + j12 * j12 + j13 * j13)
        hadamard *= math.sqrt(j20 * j20 + j21 * j21 + j22 * j22 + j23 * j23)
        hadamard *= math.sqrt(j30 * j30 + j31 * j31 + j32 * j32 + j33 * j33)
        polished = ((max(abs(v0), abs(v1), abs(v2)) <= _POLISHED * size)
                    & (abs(det) >= _CONDITIONED * hadamard))
        # the back-substituted point, where newton_roots starts from for a root that is not polished
        md[_M_H * M + j] = x0
        md[(_M_H + 1) * M + j] = x1
        md[(_M_H + 2) * M + j] = x2
        md[(_M_H + 3) * M + j] = x3
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


@njit(cache=True)
def _det_lane(j00, j01, j02, j03, j10, j11, j12, j13, j20, j21, j22, j23, x0, x1):
    """:func:`.row._det4` on scalars (the Jacobian's rows 0-2; row 3 is ``2 x0, 2 x1, 0, 0``),
    operation for operation."""
    m30 = (j01 * (j12 * j23 - j13 * j22)
           - j02 * (j11 * j23 - j13 * j21)
           + j03 * (j11 * j22 - j12 * j21))
    m31 = (j00 * (j12 * j23 - j13 * j22)
           - j02 * (j10 * j23 - j13 * j20)
           + j03 * (j10 * j22 - j12 * j20))
    return -2.0 * x0 * m30 + 2.0 * x1 * m31


@njit(cache=True)
def _swap(s, a0, a1, a2, a3, ar, b0, b1, b2, b3, br):
    """Rows ``a`` and ``b`` (four entries and the right-hand side) exchanged where ``s``."""
    return (b0 if s else a0, b1 if s else a1, b2 if s else a2, b3 if s else a3, br if s else ar,
            a0 if s else b0, a1 if s else b1, a2 if s else b2, a3 if s else b3, ar if s else br)


@njit(cache=True, error_model="numpy")
def _solve4_lane(a00, a01, a02, a03, a10, a11, a12, a13, a20, a21, a22, a23, a30, a31, a32, a33,
                 r0, r1, r2, r3, pivot):
    """:func:`.row._solve4` on scalars, operation for operation and with the same row exchanges
    (selects): ``(singular, dx0, dx1, dx2, dx3)``, ``singular`` where ``_solve4`` returns 0 (a
    pivot below ``pivot`` times the largest entry, or a determinant that rounds to zero). Entries
    below a pivot are not updated (``_solve4`` never reads them again)."""
    scale = 0.0
    scale = max(scale, abs(a00))
    scale = max(scale, abs(a01))
    scale = max(scale, abs(a02))
    scale = max(scale, abs(a03))
    scale = max(scale, abs(a10))
    scale = max(scale, abs(a11))
    scale = max(scale, abs(a12))
    scale = max(scale, abs(a13))
    scale = max(scale, abs(a20))
    scale = max(scale, abs(a21))
    scale = max(scale, abs(a22))
    scale = max(scale, abs(a23))
    scale = max(scale, abs(a30))
    scale = max(scale, abs(a31))
    scale = max(scale, abs(a32))
    scale = max(scale, abs(a33))
    tiny = pivot * scale
    det = 1.0
    # column 0
    p = 0
    best = abs(a00)
    p = 1 if abs(a10) > best else p
    best = abs(a10) if p == 1 else best
    p = 2 if abs(a20) > best else p
    best = abs(a20) if p == 2 else best
    p = 3 if abs(a30) > best else p
    best = abs(a30) if p == 3 else best
    singular = best <= tiny
    a00, a01, a02, a03, r0, a10, a11, a12, a13, r1 = _swap(p == 1, a00, a01, a02, a03, r0, a10, a11, a12, a13, r1)
    a00, a01, a02, a03, r0, a20, a21, a22, a23, r2 = _swap(p == 2, a00, a01, a02, a03, r0, a20, a21, a22, a23, r2)
    a00, a01, a02, a03, r0, a30, a31, a32, a33, r3 = _swap(p == 3, a00, a01, a02, a03, r0, a30, a31, a32, a33, r3)
    det = -det if p != 0 else det
    det *= a00
    f = a10 / a00
    a11 -= f * a01
    a12 -= f * a02
    a13 -= f * a03
    r1 -= f * r0
    f = a20 / a00
    a21 -= f * a01
    a22 -= f * a02
    a23 -= f * a03
    r2 -= f * r0
    f = a30 / a00
    a31 -= f * a01
    a32 -= f * a02
    a33 -= f * a03
    r3 -= f * r0
    # column 1
    p = 1
    best = abs(a11)
    p = 2 if abs(a21) > best else p
    best = abs(a21) if p == 2 else best
    p = 3 if abs(a31) > best else p
    best = abs(a31) if p == 3 else best
    singular = singular | (best <= tiny)
    a10, a11, a12, a13, r1, a20, a21, a22, a23, r2 = _swap(p == 2, a10, a11, a12, a13, r1, a20, a21, a22, a23, r2)
    a10, a11, a12, a13, r1, a30, a31, a32, a33, r3 = _swap(p == 3, a10, a11, a12, a13, r1, a30, a31, a32, a33, r3)
    det = -det if p != 1 else det
    det *= a11
    f = a21 / a11
    a22 -= f * a12
    a23 -= f * a13
    r2 -= f * r1
    f = a31 / a11
    a32 -= f * a12
    a33 -= f * a13
    r3 -= f * r1
    # column 2
    p = 2
    best = abs(a22)
    p = 3 if abs(a32) > best else p
    best = abs(a32) if p == 3 else best
    singular = singular | (best <= tiny)
    a20, a21, a22, a23, r2, a30, a31, a32, a33, r3 = _swap(p == 3, a20, a21, a22, a23, r2, a30, a31, a32, a33, r3)
    det = -det if p != 2 else det
    det *= a22
    f = a32 / a22
    a33 -= f * a23
    r3 -= f * r2
    # column 3
    singular = singular | (abs(a33) <= tiny)
    det *= a33
    singular = singular | (det == 0.0)
    dx3 = r3 / a33
    s = r2
    s -= a23 * dx3
    dx2 = s / a22
    s = r1
    s -= a12 * dx2
    s -= a13 * dx3
    dx1 = s / a11
    s = r0
    s -= a01 * dx1
    s -= a02 * dx2
    s -= a03 * dx3
    dx0 = s / a00
    return singular, dx0, dx1, dx2, dx3


#: Newton's state of a compacted root column (``MD[_M_ST]`` of columns ``nm`` on).
_RUNNING, _STOPPED = 1.0, 0.0


@njit(cache=True, error_model="numpy")
def newton_roots(MD, MI, nm, tol, lflag):
    """The roots of status :data:`ST_SCALAR` (not polished) to their modes, all at once: the
    Newton iteration of :func:`.row._mode_finish` on the 4x4 system from the back-substituted
    point, then the normalisation, the residual test and the joint residual, operation for
    operation (the 4x4 solve with :func:`.row._solve4`'s row exchanges as selects).

    The roots' quadrics, derivatives and points are first copied after the block's ``nm`` roots
    (columns ``nm`` to ``nm + ns - 1`` of ``MD``, which has room for as many again), so that the
    loops run over consecutive columns at constant distances and vectorise. Each mode goes back to
    its root's column (``X``, ``DET``, ``JRES``); a root failing the residual test sets its row's
    flag in ``lflag``. Returns the number of such roots."""
    md = MD.reshape(MD.size)
    M = _M_MAX
    ns = 0
    for j in range(nm):
        if md[_M_ST * M + j] != ST_SCALAR:
            continue
        c = nm + ns
        for k in range(24):
            md[(_M_CS + k) * M + c] = md[(_M_CS + k) * M + j]
            md[(_M_G + k) * M + c] = md[(_M_G + k) * M + j]
        for i in range(4):
            md[(_M_X + i) * M + c] = md[(_M_H + i) * M + j]
        md[_M_T * M + c] = j
        md[_M_ST * M + c] = _RUNNING
        ns += 1
    if ns == 0:
        return 0
    pivot = tol[_T_PIVOT]
    stop = tol[_T_NEWTON_STOP]
    rtol = tol[_T_RESIDUAL]
    # the compacted columns as their own flat view (column s of it is column nm + s of MD): indices
    # from 0, which LLVM needs to see the constant distances and vectorise the loops
    mc = md[nm:]
    for it in range(_NEWTON_ITERATIONS):
        running = 0
        for c in range(ns):
            run = mc[_M_ST * M + c] == _RUNNING
            x0 = mc[_M_X * M + c]
            x1 = mc[(_M_X + 1) * M + c]
            x2 = mc[(_M_X + 2) * M + c]
            x3 = mc[(_M_X + 3) * M + c]
            # dk_system_row and _det4 (the coefficients passed as values: loads inside a callee
            # taking the array keep LLVM from vectorising)
            o = _M_CS * M + c
            v0, j00, j01, j02, j03 = _quadric_lane(mc[o], mc[o + M], mc[o + 2 * M], mc[o + 3 * M], mc[o + 4 * M],
                                                   mc[o + 5 * M], mc[o + 6 * M], mc[o + 7 * M], x0, x1, x2, x3)
            o += 8 * M
            v1, j10, j11, j12, j13 = _quadric_lane(mc[o], mc[o + M], mc[o + 2 * M], mc[o + 3 * M], mc[o + 4 * M],
                                                   mc[o + 5 * M], mc[o + 6 * M], mc[o + 7 * M], x0, x1, x2, x3)
            o += 8 * M
            v2, j20, j21, j22, j23 = _quadric_lane(mc[o], mc[o + M], mc[o + 2 * M], mc[o + 3 * M], mc[o + 4 * M],
                                                   mc[o + 5 * M], mc[o + 6 * M], mc[o + 7 * M], x0, x1, x2, x3)
            v3 = x0 * x0 + x1 * x1 - 1.0
            det = _det_lane(j00, j01, j02, j03, j10, j11, j12, j13, j20, j21, j22, j23, x0, x1)
            singular, d0, d1, d2, d3 = _solve4_lane(j00, j01, j02, j03, j10, j11, j12, j13, j20, j21, j22, j23,
                                                    2 * x0, 2 * x1, 0.0, 0.0, -v0, -v1, -v2, -v3, pivot)
            n0 = x0 + d0
            n1 = x1 + d1
            n2 = x2 + d2
            n3 = x3 + d3
            big = 1.0
            stp = 0.0
            big = max(big, abs(n0))
            stp = max(stp, abs(d0))
            big = max(big, abs(n1))
            stp = max(stp, abs(d1))
            big = max(big, abs(n2))
            stp = max(stp, abs(d2))
            big = max(big, abs(n3))
            stp = max(stp, abs(d3))
            step = run & ~singular
            going = step & ~(stp <= stop * big)
            mc[_M_X * M + c] = n0 if step else x0
            mc[(_M_X + 1) * M + c] = n1 if step else x1
            mc[(_M_X + 2) * M + c] = n2 if step else x2
            mc[(_M_X + 3) * M + c] = n3 if step else x3
            mc[_M_DET * M + c] = det if run else mc[_M_DET * M + c]
            mc[_M_ST * M + c] = _RUNNING if going else _STOPPED
            running += 1 if going else 0
        if running == 0:
            break
    # the normalised point, its residual test and the joint residual (ST: 1 where it passes)
    for c in range(ns):
        x0 = mc[_M_X * M + c]
        x1 = mc[(_M_X + 1) * M + c]
        x2 = mc[(_M_X + 2) * M + c]
        x3 = mc[(_M_X + 3) * M + c]
        sg = -1.0 if ((x0 < 0.0) | ((x0 == 0.0) & (x1 < 0.0))) else 1.0
        nrm = sg / math.sqrt(x0 * x0 + x1 * x1)
        x0 = x0 * nrm
        x1 = x1 * nrm
        x2 = x2 * nrm
        x3 = x3 * nrm
        o = _M_CS * M + c
        v0 = _quadric_lane(mc[o], mc[o + M], mc[o + 2 * M], mc[o + 3 * M], mc[o + 4 * M], mc[o + 5 * M],
                           mc[o + 6 * M], mc[o + 7 * M], x0, x1, x2, x3)[0]
        o += 8 * M
        v1 = _quadric_lane(mc[o], mc[o + M], mc[o + 2 * M], mc[o + 3 * M], mc[o + 4 * M], mc[o + 5 * M],
                           mc[o + 6 * M], mc[o + 7 * M], x0, x1, x2, x3)[0]
        o += 8 * M
        v2 = _quadric_lane(mc[o], mc[o + M], mc[o + 2 * M], mc[o + 3 * M], mc[o + 4 * M], mc[o + 5 * M],
                           mc[o + 6 * M], mc[o + 7 * M], x0, x1, x2, x3)[0]
        size = 1.0 + x2 * x2 + x3 * x3
        rel = max(abs(v0), abs(v1), abs(v2)) / size
        jres = 0.0
        o = _M_G * M + c
        dq = _joint_derivative(mc[o], mc[o + M], mc[o + 2 * M], mc[o + 3 * M], mc[o + 4 * M], mc[o + 5 * M],
                               mc[o + 6 * M], mc[o + 7 * M], x0, x1, x2, x3)
        jres = max(jres, abs(v0) / abs(dq) if dq != 0.0 else math.inf)
        o = (_M_G + 8) * M + c
        dq = _joint_derivative(mc[o], mc[o + M], mc[o + 2 * M], mc[o + 3 * M], mc[o + 4 * M], mc[o + 5 * M],
                               mc[o + 6 * M], mc[o + 7 * M], x0, x1, x2, x3)
        jres = max(jres, abs(v1) / abs(dq) if dq != 0.0 else math.inf)
        o = (_M_G + 16) * M + c
        dq = _joint_derivative(mc[o], mc[o + M], mc[o + 2 * M], mc[o + 3 * M], mc[o + 4 * M], mc[o + 5 * M],
                               mc[o + 6 * M], mc[o + 7 * M], x0, x1, x2, x3)
        jres = max(jres, abs(v2) / abs(dq) if dq != 0.0 else math.inf)
        mc[_M_X * M + c] = x0
        mc[(_M_X + 1) * M + c] = x1
        mc[(_M_X + 2) * M + c] = x2
        mc[(_M_X + 3) * M + c] = x3
        mc[_M_JRES * M + c] = jres
        mc[_M_ST * M + c] = 1.0 if rel <= rtol else 0.0
    # back to the roots' own columns
    failed = 0
    for c in range(ns):
        j = int(mc[_M_T * M + c])
        for i in range(4):
            md[(_M_X + i) * M + j] = mc[(_M_X + i) * M + c]
        md[_M_DET * M + j] = mc[_M_DET * M + c]
        md[_M_JRES * M + j] = mc[_M_JRES * M + c]
        if mc[_M_ST * M + c] == 0.0:
            lflag[MI[_MI_LANE, j]] = 1
            failed += 1
    return failed


@njit(cache=True, error_model="numpy")
def backsub_block(S, nm, tol, lflag, MD, MI):
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
    >>> S, grid, ints, kinds, lo, hi, chart, work, small, MD, MI, X, p = block_workspace()
    >>> coefficients_block(np.array([m.q_example_float]), 0, 1, t.expo, t.coef, t.cerr, t.nmono, t.trig, True, S)
    >>> d = eliminate_block(S, t.plan, 1, True)
    >>> isolate_block(S, _S_EL + ROW_F, _S_ELE + ROW_F, d, 1, grid, 2 ** GRID_LEVELS, ints[0], ints[1], lo, hi,
    ...               chart, work, small[0], small[1], kinds)
    >>> nm = roots_block(S, d, 1, ints[1], lo, hi, chart, ints[2], MD, MI, p)
    >>> backsub_block(S, nm, kernel_tolerances(m.tolerances), ints[2], MD, MI)
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
    newton_roots(MD, MI, nm, tol, lflag)
