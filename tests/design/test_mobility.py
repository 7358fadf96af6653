"""Mobility (Grübler) of mechanisms and manipulators."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.design.mobility import gruebler, manipulator_mobility, mechanism_mobility

STROKE = [[-np.sqrt(3), np.sqrt(3)]] * 3
LEG_CASES = [
    (isp.RPR, dict(base=(0.5, -0.3), platform=(0.2, 0.1)), (1,)),
    (isp.RRR, dict(base=(0.5, -0.3), platform=(0.2, 0.1), lengths=(2, 1.5)), (0, 1, 2)),
    (isp.PRR, dict(base=(0.5, -0.3), axis=(1, 0.3), platform=(0.2, 0.1), length=1.5), (0, 1, 2)),
    (isp.RRP, dict(base=(0.5, -0.3), length=1.5, platform=(0.2, 0.1), direction=(0.3, 1)), (0, 1, 2)),
    (isp.RPP, dict(base=(0.5, -0.3), platform=(0.2, 0.1), direction=(0.3, 1), angle=1.1), (0, 1, 2)),
    (isp.PRP, dict(base=(0.5, -0.3), axis=(1, 0.3), platform=(0.2, 0.1), direction=(0.3, 1)), (0, 1, 2)),
    (isp.PPR, dict(base=(0.5, -0.3), axis=(1, 0.3), platform=(0.2, 0.1), angle=1.2), (0, 1, 2)),
]


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
