"""Issue [14]: every float path flags every count it returns wrong, and continua are reported on
every path.

The truth is the certified path (``direct_kinematics_batch(Q, certify=True)``: counts proven at
the exact binary-rational input, rows whose modes the proof does not account for solved again
root by root) and, independently of imagespace's elimination, msolve on the Euclidean formulation
of ``tests/msolve_ref.py`` (exact over Q; used on designs without an angle, whose geometry is then
exactly rational).
"""

import warnings

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from hard_rows import KIND_SETS, LEVELS, hard_rows, random_design
from imagespace.solve.continuum import continuum_at
from imagespace.solve.proof import batch_kernel
from imagespace.solve.kernel import HAVE_NUMBA
from msolve_ref import POSITIVE_DIMENSIONAL, msolve_available, planar_dk_reference

R = sp.Rational
needs_msolve = pytest.mark.skipif(not msolve_available(), reason="msolve binary not installed")


def issue_design():
    return isp.PlanarParallel([
        isp.PRR(base=(R(909, 365), R(3401, 730)), axis=(R(-3, 5), R(4, 5)), platform=(R(-9, 8), R(-7, 8)),
                length=R(9, 2)),
        isp.PRR(base=(R(-70313, 39440), R(9184, 2465)), axis=(R(21, 29), R(-20, 29)), platform=(R(25, 8), R(7, 8)),
                length=R(37, 8)),
        isp.RPR(base=(R(10059, 1168), R(939, 292)), platform=(R(25, 8), R(23, 8)))])


ISSUE_Q = [-0.5625, 3.125, 8022162915997901 / 1125899906842624]


