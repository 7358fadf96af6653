"""Workspaces under joint limits: constant orientation, reachable and dexterous.

* constant-orientation: positions ``(x, y)`` where every leg reaches the pose ``(x, y, phi)``
  with its actuated joint inside its limits;
* reachable: positions reachable with *some* ``phi`` of a range;
* dexterous: positions reachable with *every* ``phi`` of the range (seed 004).

Exact polygons where the legs' inverse kinematics is affine in ``(x, y)`` at fixed ``phi`` with
coefficients independent of ``phi`` (``q_i = a_i . p + c_i(phi)``, e.g. a PPR leg actuated at
the base slider, the 3-PPR of seed 004): each limit is a half-plane; the dexterous workspace is
the intersection of ``a_i . p <= hi_i - max c_i`` and ``a_i . p >= lo_i - min c_i`` over the range
(max/min of ``c_i`` found by a bounded maximisation after dense sampling); when the ``c_i`` differ by
constants (one common ``c(phi)``), the reachable workspace is the projection of the polytope
``{(p, c)}`` - a convex polygon, the hull of the projected vertices. Otherwise the regions are
sampled on a grid (with their boundary by scikit-image ``find_contours``) and the result says so.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._validate import _short, as_box, as_count, as_float_array, as_scalar
from .._validate import as_tolerances as check_tolerances
from ..exceptions import InputError
from ..core.mechanism import check_mechanism
from .._html import dataclass_html, dataclass_repr

__all__ = ["Workspace", "halfplane_polygon", "polygon_area", "constant_orientation_workspace",
           "reachable_workspace", "dexterous_workspace", "sampled_workspace", "MAX_MEMORY"]

MAX_MEMORY = 2 * 1024**3
"""Limit (bytes) for the estimated memory of a sampled workspace's grid (``resolution**2`` cells)."""
_BYTES_PER_CELL = 160
"""Estimated memory per grid cell of :func:`sampled_workspace` (poses, branch values, masks)."""
MAX_ORIENTATIONS = 100_000
"""The largest ``n_phi`` accepted (each orientation is one pass over the grid, or one IK batch)."""
EXTREME_XATOL = 1e-12
"""Stopping width (in ``phi``) of the bounded scalar minimiser that refines the extreme offsets
``max/min c_i(phi)`` of the dexterous and reachable workspaces (a method knob, not a threshold)."""





@dataclass(frozen=True)
class Workspace:
    """A planar workspace region.

    Attributes
    ----------
    kind : str
        ``"constant-orientation"``, ``"reachable"`` or ``"dexterous"``.
    area : float
    polygon : (k, 2) float or None
        Counter-clockwise vertices (exact kinds).
    method : str
        ``"exact: half-planes"``, ``"exact: polytope projection"`` or ``"sampled grid ..."``.
    mask : (n, m) bool or None
        Sampled kinds: the grid cells inside, axes in ``axes``.
    axes : tuple or None
    boundary : list of (k, 2) float
        Boundary curves (the polygon, or contours of the mask).
    """

    kind: str
    area: float
    polygon: np.ndarray | None
    method: str
    mask: np.ndarray | None = None
    axes: tuple | None = None
    boundary: list = field(default_factory=list)

    def contains(self, points, tolerances=None):
        """Which points ``(n, 2)`` lie inside (polygon test, or the grid cell for sampled kinds).

        A point on an exact workspace's boundary is inside to within
        ``tolerances.workspace_inside`` (``None``: the defaults).

        Raises
        ------
        TypeError
            For non-numeric points or a ``tolerances`` that is not a Tolerances.
        InputError
            For points not of shape ``(2,)`` or ``(n, 2)``, or non-finite ones.

        Examples
        --------
        >>> from imagespace.design.workspace import halfplane_polygon, Workspace
        >>> P = halfplane_polygon([[1, 0], [-1, 0], [0, 1], [0, -1]], [1, 1, 1, 1])
        >>> Workspace("constant-orientation", 4.0, P, "exact").contains([[0, 0], [2, 0]]).tolist()
        [True, False]
        """
        pts = np.atleast_2d(as_float_array(points, "points", last=2))
        tol = check_tolerances(tolerances)
        if self.polygon is not None:
            if len(self.polygon) < 3:
                return np.zeros(len(pts), dtype=bool)
            P = self.polygon
            e = np.roll(P, -1, axis=0) - P
            cross = e[None, :, 0] * (pts[:, None, 1] - P[None, :, 1]) - e[None, :, 1] * (pts[:, None, 0] - P[None, :, 0])
            return np.all(cross >= -tol.workspace_inside, axis=1)
        xs, ys = self.axes
        i = np.clip(np.round((pts[:, 0] - xs[0]) / (xs[1] - xs[0])).astype(int), 0, len(xs) - 1)
        j = np.clip(np.round((pts[:, 1] - ys[0]) / (ys[1] - ys[0])).astype(int), 0, len(ys) - 1)
        return self.mask[i, j]

    # short summaries (arrays as shape and dtype) for the terminal and Jupyter; see imagespace._html
    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


