"""Triangle meshes of implicit surfaces - above all the singularity surface - and their export.

Pipeline (:func:`mesh_implicit`): the function is evaluated on a regular grid of the box
(polynomials in two of the chart coordinates are evaluated as one matrix product over the
monomials, the fast path for the quartic); scikit-image's marching cubes places one vertex on
every grid edge where the sign changes; each vertex is then moved *along its edge* by a
safeguarded Newton iteration (bisection whenever a step leaves the bracket) until the sign change
is bracketed by an interval shorter than ``tol`` times the box size.

**What "certified" means.** A vertex is certified when two points ``P-`` and ``P+`` within
``tol * size`` of it are known to have opposite signs of the function (or one point at the vertex
is known to be a zero): the surface then passes between them, so the distance from the vertex to
the surface is at most ``max(|V - P-|, |V - P+|)``, a bound that does not rely on
``|F| / |grad F|`` (only a first-order estimate, and wrong near singular points). How a sign is
*known* depends on the implicit (``Implicit.sign_test``):

* :class:`PolynomialImplicit` (every singularity surface of a polynomial kind): the sign of the
  float value ``F`` counts only when ``|F|`` exceeds a rigorous bound on the rounding error of that
  very evaluation (a monomial sum whose error is bounded a priori, Higham, *Accuracy and Stability
  of Numerical Algorithms*, 2nd ed., SIAM 2002, ch. 3-5, doi:10.1137/1.9780898718027); below the
  bound the sign is decided in arb ball arithmetic (python-flint) on the exact expression at the
  exact binary point, and a point whose ball still contains 0 (unless the ball is exactly 0) is
  undecided. The only assumption: numpy's float64 ``sin``/``cos`` are within
  :data:`TRIG_ULPS` units in the last place (checked against arb at first use; if the check fails,
  trigonometric charts fall back to float signs and say so);
* any other :class:`Implicit` (e.g. the working-mode surfaces evaluated through the leg inverse
  kinematics): the sign of the float value, as before; ``sign_test`` then starts with
  ``"float signs"``.

A vertex whose own edge brackets no proven sign change (marching cubes put it on a grid node, or
inside a cube - the extra vertex of the ambiguous cases -, or the sign change came from rounding
noise) is searched along the other grid directions, the gradient and the cube diagonals (points
at 1/4, 1/2 and 1 cell on both sides), and the bracket found is bisected on proven signs. A vertex
that still cannot be certified is **removed** with its faces (or kept and counted, with
``on_uncertified="keep"``); ``metadata["imagespace"]`` records both counts. A surface component
of even multiplicity (``F`` touches 0 without changing sign) has no sign change to bracket: the
grid sees it only through rounding noise, whose marching-cubes faces collapse onto grid nodes and
are dropped as degenerate; a vertex there survives only as a proven zero, any other is removed.

Faces are then oriented so that normals point to the side where the function is positive (for the
singularity surface: towards the aspect ``+1``), degenerate faces removed, and a
:class:`trimesh.Trimesh` returned; ``mesh.metadata["imagespace"]`` records the chart, box,
resolution, the certified distance bound, the worst ``|F|/|grad F|``, the counts and the timings,
and ``mesh.vertex_attributes["distance_bound"]`` the bound per vertex (``inf`` if uncertified).

Charts of image space (``chart=``):

* ``"image"`` - the affine chart ``(x2/x0, x3/x0, x1/x0)`` of seed 002 (Abb. 2, 4);
* ``"pose"`` - ``(x, y, phi)``; the quartic is even, so the function is ``2 pi`` periodic in
  ``phi`` and a box ``phi in [-pi, pi]`` gives a mesh whose two ends match.

Exports (:func:`export_mesh`): PLY (binary, ``property double``) and OBJ (17 significant digits)
keep the float64 vertices bit for bit; STL and GLB store float32 by format, so their vertices are
rounded to about ``6e-8`` relative - far coarser than the certified ``tol``.

Only this module (and :mod:`imagespace.plotting`) imports scikit-image and trimesh, lazily.
"""

from __future__ import annotations

import math
import numbers
import os
import time
import warnings
from pathlib import Path

import numpy as np

from .._validate import _short, as_box, as_count, as_flag, as_float_array
from .._files import atomic_write
from ..exceptions import InputError
from .implicit import (TRIG_ULPS, FunctionImplicit, Implicit, PolynomialImplicit, ArbBudget, UNIT_ROUNDOFF,  # noqa: F401
                       as_tolerances, surface_implicit)

__all__ = ["Implicit", "PolynomialImplicit", "FunctionImplicit", "mesh_implicit", "mesh_surface",
           "export_mesh", "surface_implicit", "EXPORT_FORMATS", "EXPORT_PRECISION", "MAX_MEMORY",
           "TRIG_ULPS"]

EXPORT_FORMATS = (".stl", ".ply", ".obj", ".glb")
EXPORT_PRECISION = {".stl": "float32", ".ply": "float64", ".obj": "float64", ".glb": "float32"}
"""Precision of the vertex coordinates each export format stores (STL and GLB: float32 by format)."""
MAX_MEMORY = 2 * 1024**3
"""Default limit (bytes) for the estimated memory of a mesh's grid and marching cubes."""
_BYTES_PER_CELL = 8 * 3           # float64 grid + the monomial block + marching-cubes work

# numerical knobs of the meshing pipeline (index units are grid cells); its decision thresholds are
# Tolerances.mesh_on_grid, mesh_node_merge and mesh_min_altitude
_NEWTON_STEPS = 200               # safeguarded Newton / bisection steps along an edge
_NEWTON_SMALL = 0.25              # a Newton step below this fraction of the wanted width has converged
_SEARCH_STEPS = (0.25, 0.5, 1.0)  # neighbourhood search: points at these multiples of a cell on each side
_BISECT_TRIES = (0.5, 0.375, 0.625, 0.25, 0.75)  # tried in turn while a bisection point's sign is undecided
_BISECT_STEPS = 80                # bisection steps of the neighbourhood search (2 cells -> tol needs ~25)
_ORIENT_SAMPLE = 4096             # faces sampled to decide the orientation
_FIT_MAX_DEGREE = 8               # edges are located from a polynomial fit up to this degree in the edge variable


