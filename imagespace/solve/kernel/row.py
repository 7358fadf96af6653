"""The row-at-a-time stages of the batch kernel: everything after the coefficients for ONE row
(:func:`_solve_row`: real roots isolated on the rigorous enclosure of ``F``, refined, back-substituted,
polished, checked), the compiled twins of the DK system and the elimination, and the kernel's
thresholds (:func:`kernel_tolerances`). The lockstep kernel (:mod:`.lockstep`) runs the same steps on
blocks of rows and hands the rows it peels off to these functions."""

from __future__ import annotations

import itertools
import math

import numpy as np

from ...core._numba import njit
from ...core.elimination import eliminate_row as _eliminate_row_py
from ...core.isolate import ISOLATE_WORK_SIZE, count_real_roots_row
from ...core.quadrics import dk_system_row
from .newton import _horner, _monotone_root

_MAX = 6
_POLISHED = 1e-14            # a back-substituted mode with a relative residual below this and a
_CONDITIONED = 1e-2          # |det J| above this times Hadamard's bound is not polished by Newton
                             # (it is at rounding level already: a numerical-method knob, the
                             # residual check and the joint residual still decide)
_NEWTON_ITERATIONS = 8       # most Newton steps on the 4x4 system (one or two reach rounding level)

# The per-row scratch buffer of _solve_row, one named slice per array (numba folds these globals
# into constants): the scaled polynomial p of a chart, up to 12 chart candidates, the scaled
# quadrics Cs, Newton's val, dx, X, J, and the isolation's work and its intervals (lo, hi, chart).
_WORK_SIZES = (7, 48, 24, 4, 4, 4, 16, ISOLATE_WORK_SIZE, 6, 6, 6)
(_W_P, _W_CAND, _W_CS, _W_VAL, _W_DX, _W_X, _W_J, _W_ISO, _W_ILO, _W_IHI,
 _W_ICH) = (0, *itertools.accumulate(_WORK_SIZES[:-1]))
_WORK_SIZE = sum(_WORK_SIZES)

# The kernel's decision thresholds arrive as one float array (from the design's Tolerances, see
# kernel_tolerances); these name its entries.
(_T_CRAMER_SMALL, _T_PIVOT, _T_NEWTON_STOP, _T_RESIDUAL, _T_DUPLICATE) = range(5)


def kernel_tolerances(tol):
    """The compiled kernel's thresholds as a float array (entries named ``_T_*``), read from a
    :class:`~imagespace.tolerances.Tolerances`.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.solve.kernel import kernel_tolerances
    >>> kernel_tolerances(isp.TOLERANCES).tolist()
    [1e-07, 1e-14, 1e-09, 1e-09, 1e-09]
    """
    return np.array([tol.cramer_small, tol.newton_stop, tol.kernel_newton_stop, tol.kernel_residual,
                     tol.kernel_duplicate], dtype=float)


@njit(cache=True)
def _bf(f, off, deg, x0, x1):
    """Binary form with coefficients f[off:off+deg+1] (x0**(deg-k) x1**k) at (x0, x1), |x0|, |x1| <= 1."""
    v = 0.0
    p1 = 1.0
    for k in range(deg + 1):
        v = v * x0 + f[off + k] * p1
        p1 *= x1
    return v


# the DK system and its Jacobian: compiled from its one home in core/quadrics.py
_system = njit(cache=True)(dk_system_row)
# the elimination of one row: compiled from its one home in core/elimination.py
eliminate_row = njit(cache=True)(_eliminate_row_py)


@njit(cache=True)
def _det4(J, x0, x1):
    """det of the 4x4 system Jacobian, expanded along its last row (2 x0, 2 x1, 0, 0)."""
    m30 = (J[0, 1] * (J[1, 2] * J[2, 3] - J[1, 3] * J[2, 2])
           - J[0, 2] * (J[1, 1] * J[2, 3] - J[1, 3] * J[2, 1])
           + J[0, 3] * (J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1]))
    m31 = (J[0, 0] * (J[1, 2] * J[2, 3] - J[1, 3] * J[2, 2])
           - J[0, 2] * (J[1, 0] * J[2, 3] - J[1, 3] * J[2, 0])
           + J[0, 3] * (J[1, 0] * J[2, 2] - J[1, 2] * J[2, 0]))
    return -2.0 * x0 * m30 + 2.0 * x1 * m31


