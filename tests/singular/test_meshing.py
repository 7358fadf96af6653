"""Meshes: vertices certified on the surface, checked by independent evaluations (exact rationals,
mpmath); a sphere's area; the collinear 3-RPR (seed 003), whose vertices on grid nodes and on the
singular line used to stay uncertified; a double component, which has no sign change and is removed;
exports that load back bit for bit (PLY, OBJ) or in float32 (STL, GLB), atomically; the CLI's counts
and ``--strict``; clear errors for bad boxes, resolutions, charts and suffixes."""

import io
import os
from fractions import Fraction

import mpmath
import numpy as np
import pytest
import sympy as sp
import trimesh
from scipy.spatial import cKDTree

import imagespace as isp
import imagespace.singular.mesh_export as mesh_export
import imagespace.singular.meshing as meshing
from imagespace.cli import default_box, main
from imagespace.singular.meshing import (EXPORT_FORMATS, PolynomialImplicit, export_mesh, mesh_implicit,
                                mesh_surface)
from imagespace.singular.surface import image_chart_point

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


@pytest.mark.slow
def test_pose_chart_is_periodic_in_phi(seed002):
    mesh = mesh_surface(seed002, POSE_BOX, chart="pose", resolution=48)
    V = mesh.vertices
    lo, hi = V[np.isclose(V[:, 2], -np.pi, atol=1e-12)], V[np.isclose(V[:, 2], np.pi, atol=1e-12)]
    assert len(lo) == len(hi) > 20
    dist, _ = cKDTree(hi[:, :2]).query(lo[:, :2])
    assert dist.max() <= 2 * 1e-9 * 30


def euclidean_jx_ratio(m, pts):
    """``|det Jx| / prod(row norms)`` at poses ``(x, y, phi)`` of the 2-RPR/PPR of seed 002, from the
    legs' Euclidean constraints written here (no image space): an RPR leg ``|t + R b - A|^2 = q^2``
    gives the row ``(s, s . perp(R b))`` with ``s = t + R b - A``; the PPR leg (its platform point
    ``R c + t`` on a line of direction ``w``) gives ``(n, n . perp(R c))`` with ``n = perp(w)``."""
    out = []
    for x, y, phi in pts:
        R = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
        rows = []
        for leg in m.legs:
            g = leg.geometry(exact=False)
            Rb = R @ np.array(g["platform"])
            perp = np.array([-Rb[1], Rb[0]])
            if leg.joints == "RPR":
                d = np.array([x, y]) + Rb - np.array(g["base"])
            else:
                assert leg.joints == "PPR"
                d = np.array([-g["second_axis"][1], g["second_axis"][0]])
            rows.append([d[0], d[1], d @ perp])
        rows = np.array(rows)
        norms = np.prod(np.linalg.norm(rows, axis=1))
        out.append(abs(np.linalg.det(rows)) / norms if norms > 0 else 0.0)   # a leg of length 0: singular
    return np.array(out)


@pytest.mark.slow
def test_pose_mesh_agrees_with_the_exact_conic_sections(seed002, rng):
    """Points of the fixed-orientation conics (``SingularitySurface.section``) are singular poses by
    the Euclidean Jacobian written here (independent of the image space), and they lie near the
    marching-cubes mesh of the surface."""
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
        assert np.all(euclidean_jx_ratio(seed002.manipulator, pts) <= 1e-9)
        # not vacuous: half a length unit off the conic the Jacobian is regular
        assert np.median(euclidean_jx_ratio(seed002.manipulator, pts + [0.0, 0.5, 0.0])) > 1e-4
        dist, _ = tree.query(pts)
        assert dist.max() < 2 * h


@pytest.mark.slow
@pytest.mark.parametrize("suffix", EXPORT_FORMATS)
def test_exports_load_back(image_mesh, tmp_path, suffix):
    path = export_mesh(image_mesh, tmp_path / f"surface{suffix}")
    back = trimesh.load(path, force="mesh")
    assert len(back.vertices) == len(image_mesh.vertices)
    assert len(back.faces) == len(image_mesh.faces)


@pytest.mark.slow
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


# -- independent re-certification --------------------------------------------------------------
TOL = 1e-9


