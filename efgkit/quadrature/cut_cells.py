"""Background cells clipped to the material: the pieces of the boundary (and crack
slits) in each cell of a grid, and triangles covering the material of a cut cell.

A cut cell is split into vertical slabs at the boundary vertices in it; in a slab
the boundary pieces are non-crossing lines with the material on the left of
travel (outer loop CCW, holes CW, a crack slit both ways), and each material
interval between two lines is a trapezoid, cut into two triangles
(:func:`efgkit.quadrature.cells.cell_points` integrates them exactly).
"""

from __future__ import annotations

import numpy as np

__all__ = ["cut_triangles", "pieces", "triangle_areas"]

_EPS = 1e-9  # "on a grid line", in units of the cell size


def triangle_areas(v: np.ndarray) -> np.ndarray:
    """Areas (t,) of triangles v (t, 3, 2)."""
    e1, e2 = v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]
    return 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def _ranges(start: np.ndarray, count: np.ndarray) -> np.ndarray:
    """Concatenated ``start[i] + arange(count[i])``, shape (count.sum(),)."""
    return np.repeat(start - np.cumsum(count) + count, count) + np.arange(count.sum())


def pieces(a: np.ndarray, b: np.ndarray):
    """Split segments a -> b (m, 2), in grid units, at the grid lines.

    Returns the cell (k, 2) int of each piece and its ends p, q (k, 2) in the
    cell's unit coordinates, in travel order. Pieces lying on a grid line are
    left out: they bound cells without cutting them.
    """
    m, d = len(a), b - a
    seg, t = [np.arange(m), np.arange(m)], [np.zeros(m), np.ones(m)]
    for c in (0, 1):  # crossings of the lines x = k, then y = k
        lo = np.floor(np.minimum(a[:, c], b[:, c])) + 1
        cnt = np.maximum(np.ceil(np.maximum(a[:, c], b[:, c])) - lo, 0).astype(np.int64)
        s = np.repeat(np.arange(m), cnt)
        seg.append(s)
        t.append((_ranges(lo, cnt) - a[s, c]) / d[s, c])
    seg, t = np.concatenate(seg), np.concatenate(t)
    o = np.lexsort((t, seg))
    seg, t = seg[o], t[o]
    x = a[seg] + t[:, None] * d[seg]
    same = seg[1:] == seg[:-1]
    p, q = x[:-1][same], x[1:][same]
    mid = 0.5 * (p + q)
    keep = (np.abs(mid - np.round(mid)) > _EPS).all(axis=1)
    cell = np.floor(mid[keep]).astype(np.int64)
    return cell, np.clip(p[keep] - cell, 0, 1), np.clip(q[keep] - cell, 0, 1)


def cut_triangles(p, q, c, n_cells, inside):
    """Triangles covering the material of cut unit cells.

    p, q (k, 2) are the boundary pieces in unit cell coordinates, c (k,) their
    cell; ``inside(u (s, 2), cell (s,)) -> bool (s,)`` classifies slabs that no
    piece crosses. Returns triangles (t, 3, 2) in unit coordinates and their cell (t,).
    """
    # slabs: between consecutive distinct abscissae of piece ends (and 0, 1) in each cell
    if n_cells == 0:
        return np.zeros((0, 3, 2)), np.zeros(0, np.int64)
    cells = np.arange(n_cells)
    bc = np.concatenate([cells, cells, c, c])
    bx = np.concatenate([np.zeros(n_cells), np.ones(n_cells), p[:, 0], q[:, 0]])
    o = np.lexsort((bx, bc))
    bc, bx = bc[o], bx[o]
    nxt = (bc[1:] == bc[:-1]) & (bx[1:] - bx[:-1] > 1e-13)
    sc, xa, xb = bc[:-1][nxt], bx[:-1][nxt], bx[1:][nxt]
    ns, xm = len(sc), 0.5 * (xa + bx[1:][nxt])
    # pair every slab with every piece of its cell; keep the pieces that span the slab
    byc = np.argsort(c, kind="stable")
    cnt = np.bincount(c, minlength=n_cells)
    reps = cnt[sc]
    s = np.repeat(np.arange(ns), reps)
    j = byc[_ranges(np.cumsum(cnt)[sc] - reps, reps)]
    span = (np.minimum(p[j, 0], q[j, 0]) < xm[s]) & (xm[s] < np.maximum(p[j, 0], q[j, 0]))
    s, j = s[span], j[span]
    slope = (q[j, 1] - p[j, 1]) / (q[j, 0] - p[j, 0])
    ya = np.clip(p[j, 1] + (xa[s] - p[j, 0]) * slope, 0, 1)
    yb = np.clip(p[j, 1] + (xb[s] - p[j, 0]) * slope, 0, 1)
    # lines of each slab from the bottom (y = 0) up; material lies left of travel
    ls = np.concatenate([np.arange(ns), s])
    la, lb = np.concatenate([np.zeros(ns), ya]), np.concatenate([np.zeros(ns), yb])
    up = np.concatenate([np.zeros(ns, bool), q[j, 0] > p[j, 0]])
    bottom = np.arange(len(ls)) < ns
    # coincident lines (the two sides of a crack slit): the one travelling in -x first, so
    # that the material below and above the slit is kept and only the slit's zero-area
    # strip lies between them
    # (the mid heights are rounded: the two sides of a slit compute them from opposite ends,
    # and rounding must not decide their order)
    o = np.lexsort((up, np.where(bottom, -1.0, np.round(0.5 * (la + lb), 12)), ls))
    ls, la, lb, up, bottom = ls[o], la[o], lb[o], up[o], bottom[o]
    last = np.append(ls[1:] != ls[:-1], True)
    ua = np.where(last, 1.0, np.append(la[1:], 1.0))  # the line above: next one or y = 1
    ub = np.where(last, 1.0, np.append(lb[1:], 1.0))
    material = np.where(bottom, ~last & ~np.append(up[1:], False), up)
    empty = np.flatnonzero(bottom & last)
    material[empty] = inside(np.column_stack([xm[ls[empty]], np.full(len(empty), 0.5)]),
                             sc[ls[empty]])
    sl, m = ls[material], material
    quad = np.stack([np.stack([xa[sl], xb[sl], xb[sl], xa[sl]], 1),  # (t, 4, 2): trapezoids
                     np.stack([la[m], lb[m], ub[m], ua[m]], 1)], -1)
    tri = np.concatenate([quad[:, [0, 1, 2]], quad[:, [0, 2, 3]]])
    keep = triangle_areas(tri) > 1e-14
    return tri[keep], np.tile(sc[sl], 2)[keep]
