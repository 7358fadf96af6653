"""The joint-space atlas of a planar parallel manipulator: regions by certified number of modes.

In joint space ``q = (q1, q2, q3)`` the number of real assembly modes is constant off the
direct-kinematic singularity surface (the image of the image-space singularity surface under the
legs' inverse kinematics, every working mode included) and changes by two across it. The atlas of
a joint box is built from **certified counts only**:

1. the counts at the nodes of a regular grid of the box, each proven
   (:meth:`PlanarParallel.certified_root_counts`: kernel-proven or exact per row; a node nothing
   could certify is marked ``-1`` and left out);
2. the **regions**: connected sets of grid nodes (26-neighbourhood: a thin slab sampled along a
   diagonal stays one region) of equal count; every label is
   the certified count at each of its nodes, the region's ``sample`` is its deepest node; volume
   fractions are node fractions (estimates at the grid's resolution, exact labels);
3. the **surface**: scikit-image's marching cubes on the count volume, one level between each
   pair of consecutive counts present (``2|4`` gives one sheet, a jump ``2|6`` across one cell
   two). Every vertex lies on a grid edge whose ends have certified counts on either side of its
   level; it is moved along that edge by bisection on certified counts until the bracket is
   :data:`BISECTION_STEPS` halvings short. Each vertex so carries its **evidence**: two points at
   most ``evidence_width`` apart, on either side of it, with proven counts that differ. A vertex
   whose bracket stays wider than ``Tolerances.atlas_evidence_width`` grid cells (a bisection
   point nothing could certify) is removed with its faces and counted (``removed``), as
   :func:`imagespace.singular.meshing.mesh_implicit` does;
4. the **cusp curves** (three modes merge): traced by pseudo-arclength continuation of
   ``f = f' = f'' = 0`` in ``(theta, q)`` (:func:`imagespace.atlas.curves.cusp_curves`),
   seeded from the cusps of a few sections (:func:`imagespace.singular.cusps.cusps`). Floating
   point: the curves are drawn, not proven; :func:`imagespace.atlas.is_cuspidal` proves a cusp.

What is certified: every region label and every kept vertex's bracket. What is not: the
resolution. Features thinner than a grid cell (a sliver of a region near a cusp edge, two sheets
closer than a cell) are not seen; a region may be split or merged at a narrow neck.

References
----------
M. Zein, P. Wenger, D. Chablat, *Non-singular assembly-mode changing motions for 3-RPR parallel
manipulators*, Mech. Mach. Theory 43 (2008) 480-490, doi:10.1016/j.mechmachtheory.2007.03.005
(the joint-space view of the singularity surface and its cusp edges).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from .._html import dataclass_html, dataclass_repr
from .._validate import _short, as_box, as_count, as_flag, as_float_array
from ..core.mechanism import check_mechanism
from .boxes import check_joint_box
from ..exceptions import InputError, InputTypeError
from ..solve import front

__all__ = ["AtlasRegion", "JointAtlas", "joint_atlas", "check_joint_box", "BISECTION_STEPS",
           "MAX_NODES"]

BISECTION_STEPS = 12
"""Halvings of a surface vertex's grid edge (a numerical knob: the bracket is ``2**-12`` of a cell)."""

MAX_NODES = 20_000_000
"""Largest grid (nodes) :func:`joint_atlas` accepts (about 20 MB of counts)."""


def _resolution(resolution):
    if isinstance(resolution, (list, tuple, np.ndarray)):
        if len(resolution) != 3:
            raise InputError(f"resolution must be one whole number or three (nodes per axis), got "
                             f"{_short(resolution)}")
        res = tuple(as_count(r, f"resolution[{i}]", 4) for i, r in enumerate(resolution))
    else:
        res = (as_count(resolution, "resolution", 4),) * 3
    nodes = res[0] * res[1] * res[2]               # python ints: never wraps (np.prod does in int64)
    if nodes > MAX_NODES:
        raise InputError(f"resolution {res} asks for {nodes:,} grid nodes; at most "
                         f"{MAX_NODES:,} are allowed")
    return res


