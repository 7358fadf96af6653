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

from .._validate import _short, as_count, as_float_array
from ..core.codegen import compile_exprs
from ..exceptions import InputError

__all__ = ["Cusp", "ModeCountMap", "mode_count_map", "cusps", "cusp_loop", "CuspLoop", "cusp_edges",
           "linking_number"]


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


MAX_STEPS = 1_000_000
"""The largest ``steps`` :func:`cusp_loop` accepts (one direct-kinematics batch row per step)."""


def _free(fixed):
    if isinstance(fixed, (bool, np.bool_)) or not isinstance(fixed, (numbers.Integral, np.integer)):
        raise TypeError(f"fixed must be the whole number 0, 1 or 2 (the joint held constant), got "
                        f"{type(fixed).__name__} {_short(fixed)}")
    if fixed not in (0, 1, 2):
        raise InputError(f"fixed must be the index 0, 1 or 2 of the joint held constant, got {fixed!r}")
    return tuple(i for i in range(3) if i != fixed)


def _window(window):
    w = as_float_array(window, "window")
    if w.shape != (2, 2) or np.any(w[:, 1] <= w[:, 0]):
        raise InputError(f"window must be ((min, max), (min, max)) of the two free joints, got {w.tolist()}")
    return w


def _scalar(value, name):
    v = as_float_array(value, name)
    if v.ndim != 0:
        raise InputError(f"{name} must be a single number, got shape {v.shape}")
    return float(v)


def _resolution(resolution, name="resolution"):
    resolution = as_count(resolution, name, 8)
    if not 8 <= resolution <= 2000:
        raise InputError(f"{name} must be an int in 8..2000, got {resolution!r}")
    return resolution


def _grid(fixed, value, window, resolution):
    _free(fixed)
    value = _scalar(value, "value")
    w = _window(window)
    resolution = _resolution(resolution)
    a = np.linspace(w[0, 0], w[0, 1], resolution)
    b = np.linspace(w[1, 0], w[1, 1], resolution)
    A, B = np.meshgrid(a, b, indexing="ij")
    Q = np.empty((A.size, 3))
    fa, fb = _free(fixed)
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

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.cusps import mode_count_map
    >>> m = isp.examples.stigger_husty()
    >>> cm = mode_count_map(m, 2, float(m.q_example[2]), [(8, 12), (13, 17)], 16)
    >>> int(cm.counts.max()) <= 6
    True
    """
    from .surface import _check_manipulator

    _check_manipulator(manipulator)
    a, b, Q = _grid(fixed, value, window, resolution)
    for i, leg in enumerate(manipulator.legs):
        ok = leg.joint_values_ok(Q[:, i])
        if not np.all(ok):
            raise InputError(f"window leaves the domain of joint {i} ({leg.joints}); got values like "
                             f"{Q[~ok, i][0]}")
    res = manipulator.direct_kinematics_batch(Q)
    counts = np.where(res.row_ok, res.count, -1).reshape(len(a), len(b))
    return ModeCountMap(int(fixed), float(value), _free(fixed), (a, b), counts)


# -- the cusp system -----------------------------------------------------------------------------------
def _coefficient_functions(m):
    """Compiled coefficients of the kinematic form and their derivatives in q1, q2, q3."""
    key = "cusp_functions"
    if key not in m._symbolic_cache:
        comp = m.compiled()
        P, d = comp.polynomial, comp.degree
        coeffs = [P.coeff_monomial((d - k, k)) for k in range(d + 1)]
        exprs = list(coeffs)
        for s in m.joint_symbols:
            exprs += [sp.diff(c, s) for c in coeffs]
        m._symbolic_cache[key] = (d, compile_exprs(exprs, m.joint_symbols))
    return m._symbolic_cache[key]


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
    fa, fb = _free(fixed)
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

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.cusps import cusps
    >>> m = isp.examples.general_3rpr()
    >>> found = cusps(m, 2, 10.0, [(8, 14), (2, 8)], 60)
    >>> all(c.residual < 1e-9 for c in found)
    True
    """
    tol = _scalar(tol, "tol")
    if not tol > 0:
        raise InputError(f"tol must be a positive relative residual, got {tol!r}")
    max_seeds = as_count(max_seeds, "max_seeds")
    cm = mode_count_map(manipulator, fixed, value, window, resolution)
    value = _scalar(value, "value")
    w = _window(window)
    fa, fb = cm.free
    comp = manipulator.compiled()
    d = comp.degree
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
        if abs(coef[-1]) <= 1e-14 * np.abs(coef).sum():
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
    # of points ~1e-4 apart): keep the smallest residual within 1e-3 of the window size
    found.sort(key=lambda item: item[0])
    near = 1e-3 * float(np.max(w[:, 1] - w[:, 0]))
    out = []
    for res, qc, th in found:
        if not any(np.max(np.abs(c.q - qc)) < near and abs(c.theta - th) < 1e-3 for c in out):
            out.append(Cusp(qc, th, _pose_at(manipulator, qc, th), res))
    return sorted(out, key=lambda c: (c.q[fa], c.q[fb]))


