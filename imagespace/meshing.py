"""Triangle meshes of implicit surfaces - above all the singularity surface - and their export.

Pipeline (:func:`mesh_implicit`): the function is evaluated on a regular grid of the box
(polynomials in two of the chart coordinates are evaluated as one matrix product over the
monomials, the fast path for the quartic); scikit-image's marching cubes places one vertex on
every grid edge where the sign changes; each vertex is then moved *along its edge* by a
safeguarded Newton iteration (bisection whenever a step leaves the bracket) until the sign change
is bracketed by an interval shorter than ``tol`` times the box size. Because the function has
opposite signs at the two ends of that interval, the surface passes through it: the distance
from the vertex to the surface is at most the half-width, a bound that does not rely on
``|F| / |grad F|`` (which is only a first-order estimate and fails near singular points of the
surface). Faces are then oriented so that normals point to the side where the function is
positive (for the singularity surface: towards the aspect ``+1``), degenerate faces removed, and
a :class:`trimesh.Trimesh` returned; ``mesh.metadata["imagespace"]`` records the chart, box,
resolution, the certified distance bound, the worst ``|F|/|grad F|`` and the timings.

Charts of image space (``chart=``):

* ``"image"`` - the affine chart ``(x2/x0, x3/x0, x1/x0)`` of seed 002 (Abb. 2, 4);
* ``"pose"`` - ``(x, y, phi)``; the quartic is even, so the function is ``2 pi`` periodic in
  ``phi`` and a box ``phi in [-pi, pi]`` gives a mesh whose two ends match.

Only this module (and :mod:`imagespace.plotting`) imports scikit-image and trimesh, lazily.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import sympy as sp

from ._validate import as_float_array
from .compile import compile_exprs
from .exceptions import InputError

__all__ = ["Implicit", "PolynomialImplicit", "FunctionImplicit", "mesh_implicit", "mesh_surface",
           "export_mesh", "surface_implicit", "EXPORT_FORMATS", "MAX_MEMORY"]

EXPORT_FORMATS = (".stl", ".ply", ".obj", ".glb")
MAX_MEMORY = 2 * 1024**3
"""Default limit (bytes) for the estimated memory of a mesh's grid and marching cubes."""
_BYTES_PER_CELL = 8 * 3           # float64 grid + the monomial block + marching-cubes work


# -- implicit functions ---------------------------------------------------------------------------
class Implicit:
    """A scalar function on 3-space that :func:`mesh_implicit` can mesh (its zero set).

    Subclasses implement :meth:`value_and_gradient` and may override :meth:`grid` with a faster
    evaluation on a tensor grid.
    """

    def value_and_gradient(self, P):
        """``(F (n,), grad F (n, 3))`` at points ``P`` ``(n, 3)``."""
        raise NotImplementedError

    def value(self, P):
        """``F`` at points ``P`` ``(n, 3)``."""
        return self.value_and_gradient(P)[0]

    def grid(self, axes, block=None):
        """``F`` on the tensor grid of three 1-d ``axes``: ``(len(u), len(v), len(w))`` float.

        ``block(k, n)`` is called after each of ``n`` slabs (progress reporting).
        """
        u, v, w = axes
        out = np.empty((len(u), len(v), len(w)))
        U, V = np.meshgrid(u, v, indexing="ij")
        for k, wk in enumerate(w):
            P = np.stack([U.ravel(), V.ravel(), np.full(U.size, wk)], axis=-1)
            out[:, :, k] = self.value(P).reshape(U.shape)
            if block:
                block(k, len(w))
        return out


