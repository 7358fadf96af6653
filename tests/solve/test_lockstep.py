"""The lockstep kernel (issue [18], target 4) against the row-at-a-time kernel it replaces: every
stage holds its row-at-a-time original bit for bit (the same floats, so the same decisions), and
the whole loop gives the row loop's outputs exactly; the elimination also against sympy's exact
``eliminate`` (the bounds of both contain the exact rational forms)."""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.solve.kernel import HAVE_NUMBA

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel needs numba")

MIXED = [isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3.0, 2.5), actuated=0),
         isp.PRR(base=(6, 0), axis=(0.4, 1.0), platform=(1.5, 0), length=2.8),
         isp.RRP(base=(2, 5), length=2.0, platform=(0, 1.2), direction=(1.0, 0.3))]
NAMES = ["seed002", "general", "3ppr", "mixed"]


def design(name):
    return {"seed002": isp.examples.stigger_husty(), "general": isp.examples.general_3rpr(),
            "3ppr": isp.examples.choi_3ppr(), "mixed": isp.PlanarParallel(MIXED)}[name]


def joint_rows(m, n, seed):
    """Joint vectors of random poses (reachable ones) and of random perturbations of the example
    (some unreachable), shuffled, with rows from the whole range of the root counts."""
    rng = np.random.default_rng(seed)
    poses = np.column_stack([rng.uniform(0, 4, 4 * n), rng.uniform(0, 4, 4 * n), rng.uniform(-1, 1, 4 * n)])
    with np.errstate(all="ignore"):
        Q = m.inverse_kinematics(poses)
    Q = Q[np.all(np.isfinite(Q), axis=1)][: n // 2]
    centre = np.median(Q, axis=0)
    Q = np.concatenate([Q, centre * (1 + 0.2 * rng.standard_normal((n - len(Q), 3)))])
    return Q[rng.permutation(len(Q))]


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("proof", [True, False])
def test_lockstep_stages_equal_the_row_functions_bit_for_bit(name, proof):
    from imagespace.core.elimination import ROW_F
    from imagespace.core.isolate import ISOLATE_WORK_SIZE, count_real_roots_row
    from imagespace.solve.kernel import design_row, design_tables, eliminate_row
    from imagespace.solve.kernel.lockstep import (LOCKSTEP_ROWS as B, _S_C, _S_CE, _S_DC, _S_EL, _S_ELE,
                                                  block_workspace, coefficients_block, eliminate_block,
                                                  isolate_block)

    m = design(name)
    t = design_tables(m)
    Q = joint_rows(m, 700, 3)
    S, grid, ints, kinds, lo, hi, chart, work, small = block_workspace()[:9]
    seen = 0
    for r0 in range(0, len(Q), B):
        nb = min(B, len(Q) - r0)
        coefficients_block(Q, r0, nb, t.expo, t.coef, t.cerr, t.nmono, t.trig, proof, S)
        d = eliminate_block(S, t.plan, nb, proof)
        isolate_block(S, _S_EL + ROW_F, _S_ELE + ROW_F, d, nb, grid, grid.shape[0] // 4, ints[0], ints[1], lo, hi,
                      chart, work, small[0], small[1], kinds)
        for l in range(nb):
            buf, Ce, acc = np.zeros(48 + 18), np.zeros(24), np.zeros(8)
            design_row(Q[r0 + l], t.expo, t.coef, t.cerr, t.nmono, t.trig, proof, buf, Ce, acc)
            assert np.array_equal(S[_S_C:_S_C + 24, l], buf[:24])
            assert np.array_equal(S[_S_DC:_S_DC + 24, l], buf[24:48])
            assert np.array_equal(S[_S_CE:_S_CE + 24, l], Ce)
            out, eout = np.zeros(18), np.zeros(18)
            assert eliminate_row(buf, Ce, t.plan, out, eout, np.zeros(84), proof) == d
            assert np.array_equal(S[_S_EL:_S_EL + 18, l], out, equal_nan=True)
            assert np.array_equal(S[_S_ELE:_S_ELE + 18, l], eout, equal_nan=True)
            rlo, rhi, rch = np.empty(6), np.empty(6), np.empty(6, dtype=np.int8)
            k = count_real_roots_row(out[ROW_F:], eout[ROW_F:], d, rlo, rhi, rch, np.empty(ISOLATE_WORK_SIZE))
            assert ints[1, l] == k
            if k > 0:
                seen += 1
                assert np.array_equal(lo[l, :k], rlo[:k]) and np.array_equal(hi[l, :k], rhi[:k])
                assert np.array_equal(chart[l, :k], rch[:k])
    assert seen > len(Q) // 4


def test_lockstep_elimination_contains_the_exact_forms():
    """The lockstep elimination's values +- bounds contain sympy's exact elimination of the same
    float coefficients taken as rationals (and so does the row function's, being equal)."""
    from imagespace.core.elimination import ROW_D, ROW_F, ROW_X2, ROW_X3, eliminate, plan_array, plan_elimination
    from imagespace.core.quadrics import Quadric
    from imagespace.solve.kernel.lockstep import _S_C, _S_CE, _S_EL, _S_ELE, block_workspace, eliminate_block

    rng = np.random.default_rng(5)
    S = block_workspace()[0]
    for kinds in (["RR", "RR", "RR"], ["RR", "PR", "RP"], ["PR", "RP", "PR"]):
        plan = plan_elimination(kinds)
        nb = 6
        C = rng.standard_normal((nb, 24)) * 10.0 ** rng.integers(-3, 4, (nb, 24))
        for i, k in enumerate(kinds):
            C[:, 8 * i] = 4.0 if k == "RR" else 0.0
        S[_S_C:_S_C + 24, :nb] = C.T
        S[_S_CE:_S_CE + 24, :nb] = 0.0
        d = eliminate_block(S, plan_array(plan), nb, True)
        for l in range(nb):
            quads = [Quadric(k, *[sp.Rational(Fraction(float(v))) for v in C[l, 8 * i:8 * i + 8]])
                     for i, k in enumerate(kinds)]
            el = eliminate(quads, plan)
            for off, form in ((ROW_D, el.D), (ROW_X2, el.X2), (ROW_X3, el.X3), (ROW_F, el.F)):
                assert len(form) <= (d + 1 if off == ROW_F else 4)
                for k, v in enumerate(form):
                    val = Fraction(float(S[_S_EL + off + k, l]))
                    err = Fraction(float(S[_S_ELE + off + k, l]))
                    exact = Fraction(int(sp.Rational(v).p), int(sp.Rational(v).q))
                    assert abs(exact - val) <= err


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_lockstep_kernel_equals_the_row_kernel_exactly(name):
    """Every output of the lockstep loop (modes, poses, residuals, aspects, counts, flags; the
    certified counts and their intervals) equals the row-at-a-time loop's, bit for bit."""
    from imagespace.solve.proof import batch_kernel

    m = design(name)
    k = batch_kernel(m)
    Q = joint_rows(m, 3000, 8)
    for proof in (True, False):
        a = k(Q, proof=proof)
        b = k(Q, proof=proof, lockstep=False)
        for x, y in zip(a, b):
            assert np.array_equal(x, y, equal_nan=True)
        assert np.any(a[4] >= 2) and np.any(a[5] == 0)
    c, lo, hi, ch = k.certified_counts(Q)
    c2, lo2, hi2, ch2 = k.certified_counts(Q, lockstep=False)
    assert np.array_equal(c, c2)
    ok = c >= 0
    assert np.array_equal(lo[ok], lo2[ok], equal_nan=True) and np.array_equal(hi[ok], hi2[ok], equal_nan=True)
    assert np.array_equal(ch[ok], ch2[ok])


@pytest.mark.slow
@pytest.mark.parametrize("name", ["seed002", "mixed"])
def test_backsub_block_equals_the_row_functions_root_by_root(name):
    """The lane-wise back-substitution (:func:`backsub_block`) against :func:`_root_point`,
    :func:`_mode_start` and :func:`_mode_finish` root by root, on the refined roots of real blocks
    and on roots moved off (seeded) so that Newton runs, with thresholds moved so that the Cramer
    check and the residual test fail: each mode bit for bit, a row flagged exactly when one of its
    roots fails."""
    from imagespace.core.elimination import ROW_D, ROW_F, ROW_X2, ROW_X3
    from imagespace.solve.kernel import design_tables, kernel_tolerances
    from imagespace.solve.kernel.block_layout import _M_DET, _M_JRES, _M_ST, _M_T, _M_X, _MI_CHART, _MI_LANE
    from imagespace.solve.kernel.block_modes import ST_SCALAR, backsub_block
    from imagespace.solve.kernel.lockstep import (GRID_LEVELS, LOCKSTEP_ROWS as B, _S_CS, _S_DC, _S_EL, _S_ELE,
                                                  _S_FN, block_workspace, coefficients_block, eliminate_block,
                                                  isolate_block, roots_block)
    from imagespace.solve.kernel.row import _T_CRAMER_SMALL, _T_RESIDUAL, _mode_finish, _mode_start, _root_point

    m = design(name)
    t = design_tables(m)
    Q = joint_rows(m, 320, 11)
    rng = np.random.default_rng(12)
    S, grid, ints, kinds, lo, hi, chart, work, small, MD, MI, X, p = block_workspace()
    seen = {"done": 0, "newton": 0, "cramer": 0, "residual": 0}
    for r0 in range(0, len(Q), B):
        tol = kernel_tolerances(isp.TOLERANCES)
        if r0 // B % 3 == 1:
            tol[_T_CRAMER_SMALL] = 0.3
        elif r0 // B % 3 == 2:
            tol[_T_RESIDUAL] = 1e-16
        nb = min(B, len(Q) - r0)
        coefficients_block(Q, r0, nb, t.expo, t.coef, t.cerr, t.nmono, t.trig, True, S)
        d = eliminate_block(S, t.plan, nb, True)
        isolate_block(S, _S_EL + ROW_F, _S_ELE + ROW_F, d, nb, grid, 2 ** GRID_LEVELS, ints[0], ints[1], lo, hi,
                      chart, work, small[0], small[1], kinds)
        lflag = ints[2]
        nm = roots_block(S, d, nb, ints[1], lo, hi, chart, lflag, MD, MI, p)
        # each row's scaled quadrics, derivatives and forms in the row kernel's layout
        rows = np.concatenate([S[_S_CS:_S_CS + 24], S[_S_DC:_S_DC + 24], S[_S_EL:_S_EL + 18]]).T.copy()
        if r0 >= len(Q) // 2:     # the second half: roots moved by 1e-10 (Newton) to 1e-2 (failures)
            MD[_M_T, :nm] += rng.choice([0.0, 1e-10, 1e-6, 1e-2], nm) * rng.standard_normal(nm)
        before = lflag[:nb].copy()
        backsub_block(S, nm, tol, lflag, MD, MI)
        failed = np.zeros(nb, dtype=bool)
        for j in range(nm):
            l = MI[_MI_LANE, j]
            x0, x1 = _root_point(MD[_M_T, j], MI[_MI_CHART, j])
            buf = rows[l]
            Xs, vs, Js, dxs = np.zeros(4), np.zeros(4), np.zeros((4, 4)), np.zeros(4)
            ok, det, polished = _mode_start(buf, 48 + ROW_D, 48 + ROW_X2, 48 + ROW_X3, 2, 3, buf[:24], x0, x1,
                                            S[_S_FN + 1, l], tol, Xs, vs, Js)
            if not ok:
                seen["cramer"] += 1
            else:
                assert (MD[_M_ST, j] == ST_SCALAR) == (not polished)
                ok, det, jres = _mode_finish(buf[:24], buf[24:48], Xs, vs, Js, dxs, det, polished, tol)
                seen["residual"] += not ok
            if not ok:
                failed[l] = True
                continue
            seen["done" if polished else "newton"] += 1
            if lflag[l] == 0:
                assert np.array_equal(MD[_M_X:_M_X + 4, j], Xs)
                assert MD[_M_DET, j] == det and MD[_M_JRES, j] == jres
        assert np.array_equal(lflag[:nb], np.where(failed, 1, before))
    assert min(seen.values()) > 10, seen


def test_lane_solve_equals_the_row_solve_with_its_row_exchanges():
    """:func:`block_modes._solve4_lane` (row exchanges as selects) against the row kernel's
    ``_solve4`` on seeded matrices built to meet every case: random, ties between candidate
    pivots (repeated and negated rows), rank-deficient (a pivot below the threshold at each
    column), zero columns, a determinant that underflows, huge and tiny scales. The same
    ``singular`` verdict everywhere, the same solution bit for bit where it is regular."""
    from imagespace.solve.kernel.block_modes import _solve4_lane
    from imagespace.solve.kernel.row import _solve4

    rng = np.random.default_rng(44)
    cases = []
    for _ in range(400):
        J = rng.standard_normal((4, 4))
        kind = rng.integers(0, 7)
        if kind == 1:
            J[rng.integers(1, 4)] = J[0] * rng.choice([1.0, -1.0])          # |ties| in every column
        elif kind == 2:
            k = rng.integers(0, 4)
            J[:, k] = J[:, :k] @ rng.standard_normal(k) if k else 0.0      # a dependent column
        elif kind == 3:
            J[:, rng.integers(0, 4)] = 0.0
        elif kind == 4:
            J = J * 10.0 ** rng.integers(-160, -80)                          # det underflows
        elif kind == 5:
            J[rng.integers(0, 4)] *= 1e-15                                   # a pivot near the threshold
        elif kind == 6:
            J = np.round(J)                                                  # exact ties and zeros
        cases.append((J, rng.standard_normal(4) * 10.0 ** rng.integers(-5, 5)))
    seen = {"regular": 0, "singular": 0}
    for J, r in cases:
        dx = np.zeros(4)
        det = _solve4(J.copy(), r.copy(), dx, 1e-14)
        singular, *lane = _solve4_lane(*J.ravel(), *r, 1e-14)
        assert singular == (det == 0.0)
        seen["singular" if singular else "regular"] += 1
        if not singular:
            assert np.array_equal(np.array(lane), dx)
    assert min(seen.values()) > 50, seen