def per_call(m, q):
    """``(count, flagged)`` of the per-call float path: flagged by a NearSingularWarning, or -1
    and flagged when it raises DegenerateDesignError."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        try:
            n = len(m.direct_kinematics(q))
        except isp.DegenerateDesignError:
            return -1, True
    return n, any(issubclass(w.category, isp.NearSingularWarning) for w in rec)


# --------------------------------------------------------------------------- the issue's row

@pytest.mark.slow
@pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel needs numba")
def test_issue_row_is_flagged_on_every_float_path():
    m = issue_design()
    Q = np.array([ISSUE_Q])
    truth = len(m.direct_kinematics(ISSUE_Q, certify=True))
    assert truth == 6
    for method in ("kernel", "numpy"):
        b = m.direct_kinematics_batch(Q, method=method)
        assert b.count[0] == truth or b.near_singular[0], method
    n, flagged = per_call(m, ISSUE_Q)
    assert n == truth or flagged
    # the kernel's own isolation cannot separate this row's roots under its bounds: handed on
    _, _, _, _, count, flag = batch_kernel(m)(Q)
    assert flag[0] != 0


@needs_msolve
def test_issue_row_truth_from_msolve():
    ref = planar_dk_reference(issue_design(), ISSUE_Q)
    assert len(ref) == 6


# --------------------------------------------------------------------------- hard rows

def check_flags(m, Q, truth, record):
    """Every float path on rows ``Q``: a count different from ``truth`` must be flagged."""
    paths = ["numpy"] + (["kernel"] if batch_kernel(m) is not None else [])
    for method in paths:
        b = m.direct_kinematics_batch(Q, method=method)
        flagged = b.near_singular | ~b.row_ok
        wrong = b.count != truth
        bad = np.flatnonzero(wrong & ~flagged)
        assert bad.size == 0, (f"{method}: {m}, rows {Q[bad[:3]].tolist()}: counts {b.count[bad[:3]]}, "
                               f"certified {truth[bad[:3]]}")
        rec = record.setdefault(method, np.zeros(3, dtype=int))
        rec += [int(wrong.sum()), int((~wrong).sum()), int((flagged & ~wrong).sum())]
    for i in range(0, len(Q), 3):           # the per-call path on every third row
        n, flagged = per_call(m, Q[i])
        assert n == truth[i] or flagged, f"per call: {m}, q = {Q[i].tolist()}: {n} modes, certified {truth[i]}"
        rec = record.setdefault("per call", np.zeros(3, dtype=int))
        rec += [int(n != truth[i]), int(n == truth[i]), int(flagged and n == truth[i])]


def sample(seeds, lines):
    for seed in seeds:
        rng = np.random.default_rng(1000 + seed)
        m = random_design(rng, KIND_SETS[seed % len(KIND_SETS)])
        Q, level = hard_rows(m, rng, lines)
        b = m.direct_kinematics_batch(Q, certify=True)
        keep = b.row_ok & b.consistent
        yield m, Q[keep], b.count[keep], level[keep]


@pytest.mark.slow
@pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel needs numba")
def test_float_paths_flag_wrong_counts_next_to_the_discriminant_fast():
    record = {}
    for m, Q, truth, level in sample([0], 2):
        assert len(Q) >= 8
        check_flags(m, Q, truth, record)


@pytest.mark.slow
@pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel needs numba")
def test_float_paths_flag_wrong_counts_next_to_the_discriminant():
    """Seven designs over all seven leg types (random actuated joints, angles included), rows at
    relative distances 1e-3 ... 1e-14 and adjacent floats from a change of the certified count."""
    record = {}
    levels = np.zeros(len(LEVELS), dtype=int)
    for m, Q, truth, level in sample(range(1, 8), 3):
        levels += np.bincount(level, minlength=len(LEVELS))
        check_flags(m, Q, truth, record)
    assert np.all(levels >= 12)                       # every distance is represented
    for path, (wrong, right, flagged_right) in record.items():
        assert wrong > 0, path                        # the sample reaches rows floats get wrong
        # sanity only: most rows whose count is right are not flagged
        assert flagged_right <= 0.5 * right, (path, flagged_right, right)


@pytest.mark.slow
@needs_msolve
@pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel needs numba")
def test_hard_rows_against_msolve():
    """An independent referee on a subsample: designs without angles (exactly rational), every
    row of a bracket pair at 1e-6 and 1e-9; the certified count is msolve's, and a float count
    that differs from msolve's is flagged."""
    checked = 0
    for seed in (0, 3, 8):
        rng = np.random.default_rng(2000 + seed)
        while True:
            m = random_design(rng, KIND_SETS[seed % len(KIND_SETS)])
            if not any(leg.actuated_is_angle or hasattr(leg, "angle") for leg in m.legs):
                break
        Q, level = hard_rows(m, rng, 2)
        Q = Q[(level == 1) | (level == 2)]
        for q in Q:
            ref = planar_dk_reference(m, q)
            assert ref != POSITIVE_DIMENSIONAL
            truth = len(ref)
            assert len(m.direct_kinematics(q, certify=True)) == truth
            for method in ("numpy", "kernel"):
                b = m.direct_kinematics_batch(q[None, :], method=method)
                assert b.count[0] == truth or b.near_singular[0], (method, m, q.tolist())
            n, flagged = per_call(m, q)
            assert n == truth or flagged
            checked += 1
    assert checked >= 12


# --------------------------------------------------------------------------- continua

