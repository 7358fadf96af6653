"""The thresholds of singular/ (cusps, linking number, implicit functions, meshing) are read from
``Tolerances``: a loosened or tightened field changes the decision on a constructed input."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.singular.cusps import cusp_edges, cusps, linking_number
from imagespace.singular.meshing import PolynomialImplicit, mesh_implicit

WINDOW = [(8, 14), (2, 8)]


def with_tolerances(base, **fields):
    return isp.PlanarParallel(base.legs, tolerances=isp.Tolerances(**fields))


@pytest.mark.slow
def test_cusps_read_the_seed_merge_and_chain_thresholds():
    base = isp.examples.general_3rpr()
    sections = [9.9, 10.0, 10.1]
    assert len(cusps(base, 2, 10.0, WINDOW, 40)) >= 2
    assert cusp_edges(base, 2, sections, WINDOW, 40)
    # a merge radius the size of the whole window makes every cusp one cluster, and a reach of
    # nothing joins no cusp of one section to the next
    loose = with_tolerances(base, cusp_merge=100.0, cusp_chain_reach=1e-300)
    assert len(cusps(loose, 2, 10.0, WINDOW, 40)) == 1
    assert cusp_edges(loose, 2, sections, WINDOW, 40) == []
    # every seed's leading coefficient counts as zero: no seed, no cusp
    assert cusps(with_tolerances(base, cusp_leading_coefficient=10.0), 2, 10.0, WINDOW, 40) == []


def test_linking_number_reads_linking_parallel():
    t = np.linspace(0, 2 * np.pi, 65)
    circle = np.column_stack([np.cos(t), np.sin(t), 0 * t])
    axis = [np.array([[0.2, 0.1, -1.0], [0.2, 0.1, 1.0]])]
    assert linking_number(circle, axis) == 1
    assert linking_number(circle, axis, tolerances=isp.Tolerances()) == 1
    # every cone triangle counted as parallel to the segment: no crossing is seen
    assert linking_number(circle, axis, tolerances=isp.Tolerances(linking_parallel=1e6)) == 0
    with pytest.raises(TypeError, match="tolerances must be an imagespace.Tolerances"):
        linking_number(circle, axis, tolerances={"linking_parallel": 1.0})


def test_polynomial_implicit_reads_implicit_coefficient():
    u, v, w = sp.symbols("u v w")
    expr = u**2 + v**2 + w**2 - sp.pi              # pi rounds to float with a relative error ~1e-17
    assert PolynomialImplicit(expr, (u, v, w)).sign_test == "rounding-error bound, arb below it"
    strict = PolynomialImplicit(expr, (u, v, w), tolerances=isp.Tolerances(implicit_coefficient=1e-30))
    assert strict.sign_test.startswith("float signs")
    with pytest.raises(TypeError, match="tolerances must be an imagespace.Tolerances"):
        PolynomialImplicit(expr, (u, v, w), tolerances=1e-6)


@pytest.fixture(scope="module")
def sphere():
    u, v, w = sp.symbols("u v w")
    return PolynomialImplicit(u**2 + v**2 + w**2 - 1, (u, v, w))


def test_mesh_implicit_reads_the_meshing_thresholds(sphere):
    box = [(-1.5, 1.5)] * 3
    plain = mesh_implicit(sphere, box, 12)
    md = plain.metadata["imagespace"]
    assert len(plain.faces) > 100 and md["searched"] < len(plain.vertices)
    # every marching-cubes coordinate taken as lying on a grid plane: no vertex is on an edge, all
    # go to the neighbourhood search
    on_grid = mesh_implicit(sphere, box, 12, tolerances=isp.Tolerances(mesh_on_grid=0.6))
    assert on_grid.metadata["imagespace"]["searched"] > md["searched"]
    # every vertex within 0.6 cells of a node (on every axis) is merged onto it: fewer vertices
    merged = mesh_implicit(sphere, box, 12, tolerances=isp.Tolerances(mesh_node_merge=0.6))
    assert len(merged.vertices) < len(plain.vertices)
    # every face lower than a huge altitude is degenerate: nothing is left
    flat = mesh_implicit(sphere, box, 12, tolerances=isp.Tolerances(mesh_min_altitude=1e12))
    assert len(flat.faces) == 0
    with pytest.raises(TypeError, match="tolerances must be an imagespace.Tolerances"):
        mesh_implicit(sphere, box, 12, tolerances="loose")


def test_mesh_surface_reads_the_manipulators_tolerances():
    base = isp.examples.stigger_husty()
    box = [(-12, 12), (-12, 12), (-3, 3)]
    assert len(isp.mesh_surface(base.singularity_surface(), box, resolution=16).faces) > 0
    flat = with_tolerances(base, mesh_min_altitude=1e12)
    assert len(isp.mesh_surface(flat.singularity_surface(), box, resolution=16).faces) == 0
