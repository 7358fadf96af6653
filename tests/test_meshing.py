"""Meshes: vertices certified on the surface, checked by independent evaluations; a sphere's
area; exports that load back; clear errors for bad boxes, resolutions, charts and suffixes."""

import numpy as np
import pytest
import sympy as sp
import trimesh
from scipy.spatial import cKDTree

import imagespace as isp
from imagespace.meshing import (EXPORT_FORMATS, PolynomialImplicit, export_mesh, mesh_implicit,
                                mesh_surface)
from imagespace.singularities import image_chart_point

IMAGE_BOX = [(-12, 12), (-12, 12), (-3, 3)]
POSE_BOX = [(-15, 15), (-15, 15), (-np.pi, np.pi)]


@pytest.fixture(scope="module")
def seed002():
    return isp.examples.stigger_husty().singularity_surface()


@pytest.fixture(scope="module")
def image_mesh(seed002):
    return mesh_surface(seed002, IMAGE_BOX, chart="image", resolution=64)


def test_sphere_area_and_exact_vertex_distance():
    u, v, w = sp.symbols("u v w")
    r = 1.25
    mesh = mesh_implicit(PolynomialImplicit(u**2 + v**2 + w**2 - r**2, (u, v, w)), [(-1.5, 1.5)] * 3, 64)
    assert abs(mesh.area / (4 * np.pi * r**2) - 1) < 0.01
    # the true distance of every vertex to the sphere (not |F|/|grad F|)
    assert np.max(np.abs(np.linalg.norm(mesh.vertices, axis=1) - r)) <= 1e-9 * 3.0
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume > 0                       # normals point outwards, where F > 0


def test_every_vertex_brackets_the_surface(seed002, image_mesh):
    """Independent check with the homogeneous evaluator: S changes sign within 1e-9 * box size
    of every vertex along the normal."""
    V = image_mesh.vertices
    X, dX = image_chart_point(V)
    _, G = seed002.value_and_gradient(X)
    g = np.einsum("ni,nik->nk", G, dX)
    n = g / np.linalg.norm(g, axis=1)[:, None]
    d = 1e-9 * 24
    a = seed002(image_chart_point(V - d * n)[0])
    b = seed002(image_chart_point(V + d * n)[0])
    assert np.all(np.sign(a) * np.sign(b) <= 0)
    md = image_mesh.metadata["imagespace"]
    assert md["max_distance"] <= 1e-9 * 24 and md["uncertified"] == 0


def test_normals_point_to_the_positive_aspect(seed002, image_mesh):
    c, n = image_mesh.triangles_center, image_mesh.face_normals
    eps = 1e-6
    diff = seed002(image_chart_point(c + eps * n)[0]) - seed002(image_chart_point(c - eps * n)[0])
    assert np.mean(diff > 0) > 0.99
    assert image_mesh.is_winding_consistent
    areas = image_mesh.area_faces
    assert np.all(areas > 0)


def test_pose_chart_is_periodic_in_phi(seed002):
    mesh = mesh_surface(seed002, POSE_BOX, chart="pose", resolution=48)
    V = mesh.vertices
    lo, hi = V[np.isclose(V[:, 2], -np.pi, atol=1e-12)], V[np.isclose(V[:, 2], np.pi, atol=1e-12)]
    assert len(lo) == len(hi) > 20
    dist, _ = cKDTree(hi[:, :2]).query(lo[:, :2])
    assert dist.max() <= 2 * 1e-9 * 30


def test_pose_mesh_agrees_with_the_exact_conic_sections(seed002, rng):
    """Points of the exact fixed-orientation conics lie near the marching-cubes mesh."""
    mesh = mesh_surface(seed002, POSE_BOX, chart="pose", resolution=96)
    tree = cKDTree(mesh.vertices)
    h = 30 / 95
    for phi in rng.uniform(-2.5, 2.5, 4):
        con = seed002.section(phi)
        # points on the conic: solve it for y on vertical lines x = const
        A, B, C, D, E, F = con.coefficients
        pts = []
        for x in np.linspace(-14, 14, 57):
            for y in np.roots([C, B * x + E, A * x * x + D * x + F]):
                if abs(y.imag) < 1e-12 and abs(y.real) < 14:
                    pts.append([x, y.real, phi])
        pts = np.array(pts)
        assert len(pts) > 10
        assert np.allclose(con(pts[:, 0], pts[:, 1]), 0, atol=1e-6 * np.abs(con.coefficients).max() * 200)
        dist, _ = tree.query(pts)
        assert dist.max() < 2 * h


@pytest.mark.parametrize("suffix", EXPORT_FORMATS)
def test_exports_load_back(image_mesh, tmp_path, suffix):
    path = export_mesh(image_mesh, tmp_path / f"surface{suffix}")
    back = trimesh.load(path, force="mesh")
    assert len(back.vertices) == len(image_mesh.vertices)
    assert len(back.faces) == len(image_mesh.faces)


def test_working_mode_surface_meshes_through_the_leg_ik():
    m = isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                            isp.RPR(base=(6, 0), platform=(1, 0)),
                            isp.RPR(base=(2, 5), platform=(0, 1))])
    S = m.singularity_surfaces()[1]
    mesh = mesh_surface(S, [(-6, 8), (-6, 8), (-np.pi, np.pi)], chart="pose", resolution=24)
    assert len(mesh.faces) > 100
    md = mesh.metadata["imagespace"]
    assert md["uncertified"] == 0 and md["max_distance"] <= 1e-9 * 14
    # vertices are where the working-mode manipulator is direct-kinematically singular
    jac = m.jacobians(mesh.vertices[:200], working_modes=(1, 0, 0))
    assert np.all(jac.ratio_Jx[jac.valid] < 1e-6)


def test_a_box_the_surface_misses_gives_an_empty_mesh():
    u, v, w = sp.symbols("u v w")
    mesh = mesh_implicit(PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w)), [(5, 6)] * 3, 8)
    assert len(mesh.faces) == 0 and "does not meet" in mesh.metadata["imagespace"]["note"]


def test_bad_input(seed002, tmp_path):
    with pytest.raises(isp.InputError, match="box is empty"):
        mesh_surface(seed002, [(1, 1), (0, 1), (0, 1)])
    with pytest.raises(isp.InputError, match="box must be"):
        mesh_surface(seed002, [(0, 1), (0, 1)])
    with pytest.raises(isp.InputError, match="at least 8"):
        mesh_surface(seed002, IMAGE_BOX, resolution=4)
    with pytest.raises(isp.InputError, match="resolution must be an int"):
        mesh_surface(seed002, IMAGE_BOX, resolution=64.5)
    with pytest.raises(isp.InputError, match="GB"):
        mesh_surface(seed002, IMAGE_BOX, resolution=100000)
    with pytest.raises(isp.InputError, match="chart"):
        mesh_surface(seed002, IMAGE_BOX, chart="polar")
    with pytest.raises(isp.InputError, match="suffix"):
        export_mesh(trimesh.creation.box(), tmp_path / "surface.xyz")
    with pytest.raises(TypeError, match="Implicit"):
        mesh_implicit(lambda p: p, IMAGE_BOX)
