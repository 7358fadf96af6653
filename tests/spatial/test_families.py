"""One start system per family kind (imagespace.spatial.families), against the total-degree route.

Independent checks: the linear leg family's generic count by the total-degree solver on members
drawn here; each design's carried start against its own total-degree start (same p* and patch,
compared as point sets); certified counts of seeded designs and poses by both routes; the
fallback when the carried start is short.
"""

import numpy as np
import pytest

import designs as D  # noqa: E402  (tests/spatial on sys.path: pytest's rootdir-relative import)
import imagespace as isp
from imagespace.exceptions import InputError
from imagespace.spatial import families
from imagespace.spatial.homotopy import StartSystem, move_start_system, solve_start_system
from imagespace.spatial.quadrics import (point_on_plane_quadric, point_on_plane_quadric_linear, sphere_quadric,
                                        sphere_quadric_linear, study_quadric_matrix)
from imagespace.spatial.solver import solve_rows, start_system
from imagespace.spatial.tracker import PATH_OK, track_many

E = np.diag([1.0, 1, 1, 1, 0, 0, 0, 0])
PIDX = np.r_[np.arange(6), -1]
SAME_POINT = 1e-8        # two start solutions on one patch are the same point (they are ~1e-14 apart)


def _gs(design):
    return isp.GoughStewart(D.as_float(design.base), D.as_float(design.platform))


def _same_sets(X, Y):
    """Every row of X has a row of Y within SAME_POINT (relative) and vice versa, one to one."""
    if X.shape != Y.shape:
        return False
    dist = np.linalg.norm(X[:, None, :] - Y[None, :, :], axis=2) / (1 + np.linalg.norm(X, axis=1))[:, None]
    near = dist <= SAME_POINT
    return bool(np.all(near.sum(axis=1) == 1) and np.all(near.sum(axis=0) == 1))


def test_sphere_quadric_linear_is_the_sphere_quadric(rng):
    a, b, L = rng.normal(size=(20, 3)), rng.normal(size=(20, 3)), rng.random(20) * 3
    Q = sphere_quadric_linear(a, b, np.einsum("ni,nj->nij", a, b), (a * a).sum(1) + (b * b).sum(1) - L ** 2)
    assert np.allclose(Q, sphere_quadric(a, b, L), rtol=0, atol=1e-13)
    # linear in (a, b, W, c) jointly: the mean of two members is the member of the means
    a2, b2, W, W2, c, c2 = (rng.normal(size=s) for s in ((3,), (3,), (3, 3), (3, 3), (), ()))
    mid = sphere_quadric_linear((a[0] + a2) / 2, (b[0] + b2) / 2, (W + W2) / 2, (c + c2) / 2)
    assert np.allclose(mid, (sphere_quadric_linear(a[0], b[0], W, c) + sphere_quadric_linear(a2, b2, W2, c2)) / 2,
                       rtol=0, atol=1e-13)


def test_sphere_quadric_linear_refuses_bad_input():
    with pytest.raises(InputError, match="products"):
        sphere_quadric_linear(np.zeros(3), np.zeros(3), np.zeros(3), 0.0)
    with pytest.raises(InputError, match="finite"):
        sphere_quadric_linear([np.nan, 0, 0], np.zeros(3), np.zeros((3, 3)), 0.0)
    with pytest.raises(InputError, match="batch size"):
        sphere_quadric_linear(np.zeros((2, 3)), np.zeros((3, 3)), np.zeros((3, 3)), 0.0)
    with pytest.raises(InputError, match="not bool"):
        sphere_quadric_linear([True, False, True], np.zeros(3), np.zeros((3, 3)), 0.0)
    with pytest.raises(InputError, match="too large"):                  # 1.5e308 + 1e308 overflows
        sphere_quadric_linear(np.zeros(3), np.zeros(3), np.full((3, 3), 1.5e308), 1e308)
    with pytest.raises(InputError, match="too large"):
        point_on_plane_quadric_linear(np.zeros(3), np.full((3, 3), 1.5e308), -1.5e308)


@pytest.mark.slow
def test_coefficient_mode_with_equal_members_stays_put():
    # mode 2 between a member and itself: H = ((1 - s) + s gamma) F, every solution stays where it is
    gs = _gs(D.random_design(3))
    st = start_system(gs.family(), route="design")
    k = len(st.solutions)
    Z, status, steps = np.zeros((1, k, 8), complex), np.zeros((1, k), np.int64), np.zeros((1, k), np.int64)
    track_many(st.solutions, 2, st.A, st.E, st.pidx, st.p_star[None], st.p_star, np.zeros((7, 8), complex),
               st.A, st.patch, np.exp(2j), Z, status, steps)
    assert np.all(status == PATH_OK)
    assert np.allclose(Z[0], st.solutions, rtol=0, atol=1e-10)


