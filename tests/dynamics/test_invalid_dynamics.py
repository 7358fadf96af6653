"""Bad input to imagespace.dynamics gets a clear error naming the parameter (issue [14])."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.dynamics import (Body, LinePath, OpenTreeModel, TimeLaw, consistent_acceleration, cubic_rest_to_rest,
                                 drive_singularity, inverse_dynamics, plan_consistent_law, power_balance,
                                 seed000_model, seed000_path, sextic_through, simulate, state)

G0 = [0.69, 2.2, 2.46, 0.36, 0.0]


@pytest.fixture(scope="module")
def setup():
    model = seed000_model()
    path = LinePath(*seed000_path())
    law = cubic_rest_to_rest(1.5, 1.0)
    res = inverse_dynamics(model, path, law, [0.1, 0.2], G0)
    return model, path, law, res


@pytest.mark.parametrize("call, exc, words", [
    (lambda M, p, law, r: state(None, p, 0.0, guess=G0), TypeError, "model must be an OpenTreeModel"),
    (lambda M, p, law, r: state(M, None, 0.0, guess=G0), TypeError, "path must be a LinePath"),
    (lambda M, p, law, r: state(M, p, "abc", guess=G0), TypeError, "s must be numeric"),
    (lambda M, p, law, r: state(M, p, 0.0, sd=np.nan, guess=G0), isp.InputError, "sd must be finite"),
    (lambda M, p, law, r: state(M, p, 0.0, guess=[1.0, 2.0]), isp.InputError, r"guess must have shape \(5,\)"),
    (lambda M, p, law, r: state(M, p, 0.0), isp.InputError, "Gamma is singular"),
    (lambda M, p, law, r: drive_singularity(M, p, (0.0, 1.5), G0, samples=2.5), TypeError, "samples must be a whole"),
    (lambda M, p, law, r: drive_singularity(M, p, (0.0, 1.5), G0, samples=10**12), isp.InputError, "samples must be at most"),
    (lambda M, p, law, r: drive_singularity(M, p, 1.5, G0), isp.InputError, r"s_range must have shape \(2,\)"),
    (lambda M, p, law, r: drive_singularity(M, p, (0.0, 1.5), None), TypeError, "guess must be numeric"),
    (lambda M, p, law, r: consistent_acceleration(M, p, None, 1.7), TypeError, "sing must be a DriveSingularity"),
    (lambda M, p, law, r: plan_consistent_law(M, p, None, 1.0, 1.5), TypeError, "sing must be a DriveSingularity"),
    (lambda M, p, law, r: inverse_dynamics(M, p, None, [0.1], G0), TypeError, "law must be a TimeLaw"),
    (lambda M, p, law, r: inverse_dynamics(M, p, law, [0.1], G0, sing="x"), TypeError, "sing must be"),
    (lambda M, p, law, r: inverse_dynamics(M, p, law, [0.1], G0, eps="abc"), TypeError, "eps must be numeric"),
    (lambda M, p, law, r: inverse_dynamics(M, p, law, [0.1], G0, mu_dot_correction="no"), TypeError,
     "mu_dot_correction must be True or False"),
    (lambda M, p, law, r: inverse_dynamics(M, p, law, [-1.0], G0), isp.InputError, r"times must lie in .*\[0, T\]"),
    (lambda M, p, law, r: inverse_dynamics(M, p, law, [], G0), isp.InputError, "times must be a non-empty"),
    (lambda M, p, law, r: inverse_dynamics(M, p, law, "abc", G0), TypeError, "times must be numeric"),
    (lambda M, p, law, r: power_balance(M, p, law, None), TypeError, "result must be an InverseDynamicsResult"),
    (lambda M, p, law, r: power_balance(M, p, law, r, h=-1.0), isp.InputError, "h must be positive"),
    (lambda M, p, law, r: simulate(M, p, law, r, G0, baumgarte=20.0), isp.InputError, r"baumgarte must have shape \(2,\)"),
    (lambda M, p, law, r: simulate(M, p, law, r, G0, rtol=None), TypeError, "rtol must be numeric"),
    (lambda M, p, law, r: LinePath([0.0, 0.0], [1.0, 0.0, 0.0]), isp.InputError, r"e must have shape \(2,\)"),
    (lambda M, p, law, r: LinePath([0.0, 0.0], [0.0, 0.0]), isp.InputError, "e must be a non-zero direction"),
    (lambda M, p, law, r: LinePath(None, [1.0, 0.0]), TypeError, "x0 must be numeric"),
    (lambda M, p, law, r: TimeLaw([0.0, 1.0], 0.0), isp.InputError, "T must be positive"),
    (lambda M, p, law, r: TimeLaw("abc", 1.0), TypeError, "coefficients must be numeric"),
    (lambda M, p, law, r: law(0.5, order=-1), isp.InputError, "order must be at least 0"),
    (lambda M, p, law, r: law(0.5, order=1.5), TypeError, "order must be a whole number"),
    (lambda M, p, law, r: law("abc"), TypeError, "t must be numeric"),
    (lambda M, p, law, r: law.is_monotone(n=0), isp.InputError, "n must be at least 2"),
    (lambda M, p, law, r: cubic_rest_to_rest(None, 1.0), TypeError, "L must be numeric"),
    (lambda M, p, law, r: cubic_rest_to_rest(1.5, 2**1100), isp.InputError, "T must be within"),
    (lambda M, p, law, r: sextic_through(1.0, 1.5, "0.6", 0.662, 1.7, 10.6), TypeError, "Td must be numeric"),
    (lambda M, p, law, r: M.M([1.0, 2.0]), isp.InputError, r"eta must have shape \(5,\)"),
    (lambda M, p, law, r: M.R(G0, "abc"), TypeError, "etad must be numeric"),
    (lambda M, p, law, r: seed000_model({"m1": "__import__('os')"}), TypeError, r"params\['m1'\]"),
    (lambda M, p, law, r: seed000_model({"nope": 1.0}), isp.InputError, "params names 'nope'"),
    (lambda M, p, law, r: seed000_path({"A": 1.0}), isp.InputError, r"params\['A'\] must have shape \(2,\)"),
    (lambda M, p, law, r: Body("__import__('os')", 1.0, (0, 0), 0), TypeError, "mass must be a number"),
    (lambda M, p, law, r: Body(-1.0, 1.0, (0, 0), 0), isp.InputError, "mass must be positive"),
    (lambda M, p, law, r: Body(1.0, float("nan"), (0, 0), 0), isp.InputError, "inertia must be finite"),
    (lambda M, p, law, r: Body(1.0, 1.0, "xy", 0), TypeError, "centre must be"),
    (lambda M, p, law, r: OpenTreeModel(sp.symbols("a b"), ["__import__('os')"], [sp.Symbol("a")], [0], []),
     TypeError, r"constraints\[0\]"),
    (lambda M, p, law, r: OpenTreeModel(["a", "b"], [], [], [], []), TypeError, r"eta\[0\] must be a sympy Symbol"),
    (lambda M, p, law, r: OpenTreeModel(sp.symbols("a b"), [sp.Symbol("a")], [sp.Symbol("b")], [1.5], []),
     TypeError, r"actuated\[0\]"),
])
def test_bad_input(setup, call, exc, words):
    with pytest.raises(exc, match=words):
        call(*setup)


def test_valid_input_still_works(setup):
    model, path, law, res = setup
    assert float(law(np.float64(1.0), order=np.int64(1))) == 0.0
    assert res.mu.shape == (2, 5)
    st = state(model, path, np.float64(0.0), guess=np.array(G0))
    assert st.eta.shape == (5,)
