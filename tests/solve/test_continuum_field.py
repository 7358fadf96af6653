"""The continuum test in Q(sqrt d) arithmetic (imagespace.solve.continuum, designs whose constants
lie in one quadratic field) against sympy: the 2x2 minors of the exact quadrics' matrix and
their gcd over the algebraic field (sympy's ``gcd(..., extension=True)``), written in the test."""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.solve.continuum import continuum_at

R = sp.Rational


def sympy_rank_drop(m, q):
    """Whether some orientation has every 2x2 minor of M zero, decided by sympy: the minors'
    gcd over Q(sqrt d)[t] (the chart x0 = 1) and the constant rows at x0 = 0."""
    t = sp.Symbol("t")
    qe = [sp.Rational(Fraction(float(v))) for v in q]
    rows, top = [], []
    for qd in m.quadrics(qe):
        c, a0, a1, b0, b1, k0, k1, k2 = (sp.nsimplify(v) for v in qd.coefficients())
        rows.append((c, a0 + a1 * t, b0 + b1 * t, k0 + k1 * t + k2 * t ** 2))
        top.append((c, a1, b1, k2))
    minors = lambda rs: [sp.expand(rs[i][a] * rs[j][b] - rs[i][b] * rs[j][a]) for i in range(3)
                         for j in range(i + 1, 3) for a in range(4) for b in range(a + 1, 4)]
    if all(sp.simplify(v) == 0 for v in minors(top)):
        return True
    g = 0
    for mn in minors(rows):
        g = sp.gcd(g, mn, t, extension=True)
    return sp.degree(g, t) > 0


@pytest.fixture(scope="module")
def seed002():
    return isp.examples.stigger_husty()


@pytest.mark.slow
def test_rows_the_kernel_hands_on_have_no_continuum_as_sympy_finds(seed002):
    """The seed-002 rows (constants in Q(sqrt 181)) the kernel cannot decide, and random rows:
    "no continuum" is proven in the field (it was undecided before), as sympy's gcd finds."""
    from imagespace.solve.proof import batch_kernel

    rng = np.random.default_rng(0)
    n = 40000
    poses = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-6, 6, n), rng.uniform(-np.pi, np.pi, n)])
    Q = seed002.inverse_kinematics(poses)
    kernel = batch_kernel(seed002)
    hard = Q[kernel.certified_counts(Q)[0] < 0][:4] if kernel is not None else Q[:0]
    for q in np.concatenate([hard, Q[:3]]):
        verdict, phi = continuum_at(seed002, q)
        assert verdict is False and phi is None
        assert not sympy_rank_drop(seed002, q)


def shifted_congruent(shift):
    """The congruent triangles of continuum_at's example, the base moved by ``(shift, 0)``:
    at q = (2, 2, 2) the platform translates along a circle at phi = 2 atan(1/3)."""
    return isp.PlanarParallel([isp.RPR((shift, 0), (0, 0)), isp.RPR((4 + shift, 0), (R(16, 5), R(-12, 5))),
                               isp.RPR((1 + shift, 3), (R(13, 5), R(9, 5)))])


@pytest.mark.slow
def test_a_continuum_in_a_quadratic_field_is_never_ruled_out():
    m = shifted_congruent(sp.sqrt(2))
    assert sympy_rank_drop(m, [2.0, 2.0, 2.0])
    verdict, _ = continuum_at(m, [2.0, 2.0, 2.0])
    assert verdict is not False
    # one leg longer: no continuum, proven in Q(sqrt 2) as sympy finds
    assert not sympy_rank_drop(m, [2.0, 2.0, 2.5])
    assert continuum_at(m, [2.0, 2.0, 2.5]) == (False, None)


def test_exact_joint_values_and_designs_outside_the_field_take_the_other_routes():
    m = shifted_congruent(sp.sqrt(2))
    assert continuum_at(m, [2, 2, R(5, 2)]) == (False, None)        # exact rationals: the same route
    rational = shifted_congruent(0)
    assert continuum_at(rational, [2.0, 2.0, 2.0])[0] is True       # the rational route decides it
