"""Quadrature points of the area: background cells clipped to the domain, or triangles.

The EFG weak form is integrated on background cells or on the triangles of a
mesh through the nodes (seed 003, "integration of the weak form", Figs. 3).
Seed 003 notes that cell quadrature which only drops points outside the body is
inaccurate along curved and angled boundaries, so :func:`cell_points` clips
each cut cell to the material (:mod:`efgkit.quadrature.cut_cells`) and integrates the
triangles that cover it exactly (arcs as the polylines of :attr:`Domain.area`).
The rules on boundary lines are in :mod:`efgkit.quadrature.boundary`.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import Delaunay

from ..problem.geometry import Domain
from .cell_rule import CellRule
from .cut_cells import cut_triangles, pieces, triangle_areas
from .rules import Points, check_count, check_length, gauss_legendre, triangle_rule
from .tip_cells import tip_cells

__all__ = ["cell_points", "cell_rule", "triangle_points"]


def _on_triangles(v: np.ndarray, degree: int, ids: np.ndarray):
    """Points (t*m, 2), weights (t*m,) and owner ``ids`` (t,) repeated, on triangles v (t, 3, 2)."""
    bary, w = triangle_rule(degree)
    x = np.einsum("qk,tkd->tqd", bary, v).reshape(-1, 2)
    return x, (2 * triangle_areas(v)[:, None] * w).ravel(), np.repeat(ids, len(w))


def _grid_rule(domain: Domain, seg, origin, size, cells, order):
    """Points, weights and owner (index into cells) of the cells (c, 2) of a grid, as two
    parts of a :class:`~efgkit.quadrature.cell_rule.CellRule`: the whole cells ``(corners
    (f, 2), offsets (q, 2), weights (q,), owner (f,))`` and the cut cells' triangles
    ``(x, w, owner)``."""
    pc, p, q = pieces((seg[:, 0] - origin) / size, (seg[:, 1] - origin) / size)
    key, piece_key = cells @ [1 << 31, 1], pc @ [1 << 31, 1]  # cells of the pieces ...
    srt = np.argsort(key)
    pos = srt[np.minimum(np.searchsorted(key, piece_key, sorter=srt), len(key) - 1)]
    hit = key[pos] == piece_key  # ... among the given cells
    piece_cell = pos[hit]
    cut = np.zeros(len(cells), bool)
    cut[piece_cell] = True
    corner = origin + size * cells
    rest = np.flatnonzero(~cut)
    full = rest[domain.contains(corner[rest] + 0.5 * size)]
    xi, wi = gauss_legendre(order)
    r = np.stack(np.meshgrid((xi + 1) / 2, (xi + 1) / 2, indexing="ij"), -1).reshape(-1, 2)
    cut_ids = np.flatnonzero(cut)
    rank = np.cumsum(cut) - 1  # cell index -> index among cut cells
    tri, tc = cut_triangles(p[hit], q[hit], rank[piece_cell], len(cut_ids),
                             lambda u, k: domain.contains(corner[cut_ids[k]] + size * u))
    x_cut, w_cut, o_cut = _on_triangles(corner[cut_ids[tc], None, :] + size * tri,
                                        2 * order - 1, cut_ids[tc])
    return [(corner[full], size * r, size**2 * np.outer(wi, wi).ravel() / 4, full),
            (x_cut, w_cut, o_cut)]


def _grid(domain: Domain, cell_size: float):
    """Cells ``(i, j)`` (c, 2), row by row, of the grid covering ``domain.bbox`` and its origin (2,)."""
    x0, y0, x1, y1 = domain.bbox
    nx = max(1, math.ceil((x1 - x0) / cell_size - 1e-9))
    ny = max(1, math.ceil((y1 - y0) / cell_size - 1e-9))
    cells = np.column_stack(np.divmod(np.arange(nx * ny), nx)[::-1])
    return cells, np.array([x0, y0])


def _zone_levels(centre: np.ndarray, cell_size: float, zones) -> np.ndarray:
    """Split level (c,) of the cells of centres ``centre (c, 2)``: 0 coarse, k split into k x k."""
    level = np.zeros(len(centre), np.int64)
    for z in zones:
        inz = np.sum((centre - np.asarray(z.centre)) ** 2, axis=1) <= z.radius**2
        level[inz] = np.maximum(level[inz], math.ceil(cell_size / z.spacing - 1e-9))
    return level


def _sub_cells(cells: np.ndarray, k: int) -> np.ndarray:
    """The ``k x k`` sub-cells (c k^2, 2) of cells (c, 2) on the k times finer grid (cells if k = 0)."""
    if k <= 0:
        return cells
    sub = np.column_stack(np.divmod(np.arange(k * k), k))
    return (cells[:, None, :] * k + sub).reshape(-1, 2)


def cell_points(domain: Domain, cell_size: float, order: int, zones=(),
                refined_order: int | None = None, cracks=(), tip_rays=None,
                tip_order: int | None = None) -> Points:
    """Background-cell quadrature, with cells cut by the boundary clipped to the material.

    A grid of square cells of side ``cell_size`` starts at the lower-left
    corner of ``domain.bbox`` and covers it. Cells inside the material get the
    ``order x order`` tensor Gauss rule; cells cut by the boundary polyline
    are clipped to the material, split into triangles (module docstring) that
    get :func:`triangle_rule` of degree ``2 order - 1``; cells without
    material are dropped. Cells whose centre lies in a zone disc are split
    into ``k x k`` cells, ``k = ceil(cell_size / zone.spacing)`` (the largest
    over the zones holding the centre), that use ``refined_order``.

    Parameters
    ----------
    domain : Domain
    cell_size : float
    order, refined_order : int
        Gauss points per direction outside and inside zones (default: ``order``).
    zones : sequence of efgkit.methods.Zone
        Refinement discs (``centre``, ``radius``, ``spacing``).
    cracks : sequence of Crack
        Cells cut by a crack are split along it (the crack is a two-sided
        slit of the material), and the cells holding a tip get the fan rule
        of :func:`efgkit.quadrature.tip_cells.tip_cell_rule`.
    tip_rays : sequence of ndarray (k, 2), optional
        For every tip (in ``scene.tips`` order), the shadow-ray directions to
        split its fan at (besides the crack).
    tip_order : int, optional
        Points per direction of the tip fan rules (default: ``refined_order``).

    Returns
    -------
    Points
        ``x (n, 2)``, ``w (n,)`` summing to ``domain.area`` (arcs as the
        polylines of :meth:`Loop.polyline`), ``owner (n,)``: cell index,
        numbered ``0 .. n_cells - 1`` over the cells that hold material.

    Examples
    --------
    >>> from efgkit.problem.geometry import Domain, Loop
    >>> dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1, 0.5], 0.25)])
    >>> pts = cell_points(dom, 0.1, 3)
    >>> bool(abs(pts.w.sum() - dom.area) < 1e-12 * dom.area), bool(pts.w.min() > 0)
    (True, True)
    """
    return cell_rule(domain, cell_size, order, zones, refined_order, cracks, tip_rays,
                     tip_order).points()


def cell_rule(domain: Domain, cell_size: float, order: int, zones=(),
              refined_order: int | None = None, cracks=(), tip_rays=None,
              tip_order: int | None = None) -> CellRule:
    """The rule of :func:`cell_points` (same arguments) held per cell: its points are
    written when asked for, in their own order or in that of a key (the box order of the
    search: :meth:`~efgkit.quadrature.cell_rule.CellRule.sorted_by`)."""
    if not isinstance(domain, Domain):
        raise TypeError(f"domain must be a Domain, got {type(domain).__name__}")
    check_length("cell_size", cell_size)
    check_count("order", order)
    refined_order = order if refined_order is None else refined_order
    check_count("refined_order", refined_order)
    cells, origin = _grid(domain, cell_size)
    level = _zone_levels(origin + cell_size * (cells + 0.5), cell_size, zones)
    seg = outline = domain.boundary_segments()
    if cracks:  # each crack segment as a slit: travelled both ways
        cs = np.concatenate([c.segments for c in cracks])
        seg = np.concatenate([seg, cs, cs[:, ::-1]])
    tips = [t for c in cracks for t in c.tip_list]
    parts, offset = [], 0
    for k in np.unique(level):
        sel = _sub_cells(cells[level == k], k)
        size = cell_size / max(k, 1)
        if tips:
            sel, fans = tip_cells(sel, origin, size, tips, cracks, tip_rays,
                                   tip_order or refined_order, outline)
            for x, w in fans:
                parts.append((x, w, np.full(len(x), offset)))
                offset += 1
        for part in _grid_rule(domain, seg, origin, size, sel, refined_order if k > 0 else order):
            part[-1][...] += offset  # the owners, in place
            parts.append(part)
        offset += len(sel)
    return CellRule.from_parts(parts, offset)


def triangle_points(domain: Domain, nodes, order: int) -> Points:
    """Element quadrature on the Delaunay triangles of the nodes.

    Triangles whose centroid lies in the domain get :func:`triangle_rule` of
    degree ``2 order - 1``. This integrates the polygon spanned by the kept
    triangles, not the exact domain: curved boundaries become chords, and
    concave or holed regions are only as good as the nodes on their boundary.

    Parameters
    ----------
    domain : Domain
    nodes : array_like, shape (n_nodes, 2)
    order : int

    Returns
    -------
    Points
        ``x (n, 2)``, ``w (n,)``, ``owner (n,)``: index of the kept triangle.

    Examples
    --------
    >>> from efgkit.problem.geometry import Domain
    >>> g = np.linspace(0, 1, 5)
    >>> nodes = np.column_stack([a.ravel() for a in np.meshgrid(g, g)])
    >>> round(float(triangle_points(Domain.rectangle(0, 0, 1, 1), nodes, 2).w.sum()), 12)
    1.0
    """
    check_count("order", order)
    nodes = np.asarray(nodes, dtype=float)
    if nodes.ndim != 2 or nodes.shape[1] != 2 or len(nodes) < 3 or not np.isfinite(nodes).all():
        raise ValueError(f"nodes must be a finite array of shape (n >= 3, 2), got {nodes.shape}")
    v = nodes[Delaunay(nodes).simplices]
    keep = np.flatnonzero(triangle_areas(v) > 1e-12 * domain.size**2)
    keep = keep[domain.contains(v[keep].mean(axis=1))]
    return Points(*_on_triangles(v[keep], 2 * order - 1, np.arange(len(keep))))
