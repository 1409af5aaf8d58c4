"""Compiled (numba) assembly of the P1 stiffness of the auxiliary space
(:func:`efgkit.system.auxiliary_p1.p1_stiffness`) for large solves.

Imported only for :data:`efgkit.system.compiled_operators.COMPILED_MIN_UNKNOWNS` unknowns
and more, like the other kernels of the iterative solve. One pass over the triangles puts
each element's 3 x 3 node blocks into the rows of their first node (a counting sort by
row), a second pass merges the blocks of each node pair in the order of the triangles (the
order in which the numpy path's stable sort and ``add.reduceat`` sum them) and sorts each
row's columns: O(t) work against the numpy path's (t, 3, 3, 2, 2) temporaries and its sort
of 9 t keys (97k nodes: docs/performance.md, solve_stage_notes).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..timing import watch_compiles

__all__ = ["p1_node_blocks"]

watch_compiles()


@njit(cache=True, nogil=True)
def p1_node_blocks(tri, g, area, C, n):  # pragma: no cover - compiled
    """Node-block CSR of ``sum_e area_e B^T D B``: (indptr (n + 1,), columns (m,), blocks
    (m, 4)), block ``[c * 2 + d]`` coupling component c of the row node with component d of
    the column node; columns sorted in each row.

    ``tri`` (t, 3) int64 vertices, ``g`` (t, 3, 2) gradients of the barycentric coordinates,
    ``area`` (t,) > 0, ``C`` (4, 4) with ``B_a^T D B_b [c, d] = sum_kl g_ak g_bl C[k * 2 + l,
    c * 2 + d]`` (:func:`efgkit.system.auxiliary_p1.p1_stiffness`)."""
    t = tri.shape[0]
    start = np.zeros(n + 1, np.int64)
    for e in range(t):
        for a in range(3):
            start[tri[e, a] + 1] += 3
    for i in range(n):
        start[i + 1] += start[i]
    fill = start[:-1].copy()
    col = np.empty(9 * t, np.int64)
    val = np.empty((9 * t, 4))
    for e in range(t):
        for a in range(3):
            i = tri[e, a]
            for b in range(3):
                k = fill[i]
                fill[i] += 1
                col[k] = tri[e, b]
                for cd in range(4):
                    s = 0.0
                    for kk in range(2):
                        for ll in range(2):
                            s += g[e, a, kk] * g[e, b, ll] * C[kk * 2 + ll, cd]
                    val[k, cd] = area[e] * s
    slot = np.full(n, -1, np.int64)  # position of a column in the current row's output
    indptr = np.zeros(n + 1, np.int64)
    out_col = np.empty(9 * t, np.int64)
    out_val = np.zeros((9 * t, 4))
    m = 0
    for i in range(n):
        row0 = m
        for k in range(start[i], start[i + 1]):
            j = col[k]
            p = slot[j]
            if p < row0:  # first block of (i, j) in this row
                p = m
                slot[j] = m
                out_col[m] = j
                m += 1
            for cd in range(4):
                out_val[p, cd] += val[k, cd]
        for p in range(row0 + 1, m):  # insertion sort of the row's few columns
            q = p
            while q > row0 and out_col[q - 1] > out_col[q]:
                cj = out_col[q]
                out_col[q] = out_col[q - 1]
                out_col[q - 1] = cj
                for cd in range(4):
                    v = out_val[q, cd]
                    out_val[q, cd] = out_val[q - 1, cd]
                    out_val[q - 1, cd] = v
                q -= 1
        indptr[i + 1] = m
    return indptr, out_col[:m].copy(), out_val[:m].copy()