@pytest.mark.slow
def test_linear_leg_family_has_40_regular_solutions():
    # N' of the linear family: random members drawn here (W a full 3x3, c free), 8 total-degree
    # runs of 128 paths each; the known count of the sub-family of designs is 40, the linear
    # family's is measured, and it must equal families.LEG_FAMILY_COUNT
    for seed in range(3):
        r = np.random.default_rng(1000 + seed)
        A = np.concatenate([sphere_quadric_linear(r.normal(size=(6, 3)), r.normal(size=(6, 3)),
                                                  r.normal(size=(6, 3, 3)), r.normal(size=6)),
                            study_quadric_matrix()[None]])
        st = solve_start_system(A, E, PIDX, 6, seed=seed, attempts=8)
        assert len(st.solutions) == families.LEG_FAMILY_COUNT == 40


def test_family_kind():
    assert families.family_kind(_gs(D.random_design(1)).family()) == "legs6"
    assert families.family_kind(_gs(D.random_design_63(1)).family()) == "legs6"
    assert families.family_kind(isp.ThreeRPS(np.eye(3), 0.5 * np.eye(3)).family()) == "rps3"
    # a Gough-Stewart family with one leg's matrix off the linear family: no kind
    fam = _gs(D.random_design(1)).family()
    A = fam.A.copy()
    A[2, 0, 7] += 0.5
    A[2, 7, 0] += 0.5
    assert families.family_kind(type(fam)(A, fam.E, fam.pidx, 6, 40, fam.exact, fam.aspect)) is None


def test_bad_input_refused():
    with pytest.raises(InputError, match="kind"):
        families.family_start_system("legs3")
    with pytest.raises(InputError, match="kind"):
        families.generic_member(6)
    with pytest.raises(InputError, match="seed"):
        families.family_start_system("legs6", 0.5)
    with pytest.raises(InputError, match=r"seed must be an integer in \[0, 2\*\*63\), got -1"):
        families.family_start_system("legs6", -1)
    with pytest.raises(InputError, match="route"):
        start_system(_gs(D.random_design(1)).family(), route="fast")
    A = families.generic_member("legs6")
    st = StartSystem(A, E, PIDX, np.ones(6, complex), np.ones(8, complex), np.zeros((0, 8), complex), 0)
    with pytest.raises(InputError, match="shape"):
        move_start_system(st, st.A[:6])
    with pytest.raises(TypeError, match="StartSystem"):
        move_start_system(st.solutions, st.A)
    with pytest.raises(InputError, match="real array"):
        move_start_system(st, st.A != 0)
    with pytest.raises(InputError, match="MOVE_MAX_ENTRY"):
        move_start_system(st, st.A * 1e200)
    for seed in (True, "x", -1, 2.0):
        with pytest.raises(InputError, match="seed must be an integer"):
            move_start_system(st, st.A, seed=seed)
    for tol in ("x", -1.0, np.nan, False):
        with pytest.raises(InputError, match="tol must be a positive number"):
            move_start_system(st, st.A, tol=tol)
    with pytest.raises(TypeError, match="QuadricFamily"):
        families.design_start_system(np.zeros((7, 8, 8)))


@pytest.mark.slow
@pytest.mark.parametrize("make, count", [(D.random_design, 40), (D.random_design_63, 16),
                                         (D.random_design_33, 16)])
def test_carried_start_equals_total_degree_start(make, count):
    for seed in range(4):
        fam = _gs(make(seed)).family()
        new = start_system(fam, route="family")
        old = start_system(fam, route="design")
        assert new.paths == families.LEG_FAMILY_COUNT           # carried, not the fallback
        assert old.paths % 128 == 0                              # total degree
        assert len(new.solutions) == len(old.solutions) == count == fam.bound
        assert np.array_equal(new.p_star, old.p_star) and np.array_equal(new.patch, old.patch)
        assert _same_sets(new.solutions, old.solutions)


def test_short_carried_start_falls_back(monkeypatch):
    fam = _gs(D.random_design(2)).family()

    def short(start, A, seed=0, tol=1e-10):
        full = move_start_system(start, A, seed=seed, tol=tol)
        return StartSystem(full.A, full.E, full.pidx, full.p_star, full.patch, full.solutions[1:], full.paths)

    monkeypatch.setattr(families, "move_start_system", short)
    st = start_system(fam)
    assert st.paths % 128 == 0 and len(st.solutions) == 40       # the total-degree route


def _rps(seed):
    r = np.random.default_rng(seed)
    a, b = r.integers(-4, 5, (3, 3)) / 2.0, r.integers(-4, 5, (3, 3)) / 4.0
    return isp.ThreeRPS(a, b, base_axes=r.integers(-3, 4, (3, 3)) if seed % 2 else None)


@pytest.mark.slow
def test_three_rps_carried_start_equals_total_degree_start():
    done = 0
    for seed in range(8):
        try:
            fam = _rps(seed).family()
        except isp.DegenerateDesignError:
            continue
        new, old = start_system(fam, route="family"), start_system(fam, route="design")
        assert new.paths == families.FAMILY_COUNTS["rps3"]            # carried, not the fallback
        assert len(new.solutions) == len(old.solutions) == 16 == fam.bound
        assert _same_sets(new.solutions, old.solutions)
        done += 1
    assert done >= 5


