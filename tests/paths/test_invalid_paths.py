"""Paths refuse what is not a path and stay right on extreme representatives (issue [9])."""

import warnings
from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.paths.check import polynomial_curve, rational_curve


@pytest.mark.parametrize("call, exc, words", [
    (lambda: polynomial_curve([["1", 0, 0, 0], [0, 1, 0, 0]]), TypeError, "strings are never parsed|real numbers"),
    (lambda: rational_curve([[1, 0, 0, 0], [0, 1, 0, 0]], ["1"]), TypeError, "strings are never parsed"),
    (lambda: rational_curve([[1, 0, 0, 0], [0, 1, 0, 0]], [True]), TypeError, "bool"),
    (lambda: isp.segment([1, 0, 0, 0], None), TypeError, "b must be numeric"),
    (lambda: isp.segment([0, 0, 1, 0], [1, 0, 0, 0]), isp.InputError, "absolute line"),
])
def test_path_input_of_the_wrong_kind(call, exc, words):
    with pytest.raises(exc, match=words):
        call()


def test_a_sympy_float_is_its_binary_rational():
    """sp.Float(0.1) is 3602879701896397/2**55, not 1/10: the path goes through the float given."""
    c = polynomial_curve([[1, 0, 0, 0], [0, sp.Float(0.1), 0, 0]])
    assert Fraction(c.pieces[0][1, 1]) == Fraction(0.1) != Fraction(1, 10)


def test_huge_representative_evaluates_its_own_endpoints():
    """(1 - t) a + t b with |a| = 1e300 and |b| = 1: the monomial form a + t (b - a) rounds to 0
    at t = 1; the path must still end at b and start at a."""
    a = np.array([1.0, 0.1, 0.2, 0.3]) * 1e300
    b = np.array([1.0, -0.2, 0.5, 0.1])
    p = isp.segment(a, b)
    assert np.array_equal(p.end, b) and np.array_equal(p.start, a)


def test_check_path_does_not_depend_on_the_scale_of_a_representative():
    """Scaling one endpoint by k > 0 reparametrises the segment (same points, t -> t' monotone):
    the crossing count and kind are the same, with no overflow warning. Scaling both by k keeps
    the parameter, so the crossing interval is the same too."""
    m = isp.examples.general_3rpr()
    S = isp.singularity_surface(m)
    modes = m.direct_kinematics(m.q_example_float)
    up = next(md for md in modes if md.aspect == 1).image_point
    down = next(md for md in modes if md.aspect == -1).image_point
    a, b = up / up[0], down / down[0]
    ref = isp.check_path(S, isp.segment(a, b))
    assert ref.crosses                      # opposite aspects: the surface separates them
    for k in (1e30, 1e300):
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            one = isp.check_path(S, isp.segment(a * k, b))
            both = isp.check_path(S, isp.segment(a * k, b * k))
        assert [c.multiplicity for c in one.crossings] == [c.multiplicity for c in ref.crossings]
        assert [c.t for c in both.crossings] == [c.t for c in ref.crossings]
