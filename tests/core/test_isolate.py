"""Certified root counts in numba (imagespace.core.isolate) against exact rational arithmetic.

Every reference is exact and independent of the kernel: python-flint isolates the real roots of
the square-free factors of the exact polynomial (FLINT returns real roots with an imaginary part
exactly zero) for the counts, and sympy's Sturm sequences (``Poly.count_roots`` on a closed
rational interval, distinct roots) check that each reported interval holds exactly one root, a
simple one (the gcd with the derivative has no root there). Floats enter as the exact binary
rationals they are (``Fraction(float)``).
"""

import math
from fractions import Fraction

import flint
import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from imagespace.core.isolate import (ISOLATE_WORK_SIZE, MAX_DEGREE, certified_root_counts,
                                     count_real_roots_row)
from imagespace.exceptions import InputError

T = sp.Symbol("t")


# -- exact references ------------------------------------------------------------------------------

def exact_count(coeffs):
    """Distinct real roots on the projective line of ``sum c_k x0^(d-k) x1^k`` (exact Fractions),
    or None for the zero form."""
    d = len(coeffs) - 1
    if all(c == 0 for c in coeffs):
        return None
    p = flint.fmpq_poly([flint.fmpq(c.numerator, c.denominator) for c in coeffs])
    num = flint.fmpz_poly([int(v) for v in (p * p.denom()).coeffs()])
    count = 1 if coeffs[d] == 0 else 0          # the root x0 = 0 (t at infinity)
    if num.degree() > 0:
        _, factors = num.factor_squarefree()
        for fac, _m in factors:
            count += sum(1 for r, _ in fac.complex_roots() if r.imag.is_zero())
    return count


def chart_poly(coeffs, chart):
    """The exact polynomial of a chart: F(1, t) (chart 0) or F(s, 1) (chart 1), as a sympy Poly."""
    d = len(coeffs) - 1
    terms = [sp.Rational(c.numerator, c.denominator) for c in coeffs]
    if chart == 0:
        expr = sum(c * T**k for k, c in enumerate(terms))
    else:
        expr = sum(c * T ** (d - k) for k, c in enumerate(terms))
    return sp.Poly(expr, T)


def holds_one_simple_root(poly, lo, hi):
    a, b = sp.Rational(Fraction(lo)), sp.Rational(Fraction(hi))
    if poly.count_roots(a, b) != 1:
        return False
    g = sp.gcd(poly, poly.diff(T))
    return g.degree() < 1 or g.count_roots(a, b) == 0


def fr(values):
    return [Fraction(float(v)) for v in values]


# -- the kernel, one row ---------------------------------------------------------------------------

def run_row(F, E=None, d=None):
    F = np.asarray(F, dtype=float)
    d = len(F) - 1 if d is None else d
    E = np.zeros_like(F) if E is None else np.asarray(E, dtype=float)
    n = max(d, 1)
    lo, hi = np.full(n, np.nan), np.full(n, np.nan)
    chart = np.full(n, -1, dtype=np.int8)
    k = count_real_roots_row(F, E, d, lo, hi, chart, np.empty(ISOLATE_WORK_SIZE))
    return k, lo[:max(k, 0)], hi[:max(k, 0)], chart[:max(k, 0)]


def check_row(F, E=None, exact=None):
    """Run one row; if decided, its count must be the exact count of ``exact`` (default: the
    floats of F), and every interval must hold exactly one simple exact root. Returns the count."""
    exact = fr(F) if exact is None else exact
    k, lo, hi, chart = run_row(F, E)
    if k == -1:
        return k
    assert k == exact_count(exact), (list(F), k, exact_count(exact))
    assert np.all(np.diff(chart) >= 0)                       # chart 0 first, then chart 1
    for c in (0, 1):
        sel = chart == c
        a, b = lo[sel], hi[sel]
        assert np.all(a <= b)
        assert np.all(b[:-1] < a[1:])                        # sorted and disjoint
        if c == 0:
            assert np.all((a >= -1) & (b <= 1))
        else:
            assert np.all((a > -1) & (b < 1))
        poly = chart_poly(exact, c)
        for x, y in zip(a, b):
            assert holds_one_simple_root(poly, x, y), (list(F), c, x, y)
    return k


