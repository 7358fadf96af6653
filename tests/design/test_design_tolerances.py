"""Every Tolerances field of imagespace.design is read: changing it changes a decision on a
constructed input (manipulator.tolerances for the workspaces, the tolerances keyword of
Workspace.contains and fuzzy_minmax)."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.design.sweep import _demo_index, fuzzy_minmax, sweep
from imagespace.design.workspace import (Workspace, constant_orientation_workspace, dexterous_workspace,
                                         reachable_workspace)

STROKE = [[-np.sqrt(3), np.sqrt(3)]] * 3
BOX = [(-3, 3), (-3, 3)]


def choi(**fields):
    return isp.PlanarParallel(isp.examples.choi_3ppr().legs, tolerances=isp.Tolerances(**fields))


def prp(**fields):
    """A 3-PRP actuated at the base sliders: q_i = a_i(phi) . p + c_i(phi), affine in p at each phi
    but with coefficients that turn with phi."""
    legs = [isp.PRP(base=(-2, 0), axis=(0, 1), platform=(0, 0), direction=(1, 0.2)),
            isp.PRP(base=(0, -2), axis=(1, 0), platform=(0.3, 0), direction=(0.1, 1)),
            isp.PRP(base=(2, 2), axis=(1, -1), platform=(0, 0.3), direction=(1, 1))]
    return isp.PlanarParallel(legs, tolerances=isp.Tolerances(**fields))


def test_workspace_inside_decides_the_boundary_of_an_exact_polygon():
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    ws = Workspace("constant-orientation", 1.0, square, "exact: half-planes")
    just_out = [[1 + 1e-9, 0.5]]
    assert not ws.contains(just_out)[0]
    assert ws.contains(just_out, tolerances=isp.Tolerances(workspace_inside=1e-6))[0]
    with pytest.raises(TypeError, match="tolerances must be an imagespace.Tolerances"):
        ws.contains(just_out, tolerances=1e-6)


def test_workspace_affine_decides_the_exact_route():
    assert constant_orientation_workspace(choi(), 0.0, STROKE).method == "exact: half-planes"
    # no rounding at all allowed: the (exactly affine) IK no longer counts as affine
    tight = constant_orientation_workspace(choi(workspace_affine=1e-300), 0.0, STROKE, box=BOX, resolution=40)
    assert tight.method.startswith("sampled")


def test_workspace_affine_constant_and_common_offset_decide_for_a_turning_design():
    rng, lim = (-0.2, 0.2), [[-4, 4]] * 3
    assert dexterous_workspace(prp(), rng, lim, box=BOX, resolution=40, n_phi=5).method.startswith("sampled")
    loose = prp(workspace_affine_constant=1e3)
    assert dexterous_workspace(loose, rng, lim, box=BOX, resolution=40, n_phi=5).method == "exact: half-planes"
    # the offsets c_i(phi) do not differ by constants: reachable is sampled unless that is loosened too
    assert reachable_workspace(loose, rng, lim, box=BOX, resolution=40, n_phi=5).method.startswith("sampled")
    both = prp(workspace_affine_constant=1e3, workspace_common_offset=1e3)
    assert reachable_workspace(both, rng, lim, box=BOX, resolution=40, n_phi=5).method == "exact: polytope projection"


def test_workspace_vertex_fields_decide_the_reachable_polytope():
    rng = (-0.5, 0.5)
    area = reachable_workspace(choi(), rng, STROKE).area
    assert area > 0
    assert reachable_workspace(choi(workspace_vertex_det=1e6), rng, STROKE).area == 0.0   # no vertex at all
    assert reachable_workspace(choi(workspace_vertex_feasible=1e6), rng, STROKE).area > area  # infeasible kept


def test_fuzzy_tie_decides_which_rows_are_best():
    t = sweep(_demo_index, {"a": [1.0, 2.0, 3.0], "b": [1.0, 2.0]}, processes=0, progress=False)
    crit = {"sum": (1.0, "max")}
    assert len(fuzzy_minmax(t, crit).best) == 1
    assert len(fuzzy_minmax(t, crit, tolerances=isp.Tolerances(fuzzy_tie=1.0)).best) == len(t.errors)
    with pytest.raises(TypeError, match="tolerances must be an imagespace.Tolerances"):
        fuzzy_minmax(t, crit, tolerances="loose")