# -- meshing ------------------------------------------------------------------------------------
def _check_max_memory(max_memory):
    if isinstance(max_memory, (bool, np.bool_)) or not isinstance(max_memory, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"max_memory must be a positive number of bytes, got {type(max_memory).__name__} "
                        f"{_short(max_memory)}")
    try:
        v = float(max_memory)
    except OverflowError:
        v = math.inf
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"max_memory must be a positive finite number of bytes, got {_short(max_memory)}")
    return v


class _KindError(InputError, TypeError):
    """A parameter of the wrong kind that used to raise :class:`InputError`: a ``TypeError`` (the
    convention) that ``except InputError`` still catches."""


def _check_resolution(resolution, max_memory):
    max_memory = _check_max_memory(max_memory)
    if isinstance(resolution, np.ndarray) and resolution.ndim == 0:
        resolution = resolution[()]
    wrong = (f"resolution must be an int or three ints (whole numbers of grid points per axis), got "
             f"{type(resolution).__name__} {_short(resolution)}")
    if isinstance(resolution, (str, bytes)) or resolution is None:
        raise _KindError(wrong)
    if isinstance(resolution, (numbers.Number, np.generic)):
        items = [resolution]
    else:
        try:
            items = list(resolution)
        except TypeError:
            raise _KindError(wrong) from None
        if len(items) not in (1, 3):
            raise InputError(f"resolution must be an int or three ints (grid points per axis), got "
                             f"{len(items)} entries: {_short(resolution)}")
    names = ["resolution"] if len(items) == 1 else [f"resolution[{i}]" for i in range(3)]
    try:
        vals = [as_count(v, n, minimum=-2**63) for v, n in zip(items, names)]
    except TypeError as exc:
        raise _KindError(f"{exc}; resolution must be an int or three ints") from None
    if any(v < 8 for v in vals):
        raise InputError(f"resolution must be at least 8 grid points per axis, got {resolution!r}")
    r = vals * 3 if len(vals) == 1 else vals
    need = math.prod(r) * _BYTES_PER_CELL              # exact: 2**1100 points do not overflow here
    if need > max_memory:
        gb = need / 10**9 if need < 10**300 else math.inf
        raise InputError(f"resolution {_short(tuple(int(v) for v in r))} needs about {gb:.3g} GB for the grid "
                         f"and marching cubes, above the limit max_memory={max_memory / 1e9:.3g} GB; "
                         "lower the resolution or raise max_memory")
    return tuple(int(v) for v in r)


