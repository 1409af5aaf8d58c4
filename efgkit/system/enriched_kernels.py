"""Compiled (numba) kernels of the enrichment blocks of the stiffness for few enrichment
unknowns at every point (the extrinsic MLS enrichment's K_I, K_II of a tip): K_ne summed
point by point into a dense array (:func:`extra_dense`) and K_ee with the stresses of the
unknowns (:func:`ee_block`), each the same sums in the same order as the sparse path it
replaces in :func:`efgkit.system.assemble.stiffness`, so the same K to the bit.

Imported on the compiled path only (:data:`efgkit.jit.COMPILED_MIN` quadrature points).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..timing import watch_compiles

__all__ = ["extra_dense", "ee_block"]

watch_compiles()


@njit(cache=True, nogil=True)
def extra_dense(idx, mask, gx, gy, xx_ptr, xx_col, xx_val, yy_ptr, yy_col, yy_val, xy_ptr,
                xy_col, xy_val, out):
    """K_ne of :func:`efgkit.system.kernels.extra_rows` point by point into a dense ``out (n_functions, 2,
    n_extra)`` (C order, zeroed by the caller; ``out[I, 0]`` the x row 2 I, ``out[I, 1]``
    the y row): one pass over the points in ascending order, each point's stress rows
    spread into dense (n_extra,) rows once, each (point, slot) adding its contributions
    to the row of its function. Every entry sums the same products as :func:`efgkit.system.kernels.extra_rows`
    in the same order (the points of a function ascending; per point xx, then yy, then
    xy; an unknown absent from a stress row adds an exact zero, which leaves a sum
    unchanged but for the sign of a zero), so the non-zero values are the same to the
    bit; entries never met stay 0. One thread: the order of each sum is fixed."""
    n_points, k = idx.shape
    ne = out.shape[2]
    une = np.uint64(ne)
    uk = np.uint64(k)
    flat_out = out.ravel()
    flat_idx, flat_mask = idx.ravel(), mask.ravel()
    flat_gx, flat_gy = gx.ravel(), gy.ravel()
    sxx = np.zeros(ne)
    syy = np.zeros(ne)
    sxy = np.zeros(ne)
    for q in range(n_points):
        sxx[:] = 0.0
        syy[:] = 0.0
        sxy[:] = 0.0
        for c in range(xx_ptr[q], xx_ptr[q + 1]):
            sxx[xx_col[c]] = xx_val[c]
        for c in range(yy_ptr[q], yy_ptr[q + 1]):
            syy[yy_col[c]] = yy_val[c]
        for c in range(xy_ptr[q], xy_ptr[q + 1]):
            sxy[xy_col[c]] = xy_val[c]
        s = np.uint64(q) * uk
        end = s + uk
        while s < end:
            if flat_mask[s]:
                o = np.uint64(flat_idx[s]) * np.uint64(2) * une
                bx = flat_gx[s]
                by = flat_gy[s]
                for e in range(ne):
                    ue = np.uint64(e)
                    flat_out[o + ue] += bx * sxx[e]
                    flat_out[o + une + ue] += by * syy[e]
                    flat_out[o + ue] += by * sxy[e]
                    flat_out[o + une + ue] += bx * sxy[e]
            s += np.uint64(1)


@njit(cache=True, nogil=True)
def ee_block(indptr, indices, eps, sig, n_extra):
    """K_ee (n_extra, n_extra) dense = sum_i eps_i^T sig_i of the three strain and weighted
    stress components ``eps, sig`` (tuples of three (nnz,) data arrays) on one CSR pattern
    ``indptr, indices`` over
    (n_points, n_extra): entry (e, f) of component i sums ``sig_i[q, f] eps_i[q, e]`` over
    the points q ascending, as scipy's product ``eps_i.T @ sig_i`` does (its CSC operand
    runs down the points of column f), and the three are added as ``(P_0 + P_1) + P_2``.
    Entries that no point reaches stay 0 (the sparse sums leave them out; the caller drops
    the zeros)."""
    P = np.zeros((3, n_extra, n_extra))
    for i in range(3):
        ep, sg = eps[i], sig[i]
        for q in range(len(indptr) - 1):
            for c1 in range(indptr[q], indptr[q + 1]):
                e = indices[c1]
                for c2 in range(indptr[q], indptr[q + 1]):
                    P[i, e, indices[c2]] += sg[c2] * ep[c1]
    return (P[0] + P[1]) + P[2]