@njit(cache=True)
def _solve4(J, r, dx, pivot):
    """Solve J dx = r in place (partial pivoting); returns the determinant (0 when singular: a
    pivot below ``pivot`` times the largest entry)."""
    det = 1.0
    scale = 0.0
    for i in range(4):
        for k in range(4):
            scale = max(scale, abs(J[i, k]))
    for k in range(4):
        p = k
        for i in range(k + 1, 4):
            if abs(J[i, k]) > abs(J[p, k]):
                p = i
        if abs(J[p, k]) <= pivot * scale:
            return 0.0
        if p != k:
            for m in range(4):
                tmp = J[k, m]
                J[k, m] = J[p, m]
                J[p, m] = tmp
            tmp = r[k]
            r[k] = r[p]
            r[p] = tmp
            det = -det
        det *= J[k, k]
        for i in range(k + 1, 4):
            f = J[i, k] / J[k, k]
            for m in range(k, 4):
                J[i, m] -= f * J[k, m]
            r[i] -= f * r[k]
    for k in range(3, -1, -1):
        s = r[k]
        for m in range(k + 1, 4):
            s -= J[k, m] * dx[m]
        dx[k] = s / J[k, k]
    return det


@njit(cache=True)
def _root_point(t, chart):
    """The unit orientation ``(x0, x1)`` (``x0 >= 0``) of the root ``t`` of chart ``chart`` (0:
    ``t = x1/x0``, 1: ``t = x0/x1``)."""
    h = 1.0 / math.sqrt(1.0 + t * t)
    x0 = h if chart == 0 else t * h
    x1 = t * h if chart == 0 else h
    if x0 < 0.0 or (x0 == 0.0 and x1 < 0.0):
        x0, x1 = -x0, -x1
    return x0, x1


@njit(cache=True)
def _mode_start(buf, oD, oX2, oX3, dD, dX, Cs, x0, x1, dn, tol, X, val, J):
    """The mode of orientation ``(x0, x1)``: back-substituted into ``X`` (``x2 = X2/D``, ``x3 =
    X3/D``, the forms at ``buf[oD]``, ``buf[oX2]``, ``buf[oX3]``), the system and its Jacobian at
    it into ``val``, ``J``. Returns ``(ok, det, polished)``: ``ok`` False when the Cramer
    denominator nearly vanishes there (``|D| <= cramer_small * max |D_k|``), ``polished`` when the
    residual proves the point accurate already (Newton skipped)."""
    Dv = _bf(buf, oD, dD, x0, x1)
    if abs(Dv) <= tol[_T_CRAMER_SMALL] * dn:
        return False, 0.0, False
    X[0], X[1] = x0, x1
    X[2] = _bf(buf, oX2, dX, x0, x1) / Dv
    X[3] = _bf(buf, oX3, dX, x0, x1) / Dv
    # Newton on the 4x4 system: one step takes the back-substituted point (error ~1e-13)
    # to rounding; the error after a step is of the order of the step squared, so stop once
    # a step is below 1e-9 of the size. A point whose residual is already at rounding level
    # (about 90 % of them) is not stepped. The aspect is the sign of the determinant at the
    # last linearisation point (within a step of 1e-9 of the mode)
    _system(Cs, X, val, J)
    det = _det4(J, X[0], X[1])
    size = 1.0 + X[2] * X[2] + X[3] * X[3]
    # skipped only where that residual proves the point accurate: a small residual and a
    # well-conditioned Jacobian (|det J| against the product of its rows' norms, Hadamard's
    # bound); near a singularity (close roots) a small residual says little
    hadamard = 1.0
    for i in range(4):
        hadamard *= math.sqrt(J[i, 0] * J[i, 0] + J[i, 1] * J[i, 1] + J[i, 2] * J[i, 2] + J[i, 3] * J[i, 3])
    polished = (max(abs(val[0]), abs(val[1]), abs(val[2])) <= _POLISHED * size
                and abs(det) >= _CONDITIONED * hadamard)
    return True, det, polished


