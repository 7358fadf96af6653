"""The lockstep tracker (``kernel="lanes"``, :mod:`imagespace.spatial.lanes`) against the one-path
tracker (``kernel="scalar"``, :mod:`imagespace.spatial.tracker`), issue [18] target 5.

The two take the same decisions with floating-point operations in a different order, so on every
row the fast path can see they must agree: the same status for every path, the same endpoints to
rounding where both arrived, and the same real-mode counts, complex counts, ``reliable`` and
``certified`` flags from the solver (:func:`~imagespace.spatial.solver.solve_rows`). The sample
(seeded): reachable rows of random general 6-6 designs, Dietmaier's 40-real-mode design with its
lengths moved by 1e-12 .. 1e-2, rows at and near double modes (``near_double.py``, generated without
the code under test) of a 6-6 design and of a 3-RPS (16 paths, 3 parameters).
"""

from unittest import mock

import numpy as np
import pytest

import imagespace as isp
from imagespace.exceptions import InputError
from imagespace.spatial import lanes
from imagespace.spatial.homotopy import PATH_OK, recentre, track_parameters
from imagespace.spatial.solver import solve_rows
from imagespace.spatial.study import study_point

from near_double import design_3rps, design_66, near_double_rows

#: endpoints of the two trackers agree to this relative distance where both arrived (measured: at
#: most 2e-9 at exact double modes, where the endpoints are only sqrt(eps) accurate, 4e-11 elsewhere)
ENDPOINT_RTOL = 1e-8


def _general_rows(seed, n):
    rng = np.random.default_rng(seed)
    gs = isp.GoughStewart(rng.normal(size=(6, 3)), 0.5 * rng.normal(size=(6, 3)))
    poses = study_point(rng.normal(size=(n, 4)), rng.uniform(-0.5, 0.5, (n, 3)) + [0, 0, 1.5])
    return gs, gs.inverse_kinematics(poses)


def _dietmaier_rows(seed, n):
    rng = np.random.default_rng(seed)
    gs, L = isp.examples.dietmaier_1998()
    u = rng.normal(size=(n, 6))
    move = 10.0 ** rng.uniform(-12, -2, (n, 1)) * u / np.linalg.norm(u, axis=1)[:, None]
    return gs, np.asarray(L) * (1 + move)


def _near_double(design, seed, points):
    m = design(seed)
    return m, near_double_rows(m, np.random.default_rng(seed), points)


CASES = {
    "general 6-6 (a)": lambda: _general_rows(101, 80),
    "general 6-6 (b)": lambda: _general_rows(102, 80),
    "general 6-6 (c)": lambda: _general_rows(103, 80),
    "Dietmaier moved 1e-12..1e-2": lambda: _dietmaier_rows(104, 80),
    "6-6 near double modes": lambda: _near_double(design_66, 5, 4),
    "3-RPS near double modes": lambda: _near_double(design_3rps, 2, 3),
}


@pytest.fixture(scope="module")
def runs():
    """Per case: the platform, its rows and, per kernel, the tracked endpoints (from the start
    system re-centred by that kernel) and the solver's batch. The lanes tracker is spied on, so a
    kernel argument that stopped reaching it would fail the tests rather than compare the scalar
    tracker with itself."""
    out = {}
    with mock.patch.object(lanes, "track_lanes", wraps=lanes.track_lanes) as spy:
        for name, make in CASES.items():
            m, L = make()
            fam = m.family()
            P = (L / fam.scale) ** 2
            res = {"platform": m, "L": L}
            for kernel in ("scalar", "lanes"):
                before = spy.call_count
                start = recentre(m.start_system, np.median(P, axis=0), kernel=kernel)
                Z, status, _ = track_parameters(start, P, kernel=kernel)
                batch = solve_rows(fam, m.start_system, L ** 2, m.tolerances, lengths=L, kernel=kernel)
                res[kernel] = (Z, status, batch, spy.call_count - before)
            out[name] = res
    return out


def endpoint_mismatches(Za, sa, Zb, sb, rtol=ENDPOINT_RTOL):
    """(paths whose status differs, arrived paths whose endpoints differ by more than ``rtol``
    relative)."""
    both = (sa == PATH_OK) & (sb == PATH_OK)
    rel = np.linalg.norm(Za - Zb, axis=-1) / np.linalg.norm(Za, axis=-1)
    return int(np.sum(sa != sb)), int(np.sum(both & ~(rel <= rtol)))


def test_the_sample_is_large_and_hard(runs):
    """>= 200 rows of general designs and Dietmaier-like rows; rows at double modes where the fast
    path is not reliable, and a spread of real counts: the comparisons below cover them."""
    general = sum(len(runs[n]["L"]) for n in CASES if n.startswith(("general", "Dietmaier")))
    assert general >= 200
    near = [runs[n]["scalar"][2] for n in CASES if "near double" in n]
    assert all(len(b) >= 30 for b in near)
    assert sum(int(np.sum(~b.reliable)) for b in near) >= 2
    counts = np.concatenate([runs[n]["scalar"][2].count for n in CASES])
    assert len(set(counts.tolist())) >= 6


@pytest.mark.parametrize("name", list(CASES))
def test_lanes_and_scalar_paths_agree(runs, name):
    r = runs[name]
    Zs, ss, _, calls_s = r["scalar"]
    Zl, sl, _, calls_l = r["lanes"]
    # lanes: the re-centring and tracking here, the same two in solve_rows (>= 32 rows), and the
    # second chances of rows the certificate left unproven (solver.RETRY_STARTS), all by lanes
    assert calls_s == 0 and calls_l >= 4
    assert Zs.shape == Zl.shape and np.all(np.isfinite(Zs[ss == PATH_OK]))
    assert endpoint_mismatches(Zs, ss, Zl, sl) == (0, 0)


