"""Rich results for Jupyter (issue [11]): compact HTML tables, short reprs, the quartic as LaTeX.

The key numbers are computed here independently of the summaries (``np.bincount`` of the mode
counts, lengths, areas) and looked up in the HTML; no repr of a large result exceeds 15 lines.
"""

import re
from html.parser import HTMLParser

import numpy as np
import pytest
import sympy as sp

import imagespace as isp
from imagespace.design.sweep import DesignTable, FuzzyResult, _demo_index, sweep
from imagespace.design.workspace import constant_orientation_workspace, sampled_workspace
from imagespace.display import latex_form
from imagespace.dynamics.solve import InverseDynamicsResult
from imagespace.paths.backlash import BacklashAnalysis
from imagespace.paths.check import Crossing, check_path, polyline, segment
from imagespace.paths.cusp_loops import CuspLoop
from imagespace.paths.modechange import ModeChangePlan
from imagespace.singular.cusps import ModeCountMap

MAX_LINES = 15


class _Balance(HTMLParser):
    """Records unbalanced tags (every opened tag closed, in order)."""

    def __init__(self):
        super().__init__()
        self.stack, self.errors, self.text = [], [], []

    def handle_starttag(self, tag, attrs):
        self.stack.append(tag)

    def handle_endtag(self, tag):
        if not self.stack or self.stack.pop() != tag:
            self.errors.append(tag)

    def handle_data(self, data):
        self.text.append(data)


def check_html(text):
    """The HTML is a sequence of balanced tables; returns its text content (entities unescaped)."""
    assert text.lstrip().startswith("<table") and text.rstrip().endswith("</table>")
    p = _Balance()
    p.feed(text)
    p.close()
    assert not p.errors and not p.stack, (p.errors, p.stack)
    return "".join(p.text)


def lines(obj):
    return repr(obj).count("\n") + 1


@pytest.fixture(scope="module")
def g():
    return isp.examples.general_3rpr()


@pytest.fixture(scope="module")
def big_batch(g):
    rng = np.random.default_rng(11)
    Q = np.asarray(g.q_example_float) * (1 + 0.6 * rng.standard_normal((1000, 3)))
    Q[:3] = np.nan                                           # a few failed rows
    return g.direct_kinematics_batch(Q)


@pytest.fixture(scope="module")
def seed002():
    return isp.examples.stigger_husty()


def test_batch_html_has_the_rows_and_the_histogram_of_counts(big_batch):
    text = check_html(big_batch._repr_html_())
    counts = np.bincount(big_batch.count)
    assert len(set(np.flatnonzero(counts))) > 1               # a real histogram, not one bar
    assert "1000 rows" in text
    for k in np.flatnonzero(counts):
        assert re.search(rf"<td[^>]*>{k}</td><td[^>]*>{counts[k]}</td>", big_batch._repr_html_())
    assert f"solved rows{int(big_batch.row_ok.sum())}" in text.replace("\n", "")
    for solver, n in zip(*np.unique(big_batch.solver, return_counts=True)):
        assert f"{solver}: {n}" in text
    assert "array" not in text and "nan" not in text.lower()


def test_batch_repr_is_short_and_names_the_counts(big_batch):
    r = repr(big_batch)
    assert lines(big_batch) <= MAX_LINES and len(r) < 1000
    assert "rows=1000" in r and f"failed_rows={len(big_batch.errors)}" in r
    values, n = np.unique(big_batch.count, return_counts=True)
    assert "{" + ", ".join(f"{v}: {k}" for v, k in zip(values, n)) + "}" in r


def test_modes_tables(g):
    modes = g.direct_kinematics(g.q_example, certify=True)
    text = check_html(modes._repr_html_())
    assert f"{len(modes)} modes" in text and f"{modes.certificate.count} real roots" in text
    assert modes._repr_html_().count("<tr>") == len(modes) + 1
    one = check_html(modes[0]._repr_html_())
    assert f"{modes[0].pose[2]:.6g}" in one
    assert isinstance(g.direct_kinematics(g.q_example), list)          # the return type is unchanged


def test_path_check_and_crossing(seed002):
    res = check_path(seed002, segment([1, -0.1, 0, 1.5], [1, 0.1, 0, 1.5]))
    text = check_html(res._repr_html_())
    assert f"crossings{len(res.crossings)}" in text.replace("\n", "")
    assert "crosses" in text and "0.5" in text
    c = Crossing(2, (0.25, 0.25), 3)
    assert "piece2" in check_html(c._repr_html_()).replace("\n", "")
    assert repr(c) == "Crossing(piece=2, t=(0.25, 0.25), multiplicity=3)"      # unchanged
    many = res.__class__(False, True, False, tuple(Crossing(k, (0.5, 0.5), 1) for k in range(500)), (), 0.0,
                         True, "exact")
    assert lines(many) <= MAX_LINES and "crossings=500" in repr(many)
    assert check_html(many._repr_html_()).count("crosses") == 20 + 1            # first 20 rows, one flag


def test_mode_change_plan(seed002):
    path = polyline([[1, 0, 0, 0], [1, 0, 1, 0], [1, 0, 1, 1]])
    res = check_path(seed002, path)
    plan = ModeChangePlan(True, "two segments", path, res, np.zeros((5000, 3)), np.zeros((5000, 3)), 17)
    assert lines(plan) <= MAX_LINES
    text = check_html(plan._repr_html_())
    assert "17" in text and "2 polynomial piece(s)" in text and "array(5000, 3) float64" in text
    h = ModeChangePlan(False, "a < b")._repr_html_()
    assert "a &lt; b" in h and "a < b" not in h and "a < b" in check_html(h)