@dataclass(frozen=True)
class AtlasRegion:
    """One connected region of the grid with one certified number of real assembly modes.

    Attributes
    ----------
    label : int
        Index in :attr:`JointAtlas.regions` (and the value in :attr:`JointAtlas.labels`).
    count : int
        The certified number of real modes at every node of the region.
    sample : (3,) float
        The region's deepest node (farthest from its boundary, in grid steps).
    nodes : int
    volume_fraction : float
        ``nodes`` over the number of certified nodes of the box.
    bounds : (3, 2) float
        Bounding box of the region's nodes.
    """

    label: int
    count: int
    sample: np.ndarray
    nodes: int
    volume_fraction: float
    bounds: np.ndarray

    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html


@dataclass(frozen=True, repr=False)
class JointAtlas:
    """The joint-space atlas of a design in a joint box (see :func:`joint_atlas`).

    Attributes
    ----------
    name : str
        The design's name.
    box : (3, 2) float
    axes : tuple of three (n_i,) float
        Grid coordinates.
    counts : (n1, n2, n3) int8
        Certified counts at the grid nodes; ``-1`` where nothing could certify.
    labels : (n1, n2, n3) int32
        Region index per node (``-1`` for uncertified nodes).
    regions : tuple of AtlasRegion
        Largest first.
    vertices : (V, 3) float
        Surface vertices in joint space.
    faces : (F, 3) int
    vertex_level : (V,) float
        The count threshold each vertex separates (``3.0``: between 2 and 4 modes).
    evidence : (V, 2) int
        Certified counts at the two ends of the vertex's bracket (below, above the level).
    evidence_width : (V,) float
        Length of the bracket (joint units).
    evidence_points : (V, 2, 3) float
        The bracket's ends: certified counts ``evidence[:, 0]`` at ``evidence_points[:, 0]`` and
        ``evidence[:, 1]`` at ``evidence_points[:, 1]``; the vertex is their midpoint.
    removed : int
        Vertices removed for lack of evidence.
    cusp_curves : tuple of (k, 3) float
        Cusp curves in joint space, each traced in floating point and holding a **proven** cusp:
        :func:`imagespace.atlas.verify_cusp` (Krawczyk on the exact section system) succeeded at
        one of its points (``cusp_witnesses``). The polyline itself is drawn, not proven.
    cusp_half_angles : tuple of (k,) float
        The half-angle of the triple root along each curve.
    cusp_witnesses : tuple of CuspWitness
        The proof for each curve of ``cusp_curves``.
    cusp_candidates : tuple of (k, 3) float
        Traced curves of ``f = f' = f'' = 0`` on which no point could be proven a cusp (a float
        artefact near a fold, a degenerate set where ``f''' = 0`` too, or a design whose cusp
        system is not polynomial: an actuated revolute joint). Not drawn as cusp curves.
    uncertified_nodes : int
    seconds : dict
        Wall-clock time of each stage.
    """

    name: str
    box: np.ndarray
    axes: tuple
    counts: np.ndarray
    labels: np.ndarray
    regions: tuple
    vertices: np.ndarray
    faces: np.ndarray
    vertex_level: np.ndarray
    evidence: np.ndarray
    evidence_width: np.ndarray
    removed: int
    evidence_points: Optional[np.ndarray] = None
    cusp_curves: tuple = ()
    cusp_half_angles: tuple = ()
    uncertified_nodes: int = 0
    seconds: dict = field(default_factory=dict)
    cusp_witnesses: tuple = ()
    cusp_candidates: tuple = ()

    __repr__ = dataclass_repr
    _repr_html_ = dataclass_html

    @property
    def cell(self):
        """Grid step per axis, ``(3,) float``."""
        return np.array([a[1] - a[0] for a in self.axes])

    def fractions(self):
        """Volume fraction per certified count (node fractions of the certified nodes).

        Returns
        -------
        dict of int -> float

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.atlas import joint_atlas
        >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
        >>> round(sum(a.fractions().values()), 12)
        1.0
        """
        ok = self.counts >= 0
        total = int(ok.sum())
        values, n = np.unique(self.counts[ok], return_counts=True)
        return {int(v): float(k) / total for v, k in zip(values, n)} if total else {}

    def count_at(self, q):
        """The certified count at the grid node nearest to ``q`` (a look-up, not a new proof).

        Parameters
        ----------
        q : (3,) or (n, 3) float
            Joint vectors inside the box.

        Returns
        -------
        int or (n,) int

        Raises
        ------
        TypeError
            Non-numeric ``q``.
        InputError
            Wrong shape, or a joint vector outside the box.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.atlas import joint_atlas
        >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
        >>> a.count_at([11, 5, 10]) in (0, 2, 4, 6)
        True
        """
        Q = as_float_array(q, "q", last=3)
        single = Q.ndim == 1
        Q = np.atleast_2d(Q)
        if np.any(Q < self.box[:, 0]) or np.any(Q > self.box[:, 1]):
            raise InputError(f"q must lie inside the atlas box {self.box.tolist()}, got {_short(q)}")
        idx = [np.clip(np.rint((Q[:, k] - self.box[k, 0]) / self.cell[k]).astype(int), 0,
                       len(self.axes[k]) - 1) for k in range(3)]
        out = self.counts[idx[0], idx[1], idx[2]].astype(int)
        return int(out[0]) if single else out

    def region_table(self):
        """The regions as rows of a table (list of dicts; ``pandas.DataFrame(rows)`` if wanted).

        Returns
        -------
        list of dict
            Keys ``region, modes, nodes, volume_fraction, sample_q1..3, q1_min ... q3_max``.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.atlas import joint_atlas
        >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
        >>> sorted(a.region_table()[0])[:3]
        ['modes', 'nodes', 'q1_max']
        """
        rows = []
        for r in self.regions:
            row = {"region": r.label, "modes": r.count, "nodes": r.nodes,
                   "volume_fraction": r.volume_fraction}
            for k in range(3):
                row[f"sample_q{k + 1}"] = float(r.sample[k])
            for k in range(3):
                row[f"q{k + 1}_min"], row[f"q{k + 1}_max"] = (float(v) for v in r.bounds[k])
            rows.append(row)
        return rows

    def write_table(self, path):
        """Write :meth:`region_table` as CSV (atomically).

        Parameters
        ----------
        path : str or Path
            Ends in ``.csv``.

        Returns
        -------
        Path

        Raises
        ------
        TypeError
            ``path`` not a str or path-like.
        InputError
            ``path`` not ending in ``.csv``.

        Examples
        --------
        >>> import tempfile, pathlib, imagespace as isp
        >>> from imagespace.atlas import joint_atlas
        >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
        >>> p = a.write_table(pathlib.Path(tempfile.mkdtemp()) / "regions.csv")
        >>> p.read_text().splitlines()[0].split(",")[:2]
        ['region', 'modes']
        """
        import csv
        import io
        import os
        from pathlib import Path

        from .._files import atomic_write

        if not isinstance(path, (str, os.PathLike)) or isinstance(path, bytes):
            raise InputTypeError(f"path must be a str or pathlib.Path, got {type(path).__name__} {_short(path)}")
        path = Path(path)
        if path.suffix.lower() != ".csv":
            raise InputError(f"path must end in .csv, got {str(path)!r}")
        rows = self.region_table()
        buf = io.StringIO()
        keys = list(rows[0]) if rows else ["region", "modes", "nodes", "volume_fraction"]
        w = csv.DictWriter(buf, fieldnames=keys, lineterminator="\n")
        w.writeheader()
        for row in rows:
            w.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in row.items()})
        data = buf.getvalue().encode()
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(path, lambda f: f.write(data))
        return path

    def mesh(self):
        """The surface as a :class:`trimesh.Trimesh` (vertex attributes: level, evidence width).

        Returns
        -------
        trimesh.Trimesh

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.atlas import joint_atlas
        >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
        >>> len(a.mesh().vertices) == len(a.vertices)
        True
        """
        import trimesh

        mesh = trimesh.Trimesh(self.vertices, self.faces, process=False)
        mesh.vertex_attributes["level"] = self.vertex_level
        mesh.vertex_attributes["evidence_width"] = self.evidence_width
        mesh.metadata["imagespace"] = {"kind": "joint atlas", "design": self.name,
                                       "box": self.box.tolist(), "removed": self.removed}
        return mesh

    def export_ply(self, path):
        """Write the surface as binary PLY with float64 vertices
        (:func:`imagespace.singular.meshing.export_mesh`).

        Parameters
        ----------
        path : str or Path
            Ends in ``.ply`` (or ``.obj``, ``.stl``, ``.glb``).

        Returns
        -------
        Path

        Raises
        ------
        TypeError, InputError
            As :func:`~imagespace.singular.meshing.export_mesh`.

        Examples
        --------
        >>> import tempfile, pathlib, imagespace as isp
        >>> from imagespace.atlas import joint_atlas
        >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
        >>> a.export_ply(pathlib.Path(tempfile.mkdtemp()) / "atlas.ply").suffix
        '.ply'
        """
        from ..singular.meshing import export_mesh

        return export_mesh(self.mesh(), path)

    def figure(self, q=None, ax=None, **kwargs):
        """Matplotlib figure of the atlas; see :func:`imagespace.atlas.figures.plot_atlas`.

        Examples
        --------
        >>> import imagespace as isp
        >>> from imagespace.atlas import joint_atlas
        >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 12, cusps=False)
        >>> a.figure().axes[0].name
        '3d'
        """
        from .figures import plot_atlas

        return plot_atlas(self, q=q, ax=ax, **kwargs)