class _Progress:
    def __init__(self, enabled, total):
        self.bar = None
        if enabled is not None:
            enabled = as_flag(enabled, "progress")
        if enabled is not False:
            from tqdm.auto import tqdm

            self.bar = tqdm(total=total, delay=1.0, desc="meshing", leave=False)

    def step(self, n=1):
        if self.bar is not None:
            self.bar.update(n)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def mesh_implicit(func, box, resolution=128, tol=1e-9, progress=None, max_memory=MAX_MEMORY,
                  on_uncertified="remove", tolerances=None):
    """Mesh the zero set of an implicit function inside a box.

    Parameters
    ----------
    func : Implicit
        E.g. :class:`PolynomialImplicit` or :func:`surface_implicit`.
    box : (3, 2) float
        ``((u_min, u_max), (v_min, v_max), (w_min, w_max))``.
    resolution : int or (3,) int
        Grid points per axis, at least 8.
    tol : float
        Every vertex kept ends within ``tol * size`` of the surface, certified by a sign change
        between two points with proven signs (see the module docstring), ``size`` the box's
        longest side.
    progress : bool or None
        Progress bar (tqdm); ``None``: shown only if meshing takes longer than a second.
    max_memory : float
        Bytes; a resolution whose estimated memory is above it is refused before allocating.
    on_uncertified : {"remove", "keep"}
        What to do with a vertex no proven sign change within ``tol * size`` can be found for
        (e.g. on a surface component of even multiplicity, where ``func`` does not change sign):
        remove it with its faces (default), or keep it at its marching-cubes place and count it.
    tolerances : Tolerances, optional
        Reads ``mesh_on_grid``, ``mesh_node_merge`` and ``mesh_min_altitude`` (default
        :data:`imagespace.tolerances.TOLERANCES`).

    Returns
    -------
    trimesh.Trimesh
        Normals point to where ``func > 0``. ``mesh.metadata["imagespace"]`` holds
        ``max_distance`` (the largest certified bound over the certified vertices),
        ``max_residual`` (``max |F|/|grad F|``), ``uncertified`` (vertices left in the mesh without
        a certificate: 0 unless ``on_uncertified="keep"``), ``removed`` and ``removed_faces`` (what
        was removed for want of a certificate), ``sign_test`` (how signs were known),
        ``searched`` (vertices certified off their own edge or not at all), ``arb_evaluations`` and
        ``arb_budget_exhausted`` (more undecided signs than arb was allowed to settle),
        the box, resolution and timings. ``mesh.vertex_attributes["distance_bound"]`` is the
        certified bound of each vertex (``inf`` if uncertified).

    Raises
    ------
    TypeError
        ``func`` not an :class:`Implicit`; ``resolution`` not whole numbers (this one is also an
        :class:`InputError`, as before); ``tol``, ``max_memory``, ``progress`` or
        ``on_uncertified`` of the wrong kind (strings are never parsed); ``tolerances`` not a
        :class:`~imagespace.tolerances.Tolerances`.
    InputError
        Empty box, a side that overflows or is too short for its grid points to differ in float,
        resolution below 8, or above the memory limit; ``max_memory`` not a positive finite
        number; ``tol`` outside ``(0, 0.01)``; an unknown ``on_uncertified``; ``func`` zero at
        every grid point (its zero set is not a surface).

    Warns
    -----
    UserWarning
        ``func`` touches 0 on the grid without changing sign anywhere (a zero only on the box's
        boundary, a component of even multiplicity), or is not finite anywhere on the grid: the
        mesh is empty and ``metadata["imagespace"]["note"]`` says why. A box the surface simply
        misses gives an empty mesh without a warning.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.singular.meshing import PolynomialImplicit, mesh_implicit
    >>> u, v, w = sp.symbols("u v w")
    >>> mesh = mesh_implicit(PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w)), [(-1.5, 1.5)] * 3, 48)
    >>> bool(abs(mesh.area - 4 * 3.141592653589793) < 0.04 * 4 * 3.141592653589793)
    True
    >>> md = mesh.metadata["imagespace"]
    >>> md["max_distance"] <= 1e-9 * 3, md["uncertified"], md["removed"]
    (True, 0, 0)

    A tolerance finer than the spacing of floats near the vertices cannot be certified: those
    vertices are removed and counted (or kept and counted, ``on_uncertified="keep"``):

    >>> sphere = PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w))
    >>> md = mesh_implicit(sphere, [(-1.5, 1.5)] * 3, 12, tol=1e-18).metadata["imagespace"]
    >>> md["removed"] > 0, md["uncertified"]
    (True, 0)
    """
    import trimesh
    from skimage.measure import marching_cubes

    if not isinstance(func, Implicit):
        raise TypeError(f"func must be an imagespace.singular.meshing.Implicit, got {type(func).__name__}")
    if not isinstance(on_uncertified, str):
        raise TypeError(f"on_uncertified must be 'remove' or 'keep', got {type(on_uncertified).__name__} "
                        f"{_short(on_uncertified)}")
    if on_uncertified not in ("remove", "keep"):
        raise InputError(f"on_uncertified must be 'remove' or 'keep', got {on_uncertified!r}")
    tols = as_tolerances(tolerances)
    b = as_box(box, "box")
    res = _check_resolution(resolution, max_memory)
    if isinstance(tol, (bool, np.bool_)) or not isinstance(tol, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"tol must be a number in (0, 0.01), got {type(tol).__name__} {_short(tol)}")
    try:
        tol = float(tol)
    except OverflowError:
        tol = math.inf
    if not 0 < tol < 1e-2:
        raise InputError(f"tol must be in (0, 0.01), got {tol}")
    if progress is not None:
        as_flag(progress, "progress")
    size = float(np.max(b[:, 1] - b[:, 0]))
    axes = [np.linspace(b[i, 0], b[i, 1], res[i]) for i in range(3)]
    h = (b[:, 1] - b[:, 0]) / (np.array(res) - 1)
    ulp = np.spacing(np.max(np.abs(b), axis=1))
    if np.any(h < 1e-150) or np.any(h < 16 * ulp):
        i = int(np.argmin(h / np.maximum(16 * ulp, 1e-150)))
        raise InputError(f"box side {i} ({b[i].tolist()}) is too short for {res[i]} grid points: cells of "
                         f"{h[i]:.3g} are below {max(16 * ulp[i], 1e-150):.3g} (16 float spacings at "
                         "that position, or 1e-150: the mesher squares cell sizes); enlarge the box, "
                         "shift it nearer the origin, or lower the resolution")
    times = {}
    bar = _Progress(progress, total=16 + 3)
    t0 = time.perf_counter()
    G = func.grid(axes, block=lambda k, n: bar.step(16 / n))
    times["grid"] = time.perf_counter() - t0
    g_min, g_max = float(G.min()), float(G.max())         # NaN or inf among them unless all finite
    all_finite = bool(np.isfinite(g_min) and np.isfinite(g_max))
    finite = np.isfinite(G) if not all_finite else None
    meta = {"resolution": list(res), "box": b.tolist(), "tol": tol, "size": size,
            "sign_test": func.sign_test}
    def empty_mesh(note):
        bar.close()
        meta.update(max_distance=0.0, max_residual=0.0, uncertified=0, removed=0, removed_faces=0,
                    searched=0, arb_evaluations=0, arb_budget_exhausted=False, times=times, note=note)
        mesh = trimesh.Trimesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64),
                               metadata={"imagespace": meta}, process=False)
        mesh.vertex_attributes["distance_bound"] = np.zeros(0)
        return mesh

    if not all_finite and not finite.any():
        warnings.warn("mesh_implicit: func is NaN or infinite at every grid point of the box; the mesh "
                      "is empty", UserWarning, stacklevel=2)
        return empty_mesh("the function is not finite anywhere on the grid")
    if not all_finite:
        g_min, g_max = np.nanmin(G), np.nanmax(G)
    if g_min > 0 or g_max < 0:
        return empty_mesh("the surface does not meet the box")
    if (g_min == g_max == 0) if all_finite else not np.any(G[finite] != 0):
        bar.close()
        raise InputError("func is 0 at every grid point of the box: its zero set is not a surface there "
                         "(e.g. a function that vanishes identically, or a singularity surface of an "
                         "architecture-singular design); nothing to mesh")
    t0 = time.perf_counter()
    kw = {}
    G_values = G                    # float64, NaN where not finite: the projection's starting guesses
    if not all_finite:
        kw["mask"] = _cube_mask(finite)
        G = np.where(finite, G, 0.0)
    verts, faces = _marching_cubes(marching_cubes, G, kw)
    if verts is None:
        warnings.warn("mesh_implicit: func touches 0 on the grid but changes sign nowhere in the box "
                      "(a zero only on the box's boundary, or a surface of even multiplicity); "
                      "the mesh is empty", UserWarning, stacklevel=2)
        return empty_mesh("the function touches 0 but does not change sign in the box")
    times["marching_cubes"] = time.perf_counter() - t0
    bar.step()
    t0 = time.perf_counter()
    budget = ArbBudget()
    V, bound, resid, searched = _project(func, verts, b[:, 0], h, tol * size, budget, tols.mesh_on_grid, G_values)
    times["projection"] = time.perf_counter() - t0
    bar.step()
    t0 = time.perf_counter()
    V, faces, bound, removed, removed_faces = _clean(V, faces, bound, b[:, 0], h,
                                                     tols.mesh_min_altitude * tol * size,
                                                     remove=on_uncertified == "remove",
                                                     node_merge=tols.mesh_node_merge)
    mesh = trimesh.Trimesh(V, faces, process=False)
    mesh.vertex_attributes["distance_bound"] = bound
    agree = _orient(func, mesh)
    times["clean"] = time.perf_counter() - t0
    bar.step()
    bar.close()
    fin = np.isfinite(bound)
    meta.update(max_distance=float(bound[fin].max()) if fin.any() else 0.0, max_residual=float(resid),
                uncertified=int((~fin).sum()), removed=removed, removed_faces=removed_faces,
                searched=searched, arb_evaluations=budget.used, arb_budget_exhausted=budget.refused,
                normals_agree=float(agree), times=times,
                projection="safeguarded Newton along marching-cubes edges, then a neighbourhood search; "
                           "sign change between points of proven sign")
    mesh.metadata["imagespace"] = meta
    return mesh