def congruent(kind):
    """The congruent 3-RPR of the issue: platform = base (``"unrotated"``), rotated by
    phi = 2 atan(1/3) (``"rotated"``), or that rotated platform rounded to floats."""
    if kind == "unrotated":
        return isp.PlanarParallel([isp.RPR((0, 0), (0, 0)), isp.RPR((4, 0), (4, 0)), isp.RPR((1, 3), (1, 3))])
    if kind == "rotated":
        return isp.PlanarParallel([isp.RPR((0, 0), (0, 0)), isp.RPR((4, 0), (R(16, 5), R(-12, 5))),
                                   isp.RPR((1, 3), (R(13, 5), R(9, 5)))])
    return isp.PlanarParallel([isp.RPR((0, 0), (0, 0)), isp.RPR((4, 0), (16 / 5, -12 / 5)),
                               isp.RPR((1, 3), (13 / 5, 9 / 5))])


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["unrotated", "rotated"])
def test_continuum_raises_per_call_and_is_masked_per_row(kind):
    m = congruent(kind)
    q = [2, 2, 2]
    Q = np.array([q, [2.0, 2.0, 2.5]], dtype=float)
    with pytest.raises(isp.DegenerateDesignError, match="continuum"):
        m.direct_kinematics(q)
    with pytest.raises(isp.DegenerateDesignError, match="continuum"):
        m.direct_kinematics(q, certify=True)
    methods = ["auto", "numpy"] + (["kernel"] if HAVE_NUMBA else [])
    for method in methods:
        for certify in (False, True):
            b = m.direct_kinematics_batch(Q, method=method, certify=certify)
            assert not b.row_ok[0] and "continuum" in b.errors[0], (method, certify)
            assert b.row_ok[1]
    counts, path = m.certified_root_counts(Q)
    assert counts[0] == -1 and path[0] == "continuum" and path[1] != "continuum"
    dask = pytest.importorskip("dask")
    r = m.direct_kinematics_dask(Q)
    row_ok = dask.compute(r.row_ok, scheduler="synchronous")[0] if hasattr(r.row_ok, "compute") else r.row_ok
    assert not row_ok[0] and row_ok[1]


@needs_msolve
@pytest.mark.parametrize("kind", ["unrotated", "rotated", "rounded"])
def test_continuum_verdict_agrees_with_msolve(kind):
    m = congruent(kind)
    ref = planar_dk_reference(m, [2, 2, 2])
    verdict, _ = continuum_at(m, [2.0, 2.0, 2.0])
    assert verdict == (ref == POSITIVE_DIMENSIONAL)
    if kind == "rounded":
        # a different, exact design: six modes, four of them within 1e-4 of phi = 2 atan(1/3)
        assert len(ref) == 6
        assert len(m.direct_kinematics([2.0, 2.0, 2.0], certify=True)) == 6
        assert m.certified_root_counts(np.array([[2.0, 2.0, 2.0]]))[1][0] != "continuum"
        n, flagged = per_call(m, [2.0, 2.0, 2.0])
        assert n == 6 or flagged
        for method in ["numpy"] + (["kernel"] if HAVE_NUMBA else []):
            b = m.direct_kinematics_batch(np.array([[2.0, 2.0, 2.0]]), method=method)
            assert b.row_ok[0] and (b.count[0] == 6 or b.near_singular[0])


@needs_msolve
def test_continuum_of_lines_against_msolve():
    """Three PRR legs actuated at the link angle (PR dyads: the platform anchors on lines) with
    collinear anchors: at angle 0 every anchor lies on the x axis, and the platform slides along
    it at phi = pi (rows with c = 0, a continuum on a line); at another angle, no continuum."""
    legs = [isp.PRR(base=(0, 0), axis=(1, 0), platform=(0, 0), length=1, actuated=1),
            isp.PRR(base=(7, 0), axis=(1, 0), platform=(2, 0), length=1, actuated=1),
            isp.PRR(base=(1, 0), axis=(1, 0), platform=(5, 0), length=1, actuated=1)]
    m = isp.PlanarParallel(legs)
    for q in ([0.0, 0.0, 0.0], [0.0, 0.5, 0.0]):
        ref = planar_dk_reference(m, q)
        verdict, _ = continuum_at(m, q)
        assert verdict == (ref == POSITIVE_DIMENSIONAL), q
        counts, path = m.certified_root_counts(np.array([q]))
        assert (path[0] == "continuum") == verdict
        if verdict:
            with pytest.raises(isp.DegenerateDesignError, match="continuum"):
                m.direct_kinematics(q)
        else:
            assert len(m.direct_kinematics(q)) == len(ref)
