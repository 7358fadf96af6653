"""Bad input to imagespace.design.workspace and imagespace.design.indices gets a clear error naming the
parameter (issue [14])."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.design.indices import global_indices, isotropy, local_indices
from imagespace.design.workspace import (constant_orientation_workspace, dexterous_workspace, halfplane_polygon,
                                  polygon_area, reachable_workspace, sampled_workspace)

STROKE = [[-1.0, 1.0]] * 3


@pytest.fixture(scope="module")
def m():
    return isp.examples.choi_3ppr()


@pytest.fixture(scope="module")
def g():
    return isp.examples.general_3rpr()


@pytest.mark.parametrize("call, exc, words", [
    (lambda m, g: constant_orientation_workspace(None, 0.1, STROKE), TypeError, "manipulator must be a PlanarParallel"),
    (lambda m, g: dexterous_workspace("m", (0.0, 0.3), STROKE), TypeError, "manipulator must be a PlanarParallel"),
    (lambda m, g: reachable_workspace(None, (0.0, 0.3), STROKE), TypeError, "manipulator must be a PlanarParallel"),
    (lambda m, g: constant_orientation_workspace(m, None, STROKE), TypeError, "phi must be numeric"),
    (lambda m, g: constant_orientation_workspace(m, 2**1100, STROKE), isp.InputError, "phi must be within"),
    (lambda m, g: constant_orientation_workspace(m, [0.1, 0.2], STROKE), isp.InputError, "phi must be a single"),
    (lambda m, g: constant_orientation_workspace(m, 0.1, STROKE, resolution="abc"), TypeError, "resolution"),
    (lambda m, g: constant_orientation_workspace(m, 0.1, STROKE, box="abc"), TypeError, "box must be numeric"),
    (lambda m, g: constant_orientation_workspace(m, 0.1, STROKE, resolution=2**1100), isp.InputError,
     "lower the resolution"),
    (lambda m, g: dexterous_workspace(m, 0.3, STROKE), isp.InputError, r"phi_range must be \(min, max\)"),
    (lambda m, g: dexterous_workspace(m, [], STROKE), isp.InputError, "phi_range"),
    (lambda m, g: dexterous_workspace(m, (0.0, 0.3), STROKE, n_phi=0), isp.InputError, "n_phi must be at least"),
    (lambda m, g: dexterous_workspace(m, (0.0, 0.3), STROKE, n_phi=True), TypeError, "n_phi must be a whole"),
    (lambda m, g: reachable_workspace(m, (0.0, 0.3), STROKE, n_phi=10**9), isp.InputError, "n_phi must be at most"),
    (lambda m, g: reachable_workspace(m, (0.0, 0.3), STROKE, resolution=-1), isp.InputError, "resolution"),
    (lambda m, g: sampled_workspace(g, [[5, 15]] * 3, None, [[-5, 5], [-5, 5]], 10), TypeError, "phi_range"),
    (lambda m, g: sampled_workspace(g, [[5, 15]] * 3, (0.0, 0.1), [[-5, 5], [-5, 5]], 10, n_phi=0),
     isp.InputError, "n_phi"),
    (lambda m, g: sampled_workspace(g, [[5, 15]] * 3, (0.0, 0.1), [[-5, 5], [-5, 5]], 10, kind=["reachable"]),
     isp.InputError, "kind"),
    (lambda m, g: halfplane_polygon([[1, 0]], [1], box=None), TypeError, "box must be numeric"),
    (lambda m, g: halfplane_polygon([[1, 0]], [1], box=-1), isp.InputError, "box must be a positive"),
    (lambda m, g: halfplane_polygon([[1, 0]], [1], box=2**1100), isp.InputError, "box must be within"),
    (lambda m, g: polygon_area(None), TypeError, "P must be numeric"),
    (lambda m, g: polygon_area(np.array([1 + 1j, 2, 3])), TypeError, "P must be real"),
    (lambda m, g: polygon_area(0.5), isp.InputError, r"P must have shape \(2,\)"),
    (lambda m, g: constant_orientation_workspace(m, 0.1, STROKE).contains(0.5), isp.InputError, "points must have"),
    # indices
    (lambda m, g: local_indices(None, [0.5, 1, 0.2], 1.0), TypeError, "manipulator must be a PlanarParallel"),
    (lambda m, g: local_indices(g, 0.5, 1.0), isp.InputError, r"poses must have shape \(3,\)"),
    (lambda m, g: local_indices(g, [0.5, 1, 0.2], None), TypeError, "length must be numeric"),
    (lambda m, g: local_indices(g, [0.5, 1, 0.2], -1.0), isp.InputError, "length must be a positive"),
    (lambda m, g: global_indices(g, [0.5, 1.0], None, 1.0), TypeError, "phi_range must be numeric"),
    (lambda m, g: global_indices(g, [0.5, 1.0], 0.3, 1.0), isp.InputError, "phi_range"),
    (lambda m, g: global_indices(g, [0.5, 1.0], (0.0, 0.2), 1.0, n=2.5), TypeError, "n must be a whole number"),
    (lambda m, g: global_indices(g, [0.5, 1.0], (0.0, 0.2), 1.0, n=10**12), isp.InputError, "n must be at most"),
    (lambda m, g: global_indices(None, [0.5, 1.0], (0.0, 0.2), 1.0), TypeError, "manipulator must be"),
    (lambda m, g: isotropy(np.eye(3), kind=np.array([1, 2])), TypeError, "kind must be 'condition' or 'frobenius'"),
])
def test_bad_input(m, g, call, exc, words):
    with pytest.raises(exc, match=words):
        call(m, g)


def test_valid_input_still_works(m, g):
    assert constant_orientation_workspace(m, np.float64(0.1), np.array(STROKE)).method == "exact: half-planes"
    out = global_indices(g, [0.5, 1.0], (0.0, 0.2), np.int64(1), n=np.int64(5))
    assert np.isfinite(out["manipulability"])