def _marching_cubes(marching_cubes, G, kw):
    """scikit-image's marching cubes on the grid values ``G``, or ``(None, None)`` where it finds
    no surface. It works in float32: a grid whose values leave float32's range (above 1e38, or
    non-zero below 1e-38) is first scaled by its largest value, and what would still underflow
    is kept at +-1e-30 so that no sign is lost; only the starting points of the projection depend
    on these values, the certified vertices do not."""
    # the float32 copy marching cubes would make anyway; the range checks run on it (cheap), and a
    # non-zero value below 1e-30 shows as more small entries than exact zeros of G
    with np.errstate(over="ignore"):
        G32 = G.astype(np.float32)
    amax = max(float(G32.max()), -float(G32.min()))
    if amax > 1e30 or np.count_nonzero(np.abs(G32) < 1e-30) > G.size - np.count_nonzero(G):
        amax = float(np.max(np.abs(G)))
        G = G / amax
        tiny = (G != 0) & (np.abs(G) < 1e-30)
        if tiny.any():
            G = np.where(tiny, np.sign(G) * 1e-30, G)
        G32 = G.astype(np.float32)
    G = G32
    try:
        verts, faces, _, _ = marching_cubes(G, level=0.0, allow_degenerate=False, **kw)
    except RuntimeError as exc:
        if "No surface found" in str(exc):
            return None, None
        raise
    return verts, faces


def _clean(V, faces, bound, origin, h, height, remove, node_merge):
    """Merge vertices that landed on the same grid node (the best-certified one stays), drop faces
    that became degenerate (repeated vertex or altitude below ``height``), then the faces of
    uncertified vertices if ``remove``, and vertices no face uses.

    Returns ``(V, faces, bound, removed, removed_faces)``."""
    idx = (V - origin) / h
    node = np.flatnonzero(np.all(np.abs(idx - np.round(idx)) < node_merge, axis=1))
    remap = np.arange(len(V))
    if node.size:
        node = node[np.argsort(bound[node], kind="stable")]       # the smallest bound represents its node
        keys = np.round(idx[node]).astype(np.int64)
        _, first, inv = np.unique(keys, axis=0, return_index=True, return_inverse=True)
        remap[node] = node[first][inv.ravel()]
    F = remap[faces]
    keep = (F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2])
    F = F[keep]
    e1 = V[F[:, 1]] - V[F[:, 0]]
    e2 = V[F[:, 2]] - V[F[:, 0]]
    cross = np.cross(e1, e2)
    # twice the area over the longest possible edge (a cell diagonal): a bound on the altitude
    F = F[np.sqrt(np.einsum("ij,ij->i", cross, cross)) > height * 2 * float(np.linalg.norm(h))]
    removed = removed_faces = 0
    if remove:                    # only what a certificate would have kept counts as removed
        bad = ~np.isfinite(bound)
        drop = bad[F].any(axis=1)
        removed = int(np.unique(F[drop][bad[F[drop]]]).size)
        removed_faces = int(drop.sum())
        F = F[~drop]
    used = np.zeros(len(V), dtype=bool)
    used[F] = True
    new_index = np.cumsum(used) - 1
    return V[used], new_index[F], bound[used], removed, removed_faces


def _cube_mask(finite):
    """Marching cubes only where all 8 corners of a cube are finite (mask on grid points)."""
    m = finite.copy()
    m[:-1] &= finite[1:]
    m[:, :-1] &= m[:, 1:]
    m[:, :, :-1] &= m[:, :, 1:]
    return m


def _project(func, verts, origin, h, tol_abs, budget, on_grid, grid):
    """Move marching-cubes vertices onto the surface and certify each.

    Returns ``(V, bound, resid, searched)``: the vertices ``(n, 3)``, the certified distance bound
    per vertex (``inf`` where no proven sign change within ``tol_abs`` was found; the vertex is
    then left at its marching-cubes place), the largest ``|F|/|grad F|``, and how many vertices
    needed the neighbourhood search.
    """
    n = len(verts)
    frac = np.abs(verts - np.round(verts))
    # a vertex on a grid node (marching cubes interpolated next to a tiny value) starts at the node
    P0 = origin + np.where((frac <= on_grid).all(axis=1)[:, None], np.round(verts), verts) * h
    V = P0.copy()
    bound = np.full(n, np.inf)
    if n == 0:
        return V, bound, 0.0, 0
    on_edge = (frac > on_grid).sum(axis=1) == 1          # between grid planes along exactly one axis
    axis = np.argmax(frac, axis=1)
    k = np.flatnonzero(on_edge)
    if k.size:
        # edges along a variable F is a polynomial in: its restriction, fitted per edge
        Ve, be = _project_edges_polynomial(func, verts[k], axis[k], origin, h, tol_abs, grid)
        V[k], bound[k] = Ve, be
        k = k[~(be <= tol_abs)]
    if k.size:
        Ve, be = _project_edges(func, verts[k], axis[k], origin, h, tol_abs, budget)
        V[k], bound[k] = Ve, be
    first = np.where(on_edge, axis, -1)
    rest = np.flatnonzero(~(bound <= tol_abs))
    if rest.size:
        Vs, bs = _search(func, P0[rest], first[rest], h, tol_abs, budget)
        V[rest], bound[rest] = Vs, bs
    f, g = func.value_and_gradient(V)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.abs(f) / _norm3(g)
    r = np.where((f == 0) | ~np.isfinite(bound), 0.0, r)
    resid = float(np.nanmax(r)) if np.any(np.isfinite(r)) else 0.0
    return V, bound, resid, int(rest.size)


def _edge_frames(verts, axis, origin, h):
    """Per marching-cubes vertex: the lower grid node ``a`` of its edge, the edge vector ``e`` and
    the vertex's edge parameter ``s`` in ``[0, 1]``."""
    n = len(verts)
    rows = np.arange(n)
    lo_idx = np.round(verts).astype(float)
    lo_idx[rows, axis] = np.floor(verts[rows, axis])
    a = origin + lo_idx * h
    e = np.zeros((n, 3))
    e[rows, axis] = h[axis]
    s = verts[rows, axis] - lo_idx[rows, axis]
    return a, e, s


