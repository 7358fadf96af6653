"""Mobility (Grübler) of mechanisms and manipulators."""

import pytest

import imagespace as isp
from imagespace.design.mobility import gruebler, manipulator_mobility, mechanism_mobility


# -- mobility ----------------------------------------------------------------------------------------
def test_gruebler_counts():
    assert gruebler(8, 9).M == 3                                          # 3-RPR
    assert manipulator_mobility(isp.examples.general_3rpr()).M == 3
    m = isp.examples.choi_3ppr()
    assert manipulator_mobility(m).M == 3
    lock = manipulator_mobility(m, locked=True)
    assert lock.M == 0 and lock.kind == "structure"
    assert gruebler(4, "RRRR").M == 1                                     # four-bar
    assert gruebler(14, "UPS" * 6, D=6).M == 6                            # Gough-Stewart 6-UPS
    assert gruebler(8, "RPS" * 3, D=6).M == 3                             # 3-RPS
    assert gruebler(4, "RRRR", D=6).M == -2                               # Bennett: moves anyway (documented)
    assert mechanism_mobility(["g", "a", "b"], [("g", "a", "R"), ("a", "b", "R"), ("b", "g", "R")]).kind == "structure"


def test_gruebler_bad_input():
    with pytest.raises(isp.InputError, match="D must be"):
        gruebler(4, 4, D=4)
    with pytest.raises(isp.InputError, match="joints\\[0\\]"):
        gruebler(4, ["X"])
    with pytest.raises(isp.InputError, match="unknown link"):
        mechanism_mobility(["g", "a"], [("g", "z", "R")])
