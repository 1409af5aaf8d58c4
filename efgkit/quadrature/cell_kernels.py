"""Compiled loop of :class:`efgkit.quadrature.cell_rule.CellRule`: its points written in any order.

The points of a cell rule are numbered segment by segment (``start (s + 1,)``: the first
point of each segment). A segment of whole cells (``rule[k] >= 0``) holds the cells
``first[k], first[k] + 1, ...`` of the corner table, each with the ``q[rule[k]]`` points of
its tensor rule; point ``g`` of it is offset ``j = (g - start[k]) % q`` of cell
``first[k] + (g - start[k]) // q``. A listed segment (``rule[k] = -1``) holds the rows
``first[k], ...`` of the listed points. The loop is parallel over the output points, each
written once, with the arithmetic of the numpy path (corner + offset), so both give the
same bits.
"""

from __future__ import annotations

from numba import njit, prange

from ..timing import watch_compiles

__all__ = ["write_points"]

watch_compiles()  # before anything here compiles


@njit(cache=True, parallel=True)
def write_points(order, base, start, first, rule, q, corner, cell, offsets, weights,
                 listed_x, listed_w, listed_owner, x, w, owner, x_only):
    """Point ``order[i]`` (``base + i`` when ``order`` is empty) into ``x[i]``, ``w[i]``,
    ``owner[i]`` for every ``i < len(x)`` (only ``x`` with ``x_only``)."""
    n_seg = len(first)
    for i in prange(len(x)):
        g = order[i] if len(order) else base + i
        lo, hi = 0, n_seg - 1  # the last segment starting at or before g
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if start[mid] <= g:
                lo = mid
            else:
                hi = mid - 1
        local = g - start[lo]
        r = rule[lo]
        if r >= 0:
            k = local // q[r]
            c, j = first[lo] + k, local - k * q[r]
            x[i, 0] = corner[c, 0] + offsets[r, j, 0]
            x[i, 1] = corner[c, 1] + offsets[r, j, 1]
            if not x_only:
                w[i] = weights[r, j]
                owner[i] = cell[c]
        else:
            row = first[lo] + local
            x[i, 0] = listed_x[row, 0]
            x[i, 1] = listed_x[row, 1]
            if not x_only:
                w[i] = listed_w[row]
                owner[i] = listed_owner[row]
