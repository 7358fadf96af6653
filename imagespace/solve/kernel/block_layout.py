"""The block layout of the lockstep kernel (:mod:`.lockstep`): rows per block, levels of the
split grid, the named rows of the block workspace ``S`` (one column per row of the block) and of
the root columns ``MD`` (one column per root of the block)."""

from __future__ import annotations

import itertools

from ...core.elimination import ELIMINATION_ROW_SIZE, ROW_D, ROW_F
from ...core.isolate import MAX_DEGREE

__all__ = ["LOCKSTEP_ROWS", "GRID_LEVELS", "S_SIZE", "grid_rows"]

#: Rows per block (a speed knob: the block's workspace, ~40 kB, stays in the level-2 cache).
LOCKSTEP_ROWS = 32
#: Levels of the subdivision tree computed for the whole block before the rows' searches (a speed
#: knob: deeper nodes are split by the row that visits them).
GRID_LEVELS = 3

# the block's workspace S (S_SIZE, LOCKSTEP_ROWS), one named group of rows per quantity
_S_SIZES = (3,      # Q: the block's joint values
            4,      # TRIG: cos q, sin q and their bounds, of the current leg
            2,      # MONO: the current monomial and its bound
            8,      # ACC8: sum |products| per coefficient of the current leg
            24,     # C: the three quadrics (c, a0, a1, b0, b1, k0, k1, k2 each)
            24,     # DC: their derivatives in the joint values (scaled by modes_block)
            24,     # CE: bounds on C
            24,     # E: the elimination's rows E1, E2, E3
            24,     # EE: their bounds
            ELIMINATION_ROW_SIZE,   # EL: D, X2, X3, F (core.elimination layout)
            ELIMINATION_ROW_SIZE,   # ELE: their bounds
            ELIMINATION_ROW_SIZE,   # EACC: sum |products| per output coefficient
            5, 5,   # LIN, LINE: A3 X2 + B3 X3 + K3 D and its bounds
            2 * (MAX_DEGREE + 1),   # SC: F and E as the isolation takes them
            3,      # BERN: accumulators of the Bernstein conversion
            24,     # CS: the quadrics scaled to max |coefficient| 1
            2)      # FN, DN: max |F|, max |D|
(_S_Q, _S_TRIG, _S_MONO, _S_ACC8, _S_C, _S_DC, _S_CE, _S_E, _S_EE, _S_EL, _S_ELE, _S_EACC, _S_LIN, _S_LINE,
 _S_SC, _S_BERN, _S_CS, _S_FN) = (0, *itertools.accumulate(_S_SIZES[:-1]))
#: Rows of the block workspace.
S_SIZE = sum(_S_SIZES)


# the roots of a block (at most MAX_DEGREE per row), one column each: MD (_M_SIZE, MAX_DEGREE * rows)
_M_SIZES = (MAX_DEGREE + 1,   # P: the polynomial of the root's chart, scaled by 1 / max |F|
            6,                # A, B, FA, FB, T, W: bracket, values at its ends, iterate, width
            MAX_DEGREE + 1,   # H: Horner's value, derivative and magnitude (scratch of refine_roots)
            4, 2,             # X: the mode's image point; DET, JRES
            ROW_F - ROW_D,    # F: D, X2, X3 of the root's row (core.elimination layout, from ROW_D)
            24, 24,           # CS, G: the row's scaled quadrics and their scaled q-derivatives
            3)                # DN, CH, ST: the row's max |D|, the root's chart, its status (block_modes)
(_M_P, _M_A, _M_H, _M_X, _M_DET, _M_F, _M_CS, _M_G, _M_DN) = (0, *itertools.accumulate(_M_SIZES[:-1]))
_M_B, _M_FA, _M_FB, _M_T, _M_W = _M_A + 1, _M_A + 2, _M_A + 3, _M_A + 4, _M_A + 5
_M_JRES = _M_DET + 1
_M_CH, _M_ST = _M_DN + 1, _M_DN + 2
_M_SIZE = sum(_M_SIZES)
# columns of MD: the roots of a block (at most MAX_DEGREE * LOCKSTEP_ROWS), then room for as many
# again, where block_modes.newton_roots compacts the roots that Newton polishes
_M_MAX = 2 * MAX_DEGREE * LOCKSTEP_ROWS
# integer columns of the roots: MI (_MI_SIZE, MAX_DEGREE * rows)
_MI_LANE, _MI_CHART, _MI_DEG, _MI_DONE = range(4)
_MI_SIZE = 4


def grid_rows(levels=GRID_LEVELS):
    """Rows (nodes) of the split grid of :func:`isolate_block` for ``levels`` levels: two charts,
    the heap-ordered nodes ``1`` to ``2**(levels + 1) - 1`` of each (row 0 of a chart unused).

    Examples
    --------
    >>> from imagespace.solve.kernel.lockstep import grid_rows
    >>> grid_rows(3)
    32
    """
    return 2 * 2 ** (levels + 1)
