"""Workspaces (exact polygons against grid sampling), indices on textbook matrices, the published optimum of seed 004."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.design.sweep import fuzzy_minmax, sweep
from imagespace.design.indices import isotropy, manipulability
from imagespace.design.workspace import constant_orientation_workspace, dexterous_workspace, reachable_workspace, sampled_workspace

STROKE = [[-np.sqrt(3), np.sqrt(3)]] * 3


# -- workspaces and indices ---------------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("ratio", [0.3, 0.5, 0.7])
def test_exact_workspaces_against_grid_sampling(ratio):
    alpha = 7 * np.pi / 18
    m = isp.examples.choi_3ppr(1, ratio, alpha)
    rng_ = (alpha - np.pi / 2 - 17 * np.pi / 36, alpha - np.pi / 2 + 17 * np.pi / 36)
    box = [(-3, 3), (-3, 3)]
    for exact, kind in ((reachable_workspace(m, rng_, STROKE), "reachable"),
                        (dexterous_workspace(m, rng_, STROKE), "dexterous")):
        assert exact.method.startswith("exact")
        sampled = sampled_workspace(m, STROKE, rng_, box, 300, 91, kind)
        assert abs(sampled.area / exact.area - 1) < 0.01
    c = constant_orientation_workspace(m, 0.3, STROKE)
    s = sampled_workspace(m, STROKE, (0.3, 0.3), box, 300, 1, "constant-orientation")
    assert abs(s.area / c.area - 1) < 0.01


@pytest.mark.slow
def test_workspace_trends_of_seed_004():
    alpha = 7 * np.pi / 18
    rng_ = (alpha - np.pi / 2 - 17 * np.pi / 36, alpha - np.pi / 2 + 17 * np.pi / 36)
    R = [reachable_workspace(isp.examples.choi_3ppr(1, k, alpha), rng_, STROKE).area for k in (0.3, 0.5, 0.7)]
    D = [dexterous_workspace(isp.examples.choi_3ppr(1, k, alpha), rng_, STROKE).area for k in (0.3, 0.5, 0.7)]
    assert R[0] < R[1] < R[2] and D[0] > D[1] > D[2]


def test_indices_on_textbook_matrices():
    assert np.isclose(manipulability(np.diag([1.0, 2.0, 3.0])), 6.0)
    Q, _ = np.linalg.qr(np.random.default_rng(0).normal(size=(3, 3)))
    assert np.isclose(isotropy(2 * Q), 1.0) and np.isclose(isotropy(2 * Q, "frobenius"), 1.0)
    assert isotropy(np.diag([1.0, 1.0, 0.0])) == 0.0


# -- optimal design and sweeps ---------------------------------------------------------------------------------
@pytest.mark.slow
def test_published_optimum_of_seed_004():
    grid = {"alpha": np.arange(30, 151, 10) * np.pi / 180, "r_over_R": np.round(np.arange(0.1, 1.01, 0.1), 1)}
    table = sweep(isp.examples.choi_3ppr_indices, grid, processes=2, progress=False)
    crit = {"D": (1.0, "max"), "S": (0.9, "min"), "I": (0.8, "max"), "M": (0.7, "max"), "R": (0.6, "max")}
    res = fuzzy_minmax(table, crit)
    best = sorted((round(float(np.degrees(table.params["alpha"][i]))), float(table.params["r_over_R"][i]))
                  for i in res.best)
    assert best == [(70, 0.5), (110, 0.5)]                  # (7 pi/18, 0.5) and (11 pi/18, 0.5)
