"""Compiled (numba) kernels of the stiffness assembly (:func:`efgkit.system.assemble.stiffness`).

Imported only on the compiled path (:data:`efgkit.jit.COMPILED_MIN` quadrature points and
more), so that a small run neither imports numba nor compiles anything.

The assembly is row by row with a dense accumulator (Gustavson's sparse product): the
points of each test function (:func:`count_points` then :func:`fill_points`, over chunks of
points) are visited once; every trial function met there gets its 2 x 2 block summed in
``acc[J]`` and is listed the first time it is met, so the pattern is found in the same
pass as the values (:func:`block_rows`). For a symmetric K only the blocks J >= I are
formed; :func:`lower_part` and :func:`scalar_rows` then write the full scalar CSR matrix
straight from these upper rows, the blocks J < I as transposes.

Every kernel works on a range of points or rows and releases the GIL; the caller runs
several ranges per thread from a Python thread pool (dynamic hand-out: a thread that the
shared machine stalls holds up its own range only, not a barrier as in ``prange``). The
padded (point, slot) arrays are read through flat views indexed with unsigned integers:
numba emits no negative-index wrap-around code for those, which halved the time of the
inner loop of :func:`block_rows` (9 -> 3-5 ns per (I, q, J) on one thread).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..timing import watch_compiles

__all__ = ["block_rows", "compile_vectorised", "count_points", "extra_rows", "fill_points",
           "lower_part", "scalar_rows", "side_by_side"]

watch_compiles()


def compile_vectorised(kernel, *args) -> None:
    """Compile ``kernel`` for the types of ``args`` (or load it from numba's cache) with
    LLVM's superword-level-parallelism vectoriser on, unless that overload exists already.

    numba leaves the SLP vectoriser off by default (``NUMBA_SLP_VECTORIZE=0``: it slowed
    some numba code down); in :func:`block_rows` it packs the four read-modify-writes of
    the 2 x 2 block (and their eight products) into vector instructions, lane by lane the
    same operations in the same order, so K is the same to the bit. The switch is numba's
    global configuration, read when a function is compiled: set for this compilation only
    (numba compiles one function at a time, under its compiler lock)."""
    from numba import typeof
    from numba.core import config

    signature = tuple(typeof(a) for a in args)
    if signature in kernel.overloads:
        return
    before = config.SLP_VECTORIZE
    config.SLP_VECTORIZE = 1
    try:
        kernel.compile(signature)
    finally:
        config.SLP_VECTORIZE = before


@njit(cache=True, nogil=True)
def count_points(q0, q1, idx, mask, counts):
    """Add to ``counts (n_functions,)`` the valid entries of points ``q0 <= q < q1`` per
    function; return how many valid entries of those rows do not ascend (0: the valid
    entries of every row ascend, and the functions J >= idx[q, a] of point q are those in
    the slots b >= a). First pass of the point lists (:func:`fill_points`); releases the
    GIL: chunks of points run on parallel threads."""
    uk = np.uint64(idx.shape[1])
    one = np.uint64(1)
    flat_idx, flat_mask = idx.ravel(), mask.ravel()
    bad = 0
    for q in range(q0, q1):
        s = np.uint64(q) * uk
        end = s + uk
        last = -1
        while s < end:
            if flat_mask[s]:
                I = np.int64(flat_idx[s])
                counts[np.uint64(I)] += 1
                if I <= last:
                    bad += 1
                last = I
            s += one
    return bad


@njit(cache=True, nogil=True)
def fill_points(q0, q1, idx, mask, start, pos):
    """Second pass of the point lists: ``pos[start[I]], pos[start[I] + 1], ...`` get
    ``q k + a`` for the entries ``idx[q, a] = I`` of points ``q0 <= q < q1``, ascending
    (``start`` is advanced). With ``start`` the offsets of this chunk's entries after those
    of the chunks before it, the lists are those of one serial pass over all points."""
    uk = np.uint64(idx.shape[1])
    one = np.uint64(1)
    flat_idx, flat_mask = idx.ravel(), mask.ravel()
    s = np.uint64(q0) * uk
    end = np.uint64(q1) * uk
    while s < end:
        if flat_mask[s]:
            u = np.uint64(flat_idx[s])
            f = np.uint64(start[u])
            pos[f] = s
            start[u] = f + one
        s += one


@njit(cache=True, nogil=True)
def block_rows(order, r0, r1, t_ptr, t_pos, tgx, tgy, trial_idx, trial_mask, gx, gy, w, D,
               upper, ascending, n_cols, capacity):
    """Block rows ``I = order[i]``, ``r0 <= i < r1``, of K, in that order: (lengths
    (r1 - r0,), cols (nnz,) int32 ascending per row, blocks (nnz, 2, 2)); with ``upper``
    only the blocks J >= I (with ``ascending`` rows of ``trial_idx``, those in the slots
    from I's own on). Each row's sums do not depend on ``order``; an order that keeps the
    supports of consecutive rows close keeps their points in cache.

    ``K_IJ += w_q B_I^v(x_q)^T D B_J(x_q)`` summed over the points q of test function I in
    the order of ``t_pos`` (:func:`transpose_padded` of the test functions), into
    ``acc[J]``; J is listed the first time it is met (``marker[J] = I``). With
    ``(ax, ay) = w_q grad v_I`` and ``(bx, by) = grad phi_J``,
    ``B_I^T D B_J = [[bx c0 + by c1, bx c1 + by c3], [bx c4 + by c5, bx c5 + by c7]]``
    for any D (symmetric or not), with ``c0 = ax D00 + ay D20``, ``c1 = ax D02 + ay D22``,
    ``c3 = ax D01 + ay D21``, ``c4 = ay D10 + ax D20``, ``c5 = ay D12 + ax D22``,
    ``c7 = ay D11 + ax D21`` formed once per (I, q): 8 products per (I, q, J) instead of
    20 for ``D B_J`` and its contraction. The (point, slot) entries and the accumulator are
    flat arrays indexed with unsigned integers (module docstring). Releases the GIL: chunks
    of rows run on parallel threads.
    """
    k = trial_idx.shape[1]
    uk = np.uint64(k)
    ukt = np.uint64(tgx.shape[1])
    one = np.uint64(1)
    two = np.uint64(2)
    three = np.uint64(3)
    four = np.uint64(4)
    flat_tgx, flat_tgy = tgx.ravel(), tgy.ravel()
    flat_gx, flat_gy = gx.ravel(), gy.ravel()
    flat_idx, flat_mask = trial_idx.ravel(), trial_mask.ravel()
    d00, d01, d02 = D[0, 0], D[0, 1], D[0, 2]
    d10, d11, d12 = D[1, 0], D[1, 1], D[1, 2]
    d20, d21, d22 = D[2, 0], D[2, 1], D[2, 2]
    short = upper and ascending
    acc = np.zeros(4 * max(n_cols, 1))
    marker = np.full(max(n_cols, 1), -1, np.int64)
    found = np.empty(max(n_cols, 1), np.int32)
    lens = np.zeros(r1 - r0, np.int64)
    capacity = max(capacity, 16)
    cols = np.empty(capacity, np.int32)
    data = np.empty((capacity, 2, 2))
    fill = 0
    for i_row in range(r0, r1):
        I = np.int64(order[i_row])
        n_found = 0
        low = I if upper else -1
        for p in range(t_ptr[I], t_ptr[I + 1]):
            pos = np.uint64(t_pos[p])
            q = pos // ukt
            a = pos - q * ukt
            ax = w[q] * flat_tgx[pos]
            ay = w[q] * flat_tgy[pos]
            c0 = ax * d00 + ay * d20
            c1 = ax * d02 + ay * d22
            c3 = ax * d01 + ay * d21
            c4 = ay * d10 + ax * d20
            c5 = ay * d12 + ax * d22
            c7 = ay * d11 + ax * d21
            s = q * uk
            end = s + uk
            if short:
                s += a
            while s < end:
                if flat_mask[s]:
                    J = np.int64(flat_idx[s])
                    if J >= low:
                        u = np.uint64(J)
                        if marker[u] != I:
                            marker[u] = I
                            found[n_found] = J
                            n_found += 1
                        bx = flat_gx[s]
                        by = flat_gy[s]
                        o = four * u
                        acc[o] += bx * c0 + by * c1
                        acc[o + one] += bx * c1 + by * c3
                        acc[o + two] += bx * c4 + by * c5
                        acc[o + three] += bx * c5 + by * c7
                s += one
        if fill + n_found > capacity:
            capacity = max(2 * capacity, fill + n_found)
            grown_cols = np.empty(capacity, np.int32)
            grown_cols[:fill] = cols[:fill]
            grown = np.empty((capacity, 2, 2))
            grown[:fill] = data[:fill]
            cols, data = grown_cols, grown
        row = np.sort(found[:n_found])
        for m in range(n_found):
            J = row[m]
            cols[fill + m] = J
            o = 4 * np.uint64(J)
            for i in range(2):
                for j in range(2):
                    data[fill + m, i, j] = acc[o + np.uint64(2 * i + j)]
                    acc[o + np.uint64(2 * i + j)] = 0.0
        lens[i_row - r0] = n_found
        fill += n_found
    return lens, cols[:fill], data[:fill]


@njit(cache=True)
def lower_part(u_off, u_len, u_cols):
    """The blocks below the diagonal of a symmetric K from its upper rows (row J: the
    blocks ``u_off[J] <= c < u_off[J] + u_len[J]``): for each row I the rows J < I whose
    upper row holds column I, ascending (l_ptr (n+1,), l_row (nl,) int32, l_src (nl,)
    int64 the index of block (J, I) in the upper rows)."""
    n = len(u_off)
    l_ptr = np.zeros(n + 1, np.int64)
    for J in range(n):
        for c in range(u_off[J], u_off[J] + u_len[J]):
            if u_cols[c] > J:
                l_ptr[u_cols[c] + 1] += 1
    for I in range(n):
        l_ptr[I + 1] += l_ptr[I]
    fill = l_ptr[:-1].copy()
    l_row = np.empty(l_ptr[-1], np.int32)
    l_src = np.empty(l_ptr[-1], np.int64)
    for J in range(n):
        for c in range(u_off[J], u_off[J] + u_len[J]):
            I = u_cols[c]
            if I > J:
                l_row[fill[I]] = J
                l_src[fill[I]] = c
                fill[I] += 1
    return l_ptr, l_row, l_src


@njit(cache=True, nogil=True)
def scalar_rows(r0, r1, start, u_off, u_len, u_cols, u_data, l_ptr, l_row, l_src, indices,
                values):
    """Write block rows ``r0 <= I < r1`` of K (2 n, 2 n_cols) as scalar CSR into
    ``indices``, ``values`` from ``start[I]`` (its block rows' first entry, the indptr of
    row 2 I): row 2 I + i holds, for each block column J of block row I ascending, the
    entries (2 J, 2 J + 1); the blocks J >= I are the upper row's (``u_off[I] <= c <
    u_off[I] + u_len[I]``), the blocks J < I listed in ``l_*`` the transposes of blocks
    (J, I). Releases the GIL: chunks of rows run on parallel threads."""
    for I in range(r0, r1):
        width = np.uint64((start[I + 1] - start[I]) // 2)
        p = np.uint64(start[I])
        for m in range(l_ptr[I], l_ptr[I + 1]):
            J = np.int64(l_row[m])
            c = np.uint64(l_src[m])
            for i in range(2):
                o = p + np.uint64(i) * width
                indices[o] = 2 * J
                indices[o + np.uint64(1)] = 2 * J + 1
                values[o] = u_data[c, 0, i]
                values[o + np.uint64(1)] = u_data[c, 1, i]
            p += np.uint64(2)
        for c in range(u_off[I], u_off[I] + u_len[I]):
            J = np.int64(u_cols[c])
            uc = np.uint64(c)
            for i in range(2):
                o = p + np.uint64(i) * width
                indices[o] = 2 * J
                indices[o + np.uint64(1)] = 2 * J + 1
                values[o] = u_data[uc, i, 0]
                values[o + np.uint64(1)] = u_data[uc, i, 1]
            p += np.uint64(2)


@njit(cache=True, nogil=True)
def extra_rows(order, r0, r1, t_ptr, t_pos, gx, gy, xx_ptr, xx_col, xx_val, yy_ptr, yy_col,
               yy_val, xy_ptr, xy_col, xy_val, n_extra):
    """Rows 2 I (x) and 2 I + 1 (y) of the nodal-enrichment block K_ne for ``I = order[i]``,
    ``r0 <= i < r1``: ``sum_q (dx_I S_xx + dy_I S_xy)`` and ``sum_q (dy_I S_yy + dx_I S_xy)``
    over the points q of function I (``t_ptr``, ``t_pos`` as for :func:`block_rows`), with
    ``S_ij`` the weighted stresses of the enrichment unknowns at the points, each a CSR
    triplet (``ij_ptr`` (n_points + 1,), ``ij_col``, ``ij_val``) over (n_points, n_extra).
    Gustavson's row accumulation as in :func:`block_rows` (an unknown is listed the first
    time it is met). Returns (lengths (r1 - r0,), cols (nnz,) int32 ascending per row,
    values (nnz, 2): the x and y rows)."""
    uk = np.uint64(gx.shape[1])
    one = np.uint64(1)
    flat_gx, flat_gy = gx.ravel(), gy.ravel()
    acc = np.zeros(2 * max(n_extra, 1))
    marker = np.full(max(n_extra, 1), -1, np.int64)
    found = np.empty(max(n_extra, 1), np.int32)
    lens = np.zeros(r1 - r0, np.int64)
    capacity = 16
    cols = np.empty(capacity, np.int32)
    data = np.empty((capacity, 2))
    fill = 0
    for i_row in range(r0, r1):
        I = np.int64(order[i_row])
        n_found = 0
        for p in range(t_ptr[I], t_ptr[I + 1]):
            pos = np.uint64(t_pos[p])
            q = pos // uk
            bx = flat_gx[pos]
            by = flat_gy[pos]
            for c in range(xx_ptr[q], xx_ptr[q + one]):
                e = np.uint64(xx_col[c])
                if marker[e] != I:
                    marker[e] = I
                    found[n_found] = e
                    n_found += 1
                acc[2 * e] += bx * xx_val[c]
            for c in range(yy_ptr[q], yy_ptr[q + one]):
                e = np.uint64(yy_col[c])
                if marker[e] != I:
                    marker[e] = I
                    found[n_found] = e
                    n_found += 1
                acc[2 * e + one] += by * yy_val[c]
            for c in range(xy_ptr[q], xy_ptr[q + one]):
                e = np.uint64(xy_col[c])
                if marker[e] != I:
                    marker[e] = I
                    found[n_found] = e
                    n_found += 1
                acc[2 * e] += by * xy_val[c]
                acc[2 * e + one] += bx * xy_val[c]
        if fill + n_found > capacity:
            capacity = max(2 * capacity, fill + n_found)
            grown_cols = np.empty(capacity, np.int32)
            grown_cols[:fill] = cols[:fill]
            grown = np.empty((capacity, 2))
            grown[:fill] = data[:fill]
            cols, data = grown_cols, grown
        row = np.sort(found[:n_found])
        for m in range(n_found):
            e = np.uint64(row[m])
            cols[fill + m] = row[m]
            data[fill + m, 0] = acc[2 * e]
            data[fill + m, 1] = acc[2 * e + one]
            acc[2 * e] = 0.0
            acc[2 * e + one] = 0.0
        lens[i_row - r0] = n_found
        fill += n_found
    return lens, cols[:fill], data[:fill]


@njit(cache=True, nogil=True)
def side_by_side(l_ptr, l_ind, l_val, r_ptr, r_ind, r_val, shift, out_ptr, out_ind, out_val):
    """Rows of ``[L, R]`` into ``out_ind``, ``out_val`` from ``out_ptr[i]`` (row i's first
    entry): row i of L, then row i of R with its columns shifted by ``shift`` (the block
    rows of :func:`efgkit.system.assemble.stiffness` with the enrichment columns)."""
    for i in range(len(l_ptr) - 1):
        p = out_ptr[i]
        for c in range(l_ptr[i], l_ptr[i + 1]):
            out_ind[p] = l_ind[c]
            out_val[p] = l_val[c]
            p += 1
        for c in range(r_ptr[i], r_ptr[i + 1]):
            out_ind[p] = r_ind[c] + shift
            out_val[p] = r_val[c]
            p += 1