def _quartic_signs(m, chart):
    """The sign of the homogeneous quartic ``m.singularity_polynomial()`` at chart points, computed
    here without the meshing code: exact rationals in the image chart ``(1, w, u, v)``, mpmath at
    60 digits in the pose chart (values tested are > 1e-30 relative, or exactly 0)."""
    poly = m.singularity_polynomial()
    terms = [(sp.Rational(c), mon) for mon, c in poly.terms()]
    if chart == "image":
        terms = [(Fraction(int(c.p), int(c.q)), mon) for c, mon in terms]

        def value(p):
            u, v, w = (Fraction(float(t)) for t in p)
            X = (Fraction(1), w, u, v)
            return sum(c * X[0]**a * X[1]**b * X[2]**d * X[3]**e for c, (a, b, d, e) in terms)
    else:
        f = sp.lambdify(poly.gens, poly.as_expr(), modules="mpmath")

        def value(p):
            with mpmath.workdps(60):
                x, y, phi = (mpmath.mpf(float(t)) for t in p)
                x0, x1 = mpmath.cos(phi / 2), mpmath.sin(phi / 2)
                return f(x0, x1, (x1 * x - x0 * y) / 2, (x0 * x + x1 * y) / 2)

    def sign(p):
        val = value(p)
        return (val > 0) - (val < 0)

    def float_value(P):                      # for search directions only
        X = np.stack([np.ones(len(P)), P[:, 2], P[:, 0], P[:, 1]], axis=-1) if chart == "image" else \
            np.stack([np.cos(P[:, 2] / 2), np.sin(P[:, 2] / 2),
                      (np.sin(P[:, 2] / 2) * P[:, 0] - np.cos(P[:, 2] / 2) * P[:, 1]) / 2,
                      (np.cos(P[:, 2] / 2) * P[:, 0] + np.sin(P[:, 2] / 2) * P[:, 1]) / 2], axis=-1)
        return sp.lambdify(poly.gens, poly.as_expr(), "numpy")(*X.T) * np.ones(len(P))

    return sign, float_value


def _recertify(sign, float_value, V, r):
    """Indices of vertices for which the test finds neither an exact zero at the vertex nor a sign
    change between ``V - r d`` and ``V + r d`` for ``d`` the unit normal (central differences)
    or a coordinate axis."""
    h = 1e-6
    grad = np.stack([(float_value(V + h * e) - float_value(V - h * e)) / (2 * h) for e in np.eye(3)], axis=-1)
    norm = np.linalg.norm(grad, axis=1)
    failed = []
    for i, p in enumerate(V):
        dirs = ([grad[i] / norm[i]] if np.isfinite(norm[i]) and norm[i] > 0 else []) + list(np.eye(3))
        if any(sign(p - r * d) * sign(p + r * d) < 0 for d in dirs) or sign(p) == 0:
            continue
        failed.append(i)
    return failed


@pytest.fixture(scope="module")
def collinear():
    return isp.examples.collinear_3rpr()


@pytest.mark.slow
@pytest.mark.parametrize("chart", ["image", "pose"])
def test_collinear_3rpr_every_vertex_is_certified_and_rechecked(collinear, chart):
    """Seed 003 at 48^3 left 10 (image) and 27 (pose) vertices uncertified: marching cubes put them
    on grid nodes within rounding of the surface (u = 3 v w through rational nodes; the plane
    phi = pi 1e-16 off the box face) or inside a cube on the singular line phi = y = 0, and the
    projection guessed their edge. Every component of this quartic is simple (S = 2048 x0 x1
    (x0 x2 - 3 x1 x3)), so every vertex can be certified: none may be left or removed, and the
    test re-checks each one with its own exact evaluation."""
    S = collinear.singularity_surface()
    box = default_box(collinear, chart)
    mesh = mesh_surface(S, box, chart=chart, resolution=48)
    md = mesh.metadata["imagespace"]
    assert md["uncertified"] == 0
    assert md["removed"] == 0 and md["removed_faces"] == 0
    assert md["sign_test"] == "rounding-error bound, arb below it"
    assert md["searched"] > 0                       # the formerly uncertified vertices went through the search
    size = md["size"]
    assert md["max_distance"] <= TOL * size
    assert np.all(mesh.vertex_attributes["distance_bound"] <= TOL * size)
    sign, float_value = _quartic_signs(collinear, chart)
    assert _recertify(sign, float_value, mesh.vertices, TOL * size) == []
    assert len(mesh.vertices) > 6000


def test_recheck_would_catch_a_vertex_off_the_surface(collinear):
    """The re-check is not vacuous: a vertex moved by 10 tol * size along the normal fails it."""
    sign, float_value = _quartic_signs(collinear, "image")
    V = np.array([[0.375, 0.125, 1.0]])              # u = 3 v w exactly: on the ruled sheet
    assert sign(V[0]) == 0
    assert _recertify(sign, float_value, V, TOL * 6) == []
    n = np.array([1.0, -3.0, -0.375]) / np.linalg.norm([1.0, -3.0, -0.375])   # grad of w (u - 3 v w) there
    assert _recertify(sign, float_value, V + 10 * TOL * 6 * n, TOL * 6) == [0]