@pytest.mark.slow
def test_linear_three_rps_family_has_40_regular_solutions():
    # the 3-RPS's linear family: spheres with free W and c, planes with free V = "n b^T", drawn here
    for seed in range(2):
        r = np.random.default_rng(2000 + seed)
        A = np.concatenate([sphere_quadric_linear(r.normal(size=(3, 3)), r.normal(size=(3, 3)),
                                                  r.normal(size=(3, 3, 3)), r.normal(size=3)),
                            point_on_plane_quadric_linear(r.normal(size=(3, 3)), r.normal(size=(3, 3, 3)),
                                                          r.normal(size=3)),
                            study_quadric_matrix()[None]])
        st = solve_start_system(A, E, np.array([0, 1, 2, -1, -1, -1, -1]), 3, seed=seed, attempts=8)
        assert len(st.solutions) == families.FAMILY_COUNTS["rps3"] == 40


def test_point_on_plane_quadric_linear_is_the_plane_quadric(rng):
    for _ in range(3):
        b, c, n = rng.normal(size=(3, 3))
        Q = point_on_plane_quadric_linear(n, np.outer(n, b), n @ c)
        assert np.allclose(Q, point_on_plane_quadric(b, c, n), rtol=0, atol=1e-13)
    with pytest.raises(InputError, match="offset"):
        point_on_plane_quadric_linear(np.ones(3), np.zeros((3, 3)), [np.inf])


def test_family_start_on_disk(monkeypatch, tmp_path):
    monkeypatch.setenv("IMAGESPACE_CACHE", str(tmp_path))
    families.family_start_system.cache_clear()
    try:
        first = families.family_start_system("legs6")
        files = list((tmp_path / "kernels").glob("start_legs6_*.npz"))
        assert len(files) == 1
        families.family_start_system.cache_clear()
        again = families.family_start_system("legs6")            # read back (and polished)
        assert again is not first and _same_sets(again.solutions, first.solutions)
        files[0].write_bytes(b"not a start system")              # damaged: solved again
        families.family_start_system.cache_clear()
        assert _same_sets(families.family_start_system("legs6").solutions, first.solutions)
        # readable files whose points are near the member's solutions (polished back) or not
        # solutions at all (solved again)
        with np.load(files[0]) as f:
            data = dict(f)
        for points in (data["solutions"] + 1e-6, np.random.default_rng(3).normal(size=(40, 8)) + 0j):
            with open(files[0], "wb") as fh:
                np.savez(fh, **dict(data, solutions=points))
            families.family_start_system.cache_clear()
            assert _same_sets(families.family_start_system("legs6").solutions, first.solutions)
    finally:
        families.family_start_system.cache_clear()


@pytest.mark.slow
def test_certified_counts_agree_with_the_total_degree_route():
    # 20 seeded designs (16 general, 4 paired) x 3 seeded poses: the same certified flags and
    # real-mode counts whichever start system the rows are tracked from
    rows = 0
    for seed in range(20):
        make = D.random_design if seed < 16 else (D.random_design_63 if seed % 2 else D.random_design_33)
        gs = _gs(make(seed))
        fam = gs.family()
        L = np.array([D.float_lengths(D.squared_lengths_of_pose(make(seed), D.random_pose(100 * seed + j)))
                      for j in range(3)])
        starts = [start_system(fam, route=r) for r in ("family", "design")]
        b_new, b_old = (solve_rows(fam, st, L ** 2, gs.tolerances, lengths=L) for st in starts)
        assert np.array_equal(b_new.certified, b_old.certified)
        assert np.array_equal(b_new.reliable, b_old.reliable)
        assert np.array_equal(b_new.counts, b_old.counts)
        rows += int(b_new.certified.sum())
        # the generating pose is among the modes
        assert np.all(b_new.counts >= 1)
    assert rows >= 50          # most rows are certified (the comparison is not vacuous)


@pytest.mark.slow
def test_three_rps_certified_counts_agree_with_the_total_degree_route():
    rows = designs = 0
    for seed in range(10):
        try:
            m = _rps(seed)
            fam = m.family()
        except isp.DegenerateDesignError:
            continue
        L = np.random.default_rng(seed + 100).integers(4, 13, (3, 3)) / 4.0
        starts = [start_system(fam, route=r) for r in ("family", "design")]
        b_new, b_old = (solve_rows(fam, st, L ** 2, m.tolerances, lengths=L) for st in starts)
        assert np.array_equal(b_new.certified, b_old.certified)
        assert np.array_equal(b_new.reliable, b_old.reliable)
        assert np.array_equal(b_new.counts, b_old.counts)
        rows += int(b_new.certified.sum())
        designs += 1
    assert designs >= 6 and rows >= 12