def _levels(counts):
    present = np.unique(counts[counts >= 0])
    return [0.5 * (a + b) for a, b in zip(present[:-1], present[1:])]


def _regions(counts, axes, box):
    from scipy import ndimage

    labels = np.full(counts.shape, -1, dtype=np.int32)
    found = []
    total = int((counts >= 0).sum())
    for c in np.unique(counts[counts >= 0]):
        lab, n = ndimage.label(counts == c, structure=np.ones((3, 3, 3), dtype=bool))
        if n == 0:
            continue
        sizes = np.bincount(lab.ravel(), minlength=n + 1)
        for k in range(1, n + 1):
            found.append((int(sizes[k]), int(c), lab, k))
    found.sort(key=lambda item: -item[0])
    regions = []
    depths = {}
    for new, (size, c, lab, k) in enumerate(found):
        mask = lab == k
        labels[mask] = new
        idx = np.argwhere(mask)
        if c not in depths:
            depths[c] = _depth(counts == c)
        d = np.where(mask, depths[c], -1)
        best = np.unravel_index(int(np.argmax(d)), d.shape)
        sample = np.array([axes[j][best[j]] for j in range(3)])
        lo, hi = idx.min(axis=0), idx.max(axis=0)
        bounds = np.array([[axes[j][lo[j]], axes[j][hi[j]]] for j in range(3)])
        regions.append(AtlasRegion(new, c, sample, size, size / total if total else 0.0, bounds))
    return labels, tuple(regions)


