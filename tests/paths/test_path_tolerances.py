"""The thresholds of paths/ (mode membership and identity, cusp-loop continuity) are read from the
manipulator's ``Tolerances``: a loosened or tightened field changes the decision on a constructed
input."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.paths.check import pose_segment
from imagespace.paths.cusp_loops import cusp_loop
from imagespace.paths.modechange import joint_trajectory, plan_mode_change
from imagespace.singular.cusps import cusps


def with_tolerances(base, **fields):
    return isp.PlanarParallel(base.legs, tolerances=isp.Tolerances(**fields))


def test_joint_trajectory_reads_mode_membership():
    base = isp.examples.general_3rpr()
    q0 = base.inverse_kinematics([0.0, 0.0, 0.0])
    off = q0 + 1e-4                                   # a leg residual of ~1e-5: not the start pose
    path = pose_segment([0, 0, 0], [1, 0, 0.2])
    with pytest.raises(isp.InputError, match="path does not start at a pose of q_start"):
        joint_trajectory(base, path, off, 4)
    P, Q = joint_trajectory(with_tolerances(base, mode_membership=1e-2), path, off, 4)
    assert Q.shape == (5, 3) and np.allclose(Q[0], q0, atol=1e-3)


def test_plan_mode_change_reads_same_mode_and_mode_membership():
    base = isp.examples.stigger_husty()
    q = base.q_example_float
    modes = base.direct_kinematics(base.q_example)
    # two modes of opposite aspects: refused with a reason, not as the same mode
    plan = plan_mode_change(base, q, modes[0], modes[1])
    assert not plan.found and "opposite aspects" in plan.reason
    with pytest.raises(isp.InputError, match="the same assembly mode"):
        plan_mode_change(with_tolerances(base, same_mode=100.0), q, modes[0], modes[1])
    # a mode of slightly different joint values: refused, unless membership is loosened
    q_off = q + 1e-3
    with pytest.raises(isp.InputError, match="mode_a is not an assembly mode of q"):
        plan_mode_change(base, q_off, modes[0], modes[1])
    plan = plan_mode_change(with_tolerances(base, mode_membership=1.0), q_off, modes[0], modes[1])
    assert not plan.found and "opposite aspects" in plan.reason


@pytest.mark.slow
def test_cusp_loop_reads_the_jump_thresholds():
    base = isp.examples.general_3rpr()
    c = cusps(base, 2, 10.0, [(8, 14), (2, 8)], 60)[0]
    assert cusp_loop(base, c, 2, 0.05).continuous
    # no step may exceed a thousandth of the median step: every walk counts as jumping
    strict = with_tolerances(base, loop_jump_ratio=1e-3, loop_jump_floor=1e-300)
    loop = cusp_loop(strict, c, 2, 0.05)
    assert not loop.continuous
