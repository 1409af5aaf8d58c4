"""Compiled (numba) kernels of the stiffness assembly (:func:`efgkit.system.assemble.stiffness`).

Imported only on the compiled path (:data:`efgkit.jit.COMPILED_MIN` quadrature points and
more), so that a small run neither imports numba nor compiles anything.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..timing import watch_compiles

__all__ = ["mirror_upper", "pattern", "stiffness_blocks", "transpose_padded"]

watch_compiles()


@njit(cache=True)
def transpose_padded(idx, mask, n_functions):
    """Points of each function: CSR (indptr (n_functions+1,), point (nnz,), slot (nnz,))."""
    n, k = idx.shape
    counts = np.zeros(n_functions + 1, np.int64)
    for q in range(n):
        for a in range(k):
            if mask[q, a]:
                counts[idx[q, a] + 1] += 1
    indptr = np.cumsum(counts)
    fill = indptr[:-1].copy()
    point = np.empty(indptr[-1], np.int64)
    slot = np.empty(indptr[-1], np.int64)
    for q in range(n):
        for a in range(k):
            if mask[q, a]:
                I = idx[q, a]
                point[fill[I]] = q
                slot[fill[I]] = a
                fill[I] += 1
    return indptr, point, slot


@njit(cache=True, parallel=True)
def pattern(t_ptr, t_point, trial_idx, trial_mask, n_cols, n_threads):
    """Column pattern of every row: the trial functions met in the row's points."""
    n_rows = len(t_ptr) - 1
    row_len = np.zeros(n_rows + 1, np.int64)
    k = trial_idx.shape[1]
    for t in prange(n_threads):
        seen = np.full(n_cols, -1, np.int64)
        for I in range(t, n_rows, n_threads):
            c = 0
            for p in range(t_ptr[I], t_ptr[I + 1]):
                q = t_point[p]
                for b in range(k):
                    if trial_mask[q, b]:
                        J = trial_idx[q, b]
                        if seen[J] != I:
                            seen[J] = I
                            c += 1
            row_len[I + 1] = c
    indptr = np.cumsum(row_len)
    cols = np.empty(indptr[-1], np.int64)
    for t in prange(n_threads):
        seen = np.full(n_cols, -1, np.int64)
        for I in range(t, n_rows, n_threads):
            c = indptr[I]
            for p in range(t_ptr[I], t_ptr[I + 1]):
                q = t_point[p]
                for b in range(k):
                    if trial_mask[q, b]:
                        J = trial_idx[q, b]
                        if seen[J] != I:
                            seen[J] = I
                            cols[c] = J
                            c += 1
            cols[indptr[I]:indptr[I + 1]].sort()
    return indptr, cols


@njit(cache=True, parallel=True)
def stiffness_blocks(indptr, cols, t_ptr, t_point, t_slot, tgx, tgy, trial_idx, trial_mask,
                      gx, gy, w, D, upper, n_threads):
    """Blocks (nnz, 2, 2) of K in the pattern (indptr, cols); with ``upper`` only the blocks
    J >= I (the rest is left zero for :func:`mirror_upper`)."""
    n_rows = len(indptr) - 1
    n_cols = 0
    for c in cols:
        n_cols = max(n_cols, c + 1)
    data = np.zeros((len(cols), 2, 2))
    k = trial_idx.shape[1]
    for t in prange(n_threads):
        where = np.full(max(n_cols, 1), -1, np.int64)
        for I in range(t, n_rows, n_threads):
            for c in range(indptr[I], indptr[I + 1]):
                where[cols[c]] = c
            for p in range(t_ptr[I], t_ptr[I + 1]):
                q = t_point[p]
                a = t_slot[p]
                ax = w[q] * tgx[q, a]
                ay = w[q] * tgy[q, a]
                for b in range(k):
                    if not trial_mask[q, b] or (upper and trial_idx[q, b] < I):
                        continue
                    bx = gx[q, b]
                    by = gy[q, b]
                    # D B_b: columns for the x and y components of J.
                    s0x = D[0, 0] * bx + D[0, 2] * by
                    s1x = D[1, 0] * bx + D[1, 2] * by
                    s2x = D[2, 0] * bx + D[2, 2] * by
                    s0y = D[0, 1] * by + D[0, 2] * bx
                    s1y = D[1, 1] * by + D[1, 2] * bx
                    s2y = D[2, 1] * by + D[2, 2] * bx
                    blk = data[where[trial_idx[q, b]]]
                    blk[0, 0] += ax * s0x + ay * s2x
                    blk[0, 1] += ax * s0y + ay * s2y
                    blk[1, 0] += ay * s1x + ax * s2x
                    blk[1, 1] += ay * s1y + ax * s2y
    return data


@njit(cache=True, parallel=True)
def mirror_upper(indptr, cols, data):
    """K_JI = K_IJ^T for the blocks J > I of a symmetric pattern (sorted columns); each
    lower block is written once, by its row I."""
    n_rows = len(indptr) - 1
    for I in prange(n_rows):
        for c in range(indptr[I], indptr[I + 1]):
            J = cols[c]
            if J <= I:
                continue
            lo, hi = indptr[J], indptr[J + 1]
            while lo < hi:  # binary search for column I in row J
                mid = (lo + hi) // 2
                if cols[mid] < I:
                    lo = mid + 1
                else:
                    hi = mid
            data[lo, 0, 0] = data[c, 0, 0]
            data[lo, 0, 1] = data[c, 1, 0]
            data[lo, 1, 0] = data[c, 0, 1]
            data[lo, 1, 1] = data[c, 1, 1]
