"""Export of triangle meshes (PLY, OBJ, STL, GLB), written atomically; PLY and OBJ keep the float64
vertices bit for bit. Split from :mod:`imagespace.singular.meshing` (issue [15]), which still
re-exports :func:`export_mesh`, :data:`EXPORT_FORMATS` and :data:`EXPORT_PRECISION`.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .._files import atomic_write
from .._validate import _short
from ..exceptions import InputError, InputTypeError

__all__ = ["export_mesh", "EXPORT_FORMATS", "EXPORT_PRECISION"]

EXPORT_FORMATS = (".stl", ".ply", ".obj", ".glb")
EXPORT_PRECISION = {".stl": "float32", ".ply": "float64", ".obj": "float64", ".glb": "float32"}
"""Precision of the vertex coordinates each export format stores (STL and GLB: float32 by format)."""


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
    >>> from imagespace.singular.mesh_export import export_mesh
    >>> box = trimesh.creation.box()
    >>> box.vertices[0] += 1e-12
    >>> p = export_mesh(box, pathlib.Path(tempfile.mkdtemp()) / "box.ply")
    >>> back = trimesh.load(p, process=False)
    >>> len(back.faces), bool(np.array_equal(back.vertices, box.vertices))
    (12, True)
    """
    import trimesh

    if not isinstance(mesh, trimesh.Trimesh):
        raise InputTypeError(f"mesh must be a trimesh.Trimesh, got {type(mesh).__name__}")
    if not isinstance(path, (str, os.PathLike)) or isinstance(path, bytes):
        raise InputTypeError(f"path must be a str or pathlib.Path, got {type(path).__name__} {_short(path)}")
    path = Path(path)
    if isinstance(os.fspath(path), bytes):
        raise InputTypeError(f"path must be a str or pathlib.Path, got the bytes path {_short(path)}")
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


