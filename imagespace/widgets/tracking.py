"""Stable mode numbers in the explorers: a mode keeps its number from one joint vector to the next.

Modes are matched to the previous joint vector's modes of the same aspect by the nearest point of
the image space (an optimal assignment, so two modes never take one number); a mode without a
partner gets the smallest free number. Modes that vanish in a pair have merged (a singularity was
crossed) and left the real set; the tracker says so.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ModeTracker", "projective_distance", "assignment"]


def projective_distance(a, b):
    """Distances ``(n, m)`` between the points ``a`` (n, d) and ``b`` (m, d) of a projective space:
    each scaled to unit length, the smaller of ``|a - b|`` and ``|a + b|`` (``x`` and ``-x`` are one
    point).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.widgets.tracking import projective_distance
    >>> projective_distance(np.array([[1.0, 0, 0, 0]]), np.array([[-2.0, 0, 0, 0], [0, 1.0, 0, 0]])).round(3)
    array([[0.   , 1.414]])
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    b = b / np.linalg.norm(b, axis=1, keepdims=True)
    minus = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    plus = np.linalg.norm(a[:, None, :] + b[None, :, :], axis=2)
    return np.minimum(minus, plus)


def assignment(D):
    """Rows and columns of a minimum-cost one-to-one assignment of the cost matrix ``D`` (n, m):
    every permutation for small matrices (the planar explorer: at most six modes), else
    :func:`scipy.optimize.linear_sum_assignment` (imported only then).

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.widgets.tracking import assignment
    >>> assignment(np.array([[5.0, 1.0], [1.0, 5.0], [3.0, 3.0]]))
    ([0, 1], [1, 0])
    """
    import itertools

    D = np.asarray(D, dtype=float)
    n, m = D.shape
    if min(n, m) == 0:
        return [], []
    if max(n, m) > 7:
        from scipy.optimize import linear_sum_assignment

        r, c = linear_sum_assignment(D)
        return [int(v) for v in r], [int(v) for v in c]
    best, pick = np.inf, None
    if n <= m:
        for cols in itertools.permutations(range(m), n):
            cost = float(D[np.arange(n), cols].sum())
            if cost < best:
                best, pick = cost, (list(range(n)), list(cols))
    else:
        for rows in itertools.permutations(range(n), m):
            cost = float(D[rows, np.arange(m)].sum())
            if cost < best:
                best, pick = cost, (list(rows), list(range(m)))
        order = np.argsort(pick[0])
        pick = ([pick[0][k] for k in order], [pick[1][k] for k in order])
    return pick


def _names(numbers):
    numbers = sorted(numbers)
    if len(numbers) == 1:
        return f"mode {numbers[0]}"
    return "modes " + ", ".join(str(n) for n in numbers[:-1]) + f" and {numbers[-1]}"


class ModeTracker:
    """Numbers for the modes shown, kept while a mode lives.

    Examples
    --------
    >>> import numpy as np
    >>> from imagespace.widgets.tracking import ModeTracker
    >>> t = ModeTracker()
    >>> t.update(np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 1.0, 0]]), [1, -1, 1])
    [1, 2, 3]
    >>> t.update(np.array([[0, 0, 1.0, 0.1]]), [1])          # 1 and 2 vanished, 3 moved a little
    [3]
    >>> t.message
    'modes 1 and 2 merged and left the real modes (a singularity was crossed)'
    """

    def __init__(self):
        self.numbers = []
        self.points = np.zeros((0, 4))
        self.aspects = []
        self.message = ""
        self._started = False

    def reset(self):
        self.__init__()

    def update(self, points, aspects):
        """The numbers of the modes at ``points`` (n, d) with ``aspects`` (n,), in their order."""
        points = np.asarray(points, dtype=float).reshape(len(aspects), -1) if len(aspects) else np.zeros((0, 4))
        aspects = [1 if a >= 0 else -1 for a in aspects]
        numbers = [0] * len(aspects)
        kept = set()
        if len(self.numbers) and len(aspects) and self.points.shape[1] == points.shape[1]:
            for a in (1, -1):
                old = [i for i, s in enumerate(self.aspects) if s == a]
                new = [j for j, s in enumerate(aspects) if s == a]
                if not old or not new:
                    continue
                D = projective_distance(self.points[old], points[new])
                rows, cols = assignment(D)
                for r, c in zip(rows, cols):
                    numbers[new[c]] = self.numbers[old[r]]
                    kept.add(self.numbers[old[r]])
        free = (n for n in range(1, len(self.numbers) + len(aspects) + 2) if n not in kept)
        fresh = []
        for j in range(len(numbers)):
            if numbers[j] == 0:
                numbers[j] = next(free)
                fresh.append(numbers[j])
        gone = [n for n in self.numbers if n not in kept]
        parts = []
        if gone:
            verb = "merged and left" if len(gone) == 2 else "left"
            parts.append(f"{_names(gone)} {verb} the real modes (a singularity was crossed)")
        if fresh and self._started:
            parts.append(f"new {_names(fresh)} appeared")
        self.message = "; ".join(parts)
        self.numbers, self.points, self.aspects = list(numbers), points.copy(), list(aspects)
        self._started = True
        return list(numbers)