@njit(cache=True)
def _mode_finish(Cs, g, X, val, J, dx, det, polished, tol):
    """After :func:`_mode_start`: Newton on the 4x4 system unless ``polished``, the point
    normalised (``x0**2 + x1**2 = 1``, ``x0 >= 0``) in ``X``, its relative residual checked and
    the joint residual ``max_i |Q_i| / |dQ_i/dq_i|`` computed (``g``: the scaled derivatives).
    Returns ``(ok, det, jres)`` (``det`` at the last linearisation point)."""
    if not polished:
        for it in range(_NEWTON_ITERATIONS):
            if it > 0:
                _system(Cs, X, val, J)
                det = _det4(J, X[0], X[1])
            for i in range(4):
                val[i] = -val[i]
            if _solve4(J, val, dx, tol[_T_PIVOT]) == 0.0:
                break
            big = 1.0
            stp = 0.0
            for i in range(4):
                X[i] += dx[i]
                big = max(big, abs(X[i]))
                stp = max(stp, abs(dx[i]))
            if stp <= tol[_T_NEWTON_STOP] * big:
                break
    sg = -1.0 if (X[0] < 0.0 or (X[0] == 0.0 and X[1] < 0.0)) else 1.0
    nrm = sg / math.sqrt(X[0] * X[0] + X[1] * X[1])
    for i in range(4):
        X[i] = X[i] * nrm
    if polished:              # the quadrics are homogeneous of degree 2
        for i in range(3):
            val[i] = val[i] * (nrm * nrm)
    else:
        _system(Cs, X, val, J)
    size = 1.0 + X[2] * X[2] + X[3] * X[3]
    rel = max(abs(val[0]), abs(val[1]), abs(val[2])) / size
    if not (rel <= tol[_T_RESIDUAL]):
        return False, det, 0.0
    jres = 0.0
    for i in range(3):
        dq = _joint_derivative(g[8 * i], g[8 * i + 1], g[8 * i + 2], g[8 * i + 3], g[8 * i + 4], g[8 * i + 5],
                               g[8 * i + 6], g[8 * i + 7], X[0], X[1], X[2], X[3])
        jres = max(jres, abs(val[i]) / abs(dq) if dq != 0.0 else math.inf)
    return True, det, jres


@njit(cache=True)
def _joint_derivative(g0, g1, g2, g3, g4, g5, g6, g7, x0, x1, x2, x3):
    """``dQ_i/dq_i`` at the image point ``(x0, x1, x2, x3)`` from quadric ``i``'s derivatives
    ``g0 .. g7`` in its joint value (the quadric's layout ``c, a0, a1, b0, b1, k0, k1, k2``):
    the denominator of the joint residual (:func:`_mode_finish`, and the lockstep kernel's
    ``block_modes.backsub_roots``, which passes scalars so that its loop vectorises)."""
    return (g0 * (x2 * x2 + x3 * x3) + x2 * (g1 * x0 + g2 * x1) + x3 * (g3 * x0 + g4 * x1) + g5 * x0 * x0
            + g6 * x0 * x1 + g7 * x1 * x1)


@njit(cache=True)
def _insert_mode(out_X, out_P, out_res, out_asp, count, X, jres, det):
    """Insert the mode ``X`` (normalised image point) among the ``count`` modes of a row, sorted
    by ``phi``: image point, pose ``(x, y, phi)``, joint residual and aspect (sign of ``det``)."""
    phi = 2.0 * math.atan2(X[1], X[0])
    pos = count
    while pos > 0 and out_P[pos - 1, 2] > phi:
        for i in range(4):
            out_X[pos, i] = out_X[pos - 1, i]
        for i in range(3):
            out_P[pos, i] = out_P[pos - 1, i]
        out_res[pos] = out_res[pos - 1]
        out_asp[pos] = out_asp[pos - 1]
        pos -= 1
    for i in range(4):
        out_X[pos, i] = X[i]
    out_P[pos, 0] = 2.0 * (X[3] * X[0] + X[2] * X[1])
    out_P[pos, 1] = 2.0 * (X[3] * X[1] - X[2] * X[0])
    out_P[pos, 2] = phi
    out_res[pos] = jres
    out_asp[pos] = 1 if det > 0 else (-1 if det < 0 else 0)


@njit(cache=True)
def _duplicate_modes(out_X, count, tol):
    """Two of the ``count`` modes coincide (within ``kernel_duplicate``): two roots polished onto
    one mode, which only wrong float roots can cause."""
    for a in range(count):
        for b in range(a + 1, count):
            dd = 0.0
            for i in range(4):
                dd = max(dd, abs(out_X[a, i] - out_X[b, i]))
            if dd <= tol[_T_DUPLICATE] * (1.0 + abs(out_X[a, 2]) + abs(out_X[a, 3])):
                return True
    return False


