"""Mechanism: the legs and every derivation from them, made once and cached behind a public
interface (issue [10])."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.core.mechanism import Mechanism, check_mechanism
from imagespace.core.planar import PlanarMechanism, form_coefficients


def test_planar_parallel_is_a_mechanism_with_the_same_derivations():
    m = isp.examples.general_3rpr()
    core = PlanarMechanism(m.legs, name="core only")
    assert isinstance(m, PlanarMechanism) and isinstance(m, Mechanism)
    # the same polynomial from the core alone as from the manipulator (both derived here)
    assert sp.expand(core.kinematic_polynomial(m.q_example).as_expr()
                     - m.kinematic_polynomial(m.q_example).as_expr()) == 0
    assert core.kinds == ("RR", "RR", "RR") and core.is_numeric
    pose = np.array([0.3, -0.2, 0.4])
    assert np.allclose(core.inverse_kinematics(pose), m.inverse_kinematics(pose))


def test_derived_artefacts_are_built_once_and_cleared_on_demand():
    m = isp.examples.general_3rpr()
    first = m.kinematic_polynomial()
    assert m.kinematic_polynomial() is first                 # cached, not re-derived
    built = []
    assert m.cached("probe", lambda: built.append(1) or "value") == "value"
    assert m.cached("probe", lambda: built.append(1) or "other") == "value" and built == [1]
    assert "probe" in m.cache_keys()
    m.clear_cache()
    assert m.cache_keys() == []
    again = m.kinematic_polynomial()
    assert again is not first and sp.expand(again.as_expr() - first.as_expr()) == 0


def test_check_q_is_public_and_names_the_parameter():
    m = isp.examples.general_3rpr()
    assert m.check_q([11, 5, 10]).tolist() == [11.0, 5.0, 10.0]
    with pytest.raises(isp.InputError, match="Q must have shape"):
        m.check_q([1, 2], name="Q")
    with pytest.raises(TypeError, match="manipulator must be a PlanarParallel"):
        check_mechanism("3-RPR")


def test_form_coefficients_against_a_hand_expansion():
    x0, x1 = sp.symbols("x0 x1")
    P = sp.Poly(sp.expand((2 * x0 - x1) ** 3), x0, x1)       # 8 x0^3 - 12 x0^2 x1 + 6 x0 x1^2 - x1^3
    assert form_coefficients(P) == [8, -12, 6, -1]


def test_the_mechanisms_tolerances_reach_the_legs_inverse_kinematics():
    """``ik_tangent`` of the design's Tolerances decides whether a pose a hair beyond an RRR leg's
    reach is the stretched elbow or out of reach."""
    legs = [isp.RRR(base=(0, 0), lengths=(1, 1), platform=(0, 0)), isp.RPR(base=(5, 0), platform=(1, 0)),
            isp.RPR(base=(0, 5), platform=(0, 1))]
    pose = [2 * (1 + 1e-14), 0.0, 0.0]
    assert isp.PlanarParallel(legs).inverse_kinematics(pose)[0] == 0.0
    tight = isp.PlanarParallel(legs, tolerances=isp.Tolerances(ik_tangent=1e-17))
    with pytest.raises(isp.InputError, match="out of reach of leg"):
        tight.inverse_kinematics(pose)