@pytest.mark.parametrize("name", list(CASES))
def test_lanes_and_scalar_give_the_same_answers(runs, name):
    """The solver's answers do not depend on the kernel: counts, complex counts, ``reliable``
    (the compiled certificate, issue [14]) and ``certified``, and the modes to rounding."""
    bs, bl = runs[name]["scalar"][2], runs[name]["lanes"][2]
    assert np.array_equal(bs.count, bl.count)
    assert np.array_equal(bs.complex_count, bl.complex_count)
    assert np.array_equal(bs.reliable, bl.reliable)
    assert np.array_equal(bs.certified, bl.certified)
    sp, lp = bs.study_points, bl.study_points
    assert sp.shape == lp.shape
    close = np.abs(sp - lp) <= 1e-7 * (1 + np.abs(sp))
    # modes within a row come in the same order (same paths, same endpoints); the rows at a double
    # mode may hold two modes within rounding of each other, in either order
    rows = np.repeat(np.arange(len(bs.count)), bs.count)
    assert np.all(close.all(axis=1) | ~bs.reliable[rows])


def test_the_comparison_can_fail(runs):
    """The endpoint check flags a status flip and an endpoint moved by 1e-6 relative."""
    Zs, ss, _, _ = runs["general 6-6 (a)"]["scalar"]
    Zl, sl, _, _ = runs["general 6-6 (a)"]["lanes"]
    Zm, sm = Zl.copy(), sl.copy()
    sm[3, 5] = 1 - sm[3, 5]
    Zm[7, 2] *= 1 + 1e-6
    assert endpoint_mismatches(Zs, ss, Zm, sm) == (1, 1)


def test_the_kernel_is_validated():
    gs, L = isp.examples.dietmaier_1998()
    with pytest.raises(InputError, match=r"kernel must be one of 'auto', 'lanes', 'scalar', got 'simd'"):
        track_parameters(gs.start_system, np.ones((1, 6)), kernel="simd")
    with pytest.raises(InputError, match=r"kernel must be one of .*, got None"):
        solve_rows(gs.family(), gs.start_system, np.ones((1, 6)), gs.tolerances, kernel=None)


def test_auto_tracks_few_rows_one_path_at_a_time_and_more_in_lockstep():
    from imagespace.spatial.homotopy import LANES_MIN_ROWS

    gs, L = isp.examples.dietmaier_1998()
    P = (np.asarray(L)[None] / gs.family().scale) ** 2 * np.linspace(0.95, 1.05, LANES_MIN_ROWS)[:, None]
    with mock.patch.object(lanes, "track_lanes", wraps=lanes.track_lanes) as spy:
        _, s_few, _ = track_parameters(gs.start_system, P[:LANES_MIN_ROWS - 1])
        assert spy.call_count == 0
        _, s_many, _ = track_parameters(gs.start_system, P)
        assert spy.call_count == 1
    _, s_scalar, _ = track_parameters(gs.start_system, P, kernel="scalar")
    assert np.array_equal(s_many, s_scalar) and np.array_equal(s_few, s_scalar[:LANES_MIN_ROWS - 1])


def test_lanes_refuses_what_its_buffer_cannot_hold():
    gs, _ = isp.examples.dietmaier_1998()
    st = gs.start_system
    Z = np.zeros((1, len(st.solutions), 8), complex)
    status = np.zeros((1, len(st.solutions)), np.int64)
    with pytest.raises(InputError, match="at most 8 parameters"):
        lanes.track_lanes(st.solutions, st.A, st.E, st.pidx, np.ones((1, 9)), np.ones(9), st.patch, Z, status,
                          status.copy())
    with pytest.raises(InputError, match="A must hold 7 quadrics"):
        lanes.track_lanes(st.solutions, st.A[:6], st.E, st.pidx[:6], np.ones((1, 6)), st.p_star, st.patch, Z,
                          status, status.copy())


def test_lanes_on_empty_batches_and_more_rows_than_blocks():
    """No rows: nothing tracked; one row (fewer jobs than a block's share) and many rows (every
    block busy) give the scalar tracker's status."""
    gs, L = isp.examples.dietmaier_1998()
    st = gs.start_system
    Z, status, steps = track_parameters(st, np.zeros((0, 6)), kernel="lanes")
    assert Z.shape == (0, 40, 8) and status.shape == steps.shape == (0, 40)
    P = (np.asarray(L)[None] / gs.family().scale) ** 2 * np.linspace(0.9, 1.1, 37)[:, None]
    for rows in (P[:1], P):
        _, s_scalar, _ = track_parameters(st, rows, kernel="scalar")
        _, s_lanes, _ = track_parameters(st, rows, kernel="lanes")
        assert np.array_equal(s_scalar, s_lanes)


def test_paths_that_cannot_arrive_fail_in_both():
    """Non-finite and absurdly large parameters: every path fails in both trackers (a NaN lane
    must not stop its neighbours: the zero row beside them arrives)."""
    gs, _ = isp.examples.dietmaier_1998()
    P = np.array([np.full(6, np.nan), np.full(6, 1e30), np.zeros(6)])
    for kernel in ("scalar", "lanes"):
        _, status, _ = track_parameters(gs.start_system, P, kernel=kernel)
        assert np.all(status[:2] != PATH_OK), kernel
        assert np.all(status[2] == PATH_OK), kernel