def _depth(mask):
    from scipy import ndimage

    return ndimage.distance_transform_cdt(np.pad(mask, 1, constant_values=False),
                                          metric="taxicab")[1:-1, 1:-1, 1:-1]


def _brackets(verts, counts, box, h, level):
    """For marching-cubes vertices (index coordinates) the two grid nodes that bracket the level:
    the ends of the vertex's grid edge, or, for a vertex inside a cube (the extra vertex of an
    ambiguous case), the pair of the cube's corners on either side of the level nearest to it."""
    shape = np.array(counts.shape)
    n = len(verts)
    cube = np.clip(np.floor(verts).astype(int), 0, shape - 2)
    corners = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    C = cube[:, None, :] + corners[None, :, :]                            # (n, 8, 3)
    cc = counts[C[..., 0], C[..., 1], C[..., 2]].astype(int)             # (n, 8)
    dist = np.linalg.norm(C - verts[:, None, :], axis=2)
    big = 1e9
    below = (cc >= 0) & (cc < level)
    above = (cc >= 0) & (cc > level)
    a = np.argmin(np.where(below, dist, big), axis=1)
    b = np.argmin(np.where(above, dist, big), axis=1)
    rows = np.arange(n)
    ok = below[rows, a] & above[rows, b]
    lo = box[:, 0] + C[rows, a] * h
    hi = box[:, 0] + C[rows, b] * h
    return lo, hi, cc[rows, a], cc[rows, b], ok