def expand(roots, quadratics=(), at_infinity=0, scale=Fraction(1)):
    """Exact coefficients (Fractions, lowest power of t first) of
    scale * prod (t - r) * prod (t^2 + b t + c) * x0^at_infinity as a binary form."""
    poly = [scale]
    for r in roots:
        poly = [(poly[k - 1] if k else 0) - r * (poly[k] if k < len(poly) else 0)
                for k in range(len(poly) + 1)]
    for b, c in quadratics:
        q = [c, b, Fraction(1)]
        out = [Fraction(0)] * (len(poly) + 2)
        for i, u in enumerate(poly):
            for j, v in enumerate(q):
                out[i + j] += u * v
        poly = out
    return poly + [Fraction(0)] * at_infinity


def rounded_with_bound(exact):
    """Floats nearest to the exact coefficients and rigorous bounds E >= |float - exact|."""
    F = np.array([float(c) for c in exact])
    E = np.array([math.nextafter(float(abs(Fraction(f) - c)), math.inf) if Fraction(f) != c else 0.0
                  for f, c in zip(F, exact)])
    assert all(Fraction(e) >= abs(Fraction(f) - c) for f, e, c in zip(F, E, exact))
    return F, E


# -- tests -----------------------------------------------------------------------------------------

def test_simple_forms():
    assert run_row([-2.0, 0.0, 1.0])[0] == 2            # t = +-sqrt(2)
    assert run_row([1.0, 0.0, 1.0])[0] == 0
    k, lo, hi, chart = run_row([0.0, 1.0, 0.0])          # x0 x1: t = 0 and x0 = 0 (s = 0)
    assert k == 2 and chart.tolist() == [0, 1]
    assert lo[0] <= 0 <= hi[0] and lo[1] <= 0 <= hi[1]
    k, lo, hi, chart = run_row([-3.0, 1.0])              # degree 1: t = 3, s = 1/3
    assert k == 1 and chart.tolist() == [1] and lo[0] <= 1 / 3 <= hi[0]


@pytest.mark.slow
def test_random_integer_forms(rng):
    decided = 0
    for _ in range(300):
        d = int(rng.integers(1, MAX_DEGREE + 1))
        F = rng.integers(-9, 10, size=d + 1).astype(float)
        F[rng.random(d + 1) < 0.2] = 0.0
        if not np.any(F):
            continue
        decided += check_row(F) >= 0
    assert decided > 200


@pytest.mark.slow
def test_random_float_forms(rng):
    decided = 0
    for _ in range(300):
        d = int(rng.integers(2, MAX_DEGREE + 1))
        F = rng.normal(size=d + 1) * 10.0 ** rng.uniform(-3, 3, size=d + 1)
        decided += check_row(F) >= 0
    assert decided >= 295


