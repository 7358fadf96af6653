"""The compiled elimination twin (``eliminate_row``) against the sympy original in exact rational
arithmetic, and its error bounds against the exact forms (issue [12]: one generic kernel)."""

from fractions import Fraction

import numpy as np
import pytest
import sympy as sp

from imagespace.core.elimination import (ELIMINATION_ROW_SIZE, ELIMINATION_WORK_SIZE, ROW_D, ROW_F,
                                         ROW_X2, ROW_X3, eliminate, eliminate_row, plan_array,
                                         plan_elimination)
from imagespace.core.quadrics import Quadric

KINDS = [("RR", "RR", "RR"), ("RR", "RR", "PR"), ("RR", "PR", "RP"), ("PR", "RP", "PR"),
         ("PR", "RR", "RR")]


def random_row(rng, kinds):
    C = rng.standard_normal(24) * np.exp(rng.uniform(-3, 3, 24))
    for i, k in enumerate(kinds):
        C[8 * i] = rng.uniform(1, 8) if k == "RR" else 0.0
    return C


def exact_forms(C, kinds):
    quads = [Quadric(k, *[sp.Rational(Fraction(float(v))) for v in C[8 * i:8 * i + 8]])
             for i, k in enumerate(kinds)]
    el = eliminate(quads)
    return [list(map(sp.Rational, f)) for f in (el.D, el.X2, el.X3, el.F)]


def compiled():
    from imagespace.solve.kernel import HAVE_NUMBA
    if not HAVE_NUMBA:
        pytest.skip("numba missing")
    from imagespace.solve.kernel import eliminate_row as twin
    return twin


@pytest.mark.slow
@pytest.mark.parametrize("kinds", KINDS)
@pytest.mark.parametrize("which", ["python", "numba"])
def test_values_and_bounds_hold_against_exact_rationals(kinds, which):
    f = eliminate_row if which == "python" else compiled()
    rng = np.random.default_rng(20261202)
    plan = plan_array(plan_elimination(list(kinds)))
    for trial in range(6):
        C = random_row(rng, kinds)
        exact = exact_forms(C, kinds)
        for bounded in (True, False):
            out, err, work = np.zeros(ELIMINATION_ROW_SIZE), np.zeros(ELIMINATION_ROW_SIZE), np.zeros(ELIMINATION_WORK_SIZE)
            d = f(C, np.zeros(24), plan, out, err, work, bounded)
            assert d == len(exact[3]) - 1
            for off, form in zip((ROW_D, ROW_X2, ROW_X3, ROW_F), exact):
                scale = max(abs(float(v)) for v in form) or 1.0
                for k, v in enumerate(form):
                    got = Fraction(float(out[off + k]))
                    miss = abs(sp.Rational(got) - v)
                    if bounded:            # the exact coefficient lies inside the bound ...
                        assert miss <= sp.Rational(Fraction(float(err[off + k]))), (off, k)
                        # ... and the bound is not vacuous
                        assert err[off + k] <= 1e-12 * scale
                    else:
                        assert float(miss) <= 1e-12 * scale and err[off + k] == 0.0


@pytest.mark.parametrize("kinds", KINDS[:3])
def test_bounds_cover_every_input_inside_the_input_box(kinds):
    """With input uncertainty Ce, any exact input in C +- Ce gives forms inside out +- eout."""
    f = compiled()
    rng = np.random.default_rng(7)
    plan = plan_array(plan_elimination(list(kinds)))
    for trial in range(4):
        C = random_row(rng, kinds)
        Ce = np.abs(C) * 1e-9
        out, err, work = np.zeros(ELIMINATION_ROW_SIZE), np.zeros(ELIMINATION_ROW_SIZE), np.zeros(ELIMINATION_WORK_SIZE)
        f(C, Ce, plan, out, err, work, True)
        for corner in range(3):
            # an exact input in the box: each coefficient moved by a rational fraction of its bound
            s = rng.choice([-1, 1], 24) * rng.uniform(0, 1, 24)
            Cx = [Fraction(float(c)) + Fraction(float(si)) * Fraction(float(e)) for c, si, e in zip(C, s, Ce)]
            quads = [Quadric(k, *[sp.Rational(v) for v in Cx[8 * i:8 * i + 8]]) for i, k in enumerate(kinds)]
            el = eliminate(quads)
            for off, form in zip((ROW_D, ROW_X2, ROW_X3, ROW_F), (el.D, el.X2, el.X3, el.F)):
                for k, v in enumerate(form):
                    assert abs(sp.Rational(Fraction(float(out[off + k]))) - v) <= sp.Rational(Fraction(float(err[off + k])))
