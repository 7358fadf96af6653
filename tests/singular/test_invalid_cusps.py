"""Bad input to imagespace.singular.cusps gets a clear error naming the parameter (issue [14])."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.paths.cusp_loops import CuspLoop, cusp_loop
from imagespace.singular.cusps import Cusp, cusp_edges, cusps, linking_number, mode_count_map

W = [(8, 14), (2, 8)]


@pytest.fixture(scope="module")
def m():
    return isp.examples.general_3rpr()


@pytest.fixture(scope="module")
def cusp():
    return Cusp(np.array([11.0, 5.0, 10.0]), 0.1, np.full(3, np.nan), 0.0)


@pytest.mark.parametrize("call, exc, words", [
    (lambda m, c: isp.cusp_loop(m, None, 0, 0.1), TypeError, "cusp must be a Cusp"),
    (lambda m, c: cusp_loop(None, c, 2, 0.1), TypeError, "manipulator must be a PlanarParallel"),
    (lambda m, c: cusp_loop(m, c, 2, 0.1, steps=0), isp.InputError, "steps must be at least"),
    (lambda m, c: cusp_loop(m, c, 2, 0.1, steps=2.5), TypeError, "steps must be a whole number"),
    (lambda m, c: cusp_loop(m, c, 2, 0.1, steps=2**1100), isp.InputError, "steps must be at most"),
    (lambda m, c: cusp_loop(m, c, 2, "a"), TypeError, "radius must be numeric"),
    (lambda m, c: cusp_loop(m, c, 2, np.inf), isp.InputError, "radius must be finite"),
    (lambda m, c: cusp_loop(m, c, 2.0, 0.1), TypeError, "fixed must be the whole number"),
    (lambda m, c: mode_count_map(None, 2, 10.0, W, 8), TypeError, "manipulator must be a PlanarParallel"),
    (lambda m, c: mode_count_map(m, 1.0, 10.0, W, 8), TypeError, "fixed must be the whole number"),
    (lambda m, c: mode_count_map(m, "a", 10.0, W, 8), TypeError, "fixed"),
    (lambda m, c: mode_count_map(m, 2, None, W, 8), TypeError, "value must be numeric"),
    (lambda m, c: mode_count_map(m, 2, "a", W, 8), TypeError, "value must be numeric"),
    (lambda m, c: mode_count_map(m, 2, [1.0, 2.0], W, 8), isp.InputError, "value must be a single number"),
    (lambda m, c: mode_count_map(m, 2, 10.0, None, 8), TypeError, "window must be numeric"),
    (lambda m, c: mode_count_map(m, 2, 10.0, W, -1), isp.InputError, "resolution must be at least 8"),
    (lambda m, c: mode_count_map(m, 2, 10.0, W, 2.5), TypeError, "resolution must be a whole number"),
    (lambda m, c: cusps(m, 0, 1.0, [[0, 1], [0, 1]], resolution=0), isp.InputError, "resolution"),
    (lambda m, c: cusps(m, 2, 10.0, W, 8, tol="a"), TypeError, "tol must be numeric"),
    (lambda m, c: cusps(m, 2, 10.0, W, 8, tol=-1.0), isp.InputError, "tol must be a positive"),
    (lambda m, c: cusps(m, 2, 10.0, W, 8, max_seeds=0), isp.InputError, "max_seeds must be at least 1"),
    (lambda m, c: cusp_edges(None, 2, [9.9, 10.0], W, 8), TypeError, "manipulator must be"),
    (lambda m, c: cusp_edges(m, 2, [9.9, 10.0], None, 8), TypeError, "window must be numeric"),
    (lambda m, c: cusp_edges(m, 2, [9.9, 10.0], W, 2.5), TypeError, "resolution must be a whole number"),
    (lambda m, c: isp.linking_number(None, None), TypeError, "loop must be numeric"),
    (lambda m, c: linking_number(np.eye(3), None), TypeError, "curves must be a sequence"),
    (lambda m, c: linking_number(np.eye(3), np.zeros((4, 3))), isp.InputError, r"curves\[0\] must be a \(k, 3\)"),
    (lambda m, c: linking_number([1.0, 2.0, 3.0], []), isp.InputError, r"loop must be a \(n, 3\) polyline"),
])
def test_bad_input(m, cusp, call, exc, words):
    with pytest.raises(exc, match=words):
        call(m, cusp)


def test_certified_path_checks_its_arguments():
    m = isp.examples.general_3rpr()
    loop = CuspLoop(np.zeros((3, 3)), np.array([[0.0, 0.0, 0.1], [0.1, 0.0, 0.1], [0.2, 0.0, 0.1]]), 0, 0, False,
                    np.ones(3, int))
    with pytest.raises(TypeError, match="manipulator must be a PlanarParallel"):
        loop.certified_path(None)
    with pytest.raises(isp.InputError, match="every must be at least 1"):
        loop.certified_path(m, every=0)                 # was a ZeroDivisionError
    with pytest.raises(TypeError, match="every must be a whole number"):
        loop.certified_path(m, every=2.5)               # was an IndexError


def test_valid_input_still_works(m):
    cm = mode_count_map(m, np.int64(2), 10, np.array(W), np.int64(8))
    assert cm.counts.shape == (8, 8)
    t = np.linspace(0, 2 * np.pi, 33)
    circle = np.column_stack([np.cos(t), np.sin(t), 0 * t])
    assert linking_number(circle, [np.array([[0.2, 0.1, -1.0], [0.2, 0.1, 1.0]])]) == 1