def _half_angle_gap(phi, theta):
    """Distance of the half-angle ``phi/2`` from ``theta`` modulo ``pi`` (X and -X are one point)."""
    return abs(np.remainder(phi / 2 - theta + np.pi / 2, np.pi) - np.pi / 2)


def _pose_at(m, q, theta):
    # a cusp is a triple root: the float DK is near-singular there by construction, so the batch
    # path (which flags instead of warning) gives the modes; the one nearest theta is the cusp's
    modes = m.direct_kinematics_batch(np.asarray(q, dtype=float)[None, :], method="numpy").modes(0)
    if not modes:
        return np.full(3, np.nan)
    dist = [_half_angle_gap(mm.pose[2], theta) for mm in modes]
    return modes[int(np.argmin(dist))].pose


@dataclass(frozen=True)
class CuspLoop:
    """A circle of joint vectors around a cusp, walked with one assembly mode followed by continuation.

    Attributes
    ----------
    q : (n, 3) float
        The loop (closed: first = last).
    poses : (n, 3) float
        The followed mode at each joint vector.
    start_mode, end_mode : int
        Index (in ``direct_kinematics(q[0])``) of the mode at the start and where the walk ends.
    changed : bool
        ``end_mode != start_mode``: the loop changed the assembly mode.
    aspects : (n,) int
        Sign of det J along the walk (constant: the walk never meets a singularity).
    winding : float
        Winding number of the loop around the cusp in the section (1 for the circle).
    continuous : bool
        No step of the walk jumped (a step more than 20 times the median would mean the followed
        mode was lost - it met a singularity - and another one was picked up).
    """

    q: np.ndarray
    poses: np.ndarray
    start_mode: int
    end_mode: int
    changed: bool
    aspects: np.ndarray
    winding: float = 1.0
    continuous: bool = True

    def certified_path(self, manipulator, every=8):
        """The followed modes as an image-space polyline, with its exact certificate.

        A polyline through every ``every``-th pose of the walk (signs of the representatives
        aligned); it joins the start mode to the end mode, and :func:`imagespace.paths.check.check_path`
        decides exactly whether it touches the singularity surface. If it does, the polyline is
        refined (``every`` halved, down to every pose) before the answer is returned.

        Returns
        -------
        (ImagePath, PathCheck)

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.singular.cusps import cusps, cusp_loop
        >>> m = isp.examples.general_3rpr()
        >>> loop = cusp_loop(m, cusps(m, 2, 10.0, [(8, 14), (2, 8)], 60)[0], 2, 0.05)
        >>> path, chk = loop.certified_path(m)
        >>> chk.singularity_free
        True
        """
        from ..core.kinematic_map import image_point
        from ..paths.check import check_path, polyline
        from .surface import _check_manipulator

        _check_manipulator(manipulator)
        every = min(as_count(every, "every"), len(self.poses))      # larger steps all mean "ends only"
        while True:
            idx = np.unique(np.append(np.arange(0, len(self.poses), every), len(self.poses) - 1))
            X = image_point(self.poses[idx])
            for k in range(1, len(X)):
                if X[k, :2] @ X[k - 1, :2] < 0:
                    X[k] = -X[k]
            path = polyline(X)
            chk = check_path(manipulator, path)
            if chk.singularity_free or every == 1:
                return path, chk
            every = max(1, every // 2)          # chords cut corners near the surface: refine


def cusp_loop(manipulator, cusp, fixed, radius, steps=720):
    """Walk a circle of radius ``radius`` around a cusp in the section and follow a mode.

    The walk starts in the middle of the arc of the circle with the most real modes (inside the
    cusp's wedge, where the three modes that merge at the cusp are all real) and follows, by
    continuation, each of the three modes nearest to the cusp's orientation; the first that comes
    back as another mode is returned (the classical non-singular assembly-mode change), otherwise
    the walk of the nearest one.

    Parameters
    ----------
    manipulator : PlanarParallel
    cusp : Cusp
    fixed : int
        The section's fixed joint (as given to :func:`cusps`).
    radius : float
    steps : int

    Returns
    -------
    CuspLoop

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.cusps import cusps, cusp_loop
    >>> m = isp.examples.general_3rpr()
    >>> c = cusps(m, 2, 10.0, [(8, 14), (2, 8)], 60)[0]
    >>> loop = cusp_loop(m, c, 2, 0.05)
    >>> loop.changed, loop.continuous, bool(np.all(loop.aspects == loop.aspects[0]))
    (True, True, True)
    """
    from .surface import _check_manipulator

    _check_manipulator(manipulator)
    if not isinstance(cusp, Cusp):
        raise TypeError(f"cusp must be a Cusp (an item of cusps(...)), got {type(cusp).__name__} {_short(cusp)}")
    fa, fb = _free(fixed)
    radius = _scalar(radius, "radius")
    if not radius > 0:
        raise InputError(f"radius must be positive, got {radius!r}")
    steps = as_count(steps, "steps", 8)
    if steps > MAX_STEPS:
        raise InputError(f"steps must be at most MAX_STEPS = {MAX_STEPS}, got {_short(steps)}")
    ang = np.linspace(0, 2 * np.pi, steps + 1)[:-1]
    Q = np.repeat(cusp.q[None], steps, axis=0)
    Q[:, fa] += radius * np.cos(ang)
    Q[:, fb] += radius * np.sin(ang)
    res = manipulator.direct_kinematics_batch(Q, method="numpy")
    count = np.where(res.row_ok, res.count, -1)
    top = count == count.max()
    # the middle of the longest run of maximal count (cyclically)
    idx = np.flatnonzero(top)
    if len(idx) == len(top):
        k0 = 0
    else:
        start = idx[np.flatnonzero(~top[(idx - 1) % len(top)])]
        runs = [(int(np.sum(top[np.arange(a, a + len(top)) % len(top)].cumprod())), a) for a in start]
        length, a = max(runs)
        k0 = (a + length // 2) % len(top)
    order = np.append(np.roll(np.arange(steps), -k0), k0)
    Qo = Q[order]
    v0 = res.valid[k0]                          # modes numbered among the valid ones, as in ``end``
    modes0 = list(enumerate(zip(res.image_points[k0][v0], res.poses[k0][v0], res.aspect[k0][v0])))
    modes0 = [(j, X, P, asp) for j, (X, P, asp) in modes0]
    near = sorted(modes0, key=lambda mm: _half_angle_gap(mm[2][2], cusp.theta))[:3]
    walks = []
    for j0, X0, P0, a0 in near:
        X, poses, aspects, jumps = X0, [P0], [int(a0)], []
        for k in order[1:]:
            cand = res.image_points[k][res.valid[k]]
            if len(cand) == 0:
                break
            d = np.minimum(np.linalg.norm(cand - X, axis=1), np.linalg.norm(cand + X, axis=1))
            j = int(np.argmin(d))
            jumps.append(d[j])
            X = cand[j]
            poses.append(res.poses[k][res.valid[k]][j])
            aspects.append(int(res.aspect[k][res.valid[k]][j]))
        if len(poses) < len(order):
            continue
        d0 = [min(np.linalg.norm(Y - X), np.linalg.norm(Y + X)) for Y in res.image_points[k0][v0]]
        end = int(np.argmin(d0))
        start_j = j0
        jumps = np.array(jumps)
        continuous = bool(jumps.max() <= max(20 * np.median(jumps), 1e-9))
        loop = CuspLoop(Qo, np.array(poses), start_j, end, end != start_j, np.array(aspects),
                        continuous=continuous)
        if loop.changed and loop.continuous and np.all(loop.aspects == loop.aspects[0]):
            return loop
        walks.append(loop)
    if not walks:
        raise InputError("the loop loses every real mode; choose a smaller radius")
    return walks[0]


def cusp_edges(manipulator, fixed, values, window, resolution=60):
    """The cusp points of many parallel sections, chained into curves of joint space (the cusp
    edges of the discriminant surface).

    Cusps of consecutive sections are joined when they are mutual nearest neighbours (in the free
    joints and the half-angle) closer than a tenth of the window; a chain ends where a cusp has no
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
    from .surface import _check_manipulator

    _check_manipulator(manipulator)
    fa, fb = _free(fixed)
    w = _window(window)
    _resolution(resolution)
    reach = 0.1 * float(np.max(w[:, 1] - w[:, 0]))
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


def linking_number(loop, curves):
    """Signed crossings of open polylines through a cone spanning a closed loop (joint space).

    For curves whose ends lie outside the loop's cone this is the linking number of the loop with
    them: how many times the loop goes around them. Used to show that a mode-changing loop
    encircles a cusp edge.

    Parameters
    ----------
    loop : (n, 3) float
        A closed loop (first point = last point, or closed implicitly).
    curves : sequence of (k, 3) float

    Returns
    -------
    int

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.singular.cusps import linking_number
    >>> t = np.linspace(0, 2 * np.pi, 65)
    >>> circle = np.column_stack([np.cos(t), np.sin(t), 0 * t])
    >>> linking_number(circle, [np.array([[0.2, 0.1, -1.0], [0.2, 0.1, 1.0]])])
    1
    """
    L = as_float_array(loop, "loop", last=3)
    if L.ndim != 2 or len(L) < 3:
        raise InputError(f"loop must be a (n, 3) polyline of at least three points, got shape {L.shape}")
    if not np.allclose(L[0], L[-1]):
        L = np.vstack([L, L[:1]])
    apex = L.mean(axis=0)
    if curves is None or isinstance(curves, (str, bytes)) or not hasattr(curves, "__iter__"):
        raise TypeError(f"curves must be a sequence of (k, 3) polylines, got {type(curves).__name__} "
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
                if abs(a) < 1e-15:
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