@pytest.mark.slow
def test_products_of_linear_factors(rng):
    """Real roots anywhere on the projective line (|t| large = near x0 = 0), complex pairs."""
    decided = 0
    for _ in range(150):
        nreal = int(rng.integers(0, 7))
        roots = [Fraction(float(v)) for v in np.tan(rng.uniform(-np.pi / 2, np.pi / 2, nreal))]
        nq = int(rng.integers(0, (6 - nreal) // 2 + 1))
        quads = [(Fraction(float(b)), Fraction(float(b * b / 4 + rng.uniform(0.01, 4))))
                 for b in rng.normal(size=nq)]
        exact = expand(roots, quads, at_infinity=int(rng.integers(0, 2)) if nreal + 2 * nq < 6 else 0)
        F, E = rounded_with_bound(exact)
        decided += check_row(F, E, exact) >= 0
        check_row(F)                                     # the floats themselves, exact
    assert decided >= 140


@pytest.mark.slow
@pytest.mark.parametrize("special", ["infinity", "t0", "both"])
def test_roots_at_split_points_are_decided(special, rng):
    """x0 = 0 (s = 0) and t = 0 are the first split points of the charts: decided all the same."""
    for _ in range(20):
        roots = [Fraction(float(v)) for v in rng.uniform(-5, 5, 3)]
        inf = 1
        if special != "infinity":
            roots.append(Fraction(0))
        if special == "t0":
            inf = 0
            roots.append(Fraction(float(rng.uniform(-5, 5))))
        exact = expand(roots, at_infinity=inf)
        F, E = rounded_with_bound(exact)
        assert check_row(F, E, exact) == exact_count(exact)


@pytest.mark.parametrize("r", [1, -1])
def test_roots_at_the_chart_boundary(r):
    """t = +-1 is where the charts meet: such a root is counted right or undecided, never wrong."""
    for others in ([2, 3], [Fraction(1, 3), -7], [Fraction(-1, 2)], []):
        exact = expand([Fraction(r)] + [Fraction(v) for v in others])
        check_row(np.array([float(c) for c in exact]))
    # a root just beside t = 1 but not on it: decided, in the right chart
    for eps, chart in ((2.0**-20, 1), (-(2.0**-20), 0)):
        exact = expand([Fraction(1) + Fraction(eps), Fraction(3), Fraction(-2)])
        F = np.array([float(c) for c in exact])
        k, lo, hi, ch = run_row(F)
        assert check_row(F) == 3
        near = [c for a, b, c in zip(lo, hi, ch) if (c == 0 and a <= 1 + eps <= b)
                or (c == 1 and a <= 1 / (1 + eps) <= b)]
        assert near == [chart]


@pytest.mark.slow
@pytest.mark.parametrize("gap", [1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13, 1e-14])
def test_close_roots_right_or_undecided(gap, rng):
    decided = 0
    for _ in range(30):
        r = Fraction(float(rng.uniform(-3, 3)))
        others = [Fraction(float(v)) for v in rng.uniform(-3, 3, 2)]
        exact = expand([r, r + Fraction(gap)] + others, [(Fraction(0), Fraction(1))])
        F, E = rounded_with_bound(exact)
        decided += check_row(F, E, exact) >= 0
        check_row(F)
    if gap >= 1e-5:
        assert decided == 30


@pytest.mark.parametrize("mult", [2, 3])
def test_multiple_roots_undecided_or_right(mult, rng):
    for _ in range(20):
        r = Fraction(int(rng.integers(-64, 65)), 16)             # dyadic: exact coefficients
        exact = expand([r] * mult + [Fraction(int(rng.integers(-9, 10)), 4)])
        F = np.array([float(c) for c in exact])
        assert all(Fraction(f) == c for f, c in zip(F, exact))
        assert run_row(F)[0] == -1                                # a multiple root is never proven
    # a double root at infinity and a double root at t = 0
    assert run_row([1.0, 2.0, 0.0, 0.0])[0] == -1
    assert run_row([0.0, 0.0, 1.0, 5.0])[0] == -1


@pytest.mark.slow
@pytest.mark.parametrize("eps", [1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12])
def test_complex_pairs_close_to_the_axis(eps, rng):
    decided = 0
    for _ in range(20):
        a = Fraction(float(rng.uniform(-3, 3)))
        exact = expand([Fraction(float(v)) for v in rng.uniform(-3, 3, 2)],
                       [(-2 * a, a * a + Fraction(eps) ** 2)])
        F, E = rounded_with_bound(exact)
        decided += check_row(F, E, exact) >= 0
    if eps >= 1e-4:
        assert decided == 20


@pytest.mark.slow
def test_boxes_count_every_form_inside(rng):
    """E > 0: a decided count is the exact count of any form in the box (here: random exact
    rational forms inside it, not its centre)."""
    decided = 0
    for _ in range(100):
        d = int(rng.integers(2, MAX_DEGREE + 1))
        F = rng.normal(size=d + 1)
        E = np.abs(F) * 10.0 ** rng.uniform(-12, -4) + 1e-14
        for _ in range(3):
            exact = [Fraction(f) + Fraction(e) * Fraction(int(rng.integers(-1000, 1001)), 1000)
                     for f, e in zip(F, E)]
            decided += check_row(F, E, exact) >= 0
    assert decided >= 270


def test_box_around_a_double_root_is_undecided():
    exact = expand([Fraction(1, 3), Fraction(1, 3), Fraction(2)])
    F, E = rounded_with_bound(exact)
    assert run_row(F, E + 1e-12)[0] == -1


@pytest.mark.slow
def test_leading_and_trailing_coefficients_zero(rng):
    for _ in range(50):
        d = int(rng.integers(2, MAX_DEGREE + 1))
        F = rng.normal(size=d + 1)
        F[d] = 0.0                                   # a root at x0 = 0
        if rng.random() < 0.5:
            F[0] = 0.0                               # and one at t = 0
        assert check_row(F) >= 0


@pytest.mark.slow
def test_scale_does_not_matter(rng):
    for _ in range(10):
        F = rng.normal(size=7)
        k = check_row(F)
        for s in (2.0**-1000, 2.0**-700, 1e-300, 2.0**-300, 2.0**300, 1e300, 2.0**700):
            G = F * s
            if np.all(np.isfinite(G)) and np.all(np.where(F != 0, G != 0, True)):
                assert check_row(G) in (k, -1)
                if 2.0**-700 <= s <= 2.0**700:
                    assert check_row(G) == k


def test_degree_argument_reads_the_first_coefficients():
    F = np.array([-2.0, 0.0, 1.0, np.nan, np.nan])
    assert run_row(F, np.zeros(5), d=2)[0] == 2


@pytest.mark.parametrize("F, E", [
    ([0.0, 0.0, 0.0], None),                       # the zero form
    ([1.0, np.nan, 1.0], None),
    ([1.0, np.inf, 1.0], None),
    ([1.0, 0.0, -1.0], [0.0, np.nan, 0.0]),
    ([1.0, 0.0, -4.0], [0.0, -1.0, 0.0]),          # a negative bound
    ([1.0, 0.0, -4.0], [2.0, 2.0, 2.0]),           # the box holds the zero form
    ([1e-300, 1e300, 1.0], [0.0, 1e308, 0.0]),
])
def test_undecided_inputs(F, E):
    assert run_row(F, E)[0] == -1


def test_degree_out_of_range():
    F = np.ones(8)
    assert run_row(F, np.zeros(8), d=7)[0] == -1
    assert run_row(F, np.zeros(8), d=0)[0] == -1


# -- property test ---------------------------------------------------------------------------------

magnitudes = st.sampled_from([1e-200, 1e-8, 1e-3, 1.0, 7.0, 1e5, 1e150])


@st.composite
def forms(draw):
    d = draw(st.integers(1, MAX_DEGREE))
    kind = draw(st.sampled_from(["integers", "floats", "roots"]))
    if kind == "integers":
        exact = [Fraction(draw(st.integers(-40, 40))) for _ in range(d + 1)]
    elif kind == "floats":
        scale = draw(magnitudes)
        exact = [Fraction(draw(st.floats(-1e3, 1e3, allow_nan=False)) * scale) for _ in range(d + 1)]
    else:
        roots = draw(st.lists(st.fractions(-20, 20, max_denominator=2**12), max_size=d))
        inf = draw(st.integers(0, d - len(roots)))
        rest = d - len(roots) - inf
        quads = [(Fraction(draw(st.integers(-4, 4))), Fraction(draw(st.integers(1, 9))))
                 for _ in range(rest // 2)]
        roots += [Fraction(draw(st.integers(-5, 5)))] * (rest % 2)
        exact = expand(roots, quads, at_infinity=inf)
    if all(c == 0 for c in exact):
        exact[0] = Fraction(1)
    with_box = draw(st.booleans())
    return exact, with_box


@pytest.mark.slow
@settings(max_examples=250)
@given(forms())
def test_property_decided_counts_are_exact(case):
    exact, with_box = case
    F, E = rounded_with_bound(exact)
    if not with_box:
        exact = fr(F)                    # the floats themselves are the exact form
        E = np.zeros_like(F)
    if np.all(np.isfinite(F)):
        check_row(F, E, exact)


# -- the batch wrapper -----------------------------------------------------------------------------

def test_batch_matches_rows_and_pads(rng):
    F = rng.normal(size=(200, 7))
    F[5] = np.nan
    F[6] = [1.0, -2.0, 1.0, 0.0, 0.0, 0.0, 0.0]   # a triple root at infinity and a double at t=1
    counts, intervals, chart = certified_root_counts(F)
    assert counts.dtype == np.int8 and chart.dtype == np.int8
    assert intervals.shape == (200, 6, 2) and chart.shape == (200, 6)
    assert counts[5] == -1 and counts[6] == -1
    for i in range(200):
        k, lo, hi, ch = run_row(F[i])
        assert counts[i] == k
        kk = max(k, 0)
        np.testing.assert_array_equal(intervals[i, :kk, 0], lo)
        np.testing.assert_array_equal(intervals[i, :kk, 1], hi)
        np.testing.assert_array_equal(chart[i, :kk], ch)
        assert np.all(np.isnan(intervals[i, kk:])) and np.all(chart[i, kk:] == -1)
    for i in rng.choice(200, 20, replace=False):
        if counts[i] >= 0:
            assert counts[i] == exact_count(fr(F[i]))


def test_batch_with_bounds_and_empty():
    F = np.array([[-2.0, 0.0, 1.0], [1.0, 0.0, -1.0]])
    counts, _, _ = certified_root_counts(F, np.array([[1e-9] * 3, [0.0, 2.0, 0.0]]))
    assert counts.tolist() == [2, -1]            # the second box holds (x1 - x0)^2
    counts, intervals, chart = certified_root_counts(np.zeros((0, 4)))
    assert counts.shape == (0,) and intervals.shape == (0, 3, 2) and chart.shape == (0, 3)


@pytest.mark.parametrize("F, E, match", [
    (np.ones((3, 8)), None, "F must have shape"),
    (np.ones((3, 1)), None, "F must have shape"),
    (np.ones(7), None, "F must have shape"),
    (np.ones((3, 7)), np.ones((3, 6)), "E must have the shape"),
    (np.ones((3, 7)), -np.ones((3, 7)), "E must hold non-negative"),
])
def test_batch_invalid_input(F, E, match):
    with pytest.raises(InputError, match=match):
        certified_root_counts(F, E)


def test_batch_refuses_non_numbers():
    with pytest.raises(TypeError, match="F must"):
        certified_root_counts("1 2 3")
    with pytest.raises(TypeError, match="E must"):
        certified_root_counts(np.ones((1, 3)), [["a", "b", "c"]])


# -- realistic rows --------------------------------------------------------------------------------

@pytest.mark.slow
def test_seed002_rows_match_the_disc_certificate():
    """10,000 rows of the seed-002 kinematic polynomial with rigorous coefficient enclosures
    (irrational exact coefficients, in Q(sqrt(181))): the counts equal those of
    certify_real_roots_batch (inclusion discs with an exact fallback, a different algorithm) on
    every decided row, and at least 99.9 % of the rows are decided."""
    import imagespace as isp
    from imagespace.core.certify import certify_real_roots_batch

    m = isp.examples.stigger_husty()
    n = 10000
    rng = np.random.default_rng(2)
    poses = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-6, 6, n),
                             rng.uniform(-np.pi, np.pi, n)])
    Q = m.inverse_kinematics(poses)          # the rows of benchmarks/certified_counts.py
    enc = m.enclosure()
    F, E = enc.evaluate(Q)                   # F[:, k] multiplies x0^(6-k) x1^k, as here
    counts, intervals, chart = certified_root_counts(F, E)
    ref, _ = certify_real_roots_batch(F, E, lambda i: enc.exact_sympy(Q[i]))
    decided = counts >= 0
    assert np.mean(decided) >= 0.999
    np.testing.assert_array_equal(counts[decided], ref[decided])
