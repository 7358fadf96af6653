"""Cusp curves in joint space: where three assembly modes merge, traced by continuation.

With ``f(theta; q) = F(cos theta, sin theta; q)`` the kinematic binary form at the half-angle
``theta``, the cusps are the real solutions of ``f = f' = f'' = 0`` (derivatives in ``theta``): three
equations in the four unknowns ``(theta, q1, q2, q3)``, a curve. Seeds come from the cusps of a
few sections of the box (:func:`imagespace.singular.cusps.cusps`, three planes per joint axis);
from each seed not already on a traced curve the curve is followed both ways by pseudo-arclength
continuation (tangent: the null vector of the ``3 x 4`` Jacobian; corrector: Newton with
minimum-norm steps) until it leaves the box, closes, or the step collapses (a swallowtail point,
where four modes merge). The unknowns are scaled so that every side of the box measures ``pi``
(as ``theta`` does over its period), and ``theta`` is taken modulo ``pi`` (``f`` has even degree).

Floating point throughout: the curves are for drawing and for seeding proofs.
:func:`imagespace.atlas.is_cuspidal` proves that a cusp exists (a verified witness).
"""

from __future__ import annotations

import numpy as np

from .._validate import as_count
from ..exceptions import ImageSpaceError, InputError
from ..singular.cusps import check_section_resolution, cusp_system, cusps, free_joints
from .boxes import check_joint_box

__all__ = ["cusp_curves", "correct_cusp", "seeds_from_points"]

_NEWTON_STEPS = 8          # corrector iterations (a numerical knob)
_STEP_START = 0.03         # first continuation step, scaled units (box side = pi)
_STEP_MAX = 0.08
_STEP_MIN = 1e-5
_MAX_POINTS = 3000         # per direction
_EDGE = 1e-12              # a traced point this far (scaled) past a face has left the box
_MAX_SECTIONS = 64         # seeding planes per axis (each one a resolution**2 section)
_LEAD = 1e-12              # seeding: forms whose leading coefficient is below this (relative) are skipped


def _scaled_system(m, y, lo, scale):
    """G (3,), Js (3, 4) and the coefficient scale at scaled point y = (theta, (q - lo) * scale)."""
    x = np.concatenate([[y[0]], lo + y[1:] / scale])
    G, J, s = cusp_system(m, x[None, :])
    Js = J[0] / np.concatenate([[1.0], scale])
    return G[0], Js, float(s[0])


def _correct(m, y, lo, scale, tol):
    for _ in range(_NEWTON_STEPS):
        G, Js, s = _scaled_system(m, y, lo, scale)
        if not np.all(np.isfinite(G)) or s == 0:
            return None
        if np.max(np.abs(G)) <= tol * s:
            return y
        dy = -np.linalg.lstsq(Js, G, rcond=None)[0]
        y = y + dy
    G, Js, s = _scaled_system(m, y, lo, scale)
    return y if np.all(np.isfinite(G)) and np.max(np.abs(G)) <= tol * s else None


def correct_cusp(manipulator, x, tol=None):
    """Newton (minimum-norm steps) from ``x = (theta, q1, q2, q3)`` onto the cusp curve.

    Parameters
    ----------
    manipulator : PlanarParallel
    x : (4,) float
    tol : float, optional
        Relative residual (default ``Tolerances.atlas_cusp_residual``).

    Returns
    -------
    (4,) float or None
        The corrected point, or None if Newton did not converge.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.atlas.curves import correct_cusp
    >>> x = correct_cusp(isp.examples.general_3rpr(), [0.66, 9.78, 3.96, 10.0])
    >>> x is not None
    True
    """
    from .._validate import as_float_array

    x = as_float_array(x, "x", last=4)
    tol = manipulator.tolerances.atlas_cusp_residual if tol is None else float(tol)
    one = np.ones(3)
    y = _correct(manipulator, np.asarray(x, dtype=float).copy(), np.zeros(3), one, tol)
    return None if y is None else y


def _correct_on_face(m, y, lo, scale, tol, axis, bound):
    """Newton on the square system (cusp system, ``y[1 + axis] = bound``): the curve's exit point."""
    y = y.copy()
    y[1 + axis] = bound
    for _ in range(_NEWTON_STEPS):
        G, Js, s = _scaled_system(m, y, lo, scale)
        if not np.all(np.isfinite(G)) or s == 0:
            return None
        if np.max(np.abs(G)) <= tol * s:
            return y
        A = np.delete(Js, 1 + axis, axis=1)
        try:
            dy = -np.linalg.solve(A, G)
        except np.linalg.LinAlgError:
            return None
        y[np.arange(4) != 1 + axis] += dy
    G, Js, s = _scaled_system(m, y, lo, scale)
    return y if np.all(np.isfinite(G)) and np.max(np.abs(G)) <= tol * s else None