def _surface(manipulator, counts, axes, box, tolerances):
    """Marching cubes per level, then bisection of every vertex along its grid edge on certified
    counts. Returns vertices, faces, levels, evidence, widths, removed."""
    from skimage.measure import marching_cubes

    h = np.array([a[1] - a[0] for a in axes])
    valid = counts >= 0
    vol = counts.astype(np.float64)
    V_all, F_all, L_all, E_all, W_all, B_all = [], [], [], [], [], []
    removed = 0
    offset = 0
    for level in _levels(counts):
        if min(counts.shape) < 2:
            break
        try:
            verts, faces, _n, _v = marching_cubes(vol, level=level, mask=valid, allow_degenerate=False)
        except (ValueError, RuntimeError):
            continue
        if len(verts) == 0:
            continue
        lo, hi, clo, chi, ok = _brackets(verts, counts, box, h, level)
        alive = ok.copy()
        for _ in range(BISECTION_STEPS):
            idx = np.flatnonzero(alive)
            if not idx.size:
                break
            mid = 0.5 * (lo[idx] + hi[idx])
            cm, _p = front.certified_root_counts(manipulator, mid)
            cm = cm.astype(int)
            bad = cm < 0
            below = ~bad & (cm < level)
            above = ~bad & ~(cm < level)
            lo[idx[below]], clo[idx[below]] = mid[below], cm[below]
            hi[idx[above]], chi[idx[above]] = mid[above], cm[above]
            alive[idx[bad]] = False          # frozen: its bracket stays as it is
        width = np.linalg.norm(hi - lo, axis=1)
        keep = ok & (width <= tolerances.atlas_evidence_width * float(h.min()))
        removed += int((~keep).sum())
        new_index = np.cumsum(keep) - 1
        fkeep = keep[faces].all(axis=1)
        V_all.append(0.5 * (lo + hi)[keep])
        F_all.append(new_index[faces[fkeep]] + offset)
        L_all.append(np.full(int(keep.sum()), float(level)))
        E_all.append(np.column_stack([clo, chi])[keep])
        W_all.append(width[keep])
        B_all.append(np.stack([lo, hi], axis=1)[keep])
        offset += int(keep.sum())
    if not V_all:
        return (np.empty((0, 3)), np.empty((0, 3), dtype=np.int64), np.empty(0),
                np.empty((0, 2), dtype=int), np.empty(0), removed, np.empty((0, 2, 3)))
    return (np.vstack(V_all), np.vstack(F_all).astype(np.int64), np.concatenate(L_all),
            np.vstack(E_all), np.concatenate(W_all), removed, np.concatenate(B_all))


