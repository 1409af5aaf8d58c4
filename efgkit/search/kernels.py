"""Compiled loops of the box search: strip sizes, node registration, point queries.

A box grid here is a stack of strips across the ``axis`` direction; strip ``s`` spans
``[edges[s], edges[s + 1])`` along ``axis`` and is cut into square boxes of side
``side[s]`` from ``lo`` along the other direction (seed 000 Sect. 4.1, steps 1-5).
Boxes are numbered strip by strip: box ``offset[s] + i`` is the ``i``-th of strip ``s``.
Each box holds, in ascending order, the nodes whose support disc it touches
(``start (n_boxes + 1,)``, ``members``: a CSR list), so the candidates of a point are the
members of its one box (no neighbouring boxes to visit).

Every loop runs over nodes, strips, boxes or points once; the query loops are parallel.
The two query passes (count, then fill) keep the memory to what the neighbour graph needs.
The registration also copies each member's ``(x, y, d_mI^2)`` into
``packed (n_registrations, 3)`` in box order, so the query passes read their candidates
as one contiguous run instead of gathering coordinates and radii node by node.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..timing import watch_compiles

__all__ = ["extent", "strip_edges", "register", "box_index", "count_neighbours", "fill_padded", "fill_csr",
           "csr_serial", "compact_numbering"]

watch_compiles()  # before anything here compiles


@njit(cache=True)
def extent(x, r):
    """One pass over the nodes: ``low (2,)`` = min(x_I - d_mI), ``high (2,)`` = max(x_I + d_mI)
    per axis, the number of nodes with a non-finite coordinate and of bad radii (not finite
    and > 0); the same numbers as numpy's reductions, without their temporaries."""
    low = np.full(2, np.inf)
    high = np.full(2, -np.inf)
    bad_x, bad_r = 0, 0
    for i in range(len(x)):
        ri = r[i]
        if not (np.isfinite(x[i, 0]) and np.isfinite(x[i, 1])):
            bad_x += 1
        if not (ri > 0 and np.isfinite(ri)):
            bad_r += 1
        for k in range(2):
            low[k] = min(low[k], x[i, k] - ri)
            high[k] = max(high[k], x[i, k] + ri)
    return low, high, bad_x, bad_r


@njit(cache=True)
def strip_edges(s, r, lo, hi, factor, n_bins):
    """Strip edges ``(n_strips + 1,)`` of a nonuniform grid over ``[lo, hi]`` along one axis.

    ``s (n,)`` are the node coordinates along the axis, ``r (n,)`` the support radii. The
    axis is cut into ``n_bins`` fine bins; ``env[b]`` is the largest radius of the nodes
    whose support reaches bin ``b``. Walking from ``lo``, each strip's side is ``factor``
    times the largest ``env`` over the strip (grown until it no longer changes), the
    seed-000 rule "box side 2 h-bar with h-bar the largest smoothing length of the zone"
    with the zone made exact: the nodes whose supports reach the strip.
    """
    w = (hi - lo) / n_bins
    top = np.zeros(n_bins)
    for i in range(len(s)):
        b = min(n_bins - 1, max(0, int((s[i] - lo) / w)))
        if r[i] > top[b]:
            top[b] = r[i]
    env = np.zeros(n_bins)
    for b in range(n_bins):
        if top[b] > 0.0:
            k = int(np.ceil(top[b] / w))
            for j in range(max(0, b - k), min(n_bins, b + k + 1)):
                if top[b] > env[j]:
                    env[j] = top[b]
    edges = [lo]
    y0 = lo
    while y0 < hi:
        b0 = min(n_bins - 1, int((y0 - lo) / w))
        side = max(factor * env[b0], w)
        for _ in range(64):
            b1 = min(n_bins - 1, int((y0 + side - lo) / w))
            m = env[b0]
            for b in range(b0, b1 + 1):
                if env[b] > m:
                    m = env[b]
            if factor * m <= side:
                break
            side = factor * m
        y0 = y0 + side
        edges.append(y0)
    out = np.empty(len(edges))
    for k in range(len(edges)):
        out[k] = edges[k]
    return out


