"""Bad input to imagespace.singular.surface gets a clear error naming the parameter (issue [14]).

Each case is a reproducer that, before the fix, crashed with an internal exception or was
accepted silently."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.singular.jacobians import symbolic_jacobians
from imagespace.singular.surface import image_chart_point, pose_chart_point


@pytest.fixture(scope="module")
def m():
    return isp.examples.general_3rpr()


@pytest.fixture(scope="module")
def rrr():
    return isp.PlanarParallel([isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3, 2), actuated=0),
                               isp.RPR(base=(6, 0), platform=(1, 0)), isp.RPR(base=(2, 5), platform=(0, 1))])


@pytest.mark.parametrize("call", [
    lambda m: isp.singularity_surface(None),
    lambda m: isp.singularity_surface("m"),
    lambda m: isp.singularity_surfaces(None),
    lambda m: isp.jacobians(None, [0.5, 1.0, 0.2]),
    lambda m: symbolic_jacobians(None),
])
def test_not_a_manipulator(m, call):
    with pytest.raises(TypeError, match="manipulator must be a PlanarParallel"):
        call(m)


@pytest.mark.parametrize("call, exc, words", [
    # joint-free surface: q and working_modes are still checked, not silently ignored
    (lambda m: isp.singularity_surface(m, "abc"), TypeError, "q must be numeric"),
    (lambda m: isp.singularity_surface(m, [1.0, 2.0]), isp.InputError, r"q must have shape \(3,\)"),
    (lambda m: isp.singularity_surface(m, [[11, 5, 10]] * 2), isp.InputError, r"q must have shape \(3,\)"),
    (lambda m: isp.singularity_surface(m, [np.nan, 5, 10]), isp.InputError, "q must be finite"),
    (lambda m: isp.singularity_surface(m, [-1.0, 5, 10]), isp.InputError, r"q\[0\]"),
    (lambda m: isp.singularity_surface(m, np.array([11 + 1j, 5, 10])), TypeError, "q must be real"),
    (lambda m: isp.singularity_surface(m, [sp.Symbol("a"), "1", 0]), TypeError, r"q\[1\]"),
    (lambda m: isp.singularity_surface(m, working_modes=(0.5, 0, 0)), TypeError,
     r"working_modes\[0\] must be a whole number"),
    (lambda m: isp.singularity_surface(m, working_modes=(5, 0, 0)), isp.InputError, r"working_modes\[0\]"),
    (lambda m: isp.singularity_surface(m, working_modes=3), TypeError, "working_modes must be a sequence"),
    (lambda m: isp.singularity_surface(m, working_modes=(0, 0)), isp.InputError, "three entries"),
    (lambda m: isp.singularity_surface(m, [11, 5, 10], working_modes=(0, 0, 0)), isp.InputError, "not both"),
    (lambda m: isp.jacobians(m, [0.5, 1.0, 0.2], working_modes=(0.5, 0, 0)), TypeError, r"working_modes\[0\]"),
    (lambda m: isp.jacobians(m, [[0.5, 1.0, 0.2]] * 2, q=[[11, 5, 10]] * 3), isp.InputError,
     "one row per pose"),
    (lambda m: isp.jacobians(m, [0.5, 1.0, 0.2], q="abc"), TypeError, "q must be numeric"),
])
def test_bad_joint_values_and_working_modes(m, call, exc, words):
    with pytest.raises(exc, match=words):
        call(m)


def test_bad_working_modes_of_a_joint_dependent_surface(rrr):
    with pytest.raises(TypeError, match=r"working_modes\[0\] must be a whole number"):
        isp.singularity_surface(rrr, working_modes=(0.5, 0, 0))
    with pytest.raises(TypeError, match=r"working_modes\[1\]"):
        isp.singularity_surface(rrr, working_modes=(1, True, 0))


@pytest.mark.slow
def test_valid_input_still_works(m, rrr):
    assert isp.singularity_surface(m, m.q_example_float).kind == "joint-free"
    assert isp.singularity_surface(m, m.q_example).kind == "joint-free"
    assert isp.singularity_surface(m, working_modes=(1, 1, 1)).kind == "joint-free"
    assert isp.singularity_surface(rrr, working_modes=np.array([1, 0, 0])).working_modes == (1, None, None)
    S = isp.singularity_surface(rrr, q=(0.1, 4, 4))
    assert S.kind == "given-joints"
    jac = isp.jacobians(m, [[0.5, 1.0, 0.2]] * 2, q=m.inverse_kinematics([0.5, 1.0, 0.2]))
    assert jac.kind.tolist() == ["regular", "regular"]


@pytest.fixture(scope="module")
def S(m):
    return isp.singularity_surface(m)


@pytest.mark.parametrize("call, exc, words", [
    (lambda m, S: isp.ConicSection.of(None, 0.4), TypeError, "surface must be a SingularitySurface"),
    (lambda m, S: S.section([0.1, 0.2]), isp.InputError, "phi must be a single number"),
    (lambda m, S: S.section_coefficients([[0.1, 0.2]]), isp.InputError, r"phi must be a number or a \(n,\) array"),
    (lambda m, S: S.at_poses([0.1, 0.2, 0.3], gradient="yes"), TypeError, "gradient must be True or False"),
    (lambda m, S: S.chart_expression(np.array([1, 2])), TypeError, "chart must be 'image' or 'pose'"),
    (lambda m, S: S.section(0.4)("abc", 1.0), TypeError, "x must be numeric"),
    (lambda m, S: S.section(0.4)(2**1100, 1.0), isp.InputError, "x must be within the float range"),
    (lambda m, S: S.section(0.4)([1.0, 2.0], [1.0, 2.0, 3.0]), isp.InputError, "x and y must broadcast"),
    (lambda m, S: isp.jacobians(m, [0.5, 1.0, 0.2]).homogeneous(None), TypeError, "length must be numeric"),
    (lambda m, S: isp.jacobians(m, [0.5, 1.0, 0.2]).homogeneous(2**1100), isp.InputError, "length"),
    (lambda m, S: pose_chart_point(None), TypeError, "P must be numeric"),
    (lambda m, S: pose_chart_point([[1.0, 2.0]]), isp.InputError, r"P must have shape \(3,\)"),
    (lambda m, S: image_chart_point(0.5), isp.InputError, r"U must have shape \(3,\)"),
])
def test_bad_input_to_surface_methods(m, S, call, exc, words):
    with pytest.raises(exc, match=words):
        call(m, S)
