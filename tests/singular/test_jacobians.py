"""Seed 003's Jacobians against finite differences of the legs' IK, statics, symbolic vs numeric."""

import numpy as np
import pytest

import imagespace as isp

LEG_CASES = [
    (isp.RPR, dict(base=(0.5, -0.3), platform=(0.2, 0.1)), (1,)),
    (isp.RRR, dict(base=(0.5, -0.3), platform=(0.2, 0.1), lengths=(2, 1.5)), (0, 1, 2)),
    (isp.PRR, dict(base=(0.5, -0.3), axis=(1, 0.3), platform=(0.2, 0.1), length=1.5), (0, 1, 2)),
    (isp.RRP, dict(base=(0.5, -0.3), length=1.5, platform=(0.2, 0.1), direction=(0.3, 1)), (0, 1, 2)),
    (isp.RPP, dict(base=(0.5, -0.3), platform=(0.2, 0.1), direction=(0.3, 1), angle=1.1), (0, 1, 2)),
    (isp.PRP, dict(base=(0.5, -0.3), axis=(1, 0.3), platform=(0.2, 0.1), direction=(0.3, 1)), (0, 1, 2)),
    (isp.PPR, dict(base=(0.5, -0.3), axis=(1, 0.3), platform=(0.2, 0.1), angle=1.2), (0, 1, 2)),
]


@pytest.mark.slow
def test_jacobian_rows_are_derivatives_of_the_leg_ik(rng):
    """Row i of J = Jq^-1 Jx is the gradient of leg i's IK (central differences), every leg type."""
    others = [isp.RPR(base=(4, 0), platform=(1, 0)), isp.RPR(base=(0, 4), platform=(0, 1))]
    checked = 0
    for cls, kw, actuated in LEG_CASES:
        for act in actuated:
            try:
                m = isp.PlanarParallel([cls(**kw, actuated=act)] + others)
            except (isp.DegenerateDesignError, isp.InputError):
                continue
            for _ in range(4):
                pose = np.array([rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.6, 0.6)])
                leg = m.legs[0]
                vals = leg.actuated_values(pose)
                for b in range(leg.n_branches):
                    if not np.isfinite(vals[b]):
                        continue
                    jac = m.jacobians(pose, working_modes=(b, 0, 0))
                    if not jac.valid or jac.inverse_kinematic:
                        continue
                    h = 1e-6
                    fd = []
                    for k in range(3):
                        e = np.zeros(3)
                        e[k] = h
                        d = leg.actuated_values(pose + e)[b] - leg.actuated_values(pose - e)[b]
                        if leg.actuated_is_angle:
                            d = np.remainder(d + np.pi, 2 * np.pi) - np.pi
                        fd.append(d / (2 * h))
                    assert np.allclose(jac.J[0], fd, rtol=1e-5, atol=1e-6), (cls.__name__, act, b)
                    checked += 1
    assert checked > 40


def test_statics_is_the_transpose():
    m = isp.examples.general_3rpr()
    jac = m.jacobians([0.5, 1.0, 0.2])
    tau = np.array([1.0, -2.0, 0.5])
    F = jac.wrench(tau)
    qdot = jac.J @ np.array([0.3, -0.1, 0.05])
    assert np.isclose(tau @ qdot, F @ [0.3, -0.1, 0.05])                 # virtual power


@pytest.mark.slow
def test_symbolic_jacobians_equal_the_numeric_ones(rng):
    import sympy as sp
    from imagespace.singular.jacobians import symbolic_jacobians
    for m in (isp.examples.stigger_husty(), isp.examples.collinear_3rpr(2, 1)):
        Jx, Jq, syms = symbolic_jacobians(m)
        f = sp.lambdify(list(syms) + list(m.joint_symbols), [Jx, Jq], "numpy")
        for _ in range(5):
            pose = np.array([rng.uniform(-3, 3), rng.uniform(0.5, 3), rng.uniform(-1, 1)])
            q = m.inverse_kinematics(pose)
            jac = m.jacobians(pose)
            Jxn, Jqn = (np.array(a, dtype=float) for a in f(*pose, *q))
            assert np.allclose(Jxn, jac.Jx, rtol=1e-10, atol=1e-10)
            assert np.allclose(Jqn, jac.Jq, rtol=1e-10, atol=1e-10)