@njit(cache=True)
def _strip_of(edges, v):
    """Strip holding coordinate ``v`` (binary search), -1 outside ``[edges[0], edges[-1])``."""
    if v < edges[0] or v >= edges[-1]:
        return -1
    a, b = 0, len(edges) - 1
    while b - a > 1:
        m = (a + b) // 2
        if edges[m] <= v:
            a = m
        else:
            b = m
    return a


@njit(cache=True)
def _visit(x, r, axis, edges, side, offset, lo, counts, members, fill):
    """Count (fill=False) or write (fill=True) the registrations of every node."""
    other = 1 - axis
    for i in range(len(x)):
        # The radius grown by a part in 1e9: a point's box comes from floor((x - lo) / h),
        # which round-off can put just outside the box's geometric bounds.
        a, c, ri = x[i, axis], x[i, other], r[i] * (1.0 + 1e-9)
        s0 = _strip_of(edges, max(a - ri, edges[0]))
        s1 = _strip_of(edges, min(a + ri, np.nextafter(edges[-1], -np.inf)))
        for s in range(s0, s1 + 1):
            ya, yb = edges[s], edges[s + 1]
            ca = min(max(a, ya), yb)  # closest point of the strip along the axis
            nb = offset[s + 1] - offset[s]
            h = side[s]
            i0 = max(0, int(np.floor((c - ri - lo) / h)))
            i1 = min(nb - 1, int(np.floor((c + ri - lo) / h)))
            for j in range(i0, i1 + 1):
                cc = min(max(c, lo + j * h), lo + (j + 1) * h)
                if (ca - a) ** 2 + (cc - c) ** 2 < ri * ri:  # the disc touches the box
                    box = offset[s] + j
                    if fill:
                        members[counts[box]] = i
                    counts[box] += 1


@njit(cache=True)
def register(x, r, axis, edges, side, offset, lo):
    """CSR box lists: ``start (n_boxes + 1,)``, ``members (n_registrations,)`` and the
    members' ``packed (n_registrations, 3)`` = (x, y, d_mI^2)."""
    n_boxes = offset[-1]
    counts = np.zeros(n_boxes, np.int64)
    members = np.zeros(0, np.int64)
    _visit(x, r, axis, edges, side, offset, lo, counts, members, False)
    start = np.zeros(n_boxes + 1, np.int64)
    for b in range(n_boxes):
        start[b + 1] = start[b] + counts[b]
    members = np.empty(start[-1], np.int64)
    cursor = start[:-1].copy()
    _visit(x, r, axis, edges, side, offset, lo, cursor, members, True)
    packed = np.empty((len(members), 3))  # a gather in box order: sequential writes
    for k in range(len(members)):
        i = members[k]
        packed[k, 0] = x[i, 0]
        packed[k, 1] = x[i, 1]
        packed[k, 2] = r[i] * r[i]
    return start, members, packed


@njit(cache=True, parallel=True)
def box_index(x, axis, edges, side, offset, lo):
    """Box of every point ``x (n, 2)``, shape (n,); -1 outside the grid (the rule of
    :meth:`efgkit.search.BoxGrid.box_of`: strip by binary search, then floor((c - lo) / side))."""
    out = np.empty(len(x), np.int64)
    other = 1 - axis
    for q in prange(len(x)):
        s = _strip_of(edges, x[q, axis])
        out[q] = -1
        if s >= 0:
            j = np.floor((x[q, other] - lo) / side[s])
            if j >= 0 and j < offset[s + 1] - offset[s]:
                out[q] = offset[s] + np.int64(j)
    return out


@njit(cache=True, parallel=True)
def count_neighbours(x, box, start, packed):
    """Number of nodes I with |x_q - x_I| < r_I for every point, shape (n,)."""
    count = np.zeros(len(x), np.int64)
    for q in prange(len(x)):
        b = box[q]
        if b < 0:
            continue
        c = 0
        x0, y0 = x[q, 0], x[q, 1]
        for a in range(start[b], start[b + 1]):
            dx = packed[a, 0] - x0
            dy = packed[a, 1] - y0
            c += dx * dx + dy * dy < packed[a, 2]
        count[q] = c
    return count


