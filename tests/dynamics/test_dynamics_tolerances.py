"""Every Tolerances field of the dynamics subpackage is read: changing it changes a decision on a
constructed input (model.tolerances for the solvers, the tolerances keyword of TimeLaw.is_monotone)."""

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.dynamics import (LinePath, TimeLaw, consistent_acceleration, cubic_rest_to_rest, drive_singularity,
                                 inverse_dynamics, plan_consistent_law, seed000_model, seed000_path, state)

GUESS = [0.69, 2.2, 2.46, 0.36, 0.0]


@pytest.fixture(scope="module")
def setup():
    model = seed000_model()
    x0, e = seed000_path()
    path = LinePath(x0, e)
    st = state(model, path, 0.0, guess=GUESS)
    sing = drive_singularity(model, path, (0.0, 1.5), st.eta)
    return model, path, st, sing


def tuned(model, **fields):
    return model.with_tolerances(isp.Tolerances(**fields))


def test_the_model_carries_its_tolerances():
    t = isp.Tolerances(dynamics_residual=1e-6)
    model = seed000_model(tolerances=t)
    assert model.tolerances is t and seed000_model().tolerances == isp.Tolerances()
    assert model.with_tolerances(None).tolerances == isp.Tolerances()
    with pytest.raises(TypeError, match="tolerances must be an imagespace.Tolerances"):
        seed000_model().with_tolerances({"dynamics_residual": 1e-6})


def test_dynamics_residual_decides_whether_newton_converged():
    # the loop sin(a) + 2 = 0 has no real solution: Newton's residual stays in [1, 3]
    a, b = sp.symbols("a b", real=True)
    model = isp.dynamics.OpenTreeModel((a, b), [sp.sin(a) + 2], [b], [1], [isp.dynamics.Body(1.0, 0.1, (a, b), a)])
    path = LinePath([0.0], [1.0])
    with pytest.raises(isp.InputError, match="did not converge"):
        state(model, path, 0.5, guess=[0.3, 0.0])
    loose = state(tuned(model, dynamics_residual=10.0), path, 0.5, guess=[0.3, 0.0])
    assert loose.eta[1] == pytest.approx(0.5)     # accepted (residual >= 1 <= 10): b follows the path


@pytest.mark.slow
def test_dynamics_rank_and_alpha_zero_decide_the_row_dependence(setup):
    model, path, st, sing = setup
    assert np.count_nonzero(sing.alpha) > 0
    with pytest.raises(isp.InputError, match="rank"):
        drive_singularity(tuned(model, dynamics_rank=1.0), path, (0.0, 1.5), st.eta)
    # |alpha_p| <= 1 by the choice of the pivot row: a threshold of 2 drops every coefficient
    coarse = drive_singularity(tuned(model, dynamics_alpha_zero=2.0), path, (0.0, 1.5), st.eta)
    assert np.count_nonzero(coarse.alpha) == 0


def test_dynamics_consistency_slope_decides_whether_a_is_involved(setup):
    model, path, _, sing = setup
    assert np.isfinite(consistent_acceleration(model, path, sing, 1.7))
    with pytest.raises(isp.InputError, match="does not involve the path acceleration"):
        consistent_acceleration(tuned(model, dynamics_consistency_slope=1e12), path, sing, 1.7)


def test_dynamics_consistency_decides_whether_a_crossing_is_consistent(setup):
    model, path, st, sing = setup
    cub = cubic_rest_to_rest(1.5, 1.0)
    ts = np.linspace(0, 1, 11)
    assert not inverse_dynamics(model, path, cub, ts, st.eta, sing).consistent
    # the relative residual is at most 1 (|nu| = 1): a threshold of 2 accepts any crossing
    assert inverse_dynamics(tuned(model, dynamics_consistency=2.0), path, cub, ts, st.eta, sing).consistent


def test_dynamics_mu_dot_decides_where_the_mu_dot_term_is_restored(setup):
    model, path, st, sing = setup
    law, info = plan_consistent_law(model, path, sing, 1.0, 1.5)
    t = [info["Td"] + 2e-4]                                 # inside the band, |g| well above 1e-7
    with_term = inverse_dynamics(model, path, law, t, st.eta, sing)
    without = inverse_dynamics(model, path, law, t, st.eta, sing, mu_dot_correction=False)
    assert with_term.branch.tolist() == ["eq11"] and abs(with_term.g[0]) > 1e-7
    assert not np.allclose(with_term.mu, without.mu, rtol=1e-12, atol=0)
    # |g| <= 1 always: a threshold of 1 leaves the term out everywhere
    off = inverse_dynamics(tuned(model, dynamics_mu_dot=1.0), path, law, t, st.eta, sing)
    assert np.array_equal(off.mu, without.mu)


def test_timelaw_fields_decide_monotonicity():
    # s' = -1e-10 + 2 t: negative on [0, 5e-11), a root just inside (0, T)
    law = TimeLaw([0.0, -1e-10, 1.0], 1.0)
    assert not law.is_monotone()
    # the root is found (as interior) unless timelaw_root exceeds it; the slack must cover 1e-10 / 2
    assert not law.is_monotone(tolerances=isp.Tolerances(timelaw_monotone=1e-9))
    assert not law.is_monotone(tolerances=isp.Tolerances(timelaw_root=1e-9))
    assert law.is_monotone(tolerances=isp.Tolerances(timelaw_root=1e-9, timelaw_monotone=1e-9))
    with pytest.raises(TypeError, match="tolerances must be an imagespace.Tolerances"):
        law.is_monotone(tolerances=1e-9)
