"""HTML views of the spatial results (issue [16]): one row a mode, its translation as the Study
point says (t = 2 y conj(x) / |x|^2, written here), the batch's masks counted."""

import re

import numpy as np

import imagespace as isp
from imagespace.spatial.results import SpatialDKBatch, SpatialDKResult


def _qmul(p, q):
    w1, v1, w2, v2 = p[0], p[1:], q[0], q[1:]
    return np.concatenate([[w1 * w2 - v1 @ v2], w1 * v2 + w2 * v1 + np.cross(v1, v2)])


def test_result_table_lists_every_mode_with_its_translation():
    rng = np.random.default_rng(5)
    x = rng.normal(size=(3, 4))
    t = rng.normal(size=(3, 3))
    S = isp.spatial.study_point(x, t)
    r = SpatialDKResult(S, np.full(3, 1e-13), np.array([1, -1, 1], np.int8), 40, False, True, "homotopy")
    page = r._repr_html_()
    assert page.count("<tr>") == 1 + 3 and "3 real assembly modes of 40 complex solutions, reliable" in page
    cells = re.findall(r"<td[^>]*>\(([^)]*)\)</td>", page)
    shown = np.array([[float(v) for v in c.split(",")] for c in cells[0::2]])
    for s, row in zip(S, shown):
        xs, ys = s[:4], s[4:]
        want = 2 * _qmul(ys, xs * [1, -1, -1, -1])[1:] / (xs @ xs)
        assert np.allclose(row, want, rtol=1e-4, atol=1e-4)
    assert "NOT reliable" in SpatialDKResult(S, np.zeros(3), np.zeros(3, np.int8), 40, False, False,
                                             "homotopy")._repr_html_()


def test_batch_summary_counts_its_masks():
    b = SpatialDKBatch(np.array([2, 0, 4]), np.array([0, 2, 2, 6]), np.eye(6, 8), np.zeros(6),
                       np.ones(6, np.int8), np.array([40, 0, 40]), np.array([True, False, False]),
                       np.array([True, False, False]), np.array([True, False, True]))
    page = b._repr_html_()
    for label, value in (("rows", "3"), ("valid rows", "2"), ("reliable rows (float checks passed)", "1"),
                         ("certified rows", "1"), ("real modes per row", "{2: 1, 4: 1}"), ("real modes in all", "6")):
        assert re.search(rf">{re.escape(label)}</th><td[^>]*>{re.escape(value)}</td>", page), label