class PolynomialImplicit(Implicit):
    """An implicit function given by a sympy expression, polynomial in its first two variables.

    Parameters
    ----------
    expr : sympy expression
        Polynomial in ``symbols[0], symbols[1]``; any expression in ``symbols[2]``.
    symbols : three sympy symbols

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.meshing import PolynomialImplicit
    >>> u, v, w = sp.symbols("u v w")
    >>> sphere = PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w))
    >>> sphere.grid(([0.0, 1.0], [0.0], [0.0, 2.0])).tolist()
    [[[-1.0, 3.0]], [[0.0, 4.0]]]
    """

    def __init__(self, expr, symbols):
        symbols = tuple(symbols)
        if len(symbols) != 3:
            raise InputError(f"symbols must be three sympy symbols, got {symbols!r}")
        expr = sp.sympify(expr)
        extra = expr.free_symbols - set(symbols)
        if extra:
            raise InputError(f"expr has symbols {sorted(map(str, extra))} besides {symbols}")
        self.expr, self.symbols = expr, symbols
        u, v, w = symbols
        self._vg = compile_exprs([expr] + [sp.diff(expr, s) for s in symbols], symbols)
        self._v = compile_exprs([expr], symbols)
        try:
            poly = sp.Poly(sp.expand(expr), u, v)
            self._monomials = poly.monoms()
            self._coeffs = compile_exprs(poly.coeffs(), [w])
        except sp.PolynomialError:
            self._monomials = None

    def value_and_gradient(self, P):
        P = np.atleast_2d(P)
        out = self._vg(P[:, 0], P[:, 1], P[:, 2])
        return out[:, 0], out[:, 1:]

    def value(self, P):
        P = np.atleast_2d(P)
        return self._v(P[:, 0], P[:, 1], P[:, 2])[:, 0]

    def grid(self, axes, block=None):
        if self._monomials is None:
            return super().grid(axes, block)
        u, v, w = (np.asarray(a, dtype=float) for a in axes)
        C = self._coeffs(w)                                   # (nw, M)
        M = np.stack([np.multiply.outer(u**a, v**b).ravel() for a, b in self._monomials], axis=-1)
        out = np.empty((len(u) * len(v), len(w)))
        n_blocks = max(1, min(len(w), 16))
        edges = np.linspace(0, len(w), n_blocks + 1).astype(int)
        for k in range(n_blocks):
            s = slice(edges[k], edges[k + 1])
            np.matmul(M, C[s].T, out=out[:, s])
            if block:
                block(k, n_blocks)
        return out.reshape(len(u), len(v), len(w))


class FunctionImplicit(Implicit):
    """An implicit function given by a Python callable ``f(P) -> (F (n,), grad (n, 3))``.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.meshing import FunctionImplicit
    >>> f = FunctionImplicit(lambda P: (P[:, 0] - 0.5, np.tile([1.0, 0, 0], (len(P), 1))))
    >>> f.value(np.array([[1.0, 0, 0]])).tolist()
    [0.5]
    """

    def __init__(self, value_and_gradient, value=None):
        self._vg = value_and_gradient
        self._value = value

    def value_and_gradient(self, P):
        return self._vg(np.atleast_2d(P))

    def value(self, P):
        P = np.atleast_2d(P)
        return self._value(P) if self._value is not None else self._vg(P)[0]


def surface_implicit(surface, chart="image"):
    """A singularity surface as an :class:`Implicit` in a chart.

    Parameters
    ----------
    surface : SingularitySurface
    chart : {"image", "pose"}
        ``"image"``: ``(x2/x0, x3/x0, x1/x0)``; ``"pose"``: ``(x, y, phi)``.

    Returns
    -------
    Implicit
        A :class:`PolynomialImplicit` for polynomial surfaces (fast grid), else a
        :class:`FunctionImplicit` through the leg inverse kinematics.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.meshing import surface_implicit
    >>> type(surface_implicit(isp.examples.stigger_husty().singularity_surface(), "pose")).__name__
    'PolynomialImplicit'
    """
    from .singularities import image_chart_point, pose_chart_point

    if chart not in ("image", "pose"):
        raise InputError(f"chart must be 'image' or 'pose', got {chart!r}")
    key = ("implicit", chart)
    if key in surface._cache:
        return surface._cache[key]
    to_X = image_chart_point if chart == "image" else pose_chart_point
    if surface.is_polynomial:
        expr, syms = surface.chart_expression(chart)
        surface._cache[key] = PolynomialImplicit(expr, syms)
        return surface._cache[key]

    def vg(P):
        X, dX = to_X(P)
        v, G = surface.value_and_gradient(X)
        return v, np.einsum("ni,nik->nk", G, dX)

    surface._cache[key] = FunctionImplicit(vg, lambda P: surface(to_X(P)[0]))
    return surface._cache[key]


# -- meshing ------------------------------------------------------------------------------------
def _check_box(box):
    b = as_float_array(box, "box", allow_batch=True)
    if b.shape != (3, 2):
        raise InputError(f"box must be ((u_min, u_max), (v_min, v_max), (w_min, w_max)), shape (3, 2); "
                         f"got shape {b.shape}")
    if np.any(b[:, 1] <= b[:, 0]):
        bad = [i for i in range(3) if b[i, 1] <= b[i, 0]]
        raise InputError(f"box is empty along axis {bad}: need min < max, got {b.tolist()}")
    return b


