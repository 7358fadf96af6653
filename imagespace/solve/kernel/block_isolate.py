"""Stage 3 of the lockstep kernel (:mod:`.lockstep`): the Bernstein--Descartes isolation of
:func:`imagespace.core.isolate.count_real_roots_row` for a block of rows, with the first levels of
the subdivision tree computed and classified for the whole block at once (the split grid)."""

from __future__ import annotations

import math

import numpy as np

from ...core._numba import njit
from ...core.isolate import (BERNSTEIN_MATRIX, MAX_DEGREE, BINOM, BOUND_GAMMA, SLOT_HEAP_INDEX, BOUND_INFLATE,
                             NO_SCALING_ABOVE, NO_SCALING_BELOW, BOUND_TINY as _ISO_TINY, UNIT_ROUNDOFF as _ISO_U, search_chart,
                             store_grid, count_real_roots_row)
from .block_layout import GRID_LEVELS, LOCKSTEP_ROWS, _S_BERN, _S_SC

__all__ = ["isolate_block"]


@njit(cache=True)
def _half_split_block(src, left, right, nb):
    """de Casteljau at 1/2 of the split-grid node ``src`` (a row of the grid: field ``f`` of the
    block's row ``l`` at ``f * LOCKSTEP_ROWS + l``) for every row of the block: the children into
    ``left`` and ``right``, the certain sign of the split point into field 14 of ``src``
    (:func:`imagespace.core.isolate._split` with ``lam = 1/2``, operation for operation). The
    fields sit at constant distances, so the loop over the rows vectorises."""
    u = _ISO_U
    B = LOCKSTEP_ROWS
    for l in range(nb):
        c0 = src[l]
        c1 = src[1 * B + l]
        c2 = src[2 * B + l]
        c3 = src[3 * B + l]
        c4 = src[4 * B + l]
        c5 = src[5 * B + l]
        c6 = src[6 * B + l]
        e0 = src[7 * B + l]
        e1 = src[8 * B + l]
        e2 = src[9 * B + l]
        e3 = src[10 * B + l]
        e4 = src[11 * B + l]
        e5 = src[12 * B + l]
        e6 = src[13 * B + l]
        p0 = (c0 + c1) * 0.5
        ep0 = (e0 + e1) * 0.5 + u * abs(p0)
        p1 = (c1 + c2) * 0.5
        ep1 = (e1 + e2) * 0.5 + u * abs(p1)
        p2 = (c2 + c3) * 0.5
        ep2 = (e2 + e3) * 0.5 + u * abs(p2)
        p3 = (c3 + c4) * 0.5
        ep3 = (e3 + e4) * 0.5 + u * abs(p3)
        p4 = (c4 + c5) * 0.5
        ep4 = (e4 + e5) * 0.5 + u * abs(p4)
        p5 = (c5 + c6) * 0.5
        ep5 = (e5 + e6) * 0.5 + u * abs(p5)
        q0 = (p0 + p1) * 0.5
        eq0 = (ep0 + ep1) * 0.5 + u * abs(q0)
        q1 = (p1 + p2) * 0.5
        eq1 = (ep1 + ep2) * 0.5 + u * abs(q1)
        q2 = (p2 + p3) * 0.5
        eq2 = (ep2 + ep3) * 0.5 + u * abs(q2)
        q3 = (p3 + p4) * 0.5
        eq3 = (ep3 + ep4) * 0.5 + u * abs(q3)
        q4 = (p4 + p5) * 0.5
        eq4 = (ep4 + ep5) * 0.5 + u * abs(q4)
        r0 = (q0 + q1) * 0.5
        er0 = (eq0 + eq1) * 0.5 + u * abs(r0)
        r1 = (q1 + q2) * 0.5
        er1 = (eq1 + eq2) * 0.5 + u * abs(r1)
        r2 = (q2 + q3) * 0.5
        er2 = (eq2 + eq3) * 0.5 + u * abs(r2)
        r3 = (q3 + q4) * 0.5
        er3 = (eq3 + eq4) * 0.5 + u * abs(r3)
        s0 = (r0 + r1) * 0.5
        es0 = (er0 + er1) * 0.5 + u * abs(s0)
        s1 = (r1 + r2) * 0.5
        es1 = (er1 + er2) * 0.5 + u * abs(s1)
        s2 = (r2 + r3) * 0.5
        es2 = (er2 + er3) * 0.5 + u * abs(s2)
        v0 = (s0 + s1) * 0.5
        ev0 = (es0 + es1) * 0.5 + u * abs(v0)
        v1 = (s1 + s2) * 0.5
        ev1 = (es1 + es2) * 0.5 + u * abs(v1)
        w0 = (v0 + v1) * 0.5
        ew0 = ((ev0 + ev1) * 0.5 + u * abs(w0)) * BOUND_INFLATE + _ISO_TINY
        left[l] = c0
        left[1 * B + l] = p0
        left[2 * B + l] = q0
        left[3 * B + l] = r0
        left[4 * B + l] = s0
        left[5 * B + l] = v0
        left[6 * B + l] = w0
        left[7 * B + l] = e0
        left[8 * B + l] = ep0 * BOUND_INFLATE + _ISO_TINY
        left[9 * B + l] = eq0 * BOUND_INFLATE + _ISO_TINY
        left[10 * B + l] = er0 * BOUND_INFLATE + _ISO_TINY
        left[11 * B + l] = es0 * BOUND_INFLATE + _ISO_TINY
        left[12 * B + l] = ev0 * BOUND_INFLATE + _ISO_TINY
        left[13 * B + l] = ew0
        right[l] = w0
        right[1 * B + l] = v1
        right[2 * B + l] = s2
        right[3 * B + l] = r3
        right[4 * B + l] = q4
        right[5 * B + l] = p5
        right[6 * B + l] = c6
        right[7 * B + l] = ew0
        right[8 * B + l] = ev1 * BOUND_INFLATE + _ISO_TINY
        right[9 * B + l] = es2 * BOUND_INFLATE + _ISO_TINY
        right[10 * B + l] = er3 * BOUND_INFLATE + _ISO_TINY
        right[11 * B + l] = eq4 * BOUND_INFLATE + _ISO_TINY
        right[12 * B + l] = ep5 * BOUND_INFLATE + _ISO_TINY
        right[13 * B + l] = e6
        src[14 * B + l] = 1.0 if w0 > ew0 else (-1.0 if w0 < -ew0 else 0.0)