def _tangent(Js, prev=None):
    _, _, vt = np.linalg.svd(Js)
    t = vt[-1]
    if prev is not None and t @ prev < 0:
        t = -t
    return t


def _gap(a, b):
    """Distance in the scaled unknowns with theta modulo pi."""
    d = a - b
    d[..., 0] = np.remainder(d[..., 0] + np.pi / 2, np.pi) - np.pi / 2
    return np.linalg.norm(d, axis=-1)


def _trace(m, y0, direction, lo, scale, tol, box_scaled):
    pts = [y0]
    y, t = y0, direction
    h = _STEP_START
    steps = 0
    while len(pts) < _MAX_POINTS:
        steps += 1
        y_new = _correct(m, y + h * t, lo, scale, tol)
        if y_new is not None:
            move = _gap(y_new, y)
            _, Js, _ = _scaled_system(m, y_new, lo, scale)
            t_new = _tangent(Js, t)
            if move > 2.5 * h or t_new @ t < 0.8:
                y_new = None
        if y_new is None:
            h *= 0.5
            if h < _STEP_MIN:
                return np.array(pts), "stalled"
            continue
        outside = np.any(y_new[1:] < -_EDGE) or np.any(y_new[1:] > box_scaled + _EDGE)
        if outside:
            # the last point inside and the crossing of the box's face (linear, for the drawing)
            d = y_new - y
            with np.errstate(divide="ignore", invalid="ignore"):
                s_lo = np.where(d[1:] < 0, -y[1:] / d[1:], np.inf)
                s_hi = np.where(d[1:] > 0, (box_scaled - y[1:]) / d[1:], np.inf)
            cand = np.concatenate([s_lo, s_hi])
            k = int(np.argmin(cand))
            s_ = float(np.clip(cand[k], 0, 1))
            axis = k % 3
            bound = 0.0 if k < 3 else float(box_scaled[axis])
            end = _correct_on_face(m, y + s_ * d, lo, scale, tol, axis, bound)
            pts.append(end if end is not None else y + s_ * d)
            return np.array(pts), "box"
        pts.append(y_new)
        if len(pts) > 10 and _gap(y_new, y0) < 0.75 * h:
            pts.append(y0)
            return np.array(pts), "closed"
        y, t = y_new, t_new
        h = min(h * 1.3, _STEP_MAX)
    return np.array(pts), "length"


def _roots_theta(manipulator, Q):
    """All complex roots of the kinematic form at the rows of ``Q`` as points ``w`` of the unit
    circle's Cayley image (``t = x1/x0``, ``w = (t - i)/(t + i)``; a real root lies on the circle,
    ``t = infinity`` at ``w = 1``), ``(n, d)`` complex (NaN where the degree drops)."""
    C = manipulator.compiled().coefficients(Q)                  # column k multiplies x0^(d-k) x1^k
    n, d1 = C.shape
    d = d1 - 1
    out = np.full((n, d), np.nan + 0j)
    lead = C[:, -1]
    ok = np.abs(lead) > _LEAD * np.abs(C).sum(axis=1)
    if not ok.any() or d < 1:
        return out
    comp = np.zeros((int(ok.sum()), d, d))
    comp[:, 1:, :-1] = np.eye(d - 1)
    comp[:, :, -1] = -C[ok, :-1] / lead[ok, None]
    t = np.linalg.eigvals(comp)
    out[ok] = (t - 1j) / (t + 1j)
    return out


def seeds_from_points(manipulator, Q, keep=64):
    """Cusp-curve seeds ``(theta, q1, q2, q3)`` from joint vectors ``Q`` near the singularity
    surface (e.g. the atlas's vertices): the rows where three roots of the kinematic form are
    closest together, each with the half-angle of that cluster (a float heuristic; Newton follows).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.atlas.curves import seeds_from_points
    >>> seeds_from_points(isp.examples.general_3rpr(), np.array([[11.0, 5.0, 10.0]])).shape
    (1, 4)
    """
    W = _roots_theta(manipulator, Q)
    n, d = W.shape
    if d < 3 or n == 0:
        return np.empty((0, 4))
    D = np.abs(W[:, :, None] - W[:, None, :])
    D[:, np.arange(d), np.arange(d)] = np.inf
    D = np.where(np.isnan(D), np.inf, D)
    second = np.sort(D, axis=2)[:, :, 1]                      # each root's second-nearest neighbour
    best_root = np.argmin(second, axis=1)
    spread = second[np.arange(n), best_root]
    order = np.argsort(spread)[:keep]
    order = order[np.isfinite(spread[order])]
    w = W[order, best_root[order]]
    # the cluster's centre, back on the circle; theta from t = i (1 + w)/(1 - w)
    w = w / np.abs(w)
    t = (1j * (1 + w) / (1 - w)).real
    theta = np.arctan(t)
    return np.column_stack([theta, Q[order]])