def _check_resolution(resolution, max_memory):
    r = np.atleast_1d(np.asarray(resolution))
    if r.dtype.kind not in "iu" or r.shape not in ((1,), (3,)):
        raise InputError(f"resolution must be an int or three ints (grid points per axis), got {resolution!r}")
    r = np.broadcast_to(r, (3,)).astype(np.int64)
    if np.any(r < 8):
        raise InputError(f"resolution must be at least 8 grid points per axis, got {resolution!r}")
    need = float(np.prod(r.astype(float))) * _BYTES_PER_CELL
    if need > max_memory:
        raise InputError(f"resolution {tuple(int(v) for v in r)} needs about {need / 1e9:.3g} GB for the grid "
                         f"and marching cubes, above the limit max_memory={max_memory / 1e9:.3g} GB; "
                         "lower the resolution or raise max_memory")
    return tuple(int(v) for v in r)


class _Progress:
    def __init__(self, enabled, total):
        self.bar = None
        if enabled is not False:
            from tqdm import tqdm

            self.bar = tqdm(total=total, delay=1.0, desc="meshing", leave=False)

    def step(self, n=1):
        if self.bar is not None:
            self.bar.update(n)

    def close(self):
        if self.bar is not None:
            self.bar.close()


def mesh_implicit(func, box, resolution=128, tol=1e-9, progress=None, max_memory=MAX_MEMORY):
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
        Every vertex ends within ``tol * size`` of the surface (certified by a sign change, see
        the module docstring), ``size`` the box's longest side.
    progress : bool or None
        Progress bar (tqdm); ``None``: shown only if meshing takes longer than a second.
    max_memory : float
        Bytes; a resolution whose estimated memory is above it is refused before allocating.

    Returns
    -------
    trimesh.Trimesh
        Normals point to where ``func > 0``. ``mesh.metadata["imagespace"]`` holds
        ``max_distance`` (the certified bound), ``max_residual`` (``max |F|/|grad F|``),
        ``uncertified`` (vertices where no sign change could be bracketed, expected 0), the
        box, resolution and timings.

    Raises
    ------
    InputError
        Empty box, resolution below 8, or above the memory limit.

    Examples
    --------
    >>> import sympy as sp
    >>> from imagespace.meshing import PolynomialImplicit, mesh_implicit
    >>> u, v, w = sp.symbols("u v w")
    >>> mesh = mesh_implicit(PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w)), [(-1.5, 1.5)] * 3, 48)
    >>> bool(abs(mesh.area - 4 * 3.141592653589793) < 0.04 * 4 * 3.141592653589793)
    True
    >>> mesh.metadata["imagespace"]["max_distance"] <= 1e-9 * 3
    True
    """
    import trimesh
    from skimage.measure import marching_cubes

    if not isinstance(func, Implicit):
        raise TypeError(f"func must be an imagespace.meshing.Implicit, got {type(func).__name__}")
    b = _check_box(box)
    res = _check_resolution(resolution, max_memory)
    tol = float(tol)
    if not 0 < tol < 1e-2:
        raise InputError(f"tol must be in (0, 0.01), got {tol}")
    size = float(np.max(b[:, 1] - b[:, 0]))
    axes = [np.linspace(b[i, 0], b[i, 1], res[i]) for i in range(3)]
    h = (b[:, 1] - b[:, 0]) / (np.array(res) - 1)
    times = {}
    bar = _Progress(progress, total=16 + 3)
    t0 = time.perf_counter()
    G = func.grid(axes, block=lambda k, n: bar.step(16 / n))
    times["grid"] = time.perf_counter() - t0
    finite = np.isfinite(G)
    meta = {"resolution": list(res), "box": b.tolist(), "tol": tol, "size": size}
    empty = not finite.any() or np.nanmin(G) > 0 or np.nanmax(G) < 0
    if empty:
        bar.close()
        meta.update(max_distance=0.0, max_residual=0.0, uncertified=0, times=times,
                    note="the surface does not meet the box")
        return trimesh.Trimesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64),
                               metadata={"imagespace": meta}, process=False)
    t0 = time.perf_counter()
    kw = {}
    if not finite.all():
        kw["mask"] = _cube_mask(finite)
        G = np.where(finite, G, 0.0)
    verts, faces, _, _ = marching_cubes(G, level=0.0, allow_degenerate=False, **kw)
    times["marching_cubes"] = time.perf_counter() - t0
    bar.step()
    t0 = time.perf_counter()
    V, dist, resid, uncert = _project(func, verts, b[:, 0], h, tol * size)
    times["projection"] = time.perf_counter() - t0
    bar.step()
    t0 = time.perf_counter()
    V, faces = _clean(V, faces, b[:, 0], h, 1e-3 * tol * size)
    mesh = trimesh.Trimesh(V, faces, process=False)
    agree = _orient(func, mesh)
    times["clean"] = time.perf_counter() - t0
    bar.step()
    bar.close()
    meta.update(max_distance=float(dist), max_residual=float(resid), uncertified=int(uncert),
                normals_agree=float(agree), times=times,
                projection="safeguarded Newton along marching-cubes edges, sign change bracketed")
    mesh.metadata["imagespace"] = meta
    return mesh


def _clean(V, faces, origin, h, height):
    """Merge vertices that landed on the same grid node, drop faces that became degenerate
    (repeated vertex or altitude below ``height``) and vertices no face uses."""
    idx = (V - origin) / h
    node = np.all(np.abs(idx - np.round(idx)) < 1e-9, axis=1)
    remap = np.arange(len(V))
    if node.any():
        keys = np.round(idx[node]).astype(np.int64)
        _, first, inv = np.unique(keys, axis=0, return_index=True, return_inverse=True)
        remap[np.flatnonzero(node)] = np.flatnonzero(node)[first][inv.ravel()]
    F = remap[faces]
    keep = (F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2])
    F = F[keep]
    e1 = V[F[:, 1]] - V[F[:, 0]]
    e2 = V[F[:, 2]] - V[F[:, 0]]
    cross = np.cross(e1, e2)
    # twice the area over the longest possible edge (a cell diagonal): a bound on the altitude
    F = F[np.sqrt(np.einsum("ij,ij->i", cross, cross)) > height * 2 * float(np.linalg.norm(h))]
    used = np.zeros(len(V), dtype=bool)
    used[F] = True
    new_index = np.cumsum(used) - 1
    return V[used], new_index[F]


def _cube_mask(finite):
    """Marching cubes only where all 8 corners of a cube are finite (mask on grid points)."""
    m = finite.copy()
    m[:-1] &= finite[1:]
    m[:, :-1] &= m[:, 1:]
    m[:, :, :-1] &= m[:, :, 1:]
    return m


def _project(func, verts, origin, h, tol_abs):
    """Move marching-cubes vertices along their grid edges onto the surface.

    Returns the vertices, the largest certified distance bound, the largest ``|F|/|grad F|`` and
    the number of vertices whose edge showed no sign change (left at their interpolated place).
    """
    n = len(verts)
    frac = np.abs(verts - np.round(verts))
    axis = np.argmax(frac, axis=1)
    on_node = frac[np.arange(n), axis] < 1e-12
    lo_idx = np.round(verts).astype(float)
    lo_idx[np.arange(n), axis] = np.floor(verts[np.arange(n), axis])
    a = origin + lo_idx * h
    e = np.zeros((n, 3))
    e[np.arange(n), axis] = h[axis]
    s = verts[np.arange(n), axis] - lo_idx[np.arange(n), axis]
    s = np.where(on_node, np.round(s), s)
    delta = tol_abs / h[axis]                    # wanted bracket width in the edge parameter

    lo, hi = np.zeros(n), np.ones(n)
    f_lo = func.value(a)
    f_hi = func.value(a + e)
    sg_lo = np.sign(f_lo)
    width = np.ones(n)
    done = (f_lo == 0) | (f_hi == 0)
    s = np.where(f_lo == 0, 0.0, np.where(f_hi == 0, 1.0, s))
    width[done] = 0.0
    bad = ~done & (np.sign(f_hi) == sg_lo)       # no sign change along the edge (rounding)
    done |= bad
    act = np.flatnonzero(~done)
    for _ in range(200):
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
        small = inside & (np.abs(sn - s[act]) < 0.25 * delta[act])
        # a converged Newton step: test a bracket of width delta around it
        if small.any():
            k = act[small]
            pl = np.maximum(sn[small] - 0.5 * delta[k], lo[k])
            ph = np.minimum(sn[small] + 0.5 * delta[k], hi[k])
            fl = func.value(a[k] + pl[:, None] * e[k])
            fh = func.value(a[k] + ph[:, None] * e[k])
            for p_, f_ in ((pl, fl), (ph, fh)):
                sm = np.sign(f_) == sg_lo[k]
                lo[k] = np.where(sm & (f_ != 0), np.maximum(lo[k], p_), lo[k])
                hi[k] = np.where(~sm & (f_ != 0), np.minimum(hi[k], p_), hi[k])
                hit = f_ == 0
                lo[k[hit]] = hi[k[hit]] = p_[hit]
        s[act] = np.where(zero, s[act], sn)
        lo[act[zero]] = hi[act[zero]] = s[act[zero]]
        fin = (hi[act] - lo[act]) <= delta[act]
        s[act[fin]] = 0.5 * (lo[act[fin]] + hi[act[fin]])
        width[act[fin]] = hi[act[fin]] - lo[act[fin]]
        act = act[~fin]
    if act.size:                                  # not expected: report, keep the midpoint
        s[act] = 0.5 * (lo[act] + hi[act])
        width[act] = hi[act] - lo[act]
    V = a + s[:, None] * e
    dist = np.max(np.where(bad, 0.0, 0.5 * width * h[axis])) if n else 0.0
    f, g = func.value_and_gradient(V)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.abs(f) / np.linalg.norm(g, axis=1)
    resid = float(np.nanmax(np.where(f == 0, 0.0, r))) if n else 0.0
    return V, dist, resid, int(bad.sum() + act.size)


def _orient(func, mesh):
    """Flip all faces if most normals point to ``func < 0``; return the agreeing fraction.

    Marching cubes orients every face the same way relative to the sign of ``func``, so a
    sample of faces decides the direction for all of them."""
    if len(mesh.faces) == 0:
        return 1.0
    pick = np.random.default_rng(0).choice(len(mesh.faces), min(len(mesh.faces), 4096), replace=False)
    _, g = func.value_and_gradient(mesh.triangles_center[pick])
    dots = np.einsum("ij,ij->i", mesh.face_normals[pick], g)
    ok = np.isfinite(dots)
    agree = float(np.mean(dots[ok] > 0)) if ok.any() else 1.0
    if agree < 0.5:
        mesh.invert()
        agree = 1.0 - agree
    return agree


def mesh_surface(surface, box, chart="image", resolution=128, tol=1e-9, progress=None,
                 max_memory=MAX_MEMORY):
    """Mesh a singularity surface in the image chart or the pose chart.

    Parameters
    ----------
    surface : SingularitySurface
        From :meth:`PlanarParallel.singularity_surface`.
    box : (3, 2) float
        In chart coordinates: ``chart="image"``: ranges of ``(x2/x0, x3/x0, x1/x0)``;
        ``chart="pose"``: ranges of ``(x, y, phi)``.
    chart : {"image", "pose"}
    resolution, tol, progress, max_memory
        As in :func:`mesh_implicit`.

    Returns
    -------
    trimesh.Trimesh
        Normals point to the aspect ``+1``; ``metadata["imagespace"]`` also records the chart
        and the surface's label.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.meshing import mesh_surface
    >>> S = isp.examples.stigger_husty().singularity_surface()
    >>> mesh = mesh_surface(S, [(-12, 12), (-12, 12), (-3, 3)], resolution=32)
    >>> len(mesh.faces) > 1000, mesh.metadata["imagespace"]["chart"]
    (True, 'image')
    """
    func = surface_implicit(surface, chart)
    mesh = mesh_implicit(func, box, resolution=resolution, tol=tol, progress=progress,
                         max_memory=max_memory)
    mesh.metadata["imagespace"].update(chart=chart, surface=repr(surface))
    return mesh


def export_mesh(mesh, path):
    """Write a mesh; the format is taken from the suffix (``.stl``, ``.ply``, ``.obj``, ``.glb``).

    Parameters
    ----------
    mesh : trimesh.Trimesh
    path : str or Path

    Returns
    -------
    Path

    Examples
    --------
    >>> import tempfile, pathlib, trimesh
    >>> from imagespace.meshing import export_mesh
    >>> p = export_mesh(trimesh.creation.box(), pathlib.Path(tempfile.mkdtemp()) / "box.ply")
    >>> len(trimesh.load(p).faces)
    12
    """
    import trimesh

    if not isinstance(mesh, trimesh.Trimesh):
        raise TypeError(f"mesh must be a trimesh.Trimesh, got {type(mesh).__name__}")
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in EXPORT_FORMATS:
        raise InputError(f"path must end in one of {', '.join(EXPORT_FORMATS)} (the format is taken "
                         f"from the suffix), got {str(path)!r}")
    path.parent.mkdir(parents=True, exist_ok=True)
    clean = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    clean.export(path, file_type=suffix[1:])
    return path
