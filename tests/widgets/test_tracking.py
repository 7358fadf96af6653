"""Mode tracking (issue [16]): the small-matrix assignment against scipy's Hungarian method, and the
tracker's numbers against the nearest partner of each surviving mode."""

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

from imagespace.widgets.tracking import ModeTracker, assignment, projective_distance


@pytest.mark.slow
def test_assignment_is_optimal_like_scipys():
    rng = np.random.default_rng(16)
    for _ in range(300):
        n, m = rng.integers(1, 8, 2)
        D = rng.random((n, m))
        r, c = assignment(D)
        r2, c2 = linear_sum_assignment(D)
        assert len(set(r)) == len(r) == len(set(c)) == min(n, m)
        assert np.isclose(D[r, c].sum(), D[r2, c2].sum(), rtol=0, atol=1e-12)


def test_tracker_keeps_numbers_and_names_merges():
    rng = np.random.default_rng(3)
    P = rng.normal(size=(6, 4))
    aspects = [1, -1, 1, -1, 1, -1]
    t = ModeTracker()
    assert t.update(P, aspects) == [1, 2, 3, 4, 5, 6]
    # shuffle, move a little, drop modes 2 and 3 (one of each aspect) and flip the sign of one
    keep = [5, 0, 3, 4]
    Q = P[keep] + 1e-3 * rng.normal(size=(4, 4))
    Q[1] *= -1                                   # x and -x are one projective point
    numbers = t.update(Q, [aspects[k] for k in keep])
    assert numbers == [k + 1 for k in keep]
    assert t.message.startswith("modes 2 and 3 merged")
    # two new modes get the smallest free numbers
    R = np.vstack([Q, rng.normal(size=(2, 4)) * 10])
    assert sorted(t.update(R, [aspects[k] for k in keep] + [1, -1])) == [1, 2, 3, 4, 5, 6]
    assert "new modes 2 and 3 appeared" in t.message
    assert np.allclose(projective_distance(P[:1], -P[:1]), 0)