def cusp_curves(manipulator, joint_box, seeds=None, sections=1, resolution=48):
    """The cusp curves of ``manipulator`` inside ``joint_box`` as polylines ``(theta, q1, q2, q3)``.

    Parameters
    ----------
    manipulator : PlanarParallel
    joint_box : (3, 2) float
    seeds : (n, 3) float, optional
        Joint vectors near the singularity surface to seed from (:func:`seeds_from_points`; the
        atlas passes its surface vertices). Without them, or in addition, the cusps of
        ``sections`` planes per joint axis are used (:func:`imagespace.singular.cusps.cusps`).
    sections : int
        Seeding planes per joint axis (0: none).
    resolution : int
        Grid per axis of each seeding section.

    Returns
    -------
    list of (k, 4) float
        Rows ``(theta, q1, q2, q3)``; ``theta`` is the half-angle of the triple root, continuous
        along a curve (not reduced modulo ``pi``).

    Raises
    ------
    TypeError
        ``manipulator`` not a design; non-numeric box or seeds; ``sections``/``resolution`` not
        whole numbers.
    InputError
        A box of the wrong shape or outside the joints' domains; seeds not ``(n, 3)``;
        ``resolution`` below 8 or above ``SECTION_MAX_RESOLUTION`` (2000); ``sections`` above 64.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas.curves import cusp_curves
    >>> curves = cusp_curves(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)],
    ...                      seeds=[[9.78, 3.96, 10.0]], sections=0)
    >>> all(c.shape[1] == 4 for c in curves) and len(curves) > 0
    True
    """
    from .._validate import as_float_array

    box = check_joint_box(manipulator, joint_box)
    sections = as_count(sections, "sections", 0)
    resolution = check_section_resolution(resolution)
    if sections > _MAX_SECTIONS:
        raise InputError(f"sections must be at most {_MAX_SECTIONS} seeding planes per joint axis, got "
                         f"{sections}")
    tol = manipulator.tolerances.atlas_cusp_residual
    reach = manipulator.tolerances.atlas_cusp_seed_reach
    lo = box[:, 0]
    side = box[:, 1] - box[:, 0]
    scale = np.pi / side
    box_scaled = side * scale
    start = []
    if seeds is not None:
        S = as_float_array(seeds, "seeds", last=3)
        S = np.atleast_2d(S)
        for x in seeds_from_points(manipulator, S):
            start.append(np.concatenate([[x[0]], (x[1:] - lo) * scale]))
    for fixed in range(3):
        fa, fb = free_joints(fixed)
        window = [tuple(box[fa]), tuple(box[fb])]
        for k in range(sections):
            value = lo[fixed] + side[fixed] * (k + 0.5) / sections
            try:
                found = cusps(manipulator, fixed, value, window, resolution)
            except InputError:
                raise                        # the caller's arguments: said, never swallowed
            except ImageSpaceError:
                continue                     # a section the float solver cannot take: seed elsewhere
            for c in found:
                start.append(np.concatenate([[c.theta], (c.q - lo) * scale]))
    curves, traced = [], np.empty((0, 4))
    for y0 in start:
        if len(traced) and np.min(_gap(traced, y0)) < reach:
            continue
        y0 = _correct(manipulator, y0, lo, scale, tol)
        if y0 is None or np.any(y0[1:] < 0) or np.any(y0[1:] > box_scaled):
            continue
        if len(traced) and np.min(_gap(traced, y0)) < reach:
            continue
        _, Js, _ = _scaled_system(manipulator, y0, lo, scale)
        t0 = _tangent(Js)
        fwd, why = _trace(manipulator, y0, t0, lo, scale, tol, box_scaled)
        if why == "closed":
            pts = fwd
        else:
            back, _ = _trace(manipulator, y0, -t0, lo, scale, tol, box_scaled)
            pts = np.vstack([back[::-1], fwd[1:]])
        traced = np.vstack([traced, pts])
        curves.append(np.column_stack([pts[:, 0], lo + pts[:, 1:] / scale]))
    return curves
