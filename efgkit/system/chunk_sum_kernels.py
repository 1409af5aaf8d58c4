"""Compiled (numba) sum of the chunks' stiffnesses of the streamed assembly
(:func:`efgkit.system.streamed.chunk_sum`) into one CSR allocated once.

The output holds, for each row, room for the sum of that row's lengths over all chunks (an
upper bound of the merged row). :func:`add_chunk` merges one chunk's rows into it: a row seen
for the first time is copied, a row seen before is merged with the chunk's row from the back
of its room (both sorted by column), equal columns added, so the entries are summed in the
order of the chunks. :func:`close_gaps` then moves the rows together and drops the entries
that summed to exactly zero (as scipy's sparse sums do). O(sum of the chunks' nnz) work and one allocation,
against O(nnz log n_chunks) work and ~log2(n_chunks) fresh copies of K for pairwise sums
(docs/performance.md, stage_slopes_notes).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..timing import watch_compiles

__all__ = ["add_chunk", "close_gaps"]

watch_compiles()


@njit(cache=True, nogil=True)
def add_chunk(start, first, fill, out_idx, out_val, dof, indptr, indices, data):  # pragma: no cover
    """Add one chunk's CSR (``indptr (m + 1,)``, ``indices``, ``data``; local numbering, columns
    ascending in each row) to the rows ``dof (m,)`` (ascending local -> global) of the output.

    Output row i lives in ``out_idx, out_val [start[i] : start[i + 1]]``: its ``fill[i]``
    entries (columns ascending) from ``start[i] + first[i]`` on; both are updated. A merge
    writes from the back of the room it may need (the row's entries so far plus the chunk's,
    which the room holds); the columns both hold leave a gap in front, so ``first`` grows."""
    for r in range(dof.shape[0]):
        q0, q1 = indptr[r], indptr[r + 1]
        if q1 == q0:
            continue
        i = dof[r]
        b, f = start[i] + first[i], fill[i]
        if f == 0:  # first chunk with this row: a copy
            for q in range(q0, q1):
                out_idx[b + q - q0] = dof[indices[q]]
                out_val[b + q - q0] = data[q]
            fill[i] = q1 - q0
            continue
        w, p, q = b + f + (q1 - q0) - 1, b + f - 1, q1 - 1  # w >= p throughout
        while q >= q0:
            jc = dof[indices[q]]
            if p >= b and out_idx[p] > jc:
                out_idx[w] = out_idx[p]
                out_val[w] = out_val[p]
                p -= 1
            elif p >= b and out_idx[p] == jc:
                out_idx[w] = jc
                out_val[w] = out_val[p] + data[q]  # earlier chunks' sum + this chunk's
                p -= 1
                q -= 1
            else:
                out_idx[w] = jc
                out_val[w] = data[q]
                q -= 1
            w -= 1
        gap = w - p  # the columns in both: the row's first entries move up to close it
        if gap > 0:
            while p >= b:
                out_idx[p + gap] = out_idx[p]
                out_val[p + gap] = out_val[p]
                p -= 1
        first[i] += gap
        fill[i] = f + (q1 - q0) - gap


@njit(cache=True, nogil=True)
def close_gaps(start, first, fill, out_idx, out_val):  # pragma: no cover - compiled
    """Move the filled part of each row to the front in row order, leaving out exact zeros;
    returns the CSR ``indptr (n + 1,)`` (the dtype of ``start``) of the result in
    ``out_idx[:indptr[-1]]``, ``out_val[:indptr[-1]]``."""
    n = fill.shape[0]
    indptr = np.empty(n + 1, start.dtype)
    indptr[0] = 0
    m = 0
    for i in range(n):
        b = start[i] + first[i]
        for k in range(b, b + fill[i]):
            if out_val[k] != 0.0:
                out_idx[m] = out_idx[k]
                out_val[m] = out_val[k]
                m += 1
        indptr[i + 1] = m
    return indptr
