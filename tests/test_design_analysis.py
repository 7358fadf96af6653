"""[5/7]: mobility, Jacobians against finite differences of the IK for every leg type, seeds 003
and 004 closed forms, workspaces (exact polygons against grid sampling), indices, the published
optimum of seed 004, and local/Dask sweeps."""

import numpy as np
import pytest

import imagespace as isp
from imagespace.design.sweep import _demo_index, fuzzy_minmax, sweep
from imagespace.design.indices import isotropy, manipulability
from imagespace.design.mobility import gruebler, manipulator_mobility, mechanism_mobility
from imagespace.design.workspace import (constant_orientation_workspace, dexterous_workspace, halfplane_polygon,
                                  reachable_workspace, sampled_workspace)

STROKE = [[-np.sqrt(3), np.sqrt(3)]] * 3


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


# -- Jacobians ------------------------------------------------------------------------------------------
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
                    if not jac.valid[0] or jac.inverse_kinematic[0]:
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
                    assert np.allclose(jac.J[0, 0], fd, rtol=1e-5, atol=1e-6), (cls.__name__, act, b)
                    checked += 1
    assert checked > 40


def test_statics_is_the_transpose():
    m = isp.examples.general_3rpr()
    jac = m.jacobians([0.5, 1.0, 0.2])
    tau = np.array([1.0, -2.0, 0.5])
    F = jac.wrench(tau)[0]
    qdot = jac.J[0] @ np.array([0.3, -0.1, 0.05])
    assert np.isclose(tau @ qdot, F @ [0.3, -0.1, 0.05])                 # virtual power


# -- seeds 003 and 004 -------------------------------------------------------------------------------------
def test_seed_003_closed_form_equals_image_space_dk(rng):
    m = isp.examples.collinear_3rpr(2, 1)
    for _ in range(20):
        pose = np.array([rng.uniform(-1, 1), rng.uniform(0.3, 2), rng.uniform(-1.2, 1.2)])
        d = m.inverse_kinematics(pose)
        cf = isp.examples.collinear_3rpr_closed_form(d, 2, 1)
        dk = np.array([mm.pose for mm in m.direct_kinematics(d)])
        assert len(cf) == len(dk) == 4
        for p in cf:
            assert np.min(np.linalg.norm(dk - p, axis=1)) < 1e-9
        # mirror pairs (x, y, theta) <-> (x, -y, -theta)
        for p in cf:
            assert np.min(np.linalg.norm(cf - p * [1, -1, -1], axis=1)) < 1e-9


def test_seed_003_singular_configurations():
    m = isp.examples.collinear_3rpr(2, 1)
    # theta = 0: the three legs meet in one point (det Jx = 16 R r sin(theta) (...) = 0)
    assert m.jacobians([0.3, 1.2, 0.0]).direct_kinematic[0]
    # the other factor: R y + r x sin(theta) - r y cos(theta) = 0 -> all legs parallel
    th, x = 0.7, 0.4
    y = -x * np.sin(th) / (2 - np.cos(th))
    assert m.jacobians([x, y, th]).direct_kinematic[0]


@pytest.mark.slow
def test_seed_004_closed_form_two_modes_and_det(rng):
    for alpha in (7 * np.pi / 18, 11 * np.pi / 18, np.pi / 3):
        m = isp.examples.choi_3ppr(1, 0.5, alpha)
        for _ in range(5):
            pose = np.array([rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), alpha - np.pi / 2 + rng.uniform(-1.3, 1.3)])
            rho = m.inverse_kinematics(pose)
            cf = isp.examples.choi_3ppr_closed_form(rho, 1, 0.5, alpha)
            dk = np.array([mm.pose for mm in m.direct_kinematics(rho)])
            assert len(cf) == len(dk) == 2
            assert np.allclose(cf[0, :2], cf[1, :2])                                   # shared (x, y)
            wrap = lambda a: np.remainder(a + np.pi, 2 * np.pi) - np.pi
            assert np.isclose(wrap(cf[0, 2] + cf[1, 2] - 2 * alpha), 0, atol=1e-12)  # phi, 2 alpha - phi
            for p in cf:
                assert np.min(np.linalg.norm(dk - p, axis=1)) < 1e-9
            assert np.allclose(m.inverse_kinematics(cf), rho)                          # IK o DK
            det = np.linalg.det(m.jacobians(pose).homogeneous(1.0))[0]
            assert np.isclose(det, isp.examples.choi_det_jh(pose[2] - (alpha - np.pi / 2), 0.5, alpha), rtol=1e-10)


def test_seed_004_rotation_limits_are_where_a_link_enters_the_plate():
    """Independent geometry: is the link direction from B_i towards its slider inside the plate's
    corner at B_i (a positive combination of the two edges)?"""
    alpha, r = 7 * np.pi / 18, 0.5
    lo, hi = isp.examples.choi_rotation_limits(alpha)
    th = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])

    def enters(phi):
        B = r * np.column_stack([np.sin(th + phi), -np.cos(th + phi)])
        out = []
        for i in range(3):
            w = np.array([np.cos(th[i] + alpha), np.sin(th[i] + alpha)])
            e1, e2 = B[(i + 1) % 3] - B[i], B[(i + 2) % 3] - B[i]
            c = np.linalg.solve(np.column_stack([e1, e2]), -w)
            out.append(np.all(c > 0))
        return any(out)

    for phi in np.linspace(lo + 1e-6, hi - 1e-6, 200):
        assert not enters(phi)
    assert enters(hi + 1e-3) and enters(lo - 1e-3)


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


@pytest.mark.slow
def test_dask_and_local_sweeps_return_the_same_table():
    distributed = pytest.importorskip("distributed")
    grid = {"alpha": np.array([60, 70, 80]) * np.pi / 180, "r_over_R": np.array([0.4, 0.5])}
    local = sweep(isp.examples.choi_3ppr_indices, grid, processes=0, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, distributed.Client(cluster) as client:
        remote = sweep(isp.examples.choi_3ppr_indices, grid, client=client, progress=False)
    assert remote.how.startswith("dask") and local.equals(remote)


def test_design_bad_input():
    with pytest.raises(isp.InputError, match="single design"):
        sweep(_demo_index, {"a": [1.0], "b": [2.0]}, processes=0)
    with pytest.raises(isp.InputError, match="no values"):
        sweep(_demo_index, {"a": [], "b": [2.0]}, processes=0)
    t = sweep(_demo_index, {"a": [1.0, 2.0], "b": [2.0]}, processes=0)
    with pytest.raises(isp.InputError, match="weight"):
        fuzzy_minmax(t, {"sum": (1.5, "max")})
    with pytest.raises(isp.InputError, match="min < max"):
        dexterous_workspace(isp.examples.choi_3ppr(), (0.0, 0.5), [[1, -1]] * 3)
    with pytest.raises(isp.InputError, match="phi_range"):
        reachable_workspace(isp.examples.choi_3ppr(), (0.5, 0.5), STROKE)
    with pytest.raises(isp.InputError, match="b must have"):
        halfplane_polygon([[1, 0]], [1, 2])


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
            assert np.allclose(Jxn, jac.Jx[0], rtol=1e-10, atol=1e-10)
            assert np.allclose(Jqn, jac.Jq[0], rtol=1e-10, atol=1e-10)