def _node_order(levels):
    """The split grid's nodes of one chart ordered by their left end, then by depth: rows of heap
    index, first and last leaf index, depth. Nodes where a search stops are disjoint, so this is
    the order of their intervals."""
    nleaf = 2 ** levels
    nodes = []
    for h in range(1, 2 * nleaf):
        depth = h.bit_length() - 1
        span = nleaf >> depth
        i0 = (h - (1 << depth)) * span
        nodes.append((i0, depth, h, i0 + span))
    nodes.sort()
    return np.array([(h, i0, i1, depth) for i0, depth, h, i1 in nodes], dtype=np.int64)


_NODE_ORDER = _node_order(GRID_LEVELS)


@njit(cache=True)
def _classify_block(grid, nleaf, status, nb, kinds):
    """The split grid's nodes classified for the whole block, branch free: ``kinds[2 ch, h, l]``
    the kind of node ``h`` of chart ``ch`` (0 no root, 1 one simple root, 2 undecided:
    :func:`imagespace.core.isolate._classify`; -1 for a root node with an end of uncertain sign,
    which makes the row undecided), ``kinds[2 ch + 1, h, l]`` 1 where the row's search visits the
    node: the root, and the children of a visited undecided node whose split point has a certain
    sign (the search splits it at 1/2 first). Rows with ``status != 0`` are not searched."""
    B = LOCKSTEP_ROWS
    for ch in range(2):
        base = ch * 2 * nleaf
        kind = kinds[2 * ch]
        seen = kinds[2 * ch + 1]
        for h in range(1, 2 * nleaf):
            g = grid[base + h]
            kh = kind[h]
            for l in range(nb):
                c0 = g[l]
                c6 = g[6 * B + l]
                s0 = 1.0 if c0 > 0 else -1.0
                sd = 1.0 if c6 > 0 else -1.0
                o1 = s0 * g[B + l] < g[8 * B + l]
                o2 = s0 * g[2 * B + l] < g[9 * B + l]
                o3 = s0 * g[3 * B + l] < g[10 * B + l]
                o4 = s0 * g[4 * B + l] < g[11 * B + l]
                o5 = s0 * g[5 * B + l] < g[12 * B + l]
                m5 = s0 * g[5 * B + l] > -g[12 * B + l]
                m4 = m5 | (s0 * g[4 * B + l] > -g[11 * B + l])
                m3 = m4 | (s0 * g[3 * B + l] > -g[10 * B + l])
                m2 = m3 | (s0 * g[2 * B + l] > -g[9 * B + l])
                same = o1 | o2 | o3 | o4 | o5
                cross = (o1 & m2) | (o2 & m3) | (o3 & m4) | (o4 & m5)
                k = (2 if same else 0) if s0 == sd else (2 if cross else 1)
                if h == 1:
                    e0 = g[7 * B + l]
                    e6 = g[13 * B + l]
                    certain = (c0 > e0 or c0 < -e0) and (c6 > e6 or c6 < -e6)
                    k = k if certain else -1
                kh[l] = k
        s1 = seen[1]
        k1 = kind[1]
        for l in range(nb):
            s1[l] = 1 if (status[l] == 0 and k1[l] >= 0) else 0
        for h in range(2, 2 * nleaf):
            sv = seen[h]
            sp = seen[h // 2]
            kp = kind[h // 2]
            gp = grid[base + h // 2]
            for l in range(nb):
                sv[l] = 1 if (sp[l] == 1 and kp[l] == 2 and gp[14 * B + l] != 0.0) else 0


@njit(cache=True)
def _walk_lane(grid, nleaf, kinds, lane, d, lo, hi, chart, work):
    """:func:`~imagespace.core.isolate.count_real_roots_row` for row ``lane`` of the block from its
    classified split grid (:func:`_classify_block`): the nodes its depth-first search would stop
    at on the grid (visited, and not split there at 1/2) are taken right to left, as the search
    meets them: a node without a root is passed, a one-root node that touches neither the last
    root's interval nor an excluded end is a root, any other node is searched from
    (:func:`imagespace.core.isolate.search_chart`, splitting off the grid). The same decisions in the
    same order, hence the same count and intervals; the split budget counts every split on the
    grid up front (the search gives up at the same total)."""
    B = LOCKSTEP_ROWS
    order = _NODE_ORDER
    splits = 0
    for ch in range(2):
        base = ch * 2 * nleaf
        if kinds[2 * ch, 1, lane] < 0:
            return -1
        for h in range(1, nleaf):
            if kinds[2 * ch + 1, h, lane] == 1 and kinds[2 * ch, h, lane] == 2 and grid[base + h, 14 * B + lane] != 0.0:
                splits += 1
    count = 0
    for ch in range(2):
        base = ch * 2 * nleaf
        kind = kinds[2 * ch]
        seen = kinds[2 * ch + 1]
        start = count
        last_lo = np.inf
        for j in range(order.shape[0] - 1, -1, -1):
            h = order[j, 0]
            if seen[h, lane] == 0:
                continue
            k = kind[h, lane]
            if k == 0 or (k == 2 and h < nleaf and grid[base + h, 14 * B + lane] != 0.0):
                continue
            a = -1.0 + order[j, 1] * (2.0 / nleaf)
            b = -1.0 + order[j, 2] * (2.0 / nleaf)
            if k == 1 and b != last_lo and not (ch == 1 and (a == -1.0 or b == 1.0)):
                if count >= d:
                    return -1
                lo[count] = a
                hi[count] = b
                chart[count] = ch
                count += 1
                last_lo = a
                continue
            store_grid(work, 0, a, b, order[j, 3], grid, base + h, B, lane)
            work[SLOT_HEAP_INDEX] = h
            count, splits, last_lo = search_chart(work, ch, count, splits, last_lo, d, lo, hi, chart, grid, lane, nleaf)
            if count < 0:
                return -1
        i, j = start, count - 1
        while i < j:
            lo[i], lo[j] = lo[j], lo[i]
            hi[i], hi[j] = hi[j], hi[i]
            i += 1
            j -= 1
    return count


@njit(cache=True)
def isolate_block(S, F0, Fe0, d, nb, grid, nleaf, status, counts, lo, hi, chart, work, fl, el, kinds):
    """:func:`~imagespace.core.isolate.count_real_roots_row` for every row of the block: the form
    of degree ``d`` in rows ``F0`` to ``F0 + d`` of ``S``, its bounds in ``Fe0`` on; counts into
    ``counts[l]``, the isolating intervals into ``lo[l], hi[l], chart[l]``.

    ``grid`` (``grid_rows(levels)``, ``GRID_FIELDS * LOCKSTEP_ROWS``) takes the split grid (see
    :mod:`imagespace.core.isolate`), ``nleaf = 2**levels``;
    ``status`` (``nb``) int scratch; ``work`` (``ISOLATE_WORK_SIZE``), ``fl``, ``el`` (7) scratch
    of the rows' searches; ``kinds`` (4, 2 * nleaf, LOCKSTEP_ROWS) int scratch of :func:`_classify_block`.
    """
    # the rows' inputs as count_real_roots_row checks and scales them: rows whose forms would be
    # scaled take the slow lane (count_real_roots_row itself), non-finite ones are undecided
    for l in range(nb):
        status[l] = 0
    for k in range(d + 1):
        f = S[F0 + k]
        e = S[Fe0 + k]
        for l in range(nb):
            if not (math.isfinite(f[l]) and math.isfinite(e[l])) or not e[l] >= 0.0:
                status[l] = -1
    sc = S[_S_BERN]
    for l in range(nb):
        sc[l] = 0.0
    for k in range(d + 1):
        f = S[F0 + k]
        for l in range(nb):
            if abs(f[l]) > sc[l]:
                sc[l] = abs(f[l])
    for l in range(nb):
        big = sc[l]
        if big == 0.0:
            status[l] = -1
        elif status[l] == 0 and not NO_SCALING_BELOW <= big <= NO_SCALING_ABOVE:
            status[l] = 1
    for k in range(d + 1):
        f = S[F0 + k]
        e = S[Fe0 + k]
        g = S[_S_SC + k]
        ge = S[_S_SC + MAX_DEGREE + 1 + k]
        for l in range(nb):
            g[l] = f[l]
            ge[l] = e[l] * (1.0 + 2.0 * _ISO_U) + _ISO_TINY
    for k in range(d + 1):
        ge = S[_S_SC + MAX_DEGREE + 1 + k]
        for l in range(nb):
            if status[l] == 0 and not math.isfinite(ge[l]):
                status[l] = -1
    # the root node of each chart (Bernstein coefficients of degree 6 on [-1, 1]) and the grid
    acc = S[_S_BERN]
    mag = S[_S_BERN + 1]
    box = S[_S_BERN + 2]
    B = LOCKSTEP_ROWS
    for ch in range(2):
        root = grid[ch * 2 * nleaf + 1]
        for i in range(MAX_DEGREE + 1):
            for l in range(nb):
                acc[l] = 0.0
                mag[l] = 0.0
                box[l] = 0.0
            for k in range(d + 1):
                kk = d - k if ch == 1 else k
                w = BERNSTEIN_MATRIX[i, k]
                aw = abs(w)
                g = S[_S_SC + kk]
                ge = S[_S_SC + MAX_DEGREE + 1 + kk]
                for l in range(nb):
                    acc[l] += w * g[l]
                    mag[l] += aw * abs(g[l])
                    box[l] += aw * ge[l]
            binom = BINOM[i]
            for l in range(nb):
                b = acc[l] / binom
                root[i * B + l] = b
                root[(MAX_DEGREE + 1 + i) * B + l] = ((box[l] + BOUND_GAMMA * mag[l]) / binom + _ISO_U * abs(b)) * BOUND_INFLATE + _ISO_TINY
        h = 1
        while h < nleaf:
            base = ch * 2 * nleaf
            _half_split_block(grid[base + h], grid[base + 2 * h], grid[base + 2 * h + 1], nb)
            h += 1
    # the grid classified for the block at once, then each row's search from where it leaves the grid
    _classify_block(grid, nleaf, status, nb, kinds)
    for l in range(nb):
        if status[l] < 0:
            counts[l] = -1
        elif status[l] == 1:
            for k in range(d + 1):
                fl[k] = S[F0 + k, l]
                el[k] = S[Fe0 + k, l]
            counts[l] = count_real_roots_row(fl, el, d, lo[l], hi[l], chart[l], work)
        else:
            counts[l] = _walk_lane(grid, nleaf, kinds, l, d, lo[l], hi[l], chart[l], work)