def joint_atlas(manipulator, joint_box, resolution=40, cusps=True, progress=False):
    """The joint-space atlas of ``manipulator`` in ``joint_box`` (see the module notes).

    Parameters
    ----------
    manipulator : PlanarParallel
        A numeric design.
    joint_box : (3, 2) float
        ``((q1_min, q1_max), (q2_min, q2_max), (q3_min, q3_max))`` inside the joints' domains.
    resolution : int or (3,) int
        Grid nodes per axis (at least 4; at most :data:`MAX_NODES` nodes in all).
    cusps : bool
        Trace the cusp curves (:func:`imagespace.atlas.curves.cusp_curves`).
    progress : bool
        Print the time of each stage.

    Returns
    -------
    JointAtlas

    Raises
    ------
    TypeError
        ``manipulator`` not a design; non-numeric box or resolution; ``cusps``/``progress`` not
        booleans.
    InputError
        A box of the wrong shape, empty, or leaving a joint's domain; a resolution below 4 or
        too large; a design with free symbols.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.atlas import joint_atlas
    >>> a = joint_atlas(isp.examples.general_3rpr(), [(8, 14), (2, 8), (7, 13)], 16, cusps=False)
    >>> sorted(a.fractions())
    [0, 2, 4, 6]
    >>> bool((a.evidence[:, 0] != a.evidence[:, 1]).all())
    True
    """
    box = check_joint_box(manipulator, joint_box)
    res = _resolution(resolution)
    cusps = as_flag(cusps, "cusps")
    progress = as_flag(progress, "progress")
    if manipulator.design_symbols:
        raise InputError(f"joint_atlas needs a numeric design; the design has the symbols "
                         f"{sorted(map(str, manipulator.design_symbols))}")
    tol = manipulator.tolerances
    seconds = {}
    t0 = time.perf_counter()
    axes = tuple(np.linspace(box[k, 0], box[k, 1], res[k]) for k in range(3))
    G = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    counts, _path = front.certified_root_counts(manipulator, G)
    counts = counts.reshape(res).astype(np.int8)
    seconds["counts"] = time.perf_counter() - t0
    t1 = time.perf_counter()
    labels, regions = _regions(counts, axes, box)
    seconds["regions"] = time.perf_counter() - t1
    t2 = time.perf_counter()
    V, F, L, E, W, removed, B = _surface(manipulator, counts, axes, box, tol)
    seconds["surface"] = time.perf_counter() - t2
    curves, angles, witnesses, candidates = (), (), (), ()
    if cusps:
        from .curves import cusp_curves

        t3 = time.perf_counter()
        traced = cusp_curves(manipulator, box, seeds=V, sections=0)
        proven, unproven = _verified_curves(manipulator, traced, box)
        curves = tuple(c[:, 1:] for c, _ in proven)
        angles = tuple(c[:, 0] for c, _ in proven)
        witnesses = tuple(w for _, w in proven)
        candidates = tuple(c[:, 1:] for c in unproven)
        seconds["cusp curves"] = time.perf_counter() - t3
    seconds["total"] = time.perf_counter() - t0
    if progress:
        print("joint_atlas: " + ", ".join(f"{k} {v:.2f} s" for k, v in seconds.items()))
    return JointAtlas(manipulator.name, box, axes, counts, labels, regions, V, F, L, E, W, removed, B,
                      curves, angles, int((counts < 0).sum()), seconds, witnesses, candidates)


#: Points of a traced cusp curve handed to the interval proof (evenly along it), at most.
CUSP_PROOF_POINTS = 5


def _verified_curves(m, traced, box):
    """Split traced curves ``(theta, q1, q2, q3)`` into ``[(curve, witness)]`` holding a proven
    cusp and the candidates on which no point could be proven (:func:`verify_cusp`)."""
    from .cuspidal import verify_cusp

    proven, candidates = [], []
    polynomial = not any(leg.actuated_is_angle for leg in m.legs)
    for c in traced:
        witness = None
        if polynomial:                  # else no polynomial cusp system: nothing to prove with
            picks = np.linspace(0, len(c) - 1, min(CUSP_PROOF_POINTS, len(c)) + 2)[1:-1]
            for k in np.unique(picks.astype(int)):
                witness = verify_cusp(m, c[k], box)
                if witness is not None:
                    break
        if witness is None:
            candidates.append(c)
        else:
            proven.append((c, witness))
    return proven, candidates