@njit(cache=True, parallel=True)
def fill_padded(x, box, start, members, packed, kmax):
    """Padded neighbour indices ``(n, kmax)`` int32 (node counts stay below 2**31),
    valid entries first and ascending."""
    idx = np.zeros((len(x), kmax), np.int32)
    for q in prange(len(x)):
        b = box[q]
        if b < 0:
            continue
        c = 0
        x0, y0 = x[q, 0], x[q, 1]
        for a in range(start[b], start[b + 1]):
            dx = packed[a, 0] - x0
            dy = packed[a, 1] - y0
            if dx * dx + dy * dy < packed[a, 2]:
                idx[q, c] = members[a]
                c += 1
    return idx


@njit(cache=True, parallel=True)
def fill_csr(x, box, start, members, packed, indptr):
    """CSR neighbour indices ``(indptr[-1],)``, each row ascending."""
    out = np.empty(indptr[-1], np.int64)
    for q in prange(len(x)):
        b = box[q]
        if b < 0:
            continue
        c = indptr[q]
        x0, y0 = x[q, 0], x[q, 1]
        for a in range(start[b], start[b + 1]):
            dx = packed[a, 0] - x0
            dy = packed[a, 1] - y0
            if dx * dx + dy * dy < packed[a, 2]:
                out[c] = members[a]
                c += 1
    return out


@njit(cache=True)
def csr_serial(x, box, start, members, packed):
    """One pass of count and fill on one thread: ``indptr (n + 1,)`` and ``indices``.

    Each point's neighbours are written straight into the output, whose size is
    estimated from the lists found so far (5 % over) and grown when fewer than one box's
    candidates are left; the result is a view of it when at most a quarter is unused,
    a copy otherwise. The count pass this replaces read every candidate a second time.
    """
    n = len(x)
    indptr = np.zeros(n + 1, np.int64)
    widest = 0
    for b in range(len(start) - 1):
        widest = max(widest, start[b + 1] - start[b])
    out = np.empty(min(n, 4096) * 32 + widest, np.int64)
    c = 0
    for q in range(n):
        if c + widest > len(out):  # room for one more box: grow to the estimated total
            est = int(1.05 * c * n / q) + widest + 16
            grown = np.empty(max(est, c + widest, (5 * len(out)) // 4), np.int64)
            grown[:c] = out[:c]
            out = grown
        b = box[q]
        if b >= 0:
            x0, y0 = x[q, 0], x[q, 1]
            for a in range(start[b], start[b + 1]):
                dx = packed[a, 0] - x0
                dy = packed[a, 1] - y0
                if dx * dx + dy * dy < packed[a, 2]:
                    out[c] = members[a]
                    c += 1
        indptr[q + 1] = c
    return indptr, out[:c] if 4 * len(out) <= 5 * c + 64 else out[:c].copy()


@njit(cache=True)
def compact_numbering(idx, mask, n_nodes):
    """The nodes held by the valid entries of ``idx, mask (n, k)`` ascending (m,) int64, and
    ``idx`` renumbered over them (int32, masked entries 0): a mark pass, a count over the
    ``n_nodes`` marks and a renumbering pass."""
    n, k = idx.shape
    local = np.full(n_nodes, -1, np.int64)
    for q in range(n):
        for a in range(k):
            if mask[q, a]:
                local[idx[q, a]] = 0
    m = 0
    for i in range(n_nodes):
        if local[i] == 0:
            local[i] = m
            m += 1
    nodes = np.empty(m, np.int64)
    for i in range(n_nodes):
        if local[i] >= 0:
            nodes[local[i]] = i
    out = np.zeros((n, k), np.int32)
    for q in range(n):
        for a in range(k):
            if mask[q, a]:
                out[q, a] = local[idx[q, a]]
    return out, nodes