def _project_edges_polynomial(func, verts, axis, origin, h, tol_abs, G):
    """Vertices on edges along a variable in which ``func`` is a polynomial of degree ``d``
    (:meth:`Implicit.degree_in`): its restriction to the grid line through the edge is the
    interpolant of ``d + 1`` consecutive grid values ``G`` on that line (the edge's two nodes among
    them), its root in the edge located by safeguarded Newton on that interpolant, and the vertex
    certified exactly as in :func:`_project_edges`, by proven opposite signs of ``func`` itself at
    two points about ``tol_abs / 2`` on either side. The interpolant only proposes where to look.
    Returns ``(V, bound)`` with ``bound = inf`` where this found no certificate (those go through
    :func:`_project_edges`)."""
    n = len(verts)
    G = np.ascontiguousarray(G, dtype=float)            # flat indices below assume C order
    a, e, s0 = _edge_frames(verts, axis, origin, h)
    node = np.round((a - origin) / h).astype(np.int64)
    V = a + np.clip(s0, 0.0, 1.0)[:, None] * e
    bound = np.full(n, np.inf)
    for k in range(3):
        d = func.degree_in(k)
        rows = np.flatnonzero(axis == k)
        N = G.shape[k]
        if d is None or d < 1 or d > _FIT_MAX_DEGREE or d + 1 > N or rows.size == 0:
            continue
        i = node[rows, k]
        start = np.clip(i - (d - 1) // 2, 0, N - 1 - d)
        off = start - i                                    # the window's first node, relative to the edge's
        stride = G.strides[k] // G.itemsize
        flat = np.ravel_multi_index(tuple(node[rows].T), G.shape) + off * stride
        Gf = G.reshape(-1)
        F = np.stack([Gf[flat + j * stride] for j in range(d + 1)], axis=-1)
        f0 = F[np.arange(rows.size), -off]
        f1 = F[np.arange(rows.size), 1 - off]
        ok = np.isfinite(F).all(axis=1) & (f0 != 0) & (f1 != 0) & (np.sign(f0) != np.sign(f1))
        rows, F, off, f0 = rows[ok], F[ok], off[ok], f0[ok]
        if rows.size == 0:
            continue
        C = np.empty_like(F)                               # power basis in the edge parameter
        for o in np.unique(off):
            sel = off == o
            # by einsum, not a BLAS product (its threads keep spinning after small products)
            C[sel] = np.einsum("ij,kj->ik", F[sel], np.linalg.inv(np.vander(o + np.arange(d + 1.0), increasing=True)))
        ak, ek = a[rows], e[rows]
        sg_lo = np.sign(f0)
        delta = tol_abs / h[k]
        s = np.clip(s0[rows], 0.0, 1.0)
        lo, hi = np.zeros(rows.size), np.ones(rows.size)
        act = np.arange(rows.size)
        full = True                                        # whole arrays while most rows still move
        for _ in range(_NEWTON_STEPS):
            if act.size == 0:
                break
            if full and 4 * act.size < rows.size:
                full = False
            if full:
                act = np.arange(rows.size)
            sa, Ca = s[act], C[act]
            p = Ca[:, d].copy()
            dp = np.zeros(act.size)
            for j in range(d - 1, -1, -1):                # Horner for the value and the derivative
                dp = dp * sa + p
                p = p * sa + Ca[:, j]
            same = np.sign(p) == sg_lo[act]
            lo[act] = np.where(same, sa, lo[act])
            hi[act] = np.where(~same & (p != 0), sa, hi[act])
            with np.errstate(divide="ignore", invalid="ignore"):
                sn = sa - p / dp
            inside = np.isfinite(sn) & (sn > lo[act]) & (sn < hi[act])
            sn = np.where(p == 0, sa, np.where(inside, sn, 0.5 * (lo[act] + hi[act])))
            s[act] = sn
            act = act[~((np.abs(sn - sa) < _NEWTON_SMALL * delta) | (p == 0) | (hi[act] - lo[act] <= delta))]
        pl = np.maximum(s - 0.5 * delta, 0.0)
        ph = np.minimum(s + 0.5 * delta, 1.0)
        Pl, Ph = ak + pl[:, None] * ek, ak + ph[:, None] * ek
        f, b, _ = func.value_bound(np.concatenate([Pl, Ph]))
        m = rows.size
        fl, fh, bl, bh = f[:m], f[m:], b[:m], b[m:]
        proven = (np.abs(fl) > bl) & (np.abs(fh) > bh) & (np.sign(fl) * np.sign(fh) < 0)
        Vk = ak + (0.5 * (pl + ph))[:, None] * ek
        # the three points differ in coordinate k only (the others are ak's, exactly): the
        # distances are the differences there
        bk = np.maximum(np.abs(Vk[:, k] - Pl[:, k]), np.abs(Vk[:, k] - Ph[:, k])) * (1 + 8 * UNIT_ROUNDOFF)
        good = proven & (bk <= tol_abs)
        V[rows[good]], bound[rows[good]] = Vk[good], bk[good]
    return V, bound


def _project_edges(func, verts, axis, origin, h, tol_abs, budget):
    """Safeguarded Newton along the marching-cubes edge of each vertex, certified by two points
    about ``tol_abs / 2`` on either side whose signs are proven (:meth:`Implicit.proven_sign`).
    Returns ``(V, bound)``."""
    n = len(verts)
    a, e, s = _edge_frames(verts, axis, origin, h)
    delta = tol_abs / h[axis]                    # wanted bracket width in the edge parameter

    lo, hi = np.zeros(n), np.ones(n)
    pair = np.full((n, 2), np.nan)               # edge parameters of a pair with proven opposite signs
    f_lo = func.value(a)
    f_hi = func.value(a + e)
    sg_lo = np.sign(f_lo)
    done = (f_lo == 0) | (f_hi == 0)
    s = np.where(f_lo == 0, 0.0, np.where(f_hi == 0, 1.0, s))
    lo[done] = hi[done] = s[done]
    bad = ~done & (np.sign(f_hi) == sg_lo)       # no float sign change along the edge
    done |= bad
    act = np.flatnonzero(~done)
    for _ in range(_NEWTON_STEPS):
        if act.size == 0:
            break
        P = a[act] + s[act, None] * e[act]
        f, g = func.value_and_gradient(P)
        df = np.einsum("ij,ij->i", g, e[act])
        zero = f == 0
        same = np.sign(f) == sg_lo[act]
        lo[act] = np.where(same & ~zero, s[act], lo[act])
        hi[act] = np.where(~same & ~zero, s[act], hi[act])
        with np.errstate(divide="ignore", invalid="ignore"):
            sn = s[act] - f / df
        inside = np.isfinite(sn) & (sn > lo[act]) & (sn < hi[act])
        sn = np.where(inside, sn, 0.5 * (lo[act] + hi[act]))
        small = inside & (np.abs(sn - s[act]) < _NEWTON_SMALL * delta[act])
        # a converged Newton step: test the points delta/2 on either side of it. Proven opposite
        # signs there certify the vertex at once; otherwise their float signs shrink the bracket.
        certified = np.zeros(act.size, dtype=bool)
        if small.any():
            k = act[small]
            pl = np.maximum(sn[small] - 0.5 * delta[k], 0.0)
            ph = np.minimum(sn[small] + 0.5 * delta[k], 1.0)
            fl, bl, _ = func.value_bound(a[k] + pl[:, None] * e[k])
            fh, bh, _ = func.value_bound(a[k] + ph[:, None] * e[k])
            ok = (np.abs(fl) > bl) & (np.abs(fh) > bh) & (np.sign(fl) * np.sign(fh) < 0)
            pair[k[ok]] = np.stack([pl[ok], ph[ok]], axis=-1)
            certified[small] = ok
            for p_, f_ in ((pl, fl), (ph, fh)):
                sm = np.sign(f_) == sg_lo[k]
                lo[k] = np.where(sm & (f_ != 0), np.maximum(lo[k], p_), lo[k])
                hi[k] = np.where(~sm & (f_ != 0), np.minimum(hi[k], p_), hi[k])
                hit = f_ == 0
                lo[k[hit]] = hi[k[hit]] = p_[hit]
        s[act] = np.where(zero, s[act], sn)
        lo[act[zero]] = hi[act[zero]] = s[act[zero]]
        fin = ((hi[act] - lo[act]) <= delta[act]) | certified
        act = act[~fin]
    proven = ~np.isnan(pair[:, 0])
    s = np.where(bad, s, np.where(proven, 0.5 * (pair[:, 0] + pair[:, 1]), 0.5 * (lo + hi)))
    V = a + s[:, None] * e
    # the certificate: proven signs at two float points about delta/2 on either side of the vertex
    # (inside the edge): the pair proven in the loop, else the points at s -+ delta/2. Not the float
    # bracket's own ends: Newton leaves one of them within rounding of the root, where no sign can
    # be proven.
    P_lo = a + np.where(proven, pair[:, 0], np.maximum(s - 0.5 * delta, 0.0))[:, None] * e
    P_hi = a + np.where(proven, pair[:, 1], np.minimum(s + 0.5 * delta, 1.0))[:, None] * e
    bound = np.full(n, np.inf)
    if proven.any():
        b = np.maximum(np.linalg.norm(V[proven] - P_lo[proven], axis=1),
                       np.linalg.norm(V[proven] - P_hi[proven], axis=1)) * (1 + 8 * UNIT_ROUNDOFF)
        bound[proven] = np.where(b <= tol_abs, b, np.inf)
    check = np.flatnonzero(~bad & ~(bound <= tol_abs))
    if check.size:
        sg, known = func.proven_sign(np.concatenate([P_lo[check], P_hi[check]]), budget)
        s1, s2 = sg[:check.size], sg[check.size:]
        k1, k2 = known[:check.size], known[check.size:]
        Vc = V[check]
        d1 = np.linalg.norm(Vc - P_lo[check], axis=1)
        d2 = np.linalg.norm(Vc - P_hi[check], axis=1)
        b = np.full(check.size, np.inf)
        crossing = k1 & k2 & (s1 * s2 < 0)
        b = np.where(crossing, np.maximum(d1, d2), b)
        b = np.where(k1 & (s1 == 0), np.minimum(b, d1), b)     # a proven zero at a bracket end
        b = np.where(k2 & (s2 == 0), np.minimum(b, d2), b)
        b = b * (1 + 8 * UNIT_ROUNDOFF)
        bound[check] = np.where(b <= tol_abs, b, np.inf)
    return V, bound


def _norm3(g):
    """Row norms of ``(n, 3)`` gradients without overflow in the squares (gradients of 1e200)."""
    return np.hypot(np.hypot(g[:, 0], g[:, 1]), g[:, 2])


def _directions(func, P0, first, h):
    """Candidate search directions per vertex, ``(8, m, 3)``: the vertex's own edge axis first
    (if any), the other grid axes, the gradient (scaled to the smallest cell side; NaN where it
    vanishes), the four cube diagonals."""
    m = len(P0)
    axes = np.where(first[:, None] >= 0, (first[:, None] + np.arange(3)[None, :]) % 3, np.arange(3)[None, :])
    D = np.full((8, m, 3), np.nan)
    for i in range(3):
        D[i] = 0.0
        D[i, np.arange(m), axes[:, i]] = h[axes[:, i]]
    _, g = func.value_and_gradient(P0)
    gn = _norm3(g)
    with np.errstate(divide="ignore", invalid="ignore"):
        D[3] = np.where((gn > 0)[:, None] & np.isfinite(g), g / gn[:, None] * h.min(), np.nan)
    for i, sgn in enumerate(((1, 1, 1), (1, 1, -1), (1, -1, 1), (-1, 1, 1))):
        D[4 + i] = np.asarray(sgn) * h
    return D


def _search(func, P0, first, h, tol_abs, budget):
    """Certify vertices whose own edge gave no proven bracket: a proven zero at the vertex, or the
    nearest proven sign change along the candidate directions (points at ``_SEARCH_STEPS`` cells on
    both sides), bisected on proven signs. Returns ``(V, bound)``; ``V = P0`` and ``bound = inf``
    where nothing was found."""
    m = len(P0)
    V, bound = P0.copy(), np.full(m, np.inf)
    s0, k0 = func.proven_sign(P0, budget)
    bound[k0 & (s0 == 0)] = 0.0
    D = _directions(func, P0, first, h)
    t = np.concatenate([-np.asarray(_SEARCH_STEPS)[::-1], [0.0], np.asarray(_SEARCH_STEPS)])
    i0 = len(_SEARCH_STEPS)
    # no two distinct floats near P0 are closer than this: a shorter bracket cannot exist there
    hopeless = tol_abs < 0.5 * np.spacing(np.abs(P0)).min(axis=1)
    for Dk in D:
        todo = np.flatnonzero(~(bound <= tol_abs) & ~hopeless & np.isfinite(Dk).all(axis=1))
        if todo.size == 0:
            continue
        pts = P0[todo, None, :] + t[None, :, None] * Dk[todo, None, :]
        pts[:, i0] = P0[todo]
        sg, kn = func.proven_sign(pts.reshape(-1, 3), budget)
        sg, kn = sg.reshape(len(todo), len(t)), kn.reshape(len(todo), len(t))
        lo_pt, hi_pt, s_lo, owner = [], [], [], []
        for r, j in enumerate(todo):
            best = None                                   # (radius, lo index, hi index or None)
            idx = np.flatnonzero(kn[r])
            for a_, b_ in zip(idx[:-1], idx[1:]):
                if sg[r, a_] * sg[r, b_] < 0:
                    rad = max(abs(t[a_]), abs(t[b_]))
                    if best is None or rad < best[0]:
                        best = (rad, a_, b_)
            for a_ in idx[sg[r, idx] == 0]:
                if best is None or abs(t[a_]) <= best[0]:
                    best = (abs(t[a_]), a_, None)
            if best is None:
                continue
            if best[2] is None:                           # a proven zero
                V[j], bound[j] = pts[r, best[1]], 0.0
                continue
            lo_pt.append(pts[r, best[1]])
            hi_pt.append(pts[r, best[2]])
            s_lo.append(sg[r, best[1]])
            owner.append(j)
        if owner:
            Vb, bb = _bisect(func, np.array(lo_pt), np.array(hi_pt), np.array(s_lo), tol_abs, budget)
            owner = np.array(owner)
            ok = bb <= tol_abs
            V[owner[ok]], bound[owner[ok]] = Vb[ok], bb[ok]
    return V, bound


def _bisect(func, lo, hi, s_lo, tol_abs, budget):
    """Bisect brackets ``[lo, hi]`` (points with proven signs ``s_lo`` and ``-s_lo``) on proven
    signs until shorter than ``tol_abs``; an undecided midpoint is replaced by the next point of
    ``_BISECT_TRIES``. Returns ``(V, bound)`` with ``bound = inf`` where the bisection got stuck."""
    k = len(lo)
    lo, hi = lo.copy(), hi.copy()
    zero_at = np.full((k, 3), np.nan)
    stuck = np.zeros(k, dtype=bool)
    for _ in range(_BISECT_STEPS):
        act = np.flatnonzero(~stuck & np.isnan(zero_at[:, 0]) & (np.linalg.norm(hi - lo, axis=1) > tol_abs))
        if act.size == 0:
            break
        pending = act
        for tr in _BISECT_TRIES:
            if pending.size == 0:
                break
            P = lo[pending] + tr * (hi[pending] - lo[pending])
            # a point that rounds onto an end of its bracket tells nothing: the bracket is as short
            # as the float spacing allows
            fresh = np.any(P != lo[pending], axis=1) & np.any(P != hi[pending], axis=1)
            stuck[pending[~fresh]] = True
            pending, P = pending[fresh], P[fresh]
            sg, kn = func.proven_sign(P, budget)
            z = kn & (sg == 0)
            zero_at[pending[z]] = P[z]
            same = kn & (sg == s_lo[pending])
            opp = kn & (sg == -s_lo[pending])
            lo[pending[same]] = P[same]
            hi[pending[opp]] = P[opp]
            pending = pending[~kn]
        stuck[pending] = True
    V = 0.5 * (lo + hi)
    bound = np.maximum(np.linalg.norm(V - lo, axis=1), np.linalg.norm(V - hi, axis=1)) * (1 + 8 * UNIT_ROUNDOFF)
    z = ~np.isnan(zero_at[:, 0])
    V[z], bound[z] = zero_at[z], 0.0
    bound[~z & (stuck | (bound > tol_abs))] = np.inf
    return V, bound


def _orient(func, mesh):
    """Flip all faces if most normals point to ``func < 0``; return the agreeing fraction.

    Marching cubes orients every face the same way relative to the sign of ``func``, so a
    sample of faces decides the direction for all of them."""
    if len(mesh.faces) == 0:
        return 1.0
    pick = np.random.default_rng(0).choice(len(mesh.faces), min(len(mesh.faces), _ORIENT_SAMPLE), replace=False)
    T = np.asarray(mesh.vertices)[np.asarray(mesh.faces)[pick]]          # only the sampled triangles
    n = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    length = np.linalg.norm(n, axis=1)
    n = n / np.where(length > 0, length, 1.0)[:, None]        # a degenerate face: a zero normal
    _, g = func.value_and_gradient(T.mean(axis=1))
    dots = np.einsum("ij,ij->i", n, g)
    ok = np.isfinite(dots)
    agree = float(np.mean(dots[ok] > 0)) if ok.any() else 1.0
    if agree < 0.5:
        mesh.invert()
        agree = 1.0 - agree
    return agree


def mesh_surface(surface, box=None, chart="image", resolution=128, tol=1e-9, progress=None,
                 max_memory=MAX_MEMORY, on_uncertified="remove"):
    """Mesh a singularity surface in the image chart or the pose chart.

    Parameters
    ----------
    surface : SingularitySurface
        From :meth:`PlanarParallel.singularity_surface`.
    box : (3, 2) float, optional
        In chart coordinates: ``chart="image"``: ranges of ``(x2/x0, x3/x0, x1/x0)``;
        ``chart="pose"``: ranges of ``(x, y, phi)``. Default
        :func:`~imagespace.singular.boxes.default_box` (scaled to the design; the command line's).
    chart : {"image", "pose"}
    resolution, tol, progress, max_memory, on_uncertified
        As in :func:`mesh_implicit`; the meshing thresholds are read from the surface's
        manipulator (``surface.manipulator.tolerances``).

    Returns
    -------
    trimesh.Trimesh
        Normals point to the aspect ``+1``; ``metadata["imagespace"]`` also records the chart
        and the surface's label.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.singular.meshing import mesh_surface
    >>> S = isp.examples.stigger_husty().singularity_surface()
    >>> mesh = mesh_surface(S, [(-12, 12), (-12, 12), (-3, 3)], resolution=32)
    >>> len(mesh.faces) > 1000, mesh.metadata["imagespace"]["chart"]
    (True, 'image')
    >>> mesh.metadata["imagespace"]["uncertified"], mesh.metadata["imagespace"]["removed"]
    (0, 0)
    >>> mesh_surface(S, resolution=16).metadata["imagespace"]["box"][2]     # the default box
    [-3.0, 3.0]
    """
    if box is None:
        from .boxes import default_box

        box = default_box(surface.manipulator, chart)
    func = surface_implicit(surface, chart)
    mesh = mesh_implicit(func, box, resolution=resolution, tol=tol, progress=progress,
                         max_memory=max_memory, on_uncertified=on_uncertified,
                         tolerances=surface.manipulator.tolerances)
    mesh.metadata["imagespace"].update(chart=chart, surface=repr(surface))
    return mesh


# -- export ---------------------------------------------------------------------------------------
def export_mesh(mesh, path):
    """Write a mesh atomically; the format is taken from the suffix (``.stl``, ``.ply``, ``.obj``, ``.glb``).

    Precision of the stored vertices (:data:`EXPORT_PRECISION`):

    * ``.ply`` - binary little endian with ``property double x/y/z``: the float64 vertices bit
      for bit (``trimesh.load`` reads them back exactly);
    * ``.obj`` - text with 17 significant digits: float64 bit for bit;
    * ``.stl``, ``.glb`` - **float32 by format**: every coordinate is rounded to 24 bits, an error
      of up to ``2**-24 ~ 6e-8`` of its magnitude - far more than a certified ``tol`` of ``1e-9``
      of the box. Use PLY or OBJ where the certificate matters.

    The file is written to a temporary file in the target's folder, flushed and synced, then
    renamed over the target (``os.replace``): a failure midway leaves an existing file unchanged.

    Parameters
    ----------
    mesh : trimesh.Trimesh
    path : str or Path

    Returns
    -------
    Path

    Raises
    ------
    TypeError
        ``mesh`` is not a :class:`trimesh.Trimesh`; ``path`` is not a ``str`` or path-like (bytes
        paths are refused).
    InputError
        Unknown suffix.
    IsADirectoryError, NotADirectoryError
        ``path`` is an existing folder, or lies under a file.

    Examples
    --------
    >>> import tempfile, pathlib, trimesh, numpy as np
    >>> from imagespace.singular.meshing import export_mesh
    >>> box = trimesh.creation.box()
    >>> box.vertices[0] += 1e-12
    >>> p = export_mesh(box, pathlib.Path(tempfile.mkdtemp()) / "box.ply")
    >>> back = trimesh.load(p, process=False)
    >>> len(back.faces), bool(np.array_equal(back.vertices, box.vertices))
    (12, True)
    """
    import trimesh

    if not isinstance(mesh, trimesh.Trimesh):
        raise TypeError(f"mesh must be a trimesh.Trimesh, got {type(mesh).__name__}")
    if not isinstance(path, (str, os.PathLike)) or isinstance(path, bytes):
        raise TypeError(f"path must be a str or pathlib.Path, got {type(path).__name__} {_short(path)}")
    path = Path(path)
    if isinstance(os.fspath(path), bytes):
        raise TypeError(f"path must be a str or pathlib.Path, got the bytes path {_short(path)}")
    suffix = path.suffix.lower()
    if suffix not in EXPORT_FORMATS:
        raise InputError(f"path must end in one of {', '.join(EXPORT_FORMATS)} (the format is taken "
                         f"from the suffix), got {str(path)!r}")
    if path.is_dir():
        raise IsADirectoryError(f"path {str(path)!r} is an existing folder, not a file")
    for parent in path.parents:
        if parent.exists():
            if not parent.is_dir():
                raise NotADirectoryError(f"path {str(path)!r} lies under {str(parent)!r}, which is a file")
            break
    V = np.ascontiguousarray(mesh.vertices, dtype=np.float64)
    F = np.ascontiguousarray(mesh.faces, dtype=np.int64)
    path.parent.mkdir(parents=True, exist_ok=True)
    if suffix == ".ply":
        atomic_write(path, lambda f: _write_ply(f, V, F))
    elif suffix == ".obj":
        atomic_write(path, lambda f: _write_obj(f, V, F))
    else:
        data = trimesh.Trimesh(V, F, process=False).export(file_type=suffix[1:])
        atomic_write(path, lambda f: f.write(data))
    return path


def _write_ply(f, V, F):
    """Binary little-endian PLY with float64 vertices and int32 triangle indices."""
    if len(V) > np.iinfo(np.int32).max:
        raise InputError(f"a PLY export holds at most {np.iinfo(np.int32).max} vertices, got {len(V)}")
    header = ("ply\nformat binary_little_endian 1.0\ncomment imagespace: vertices in float64\n"
              f"element vertex {len(V)}\nproperty double x\nproperty double y\nproperty double z\n"
              f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n")
    f.write(header.encode("ascii"))
    f.write(V.astype("<f8").tobytes())
    rec = np.empty(len(F), dtype=[("n", "u1"), ("v", "<i4", (3,))])
    rec["n"] = 3
    rec["v"] = F
    f.write(rec.tobytes())


def _write_obj(f, V, F):
    """Wavefront OBJ with 17 significant digits (float64 round trip) and 1-based faces."""
    f.write(b"# imagespace: vertices with 17 significant digits (float64)\n")
    if len(V):
        f.write(("\n".join("v %.17g %.17g %.17g" % tuple(r) for r in V.tolist()) + "\n").encode("ascii"))
    if len(F):
        f.write(("\n".join("f %d %d %d" % tuple(r) for r in (F + 1).tolist()) + "\n").encode("ascii"))


