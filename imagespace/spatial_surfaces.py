"""Meshes of the spatial singularity loci (top layer: it joins :mod:`imagespace.spatial`, which may
not import the meshing machinery, with :mod:`imagespace.singular.meshing`).

The constant-orientation singularity surface of a Gough-Stewart platform
(:func:`imagespace.spatial.singularities.constant_orientation_singularity`, a cubic in the
position for a general 6-6 platform) is meshed by the certified mesher
(:func:`imagespace.singular.meshing.mesh_implicit`: every vertex kept is within ``tol`` times the
box size of the surface, proven by a sign change between two points of proven sign) and exported
with :func:`imagespace.singular.meshing.export_mesh`.
"""

from __future__ import annotations

from .exceptions import InputTypeError
from .singular.meshing import MAX_MEMORY, PolynomialImplicit, mesh_implicit
from .spatial.singularities import ConstantOrientationSingularity, constant_orientation_singularity

__all__ = ["mesh_constant_orientation_singularity"]


def mesh_constant_orientation_singularity(gs, rotation, box, resolution=64, tol=1e-9, progress=None,
                                          max_memory=MAX_MEMORY, tolerances=None):
    """A certified triangle mesh of the constant-orientation singularity surface in ``(x, y, z)``.

    Parameters
    ----------
    gs : GoughStewart
    rotation : (3, 3) float, (4,) float, or ConstantOrientationSingularity
        The fixed orientation (a rotation matrix or a quaternion), or a locus already computed
        by :func:`~imagespace.spatial.singularities.constant_orientation_singularity`.
    box : (3, 2) float
        Ranges of the position ``x, y, z`` of the platform frame's origin.
    resolution : int or (3,) int
        Grid points per axis, at least 8.
    tol : float
        Certified distance of every vertex to the surface, relative to the box's longest side
        (see :func:`imagespace.singular.meshing.mesh_implicit`).
    progress : bool or None
    max_memory : float
        Bytes; see :func:`~imagespace.singular.meshing.mesh_implicit`.
    tolerances : Tolerances, optional
        Default: ``gs.tolerances``.

    Returns
    -------
    trimesh.Trimesh
        Normals point to where ``det J > 0`` (aspect +1). ``mesh.metadata["imagespace"]`` is the
        mesher's record plus ``"locus"``: ``"constant-orientation singularity"``, ``"degree"`` and
        ``"rotation"``.

    Raises
    ------
    TypeError
        ``gs`` not a GoughStewart; arguments of the wrong kind (see
        :func:`~imagespace.singular.meshing.mesh_implicit`).
    InputError
        An invalid rotation, box, resolution or tolerance.
    DegenerateDesignError
        If the design is singular at every position with this orientation.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.spatial.gough_stewart import GoughStewart
    >>> rng = np.random.default_rng(0)
    >>> gs = GoughStewart(rng.normal(size=(6, 3)), rng.normal(size=(6, 3)))
    >>> mesh = mesh_constant_orientation_singularity(gs, np.eye(3), [(-2, 2)] * 3, resolution=16)
    >>> md = mesh.metadata["imagespace"]
    >>> len(mesh.faces) > 0, md["degree"], md["max_distance"] <= 1e-9 * 4
    (True, 3, True)
    """
    if isinstance(rotation, ConstantOrientationSingularity):
        locus = rotation
        if locus.gs is not gs:
            raise InputTypeError("rotation is a ConstantOrientationSingularity of another design; pass the "
                                 "orientation itself, or the locus together with its own gs")
    else:
        locus = constant_orientation_singularity(gs, rotation, tolerances=tolerances)
    tols = gs.tolerances if tolerances is None else tolerances
    func = PolynomialImplicit(locus.polynomial, locus.variables, tolerances=tols)
    mesh = mesh_implicit(func, box, resolution=resolution, tol=tol, progress=progress,
                         max_memory=max_memory, tolerances=tols)
    mesh.metadata["imagespace"].update(locus="constant-orientation singularity", degree=locus.degree,
                                       rotation=locus.rotation.tolist())
    return mesh