def halfplane_polygon(A, b, box=1e6):
    """The polygon ``{p : A p <= b}`` (clipped to ``[-box, box]^2``), counter-clockwise.

    Parameters
    ----------
    A : (k, 2) float
    b : (k,) float
    box : float

    Returns
    -------
    (m, 2) float
        Empty ``(0, 2)`` when infeasible.

    Raises
    ------
    TypeError
        For non-numeric ``A``, ``b`` or ``box``.
    InputError
        For ``A`` not ``(k, 2)``, ``b`` not ``(k,)``, a non-finite entry, or a ``box`` that is not
        one positive number.

    Examples
    --------
    >>> from imagespace.design.workspace import halfplane_polygon, polygon_area
    >>> polygon_area(halfplane_polygon([[1, 0], [-1, 0], [0, 1], [0, -1]], [1, 1, 2, 0]))
    4.0
    """
    A = as_float_array(A, "A", last=2)
    b = as_float_array(b, "b")
    A = np.atleast_2d(A)
    box = as_scalar(box, "box")
    if not box > 0:
        raise InputError(f"box must be a positive half-width, got {box!r}")
    if b.shape != (len(A),):
        raise InputError(f"b must have one entry per row of A ({len(A)}), got shape {b.shape}")
    P = np.array([[-box, -box], [box, -box], [box, box], [-box, box]], dtype=float)
    for a, c in zip(A, b):
        if len(P) == 0:
            break
        val = P @ a - c
        out = []
        for k in range(len(P)):
            cur, nxt = P[k], P[(k + 1) % len(P)]
            vc, vn = val[k], val[(k + 1) % len(P)]
            if vc <= 0:
                out.append(cur)
            if (vc < 0 < vn) or (vn < 0 < vc):
                t = vc / (vc - vn)
                out.append(cur + t * (nxt - cur))
        P = np.array(out).reshape(-1, 2)
    return P


def polygon_area(P):
    """Shoelace area of a simple polygon ``(k, 2)``.

    Raises
    ------
    TypeError
        For non-numeric input.
    InputError
        For an array that is not ``(k, 2)``.

    Examples
    --------
    >>> from imagespace.design.workspace import polygon_area
    >>> polygon_area([[0, 0], [2, 0], [0, 1]])
    1.0
    """
    P = as_float_array(P, "P", last=2, finite=False)
    if P.ndim != 2:
        raise InputError(f"P must be a (k, 2) polygon, got shape {P.shape}")
    if len(P) < 3:
        return 0.0
    x, y = P[:, 0], P[:, 1]
    return float(abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) / 2)


def _limits(limits):
    L = as_float_array(limits, "limits", finite=False)
    if L.shape != (3, 2):
        raise InputError(f"limits must be (3, 2): (min, max) of each actuated joint, got shape {L.shape}")
    if np.any(np.isnan(L)) or np.any(L[:, 0] >= L[:, 1]):
        raise InputError(f"limits must have min < max for every joint (an empty or reversed range), got {L.tolist()}")
    return L


def check_phi_range(phi_range, allow_equal=False):
    """``phi_range`` as ``(lo, hi)`` floats with ``lo < hi`` (or ``lo <= hi`` if ``allow_equal``).

    Shared with :mod:`imagespace.design.indices` (internal; not in ``__all__``).

    Raises
    ------
    TypeError
        For non-numeric input.
    InputError
        For a shape other than ``(2,)``, a non-finite end, or ``min >= max``.

    Examples
    --------
    >>> from imagespace.design.workspace import check_phi_range
    >>> check_phi_range([-0.5, 0.5])
    (-0.5, 0.5)
    """
    r = as_float_array(phi_range, "phi_range")
    if r.shape != (2,):
        raise InputError(f"phi_range must be (min, max), got shape {r.shape}: {_short(phi_range)}")
    lo, hi = float(r[0]), float(r[1])
    if not (hi > lo or (allow_equal and hi == lo)):
        raise InputError(f"phi_range must be (min, max) with min < max, got {phi_range!r}")
    return lo, hi


