"""Exact counts in Q(sqrt d) (imagespace.core.quadratic_field) against sympy's exact arithmetic
and the general certified path (sympy evaluation, arb isolation), on the seed-002 design whose
constants lie in Q(sqrt 181)."""

from fractions import Fraction

import flint
import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.core.quadratic_field import QuadraticFieldForms, count_distinct_real_roots, quadratic_field_count


@pytest.fixture(scope="module")
def seed002():
    return isp.examples.stigger_husty()


@pytest.mark.slow
def test_coefficients_equal_sympy_exact_values(seed002):
    P = seed002.kinematic_polynomial()
    d = P.total_degree()
    coeffs = [P.coeff_monomial(P.gens[0] ** (d - k) * P.gens[1] ** k) for k in range(d + 1)]
    forms = QuadraticFieldForms([coeffs], seed002.joint_symbols)
    assert forms.d == 181
    rng = np.random.default_rng(2)
    for q in np.asarray(seed002.q_example_float) * (1 + 0.1 * rng.standard_normal((3, 3))):
        sub = {s: sp.Rational(Fraction(float(v))) for s, v in zip(seed002.joint_symbols, q)}
        for (a, b), c in zip(forms.at(q)[0], coeffs):
            mine = sp.Rational(int(a.p), int(a.q)) + sp.Rational(int(b.p), int(b.q)) * sp.sqrt(181)
            assert sp.expand(c.subs(sub) - mine) == 0


@pytest.mark.slow
def test_counts_equal_the_general_certified_path_next_to_the_discriminant(seed002):
    """Rows the kernel's float bounds cannot decide (roots closer than its bounds) and random
    rows: the Q(sqrt 181) count equals the count of the general certified path (sympy numbers,
    arb isolation) on every one."""
    from imagespace.solve.certified import exact_certificate
    from imagespace.solve.proof import batch_kernel

    rng = np.random.default_rng(0)
    n = 40000
    poses = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-6, 6, n), rng.uniform(-np.pi, np.pi, n)])
    Q = seed002.inverse_kinematics(poses)
    kernel = batch_kernel(seed002)
    hard = Q[kernel.certified_counts(Q)[0] < 0] if kernel is not None else Q[:0]
    rows = np.concatenate([hard, Q[:12]])
    assert len(rows) >= 14
    for q in rows:
        assert quadratic_field_count(seed002, q) == exact_certificate(seed002, q).count


def test_repeated_and_vanishing_forms_are_left_to_the_general_path():
    q = flint.fmpq
    # (t - sqrt 2)^2 (t + 1): a repeated root, no count
    assert count_distinct_real_roots([(q(2), q(0)), (q(2), q(-2)), (q(1), q(-2)), (q(1), q(0))], 2) == (None, False)
    # x0 * (x1^2 - 3 x0^2) * x0: a double root at x0 = 0
    assert count_distinct_real_roots([(q(-3), q(0)), (q(0), q(0)), (q(1), q(0)), (q(0), q(0)), (q(0), q(0))],
                                     3) == (None, False)
    assert count_distinct_real_roots([(q(0), q(0))] * 3, 5) is None
    # sqrt(5) x1^2 - x0^2 and x0 (x1^2 + x0^2): two real roots, and one (at x0 = 0)
    assert count_distinct_real_roots([(q(-1), q(0)), (q(0), q(0)), (q(0), q(1))], 5) == (2, True)
    assert count_distinct_real_roots([(q(0), q(0)), (q(1), q(0)), (q(0), q(0)), (q(1), q(0))], 5) == (1, True)


def test_designs_outside_one_quadratic_field_are_refused():
    assert quadratic_field_count(isp.examples.general_3rpr(), isp.examples.general_3rpr().q_example_float) is None
    s = sp.symbols("q1:4")
    with pytest.raises(ValueError, match="quadratic field"):
        QuadraticFieldForms([[s[0] + sp.sqrt(2), sp.sqrt(3)]], s)
    with pytest.raises(ValueError, match="quadratic field"):
        QuadraticFieldForms([[s[0] + sp.cos(1)]], s)