def test_a_double_component_claims_no_sign_change():
    """(u + v + w)^2 touches 0 without a sign change: the grid meets it only through rounding noise
    (at 15 and 17 points many nodes lie within rounding of the plane). Noise vertices sit on grid
    nodes, their faces collapse and are dropped; nothing is left that would claim a sign change."""
    u, v, w = sp.symbols("u v w")
    F = PolynomialImplicit(sp.expand((u + v + w)**2), (u, v, w))
    axis = np.linspace(-1, 1, 15)
    noisy = F.grid([axis] * 3)
    assert np.any(noisy < 0)                         # the float grid does show spurious sign changes
    for res in (15, 17):
        mesh = mesh_implicit(F, [(-1, 1)] * 3, res, on_uncertified="keep")
        md = mesh.metadata["imagespace"]
        assert md["searched"] > 0 and md["uncertified"] == 0
        assert len(mesh.faces) == 0 and len(mesh.vertices) == 0


def test_a_tolerance_below_float_spacing_removes_and_counts():
    """tol = 1e-18 of the box asks for brackets shorter than the spacing of floats near the
    vertices: no sign change can be certified so finely (only exact zeros could be), so the
    vertices are removed and counted - or kept and counted as uncertified."""
    u, v, w = sp.symbols("u v w")
    sphere = PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w))
    mesh = mesh_implicit(sphere, [(-1.5, 1.5)] * 3, 16, tol=1e-18)
    md = mesh.metadata["imagespace"]
    assert md["removed"] > 400 and md["removed_faces"] > 900 and md["uncertified"] == 0
    assert np.all(mesh.vertex_attributes["distance_bound"] == 0)      # survivors: proven zeros
    for p in mesh.vertices:
        assert sum(Fraction(float(t))**2 for t in p) == 1
    kept = mesh_implicit(sphere, [(-1.5, 1.5)] * 3, 16, tol=1e-18, on_uncertified="keep")
    mk = kept.metadata["imagespace"]
    assert mk["removed"] == 0 and mk["uncertified"] == md["removed"]
    assert np.sum(~np.isfinite(kept.vertex_attributes["distance_bound"])) == md["removed"]
    # the same sphere at tol = 1e-16 (a few ulps of the coordinates) is certified everywhere
    fine = mesh_implicit(sphere, [(-1.5, 1.5)] * 3, 16, tol=1e-16).metadata["imagespace"]
    assert fine["removed"] == 0 and fine["uncertified"] == 0 and fine["max_distance"] <= 3e-16


def test_proven_signs_are_never_wrong(collinear, rng):
    """Points within rounding of the collinear surface, where the float value's sign is noise:
    every sign ``proven_sign`` claims agrees with the exact sign; most are decided."""
    S = collinear.singularity_surface()
    func = meshing.surface_implicit(S, "image")
    sign, _ = _quartic_signs(collinear, "image")
    v = rng.uniform(-2, 2, 400)
    w = rng.uniform(-3, 3, 400)
    P = np.stack([3 * v * w, v, w], axis=-1)          # u = 3 v w up to rounding
    P[:100, 0] = np.nextafter(P[:100, 0], np.inf)
    P[100:200, 2] = 0.0                               # on the plane w = 0 exactly
    s, known = func.proven_sign(P)
    exact = np.array([sign(p) for p in P])
    float_sign = np.sign(func.value(P))
    assert np.all(s[known] == exact[known])
    assert known.mean() > 0.9
    assert np.any(float_sign != exact)               # the float value alone would have been wrong


def test_unknown_on_uncertified_is_refused():
    u, v, w = sp.symbols("u v w")
    with pytest.raises(isp.InputError, match="on_uncertified"):
        mesh_implicit(PolynomialImplicit(u - v, (u, v, w)), [(-1, 1)] * 3, 8, on_uncertified="drop")


# -- exports -----------------------------------------------------------------------------------
def _bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.uint64)


@pytest.mark.parametrize("suffix", [".ply", ".obj"])
def test_ply_and_obj_round_trip_bit_for_bit(image_mesh, tmp_path, suffix):
    V = image_mesh.vertices.copy()
    V[0] = [-0.0, 5e-324, 1.0 + 2.0**-52]             # signed zero, a subnormal, the last bit
    mesh = trimesh.Trimesh(V, image_mesh.faces, process=False)
    path = export_mesh(mesh, tmp_path / f"surface{suffix}")
    back = trimesh.load(path, force="mesh", process=False)
    assert back.vertices.dtype == np.float64
    assert np.array_equal(_bits(back.vertices), _bits(V))
    assert np.array_equal(back.faces, image_mesh.faces)
    if suffix == ".ply":
        header = path.read_bytes().split(b"end_header\n")[0]
        assert b"property double x" in header and b"binary_little_endian" in header