@njit(cache=True)
def _solve_row(buf, Ef, layout, tol, out_X, out_P, out_res, out_asp, work):
    """Everything after the coefficients for one row. Returns (count, flag): flag 0 ok,
    1 special (careful path), 2 suspect (certified path). ``tol``: :func:`kernel_tolerances`;
    ``work``: ``_WORK_SIZE`` floats of scratch (named slices ``_W_*``)."""
    dD, dX, dF = layout[0], layout[1], layout[2]
    oD, oX2, oX3, oF = 48, 48 + dD + 1, 48 + dD + dX + 2, 48 + dD + 2 * dX + 3
    p = work[_W_P:_W_P + 7]
    cand = work[_W_CAND:_W_CAND + 48].reshape((12, 4))
    Cs = work[_W_CS:_W_CS + 24]
    val, dx, X = work[_W_VAL:_W_VAL + 4], work[_W_DX:_W_DX + 4], work[_W_X:_W_X + 4]
    J = work[_W_J:_W_J + 16].reshape((4, 4))
    # scaled quadrics (zero set unchanged) and their q-derivatives with the same scale
    for i in range(3):
        s = 0.0
        for k in range(8):
            s = max(s, abs(buf[8 * i + k]))
        if not (s > 0.0) or not np.isfinite(s):
            return 0, 1
        for k in range(8):
            Cs[8 * i + k] = buf[8 * i + k] / s
            buf[24 + 8 * i + k] = buf[24 + 8 * i + k] / s
    fn = 0.0
    for k in range(dF + 1):
        if not np.isfinite(buf[oF + k]):
            return 0, 1
        fn = max(fn, abs(buf[oF + k]))
    if fn == 0.0:
        return 0, 1
    dn = 0.0
    for k in range(dD + 1):
        dn = max(dn, abs(buf[oD + k]))
    if dn == 0.0:
        return 0, 1
    # the real roots of F on the projective line, in two charts (t = x1/x0 on [-1, 1], s = x0/x1
    # on (-1, 1), so half-turns are ordinary roots and every root is found where its chart is
    # well conditioned): isolated by Descartes' rule in the Bernstein basis on the box F +- Ef
    # (core.isolate; Ef are rigorous bounds when the kernel runs with proof, so the count is
    # proven; a row it cannot decide, close or multiple roots, is flagged 2), then each refined
    # by Newton kept inside its isolating interval, on whose ends the polynomial has opposite signs
    ich = work[_W_ICH:_W_ICH + 6]
    nr = count_real_roots_row(buf[oF:oF + dF + 1], Ef, dF, work[_W_ILO:_W_ILO + 6],
                              work[_W_IHI:_W_IHI + 6], ich, work[_W_ISO:_W_ISO + ISOLATE_WORK_SIZE])
    if nr < 0:
        return 0, 2
    ncand = 0
    for m in range(nr):
        chart = 0 if ich[m] == 0.0 else 1
        for k in range(dF + 1):
            p[k] = buf[oF + k] / fn if chart == 0 else buf[oF + dF - k] / fn
        deg = dF
        while deg > 0 and p[deg] == 0.0:
            deg -= 1
        a = work[_W_ILO + m]
        b = work[_W_IHI + m]
        fa = _horner(p, deg, a)
        fb = _horner(p, deg, b)
        if deg == 0 or not (fa * fb < 0.0):
            return 0, 1          # rounding hid the sign change the isolation proved: careful path
        t = _monotone_root(p, deg, a, b, fa, fb)
        x0, x1 = _root_point(t, chart)
        cand[ncand, 0] = x0
        cand[ncand, 1] = x1
        ncand += 1
    count = 0
    for j in range(ncand):
        ok, det, polished = _mode_start(buf, oD, oX2, oX3, dD, dX, Cs, cand[j, 0], cand[j, 1], dn, tol, X, val, J)
        if not ok:
            return 0, 1
        ok, det, jres = _mode_finish(Cs, buf[24:48], X, val, J, dx, det, polished, tol)
        if not ok:
            return 0, 1
        if count >= _MAX:
            return 0, 1
        _insert_mode(out_X, out_P, out_res, out_asp, count, X, jres, det)
        count += 1
    # two roots may polish onto one mode only if the float roots were wrong: let the careful path decide
    if _duplicate_modes(out_X, count, tol):
        return 0, 1
    return count, 0