def _check_box(box, required=False):
    if box is None and required:
        raise InputError("box ((x_min, x_max), (y_min, y_max)) is needed to sample a workspace, got None")
    return as_box(box, "box", dim=2, required=False)


def _gb(nbytes):
    return f"{nbytes / 1e9:.3g}" if nbytes < 1e300 else "more than 1e291"


def _check_grid(resolution, n_phi):
    resolution = as_count(resolution, "resolution", 8)
    need = resolution * resolution * _BYTES_PER_CELL            # exact: resolution may be huge
    if need > MAX_MEMORY:
        raise InputError(f"resolution {_short(resolution)} needs about {_gb(need)} GB for the grid, above the limit "
                         f"MAX_MEMORY={MAX_MEMORY / 1e9:.3g} GB; lower the resolution (at most "
                         f"{int(np.sqrt(MAX_MEMORY / _BYTES_PER_CELL))})")
    if n_phi is not None:
        n_phi = as_count(n_phi, "n_phi", 1)
        if n_phi > MAX_ORIENTATIONS:
            raise InputError(f"n_phi must be at most MAX_ORIENTATIONS = {MAX_ORIENTATIONS}, got {n_phi}")
    return resolution, n_phi


def _affine(manipulator, phis):
    """``a (3, 2)`` and ``c (len(phis), 3)`` with ``q_i = a_i . p + c_i(phi)``, or None."""
    tol = manipulator.tolerances
    rng = np.random.default_rng(0)
    probe = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] + rng.normal(size=(3, 2)).tolist())
    cols = []
    for phi in (phis[0], phis[len(phis) // 2], phis[-1]):
        Q = manipulator.inverse_kinematics(np.column_stack([probe, np.full(len(probe), phi)]))
        if not np.all(np.isfinite(Q)):
            return None
        a = np.stack([Q[1] - Q[0], Q[2] - Q[0]], axis=-1)            # (3, 2)
        pred = Q[0] + probe[3:] @ a.T
        if not np.allclose(pred, Q[3:], rtol=tol.workspace_affine,
                           atol=tol.workspace_affine * (1 + np.abs(Q).max())):
            return None
        cols.append(a)
    if not all(np.allclose(a, cols[0], atol=tol.workspace_affine_constant) for a in cols):
        return None
    a = cols[0]
    c = manipulator.inverse_kinematics(np.column_stack([np.zeros(len(phis)), np.zeros(len(phis)), phis]))
    return a, c


def _extreme(manipulator, i, lo, hi, phis, c, sign):
    """max over [lo, hi] of sign * c_i(phi), refined around the best sample."""
    from scipy.optimize import minimize_scalar

    k = int(np.argmax(sign * c[:, i]))
    a, b = phis[max(k - 1, 0)], phis[min(k + 1, len(phis) - 1)]

    def f(t):
        return -sign * manipulator.inverse_kinematics([0.0, 0.0, t])[i]
    r = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": EXTREME_XATOL})
    return max(sign * c[k, i], -r.fun)


def _limit_polygon(a, L, cmax, cmin):
    """``{p : L_lo_i <= a_i . p + c_i <= L_hi_i}`` for offsets ``c_i`` between ``cmin`` and ``cmax``."""
    return halfplane_polygon(np.vstack([a, -a]), np.concatenate([L[:, 1] - cmax, -(L[:, 0] - cmin)]))


def _exact_result(kind, P, method):
    return Workspace(kind, polygon_area(P), P, method, boundary=[np.vstack([P, P[:1]])] if len(P) else [])


def constant_orientation_workspace(manipulator, phi, limits, box=None, resolution=400):
    """Positions reachable at the orientation ``phi`` with every actuated joint inside ``limits``.

    Parameters
    ----------
    manipulator : PlanarParallel
    phi : float
    limits : (3, 2) float
    box : (2, 2) float, optional
        Sampling window for non-affine designs (required there).
    resolution : int

    Returns
    -------
    Workspace

    Raises
    ------
    TypeError
        For a ``manipulator`` that is not a PlanarParallel, or non-numeric arguments.
    InputError
        For ``limits`` not ``(3, 2)`` with ``min < max``, a malformed ``phi`` or ``box``, a
        ``resolution`` whose grid exceeds :data:`MAX_MEMORY`, or a design that needs the
        sampled route without a ``box``.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.design.workspace import constant_orientation_workspace
    >>> m = isp.examples.choi_3ppr()
    >>> ws = constant_orientation_workspace(m, 0.0, [[-np.sqrt(3), np.sqrt(3)]] * 3)
    >>> ws.method, ws.area > 0
    ('exact: half-planes', True)
    """
    check_mechanism(manipulator)
    L = _limits(limits)
    phi = as_scalar(phi, "phi")
    _check_box(box)
    _check_grid(resolution, None)
    aff = _affine(manipulator, np.array([phi]))
    if aff is not None:
        a, c = aff
        return _exact_result("constant-orientation", _limit_polygon(a, L, c[0], c[0]), "exact: half-planes")
    return sampled_workspace(manipulator, L, (phi, phi), box, resolution, n_phi=1, kind="constant-orientation")


def _orientation_range_inputs(manipulator, phi_range, limits, box, resolution, n_phi):
    """The checked inputs of the workspaces over an orientation range: limits, range, the sampled
    orientations and the design's affine form (None where it has none)."""
    check_mechanism(manipulator)
    L = _limits(limits)
    lo, hi = check_phi_range(phi_range)
    _check_box(box)
    _, n_phi = _check_grid(resolution, n_phi)
    if n_phi < 2:
        raise InputError(f"n_phi must be at least 2 (orientations sampled over phi_range), got {n_phi}")
    phis = np.linspace(lo, hi, n_phi)
    return L, lo, hi, phis, _affine(manipulator, phis)


def dexterous_workspace(manipulator, phi_range, limits, box=None, resolution=400, n_phi=181):
    """Positions reachable with every ``phi`` in ``phi_range``.

    Exact where the legs' inverse kinematics is affine (decided with the manipulator's
    ``tolerances.workspace_*`` fields), otherwise sampled on a grid over ``box``.

    Raises
    ------
    TypeError
        For a ``manipulator`` that is not a PlanarParallel, or non-numeric arguments.
    InputError
        For ``limits`` not ``(3, 2)`` with ``min < max``, a malformed ``phi_range`` or ``box``, a
        ``resolution`` whose grid exceeds :data:`MAX_MEMORY`, ``n_phi`` outside ``2..MAX_ORIENTATIONS``, or a design that needs the
        sampled route without a ``box``.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.design.workspace import dexterous_workspace
    >>> m = isp.examples.choi_3ppr()
    >>> dexterous_workspace(m, (-0.5, 0.5), [[-np.sqrt(3), np.sqrt(3)]] * 3).method
    'exact: half-planes'
    """
    L, lo, hi, phis, aff = _orientation_range_inputs(manipulator, phi_range, limits, box, resolution, n_phi)
    if aff is not None:
        a, c = aff
        cmax = np.array([_extreme(manipulator, i, lo, hi, phis, c, 1.0) for i in range(3)])
        cmin = -np.array([_extreme(manipulator, i, lo, hi, phis, c, -1.0) for i in range(3)])
        return _exact_result("dexterous", _limit_polygon(a, L, cmax, cmin), "exact: half-planes")
    return sampled_workspace(manipulator, L, (lo, hi), box, resolution, n_phi, kind="dexterous")


def reachable_workspace(manipulator, phi_range, limits, box=None, resolution=400, n_phi=181):
    """Positions reachable with some ``phi`` in ``phi_range``.

    Exact where the legs' inverse kinematics is affine (decided with the manipulator's
    ``tolerances.workspace_*`` fields), otherwise sampled on a grid over ``box``.

    Raises
    ------
    TypeError
        For a ``manipulator`` that is not a PlanarParallel, or non-numeric arguments.
    InputError
        For ``limits`` not ``(3, 2)`` with ``min < max``, a malformed ``phi_range`` or ``box``, a
        ``resolution`` whose grid exceeds :data:`MAX_MEMORY`, ``n_phi`` outside ``2..MAX_ORIENTATIONS``, or a design that needs the
        sampled route without a ``box``.

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.design.workspace import reachable_workspace
    >>> m = isp.examples.choi_3ppr()
    >>> reachable_workspace(m, (-0.5, 0.5), [[-np.sqrt(3), np.sqrt(3)]] * 3).method
    'exact: polytope projection'
    """
    L, lo, hi, phis, aff = _orientation_range_inputs(manipulator, phi_range, limits, box, resolution, n_phi)
    if aff is not None:
        a, c = aff
        offs = c - c[:, :1]
        tol = manipulator.tolerances
        if np.allclose(offs, offs[0], atol=tol.workspace_common_offset * (1 + np.abs(c).max())):
            from scipy.spatial import ConvexHull

            k = offs[0]                                   # c_i = c_0 + k_i
            cmax = _extreme(manipulator, 0, lo, hi, phis, c, 1.0)
            cmin = -_extreme(manipulator, 0, lo, hi, phis, c, -1.0)
            # polytope in (x, y, s): L_lo_i <= a_i p + s + k_i <= L_hi_i, cmin <= s <= cmax
            G = np.vstack([np.column_stack([a, np.ones(3)]), -np.column_stack([a, np.ones(3)]),
                           [[0, 0, 1.0]], [[0, 0, -1.0]]])
            h = np.concatenate([L[:, 1] - k, -(L[:, 0] - k), [cmax], [-cmin]])
            verts = []
            for i in range(len(G)):
                for j in range(i + 1, len(G)):
                    for l in range(j + 1, len(G)):
                        M = G[[i, j, l]]
                        if abs(np.linalg.det(M)) < tol.workspace_vertex_det:
                            continue
                        v = np.linalg.solve(M, h[[i, j, l]])
                        if np.all(G @ v <= h + tol.workspace_vertex_feasible * (1 + np.abs(h))):
                            verts.append(v[:2])
            if len(verts) < 3:
                return Workspace("reachable", 0.0, np.zeros((0, 2)), "exact: polytope projection")
            V = np.array(verts)
            hull = ConvexHull(V)
            return _exact_result("reachable", V[hull.vertices], "exact: polytope projection")
    return sampled_workspace(manipulator, L, (lo, hi), box, resolution, n_phi, kind="reachable")


def sampled_workspace(manipulator, limits, phi_range, box, resolution=400, n_phi=91, kind="reachable"):
    """A workspace sampled on a grid: every leg's IK (all branches) inside its limits.

    Parameters
    ----------
    manipulator : PlanarParallel
    limits : (3, 2) float
    phi_range : (float, float)
        Equal ends for a single orientation.
    box : (2, 2) float
        The window ``((x_min, x_max), (y_min, y_max))``.
    resolution : int
        Grid points per axis.
    n_phi : int
    kind : {"reachable", "dexterous", "constant-orientation"}

    Returns
    -------
    Workspace
        ``area`` = cells inside x cell area; ``boundary`` from ``find_contours``.

    Raises
    ------
    TypeError
        For a ``manipulator`` that is not a PlanarParallel, or non-numeric arguments.
    InputError
        For ``limits`` not ``(3, 2)`` with ``min < max``, a missing or malformed ``box``, a
        malformed ``phi_range``, an unknown ``kind``, a ``resolution`` whose grid exceeds
        :data:`MAX_MEMORY`, or ``n_phi`` outside ``1..MAX_ORIENTATIONS`` (at least 2 for a range).

    Examples
    --------
    >>> import numpy as np, imagespace as isp
    >>> from imagespace.design.workspace import sampled_workspace
    >>> m = isp.examples.choi_3ppr()
    >>> ws = sampled_workspace(m, [[-np.sqrt(3), np.sqrt(3)]] * 3, (0.0, 0.0), [(-2, 2), (-2, 2)], 100, 1,
    ...                        "constant-orientation")
    >>> ws.method.startswith("sampled")
    True
    """
    from skimage.measure import find_contours

    check_mechanism(manipulator)
    L = _limits(limits)
    bx = _check_box(box, required=True)
    if not isinstance(kind, str) or kind not in ("reachable", "dexterous", "constant-orientation"):
        raise InputError(f"kind must be reachable, dexterous or constant-orientation, got {kind!r}")
    resolution, n_phi = _check_grid(resolution, n_phi)
    lo, hi = check_phi_range(phi_range, allow_equal=True)
    if hi > lo and n_phi < 2:
        raise InputError(f"n_phi must be at least 2 for a range of orientations, got {n_phi}")
    xs = np.linspace(*bx[0], resolution)
    ys = np.linspace(*bx[1], resolution)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    phis = np.linspace(lo, hi, n_phi) if hi > lo else np.array([lo])
    acc = None
    for phi in phis:
        P = np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, phi)])
        ok = np.ones(X.size, dtype=bool)
        for i, leg in enumerate(manipulator.legs):
            vals = leg.actuated_values(P)
            inside = (vals >= L[i, 0]) & (vals <= L[i, 1])
            ok &= np.any(inside, axis=-1)
        ok = ok.reshape(X.shape)
        acc = ok if acc is None else (acc | ok if kind == "reachable" else acc & ok)
    cell = (xs[1] - xs[0]) * (ys[1] - ys[0])
    contours = [np.column_stack([np.interp(cn[:, 0], np.arange(len(xs)), xs), np.interp(cn[:, 1], np.arange(len(ys)), ys)])
                for cn in find_contours(acc.astype(float), 0.5)]
    return Workspace(kind, float(acc.sum() * cell), None,
                     f"sampled grid {resolution}x{resolution}, {len(phis)} orientations", acc, (xs, ys), contours)
