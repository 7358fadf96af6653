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
import time
import warnings

import numpy as np

from .._validate import _short, as_box, as_count, as_flag, as_tolerances
from ..exceptions import InputError, InputTypeError
from .implicit import TRIG_ULPS, FunctionImplicit, Implicit, PolynomialImplicit, surface_implicit
# the vertex step and the export live in singular.mesh_vertices and singular.mesh_export (issue
# [15]); their public names stay importable here
from .mesh_export import EXPORT_FORMATS, EXPORT_PRECISION, export_mesh
from .mesh_vertices import certify_vertices
from .proven_sign import ArbBudget

__all__ = ["Implicit", "PolynomialImplicit", "FunctionImplicit", "mesh_implicit", "mesh_surface",
           "export_mesh", "surface_implicit", "EXPORT_FORMATS", "EXPORT_PRECISION", "MAX_MEMORY",
           "TRIG_ULPS"]

MAX_MEMORY = 2 * 1024**3
"""Default limit (bytes) for the estimated memory of a mesh's grid and marching cubes."""
_BYTES_PER_CELL = 8 * 3           # float64 grid + the monomial block + marching-cubes work

# numerical knobs of the meshing pipeline (index units are grid cells; those of the vertex step are
# in singular.mesh_vertices); its decision thresholds are Tolerances.mesh_on_grid, mesh_node_merge
# and mesh_min_altitude
_ORIENT_SAMPLE = 4096             # faces sampled to decide the orientation


# -- meshing ------------------------------------------------------------------------------------
def _check_max_memory(max_memory):
    if isinstance(max_memory, (bool, np.bool_)) or not isinstance(max_memory, (numbers.Real, np.floating, np.integer)):
        raise InputTypeError(f"max_memory must be a positive number of bytes, got {type(max_memory).__name__} "
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
        raise InputTypeError(f"func must be an imagespace.singular.meshing.Implicit, got {type(func).__name__}")
    if not isinstance(on_uncertified, str):
        raise InputTypeError(f"on_uncertified must be 'remove' or 'keep', got {type(on_uncertified).__name__} "
                             f"{_short(on_uncertified)}")
    if on_uncertified not in ("remove", "keep"):
        raise InputError(f"on_uncertified must be 'remove' or 'keep', got {on_uncertified!r}")
    tols = as_tolerances(tolerances)
    b = as_box(box, "box")
    res = _check_resolution(resolution, max_memory)
    if isinstance(tol, (bool, np.bool_)) or not isinstance(tol, (numbers.Real, np.floating, np.integer)):
        raise InputTypeError(f"tol must be a number in (0, 0.01), got {type(tol).__name__} {_short(tol)}")
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
    V, bound, resid, searched = certify_vertices(func, verts, b[:, 0], h, tol * size, budget, tols.mesh_on_grid, G_values)
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