def test_workspaces():
    c = isp.examples.choi_3ppr()
    box = [[-np.sqrt(3), np.sqrt(3)]] * 3
    exact = constant_orientation_workspace(c, 0.0, box)
    sampled = sampled_workspace(c, box, (0.0, 0.0), [(-2, 2), (-2, 2)], 200, 1, "constant-orientation")
    for ws in (exact, sampled):
        assert lines(ws) <= MAX_LINES
        text = check_html(ws._repr_html_())
        assert f"{ws.area:.6g}" in text and ws.method in text
    assert f"bool array(200, 200), {int(sampled.mask.sum())} True" in repr(sampled)
    assert f"array({len(exact.polygon)}, 2) float64" in repr(exact)


def test_design_table_and_escaping():
    t = sweep(_demo_index, {"a": np.arange(40.0), "b": np.arange(25.0)}, processes=0)
    assert lines(t) <= MAX_LINES
    text = check_html(t._repr_html_())
    assert "rows1000" in text.replace("\n", "") and "(40, 25)" in text
    assert f"[0, {39 + 24}]" in text                                        # the range of "sum"
    odd = DesignTable(params={"a<b": np.arange(4.0)}, values={"v&w": np.ones(4)}, shape=(4,), how="serial")
    h = odd._repr_html_()
    assert "a&lt;b" in h and "v&amp;w" in h and "a<b" not in h
    check_html(h)


def test_no_repr_of_a_large_result_exceeds_15_lines(g, seed002, big_batch):
    n = 1000
    objs = [
        big_batch, g, seed002, seed002.singularity_surface(), seed002.singularity_surface().section(0.4),
        g.jacobians(np.tile([0.0, 0.0, 0.1], (n, 1))),
        g.direct_kinematics(g.q_example, certify=True),
        polyline(np.tile([[1, 0, 0, 0], [1, 0, 1, 0]], (n // 2, 1))),
        CuspLoop(np.zeros((n, 3)), np.zeros((n, 3)), 0, 1, True, np.ones(n, int)),
        BacklashAnalysis(0, 0.1, np.zeros(3), g.direct_kinematics(g.q_example), np.zeros((6, 6)),
                         np.zeros((6, 6), bool), np.zeros(6), np.zeros(n), np.zeros((n, 2, 4)), np.zeros((n, 2))),
        InverseDynamicsResult(np.zeros(n), np.zeros((n, 5)), np.full(n, "a"), np.zeros(n), np.zeros(n),
                              [None] * n, True, 0.0),
        ModeCountMap(0, 1.0, (1, 2), (np.zeros(n), np.zeros(n)), np.zeros((n, n), int)),
        FuzzyResult(np.zeros(n), {"a": np.zeros(n)}, list(range(n))),
    ]
    for obj in objs:
        assert lines(obj) <= MAX_LINES, (type(obj).__name__, repr(obj)[:300])
        if hasattr(obj, "_repr_html_"):
            assert check_html(obj._repr_html_()).count("\n") < 100, type(obj).__name__


def _top_level_terms(latex):
    """The terms of a sum at parenthesis depth 0 (``\\left( ... \\right)`` and braces nest)."""
    body = latex.strip("$").removeprefix(r"\displaystyle ").removesuffix(" = 0")
    depth, terms = 0, 1
    for k, ch in enumerate(body):
        if ch in "({":
            depth += 1
        elif ch in ")}":
            depth -= 1
        elif depth == 0 and ch in "+-" and k > 0 and body[k - 1] == " " and body[k + 1] == " ":
            terms += 1
    return terms


def test_latex_of_the_seed_002_surface(seed002):
    S = seed002.singularity_surface()
    text = S._repr_latex_()
    assert text.startswith("$") and text.endswith("= 0$")
    assert re.search(r"x_\{0\}\^\{[234]\}", text) and "x_{1}" in text
    x0, x1 = (s for s in sorted(S.polynomial.gens, key=str) if s.name in ("x0", "x1"))
    expanded = sp.expand(S.polynomial.as_expr())
    groups = {(sp.degree(t, x0), sp.degree(t, x1)) for t in sp.Add.make_args(expanded)}
    assert _top_level_terms(text) == len(groups)
    assert latex_form(S.polynomial) in text


def test_latex_form_validates_and_shortens(seed002):
    with pytest.raises(TypeError, match="poly must be a sympy Poly"):
        latex_form([1, 2])
    with pytest.raises(TypeError, match="by must be a sequence of variable names"):
        latex_form(seed002.singularity_polynomial(), by="x0")
    with pytest.raises(isp.InputError, match="digits must be at least 1"):
        latex_form(seed002.singularity_polynomial(), digits=0)
    poly = seed002.kinematic_polynomial()
    assert len(latex_form(poly, digits=40)) > 2000                         # long: the coefficients are rounded
    long = latex_form(poly)
    # the rounded coefficients of q1^2 q3 are sympy's own coefficients to 6 significant digits
    x0, x1 = poly.gens
    q1, q2, q3 = sorted(poly.free_symbols - set(poly.gens), key=str)
    want = sorted(abs(float(sp.Poly(c, q1, q2, q3).coeff_monomial(q1**2 * q3)))
                  for c in sp.Poly(poly.as_expr(), x0, x1).coeffs()
                  if sp.Poly(c, q1, q2, q3).coeff_monomial(q1**2 * q3) != 0)
    got = sorted(float(v) for v in re.findall(r"([0-9]+(?:\.[0-9]+)?) q_\{1\}\^\{2\} q_\{3\}", long))
    assert want and len(got) == len(want)
    assert all(abs(g - w) <= 5e-6 * w for g, w in zip(got, want))