@pytest.mark.parametrize("suffix", [".stl", ".glb"])
def test_stl_and_glb_store_float32_as_documented(image_mesh, tmp_path, suffix):
    path = export_mesh(image_mesh, tmp_path / f"surface{suffix}")
    back = trimesh.load(path, force="mesh", process=False)
    V = image_mesh.vertices[image_mesh.faces].reshape(-1, 3) if suffix == ".stl" else image_mesh.vertices
    assert np.array_equal(back.vertices, V.astype(np.float32).astype(np.float64))
    err = np.abs(back.vertices - V)
    assert err.max() > 1e-9 * 24                     # coarser than the certificate ...
    assert np.all(err <= 2.0**-24 * np.abs(V))        # ... by the float32 rounding, no more
    assert meshing.EXPORT_PRECISION[suffix] == "float32"
    assert "float32 by format" in export_mesh.__doc__


@pytest.mark.parametrize("suffix", EXPORT_FORMATS)
def test_a_failed_export_leaves_the_old_file(image_mesh, tmp_path, monkeypatch, suffix):
    """The writer (PLY, OBJ) or the final sync (every format) fails midway: the previous file is
    still there, unchanged, and no temporary file is left behind."""
    target = tmp_path / f"surface{suffix}"
    target.write_bytes(b"the previous export")

    def broken_writer(f, *args):
        f.write(b"half a file")
        raise RuntimeError("disk full")

    def broken_fsync(fd):
        raise OSError("disk full")

    if suffix == ".ply":
        monkeypatch.setattr(mesh_export, "_write_ply", broken_writer)
    elif suffix == ".obj":
        monkeypatch.setattr(mesh_export, "_write_obj", broken_writer)
    else:
        monkeypatch.setattr(os, "fsync", broken_fsync)
    with pytest.raises((RuntimeError, OSError), match="disk full"):
        export_mesh(image_mesh, target)
    assert target.read_bytes() == b"the previous export"
    assert sorted(os.listdir(tmp_path)) == [target.name]          # no temporary file left behind


def test_a_new_export_gets_the_usual_permissions(image_mesh, tmp_path):
    mask = os.umask(0o022)
    os.umask(mask)
    path = export_mesh(image_mesh, tmp_path / "surface.ply")
    assert os.stat(path).st_mode & 0o777 == 0o666 & ~mask
    os.chmod(path, 0o600)
    export_mesh(image_mesh, path)                    # an existing file keeps its mode
    assert os.stat(path).st_mode & 0o777 == 0o600


# -- the command ---------------------------------------------------------------------------------
def _run(argv, capsys):
    out = io.StringIO()
    rc = main(argv, stream=out)
    return rc, out.getvalue(), capsys.readouterr().err


def test_cli_mesh_collinear_is_certified_and_strict_passes(tmp_path, capsys):
    target = tmp_path / "c.ply"
    rc, out, err = _run(["mesh", "--example", "collinear-3rpr", "--resolution", "48", "--strict",
                         "-o", str(target)], capsys)
    assert rc == 0, err
    assert "every vertex within" in out and "float64" in out
    assert len(trimesh.load(target, process=False).vertices) > 6000


def test_cli_mesh_float32_formats_say_so(tmp_path, capsys):
    rc, out, _ = _run(["mesh", "--resolution", "16", "-o", str(tmp_path / "s.stl")], capsys)
    assert rc == 0 and "float32" in out and "STL" in out


@pytest.mark.slow
@pytest.mark.parametrize("keep", [False, True])
def test_cli_mesh_reports_uncertified_vertices_and_strict_fails(tmp_path, capsys, keep):
    """--tol 1e-18 cannot be certified (see above): the CLI must not claim every vertex, must give
    the counts, and --strict must exit non-zero; the same mesh at the default tol passes --strict."""
    argv = ["mesh", "--resolution", "12", "--tol", "1e-18", "-o", str(tmp_path / "d.ply")]
    argv += ["--keep-uncertified"] if keep else []
    rc, out, err = _run(argv, capsys)
    assert rc == 0                                   # without --strict: written, and said
    assert "every vertex" not in out
    assert ("were kept" if keep else "were removed") in out
    rc, out, err = _run(argv + ["--strict"], capsys)
    assert rc == 1 and "--strict" in err and "without a certificate" in err
    rc, out, err = _run(["mesh", "--resolution", "12", "--strict", "-o", str(tmp_path / "d.ply")], capsys)
    assert rc == 0 and "every vertex within" in out
