"""Bad input to imagespace.design.mobility gets a clear error naming the parameter (issue [14])."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.design.mobility import gruebler, manipulator_mobility, mechanism_mobility


@pytest.mark.parametrize("call, exc, words", [
    (lambda: isp.manipulator_mobility(None), TypeError, "manipulator must be a PlanarParallel"),
    (lambda: isp.manipulator_mobility("m"), TypeError, "manipulator must be a PlanarParallel"),
    (lambda: manipulator_mobility(isp.examples.choi_3ppr(), locked="yes"), TypeError,
     "locked must be True or False"),
    (lambda: gruebler(-3, [1, 1]), isp.InputError, "n must be at least 1"),
    (lambda: gruebler(2.5, [1]), TypeError, "n must be a whole number"),
    (lambda: gruebler(4, None), TypeError, "joints must be"),
    (lambda: gruebler(4, 2.5), TypeError, "joints must be"),
    (lambda: gruebler(4, [2.5]), TypeError, r"joints\[0\] must be a whole number"),
    (lambda: gruebler(4, [None]), TypeError, r"joints\[0\]"),
    (lambda: gruebler(4, [-1]), isp.InputError, r"joints\[0\] must be at least 0"),
    (lambda: gruebler(4, 4, D=3.0), TypeError, "D must be the whole number"),
    (lambda: gruebler(4, 4, D="3"), TypeError, "D must be"),
    (lambda: mechanism_mobility(None, []), TypeError, "links must be a sequence"),
    (lambda: mechanism_mobility([[1], [2]], []), TypeError, r"links\[0\] must be a hashable name"),
    (lambda: mechanism_mobility([], []), isp.InputError, "links must name at least one link"),
    (lambda: mechanism_mobility(["g", "a"], None), TypeError, "joints must be a sequence"),
])
def test_bad_input(call, exc, words):
    with pytest.raises(exc, match=words):
        call()


def test_valid_input_still_works():
    assert gruebler(np.int64(8), np.int64(9)).M == 3
    assert gruebler(4, "RRRR", D=np.int64(3)).M == 1
    assert manipulator_mobility(isp.examples.choi_3ppr(), locked=np.bool_(True)).M == 0
