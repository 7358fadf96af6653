"""Cusps of the direct kinematics on a section of joint space.

On a plane of joint space (one joint value fixed) the joint vectors where two assembly modes merge
form the discriminant curve of the kinematic polynomial; where three modes merge the curve has a
cusp. Encircling a cusp in joint space is how a manipulator changes assembly mode without meeting
a singularity (Innocenti & Parenti-Castelli; McAree & Daniel; Zein, Wenger & Chablat).

Here, with ``f(theta; q) = F(cos theta, sin theta; q)`` the kinematic binary form at the
half-angle ``theta = phi/2`` (so half-turns are ordinary), a cusp is a solution of
``f = df/dtheta = d2f/dtheta2 = 0`` in ``(theta, q_a, q_b)``. :func:`mode_count_map` counts the
real modes on a grid of the section (its region boundaries are the discriminant curve);
:func:`cusps` starts Newton's method on that 3x3 system from the boundary cells (the near-double
root gives ``theta``) and keeps the converged, distinct solutions, each checked to be a triple
root: ``|f|, |f'|, |f''|`` below ``1e-9`` of the coefficients' size. :func:`cusp_loop` walks a
circle of joint vectors around a cusp, following one mode by continuation, and reports the mode it
returns in.

References
----------
C. Innocenti, V. Parenti-Castelli, *Singularity-free evolution from one configuration to another
in serial and fully-parallel manipulators*, J. Mech. Des. 120 (1998) 73-79, doi:10.1115/1.2826679;
M. Zein, P. Wenger, D. Chablat, *Non-singular assembly-mode changing motions for 3-RPR parallel
manipulators*, Mech. Mach. Theory 43 (2008) 480-490, doi:10.1016/j.mechmachtheory.2007.03.005.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

import numbers

from .._validate import _short, as_box, as_count, as_float_array, as_scalar
from ..core.codegen import compile_exprs
from ..core.elimination import form_coefficients
from ..exceptions import InputError, InputTypeError
from ..core.mechanism import check_mechanism
from .._validate import as_tolerances
from .._html import dataclass_html, dataclass_repr
from ..solve import front

__all__ = ["Cusp", "ModeCountMap", "mode_count_map", "cusps", "cusp_edges", "cusp_system", "free_joints",
           "check_section_resolution", "SECTION_MAX_RESOLUTION",
           "half_angle_gap", "linking_number"]


@dataclass(frozen=True)
class ModeCountMap:
    """Real assembly modes on a grid of a joint-space section.

    Attributes
    ----------
    fixed : int
        The joint held at ``value``.
    value : float
    free : (int, int)
        The two free joints, in axis order.
    axes : ((n,) float, (m,) float)
    counts : (n, m) int
        ``-1`` where a row could not be solved.
    """

    fixed: int
    value: float
    free: tuple
    axes: tuple
    counts: np.ndarray

    def boundary(self):
        """Grid cells ``(i, j)`` whose count differs from a neighbour's: the discriminant curve.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.singular.cusps import mode_count_map
        >>> m = isp.examples.general_3rpr()
        >>> cm = mode_count_map(m, 2, 10.0, [(8, 14), (2, 8)], 24)
        >>> cm.boundary().shape[1]
        2
        """
        C = self.counts
        edge = np.zeros_like(C, dtype=bool)
        edge[:-1] |= C[:-1] != C[1:]
        edge[1:] |= C[:-1] != C[1:]
        edge[:, :-1] |= C[:, :-1] != C[:, 1:]
        edge[:, 1:] |= C[:, :-1] != C[:, 1:]
        return np.argwhere(edge & (C >= 0))

    # short summaries (arrays as shape and dtype) for the terminal and Jupyter; see imagespace._html
    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


def free_joints(fixed):
    """The indices of the two joints that vary when joint ``fixed`` (0, 1 or 2) is held.

    Raises
    ------
    TypeError
        ``fixed`` not a whole number.
    InputError
        ``fixed`` not 0, 1 or 2.

    Examples
    --------
    >>> from imagespace.singular.cusps import free_joints
    >>> free_joints(2)
    (0, 1)
    """
    if isinstance(fixed, (bool, np.bool_)) or not isinstance(fixed, (numbers.Integral, np.integer)):
        raise InputTypeError(f"fixed must be the whole number 0, 1 or 2 (the joint held constant), got "
                             f"{type(fixed).__name__} {_short(fixed)}")
    if fixed not in (0, 1, 2):
        raise InputError(f"fixed must be the index 0, 1 or 2 of the joint held constant, got {fixed!r}")
    return tuple(i for i in range(3) if i != fixed)


def _window(window):
    # None is refused as non-numeric (TypeError), like any other non-array window
    return as_box(as_float_array(window, "window"), "window", dim=2)


#: The largest grid per axis of a joint-space section (``resolution**2`` joint vectors solved).
SECTION_MAX_RESOLUTION = 2000


def check_section_resolution(resolution, name="resolution"):
    """The grid per axis of a joint-space section, checked: an int from 8 to the bound.

    The bound is ``SECTION_MAX_RESOLUTION`` (2000 per axis).

    Raises
    ------
    TypeError
        Not a whole number.
    InputError
        Outside the range.

    Examples
    --------
    >>> from imagespace.singular.cusps import check_section_resolution
    >>> check_section_resolution(48)
    48
    """
    resolution = as_count(resolution, name, 8)
    if not 8 <= resolution <= SECTION_MAX_RESOLUTION:
        raise InputError(f"{name} must be an int in 8..{SECTION_MAX_RESOLUTION}, got {resolution!r}")
    return resolution


def _grid(fixed, value, window, resolution):
    free_joints(fixed)
    value = as_scalar(value, "value")
    w = _window(window)
    resolution = check_section_resolution(resolution)
    a = np.linspace(w[0, 0], w[0, 1], resolution)
    b = np.linspace(w[1, 0], w[1, 1], resolution)
    A, B = np.meshgrid(a, b, indexing="ij")
    Q = np.empty((A.size, 3))
    fa, fb = free_joints(fixed)
    Q[:, fa], Q[:, fb], Q[:, fixed] = A.ravel(), B.ravel(), float(value)
    return a, b, Q


def mode_count_map(manipulator, fixed, value, window, resolution=120):
    """Number of real assembly modes on a grid of the section ``q[fixed] = value``.

    Parameters
    ----------
    manipulator : PlanarParallel
    fixed : int
    value : float
    window : (2, 2) float
        Ranges of the two free joints (in increasing joint index).
    resolution : int
        Grid points per axis.

    Returns
    -------
    ModeCountMap

    Raises
    ------
    TypeError
        ``manipulator`` not a design, ``fixed`` not a whole number, non-numeric ``value``,
        ``window`` or ``resolution``.
    InputError
        ``fixed`` not 0, 1 or 2; ``window`` not ``(2, 2)`` with min < max; ``resolution``
        outside 8..2000; a window leaving a joint's domain.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.cusps import mode_count_map
    >>> m = isp.examples.stigger_husty()
    >>> cm = mode_count_map(m, 2, float(m.q_example[2]), [(8, 12), (13, 17)], 16)
    >>> int(cm.counts.max()) <= 6
    True
    """
    check_mechanism(manipulator)
    a, b, Q = _grid(fixed, value, window, resolution)
    for i, leg in enumerate(manipulator.legs):
        ok = leg.joint_values_ok(Q[:, i])
        if not np.all(ok):
            raise InputError(f"window leaves the domain of joint {i} ({leg.joints}); got values like "
                             f"{Q[~ok, i][0]}")
    res = front.direct_kinematics_batch(manipulator, Q)
    counts = np.where(res.row_ok, res.count.astype(np.int64), -1).reshape(len(a), len(b))   # uint8: widen first
    return ModeCountMap(int(fixed), float(value), free_joints(fixed), (a, b), counts)


# -- the cusp system -----------------------------------------------------------------------------------
def _coefficient_functions(m):
    """Compiled coefficients of the kinematic form and their derivatives in q1, q2, q3."""
    return m.cached("cusp_functions", lambda: _build_coefficient_functions(m))


def _build_coefficient_functions(m):
    comp = m.compiled()
    P, d = comp.polynomial, comp.degree
    coeffs = form_coefficients(P)
    exprs = list(coeffs)
    for s in m.joint_symbols:
        exprs += [sp.diff(c, s) for c in coeffs]
    return d, compile_exprs(exprs, m.joint_symbols)


def _mul(u, v):
    """Truncated product of Taylor series stored on the last axis (length 4)."""
    out = np.zeros(np.broadcast_shapes(u.shape, v.shape))
    for i in range(4):
        out[..., i] = sum(u[..., j] * v[..., i - j] for j in range(i + 1))
    return out


def _series(theta, coeffs, d):
    """Taylor coefficients in h, up to h**3, of ``sum_k c_k cos(theta+h)^(d-k) sin(theta+h)^k``.

    ``theta`` (n,), ``coeffs`` (n, d + 1) -> (n, 4)."""
    c, s = np.cos(theta), np.sin(theta)
    C = np.stack([c, -s, -c / 2, s / 6], axis=-1)
    S = np.stack([s, c, -s / 2, -c / 6], axis=-1)
    one = np.zeros_like(C)
    one[..., 0] = 1.0
    powC, powS = [one], [one]
    for _ in range(d):
        powC.append(_mul(powC[-1], C))
        powS.append(_mul(powS[-1], S))
    out = np.zeros_like(C)
    for k in range(d + 1):
        out += coeffs[:, k, None] * _mul(powC[d - k], powS[k])
    return out


_FACT = np.array([1.0, 1.0, 2.0, 6.0])


def _system(m, x, fixed, value):
    """The cusp system at points ``x`` (n, 3) = (theta, q_a, q_b): values (n, 3), Jacobians
    (n, 3, 3), coefficient scales (n,) and the joint vectors (n, 3)."""
    d, fn = _coefficient_functions(m)
    fa, fb = free_joints(fixed)
    x = np.atleast_2d(x)
    q = np.empty((len(x), 3))
    q[:, fa], q[:, fb], q[:, fixed] = x[:, 1], x[:, 2], value
    allc = fn(*q.T)
    n = d + 1
    c = allc[:, :n]
    derivs = _series(x[:, 0], c, d) * _FACT
    G = derivs[:, :3]
    J = np.empty((len(x), 3, 3))
    J[:, :, 0] = derivs[:, 1:4]
    for col, j in ((1, fa), (2, fb)):
        J[:, :, col] = (_series(x[:, 0], allc[:, n * (1 + j): n * (2 + j)], d) * _FACT)[:, :3]
    scale = np.sum(np.abs(c), axis=1)
    return G, J, scale, q


def cusp_system(manipulator, X):
    """The cusp system ``(f, df/dtheta, d2f/dtheta2)`` and its Jacobian in all four unknowns.

    ``f(theta; q) = F(cos theta, sin theta; q)`` is the kinematic binary form at the half-angle
    ``theta`` (see the module notes); a cusp is a common zero of the three values. Floating point
    (a speed path for continuation and seeding; decisions are made elsewhere, exactly).

    Parameters
    ----------
    manipulator : PlanarParallel
    X : (n, 4) float
        Rows ``(theta, q1, q2, q3)``.

    Returns
    -------
    G : (n, 3) float
        ``f, f', f''`` (derivatives in ``theta``).
    J : (n, 3, 4) float
        Their derivatives in ``(theta, q1, q2, q3)``.
    scale : (n,) float
        Sum of the absolute values of the form's coefficients (to make residuals relative).

    Raises
    ------
    TypeError
        ``manipulator`` not a design; non-numeric ``X``.
    InputError
        ``X`` not of shape ``(n, 4)`` (or ``(4,)``).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.singular.cusps import cusp_system
    >>> G, J, scale = cusp_system(isp.examples.general_3rpr(), np.array([[0.3, 11.0, 5.0, 10.0]]))
    >>> G.shape, J.shape
    ((1, 3), (1, 3, 4))
    """
    check_mechanism(manipulator)
    X = as_float_array(X, "X", last=4)
    if X.ndim == 1:
        X = X[None, :]
    if X.ndim != 2:
        raise InputError(f"X must be (n, 4) rows (theta, q1, q2, q3), got shape {X.shape}")
    d, fn = _coefficient_functions(manipulator)
    M, freq = _fourier_matrix(d)
    n = d + 1
    allc = np.atleast_2d(np.asarray(fn(*X[:, 1:].T), dtype=float))
    if allc.shape[0] != len(X):
        allc = np.broadcast_to(allc, (len(X), allc.shape[1]))
    # f(theta) = sum_k c_k cos^(d-k) sin^k = Re sum_m a_m e^(i m theta): derivatives are (i m)^j a_m
    E = np.exp(1j * np.outer(X[:, 0], freq))                           # (n, d + 1)
    powers = np.stack([(1j * freq) ** j for j in range(4)])             # (4, d + 1)
    blocks = allc.reshape(len(X), 4, n) @ M                             # (n, 4, d + 1) Fourier coeffs
    D = np.einsum("nbm,jm,nm->nbj", blocks, powers, E).real             # (n, 4 blocks, 4 derivs)
    G = D[:, 0, :3]
    J = np.empty((len(X), 3, 4))
    J[:, :, 0] = D[:, 0, 1:4]
    J[:, :, 1:] = np.transpose(D[:, 1:, :3], (0, 2, 1))
    return G, J, np.sum(np.abs(allc[:, :n]), axis=1)


_FOURIER: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _fourier_matrix(d):
    """``(d + 1, d + 1)`` complex matrix taking the coefficients ``c_k`` of
    ``sum_k c_k cos^(d-k) sin^k`` to the coefficients ``a_m`` of ``e^(i m theta)``,
    ``m = -d, -d + 2, ..., d`` (exact expansion of ``cos = (z + 1/z)/2``, ``sin = (z - 1/z)/2i``)."""
    if d not in _FOURIER:
        cos = np.array([0.5, 0, 0.5], dtype=complex)          # Laurent coefficients of z^-1 .. z^1
        sin = np.array([-0.5 / 1j, 0, 0.5 / 1j], dtype=complex)
        rows = []
        for k in range(d + 1):
            p = np.array([1.0 + 0j])
            for _ in range(d - k):
                p = np.convolve(p, cos)
            for _ in range(k):
                p = np.convolve(p, sin)
            rows.append(p[::2])                               # exponents -d, -d+2, ..., d
        _FOURIER[d] = (np.array(rows), np.arange(-d, d + 1, 2, dtype=float))
    return _FOURIER[d]


def half_angle_gap(phi, theta):
    """Distance of the half-angle ``phi/2`` from ``theta`` modulo ``pi`` (X and -X are one point).

    Examples
    --------
    >>> from imagespace.singular.cusps import half_angle_gap
    >>> round(float(half_angle_gap(0.2, 0.1 + 3.141592653589793)), 12)
    0.0
    """
    return abs(np.remainder(phi / 2 - theta + np.pi / 2, np.pi) - np.pi / 2)


def _pose_at(m, q, theta):
    # a cusp is a triple root: the float DK is near-singular there by construction, so the batch
    # path (which flags instead of warning) gives the modes; the one nearest theta is the cusp's
    modes = front.direct_kinematics_batch(m, np.asarray(q, dtype=float)[None, :], method="numpy").modes(0)
    if not modes:
        return np.full(3, np.nan)
    dist = [half_angle_gap(mm.pose[2], theta) for mm in modes]
    return modes[int(np.argmin(dist))].pose


@dataclass(frozen=True)
class Cusp:
    """A point of joint space where three assembly modes merge.

    Attributes
    ----------
    q : (3,) float
    theta : float
        Half-angle of the triple root (``phi = 2 theta``).
    pose : (3,) float
        The merged pose (NaN if the back-substitution failed).
    residual : float
        ``max(|f|, |f'|, |f''|)`` over the sum of the coefficients' absolute values.
    """

    q: np.ndarray
    theta: float
    pose: np.ndarray
    residual: float


def cusps(manipulator, fixed, value, window, resolution=120, tol=1e-9, max_seeds=400):
    """Cusps of the discriminant curve on the section ``q[fixed] = value``.

    Parameters
    ----------
    manipulator : PlanarParallel
    fixed : int
    value : float
    window : (2, 2) float
        Ranges of the two free joints.
    resolution : int
        Grid of the seed search (:func:`mode_count_map`).
    tol : float
        A converged point is kept when the relative residual is below ``tol``.
    max_seeds : int
        At most this many boundary cells (evenly spread) start Newton's method.

    Returns
    -------
    list of Cusp
        Distinct cusps inside the window, sorted by the free joints.

    Raises
    ------
    TypeError
        As :func:`mode_count_map`; non-numeric ``tol``, ``max_seeds`` not a whole number.
    InputError
        As :func:`mode_count_map`; ``tol`` not positive, ``max_seeds`` below 1.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.cusps import cusps
    >>> m = isp.examples.general_3rpr()
    >>> found = cusps(m, 2, 10.0, [(8, 14), (2, 8)], 60)
    >>> all(c.residual < 1e-9 for c in found)
    True
    """
    tol = as_scalar(tol, "tol")
    if not tol > 0:
        raise InputError(f"tol must be a positive relative residual, got {tol!r}")
    max_seeds = as_count(max_seeds, "max_seeds")
    cm = mode_count_map(manipulator, fixed, value, window, resolution)
    value = as_scalar(value, "value")
    w = _window(window)
    fa, fb = cm.free
    comp = manipulator.compiled()
    tols = manipulator.tolerances
    found = []
    cells = cm.boundary()
    if len(cells) > max_seeds:
        cells = cells[np.linspace(0, len(cells) - 1, max_seeds).astype(int)]
    seeds = []
    for i, j in cells:
        q = np.empty(3)
        q[fa], q[fb], q[fixed] = cm.axes[0][i], cm.axes[1][j], value
        coef = comp.coefficients(q)
        # the closest pair of roots of the form in (x0 : x1): theta from the pair's mean
        if abs(coef[-1]) <= tols.cusp_leading_coefficient * np.abs(coef).sum():
            continue
        roots = np.roots(coef[::-1])
        if len(roots) < 2:
            continue
        th = np.arctan(roots.real)
        k1, k2 = min(((a, b) for a in range(len(th)) for b in range(a + 1, len(th))),
                     key=lambda ab: abs(roots[ab[0]] - roots[ab[1]]))
        seeds.append([0.5 * (th[k1] + th[k2]), q[fa], q[fb]])
    if not seeds:
        return []
    x = np.array(seeds)
    span = 10 * float(np.max(w[:, 1] - w[:, 0])) + float(np.max(np.abs(w)))
    best, best_res = x.copy(), np.full(len(x), np.inf)
    alive = np.ones(len(x), dtype=bool)
    with np.errstate(all="ignore"):
        for _ in range(60):
            G, J, scale, _q = _system(manipulator, x, fixed, value)
            r = np.max(np.abs(G), axis=1) / np.where(scale > 0, scale, np.nan)
            better = alive & (r < best_res)
            best[better], best_res[better] = x[better], r[better]
            ok = alive & np.isfinite(r) & (np.abs(np.linalg.det(J)) > 0)
            step = np.zeros_like(x)
            if ok.any():
                step[ok] = np.linalg.solve(J[ok], -G[ok][:, :, None])[:, :, 0]
            alive &= ok
            x = x + step
            alive &= np.all(np.isfinite(x), axis=1) & (np.abs(x[:, 1:]).max(axis=1) <= span)
            x[~alive] = best[~alive]
            if not alive.any():
                break
    _, _, _, Qc = _system(manipulator, best, fixed, value)
    for xb, res, qc in zip(best, best_res, Qc):
        inside = w[0, 0] <= xb[1] <= w[0, 1] and w[1, 0] <= xb[2] <= w[1, 1]
        if res < tol and inside:
            th = float(np.remainder(xb[0] + np.pi / 2, np.pi) - np.pi / 2)
            found.append((float(res), qc, th))
    # one cusp per cluster (ill-conditioned cusps, e.g. near a swallowtail, converge to a cloud
    # of points ~1e-4 apart): keep the smallest residual within Tolerances.cusp_merge (1e-3) of the
    # window size
    found.sort(key=lambda item: item[0])
    near = tols.cusp_merge * float(np.max(w[:, 1] - w[:, 0]))
    out = []
    for res, qc, th in found:
        if not any(np.max(np.abs(c.q - qc)) < near and abs(c.theta - th) < tols.cusp_merge for c in out):
            out.append(Cusp(qc, th, _pose_at(manipulator, qc, th), res))
    return sorted(out, key=lambda c: (c.q[fa], c.q[fb]))


def cusp_edges(manipulator, fixed, values, window, resolution=60):
    """The cusp points of many parallel sections, chained into curves of joint space (the cusp
    edges of the discriminant surface).

    Cusps of consecutive sections are joined when they are mutual nearest neighbours (in the free
    joints and the half-angle) closer than ``Tolerances.cusp_chain_reach`` (a tenth) of the window; a chain ends where a cusp has no
    partner (a swallowtail point, or the window's edge).

    Parameters
    ----------
    manipulator : PlanarParallel
    fixed : int
    values : (k,) float
        Increasing values of the fixed joint (the sections).
    window : (2, 2) float
    resolution : int

    Returns
    -------
    list of (n_i, 3) float
        Polylines in joint space.

    Raises
    ------
    TypeError
        As :func:`mode_count_map`; non-numeric ``values``.
    InputError
        As :func:`mode_count_map`; ``values`` not at least two increasing numbers.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.cusps import cusp_edges
    >>> m = isp.examples.general_3rpr()
    >>> edges = cusp_edges(m, 2, [9.9, 10.0, 10.1], [(8, 14), (2, 8)], 40)
    >>> all(e.shape[1] == 3 for e in edges)
    True
    """
    vals = as_float_array(values, "values")
    if vals.ndim != 1 or len(vals) < 2 or np.any(np.diff(vals) <= 0):
        raise InputError(f"values must be at least two increasing numbers, got {np.asarray(values).tolist()}")
    check_mechanism(manipulator)
    fa, fb = free_joints(fixed)
    w = _window(window)
    check_section_resolution(resolution)
    reach = manipulator.tolerances.cusp_chain_reach * float(np.max(w[:, 1] - w[:, 0]))
    sections = [cusps(manipulator, fixed, v, window, resolution) for v in vals]

    def key(c):
        return np.array([c.q[fa], c.q[fb], c.theta])

    chains, open_chains = [], {}
    for s, sec in enumerate(sections):
        new_open = {}
        prev = sections[s - 1] if s else []
        for j, c in enumerate(sec):
            partner = None
            if prev:
                d = [np.linalg.norm(key(c) - key(p)) for p in prev]
                i = int(np.argmin(d))
                back = [np.linalg.norm(key(prev[i]) - key(o)) for o in sec]
                if d[i] < reach and int(np.argmin(back)) == j and i in open_chains:
                    partner = i
            chain = open_chains.pop(partner) if partner is not None else []
            chain.append(c.q)
            new_open[j] = chain
        chains += list(open_chains.values())
        open_chains = new_open
    chains += list(open_chains.values())
    return [np.array(c) for c in chains if len(c) >= 2]


def linking_number(loop, curves, tolerances=None):
    """Signed crossings of open polylines through a cone spanning a closed loop (joint space).

    For curves whose ends lie outside the loop's cone this is the linking number of the loop with
    them: how many times the loop goes around them. Used to show that a mode-changing loop
    encircles a cusp edge.

    Parameters
    ----------
    loop : (n, 3) float
        A closed loop (first point = last point, or closed implicitly).
    curves : sequence of (k, 3) float
    tolerances : Tolerances, optional
        Reads ``linking_parallel`` (default :data:`imagespace.tolerances.TOLERANCES`).

    Returns
    -------
    int

    Raises
    ------
    TypeError
        ``curves`` not a sequence of polylines; non-numeric points; ``tolerances`` not a
        :class:`~imagespace.tolerances.Tolerances`.
    InputError
        ``loop`` not a ``(n, 3)`` polyline of at least three points, or a curve not ``(k, 3)``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.singular.cusps import linking_number
    >>> t = np.linspace(0, 2 * np.pi, 65)
    >>> circle = np.column_stack([np.cos(t), np.sin(t), 0 * t])
    >>> linking_number(circle, [np.array([[0.2, 0.1, -1.0], [0.2, 0.1, 1.0]])])
    1
    """
    parallel = as_tolerances(tolerances).linking_parallel
    L = as_float_array(loop, "loop", last=3)
    if L.ndim != 2 or len(L) < 3:
        raise InputError(f"loop must be a (n, 3) polyline of at least three points, got shape {L.shape}")
    if not np.allclose(L[0], L[-1]):
        L = np.vstack([L, L[:1]])
    apex = L.mean(axis=0)
    if curves is None or isinstance(curves, (str, bytes)) or not hasattr(curves, "__iter__"):
        raise InputTypeError(f"curves must be a sequence of (k, 3) polylines, got {type(curves).__name__} "
                             f"{_short(curves)}")
    total = 0
    for k, curve in enumerate(curves):
        C = as_float_array(curve, f"curves[{k}]", last=3)
        if C.ndim != 2:
            raise InputError(f"curves[{k}] must be a (k, 3) polyline, got shape {C.shape} (pass a list "
                             "of polylines, even for one curve)")
        for P0, P1 in zip(C[:-1], C[1:]):
            d = P1 - P0
            for A, B in zip(L[:-1], L[1:]):
                e1, e2 = A - apex, B - apex
                h = np.cross(d, e2)
                a = e1 @ h
                if abs(a) < parallel:
                    continue
                s_ = P0 - apex
                u = (s_ @ h) / a
                if u < 0 or u > 1:
                    continue
                qv = np.cross(s_, e1)
                v = (d @ qv) / a
                if v < 0 or u + v > 1:
                    continue
                t = (e2 @ qv) / a
                if 0 <= t < 1:
                    total += int(np.sign(np.cross(e1, e2) @ d))
    return total
