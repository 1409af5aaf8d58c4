"""Quadrature points of the area: Gauss rules, background cells clipped to the domain.

The EFG weak form is integrated on background cells or on the triangles of a
mesh through the nodes (seed 003, "integration of the weak form", Figs. 3).
Seed 003 notes that cell quadrature which only drops points outside the body is
inaccurate along curved and angled boundaries, so :func:`cell_points` clips
each cut cell to the material (:mod:`efgkit.cut_cells`) and integrates the
triangles that cover it exactly (arcs as the polylines of :attr:`Domain.area`).
The rules on boundary lines are in :mod:`efgkit.boundary_quadrature`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import Delaunay
from scipy.special import roots_jacobi

from .cut_cells import cut_triangles, pieces, triangle_areas
from .geometry import Domain
from .tip_quadrature import tip_cells

__all__ = ["Points", "cell_points", "gauss_legendre", "triangle_points", "triangle_rule"]


@dataclass(frozen=True, eq=False)
class Points:
    """Quadrature or evaluation points.

    Attributes
    ----------
    x : ndarray, shape (n, 2)
    w : ndarray, shape (n,)
        Weights: areas for domain rules, lengths for boundary rules.
    owner : ndarray, shape (n,), int, or None
        Cell, triangle, edge or node each point belongs to.
    normal : ndarray, shape (n, 2), or None
        Outward unit normals of boundary points.

    Examples
    --------
    >>> a = Points(np.zeros((2, 2)), np.ones(2), owner=np.array([0, 1]))
    >>> b = a + a
    >>> b.n, b.owner.tolist(), b.normal is None
    (4, [0, 1, 0, 1], True)
    """

    x: np.ndarray
    w: np.ndarray
    owner: np.ndarray | None = None
    normal: np.ndarray | None = None

    def __post_init__(self):
        x = np.asarray(self.x, dtype=float)
        n = len(x) if x.ndim else -1
        for name, shape, kind in [("x", (n, 2), "f"), ("w", (n,), "f"), ("owner", (n,), "i"),
                                  ("normal", (n, 2), "f")]:
            if getattr(self, name) is None:
                continue
            v = np.asarray(getattr(self, name))
            if v.shape != shape or (v.size and v.dtype.kind not in "iu" + "f" * (kind == "f")):
                raise ValueError(f"Points.{name} must be {'integers' if kind == 'i' else 'reals'}"
                                 f" of shape {shape}, got {v.dtype} array of shape {v.shape}")
            object.__setattr__(self, name, v.astype(np.int64 if kind == "i" else float))

    @property
    def n(self) -> int:
        return len(self.x)

    @classmethod
    def concatenate(cls, *points: Points) -> Points:
        """Join rules; ``owner``/``normal`` are kept (unchanged) only if all parts have them."""
        if not points:
            raise ValueError("Points.concatenate needs at least one Points")

        def join(name):
            parts = [getattr(p, name) for p in points]
            return None if any(v is None for v in parts) else np.concatenate(parts)

        return cls(np.concatenate([p.x for p in points]), np.concatenate([p.w for p in points]),
                   join("owner"), join("normal"))

    def __add__(self, other: Points) -> Points:
        if not isinstance(other, Points):
            return NotImplemented
        return Points.concatenate(self, other)


def _check_int(name, v, low=1):
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {v!r}")
    if v < low:
        raise ValueError(f"{name} must be >= {low}, got {v!r}")


def _check_length(name, v):
    if isinstance(v, bool) or not isinstance(v, (int, float, np.number)):
        raise TypeError(f"{name} must be a real number, got {v!r}")
    if not (math.isfinite(v) and v > 0):
        raise ValueError(f"{name} must be finite and > 0, got {v!r}")


def gauss_legendre(order: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre rule on [-1, 1], exact for polynomials of degree 2 order - 1.

    Returns
    -------
    xi : ndarray, shape (order,)
    w : ndarray, shape (order,), summing to 2

    Examples
    --------
    >>> xi, w = gauss_legendre(3)
    >>> round(float(w.sum()), 14), round(float(w @ xi**4), 14)  # 2 and 2/5
    (2.0, 0.4)
    """
    _check_int("order", order)
    return np.polynomial.legendre.leggauss(order)


def triangle_rule(degree: int) -> tuple[np.ndarray, np.ndarray]:
    """Collapsed (Duffy) Gauss rule on the reference triangle (0,0), (1,0), (0,1).

    The square [0, 1]^2 is mapped by ``x = u, y = v (1 - u)``, with Jacobian
    ``1 - u``: ``m = ceil((degree + 1) / 2)`` Gauss-Jacobi (alpha=1, beta=0)
    points in u absorb the Jacobian and m Gauss-Legendre points in v, so the
    rule is exact for total degree ``degree``; all weights are positive and
    all points strictly inside.

    Returns
    -------
    bary : ndarray, shape (m*m, 3)
        Barycentric coordinates ``(1 - x - y, x, y)``.
    w : ndarray, shape (m*m,)
        Weights, summing to 1/2 (the reference area).

    Examples
    --------
    >>> bary, w = triangle_rule(5)
    >>> bary.shape, round(float(w.sum()), 15)
    ((9, 3), 0.5)
    >>> round(float(w @ (bary[:, 1]**2 * bary[:, 2]**3)), 15) == round(2 * 6 / 5040, 15)
    True
    """
    _check_int("degree", degree, low=0)
    m = max(1, math.ceil((degree + 1) / 2))
    a, wa = roots_jacobi(m, 1.0, 0.0)  # weight (1 - a) on [-1, 1]
    b, wb = np.polynomial.legendre.leggauss(m)
    u, v = np.meshgrid((1 + a) / 2, (1 + b) / 2, indexing="ij")
    x, y = u.ravel(), (v * (1 - u)).ravel()
    return np.column_stack([1 - x - y, x, y]), np.outer(wa / 4, wb / 2).ravel()


def _on_triangles(v: np.ndarray, degree: int, ids: np.ndarray):
    """Points (t*m, 2), weights (t*m,) and owner ``ids`` (t,) repeated, on triangles v (t, 3, 2)."""
    bary, w = triangle_rule(degree)
    x = np.einsum("qk,tkd->tqd", bary, v).reshape(-1, 2)
    return x, (2 * triangle_areas(v)[:, None] * w).ravel(), np.repeat(ids, len(w))


def _grid_rule(domain: Domain, seg, origin, size, cells, order):
    """Points, weights and owner (index into cells) of the cells (c, 2) of a grid."""
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
    x_full = (corner[full, None, :] + size * r).reshape(-1, 2)
    w_full = np.tile(size**2 * np.outer(wi, wi).ravel() / 4, len(full))
    cut_ids = np.flatnonzero(cut)
    rank = np.cumsum(cut) - 1  # cell index -> index among cut cells
    tri, tc = cut_triangles(p[hit], q[hit], rank[piece_cell], len(cut_ids),
                             lambda u, k: domain.contains(corner[cut_ids[k]] + size * u))
    x_cut, w_cut, o_cut = _on_triangles(corner[cut_ids[tc], None, :] + size * tri,
                                        2 * order - 1, cut_ids[tc])
    owner = np.concatenate([np.repeat(full, len(r)), o_cut])
    return np.concatenate([x_full, x_cut]), np.concatenate([w_full, w_cut]), owner


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
        of :func:`efgkit.tip_quadrature.tip_cell_rule`.
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
    >>> from efgkit.geometry import Domain, Loop
    >>> dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1, 0.5], 0.25)])
    >>> pts = cell_points(dom, 0.1, 3)
    >>> bool(abs(pts.w.sum() - dom.area) < 1e-12 * dom.area), bool(pts.w.min() > 0)
    (True, True)
    """
    if not isinstance(domain, Domain):
        raise TypeError(f"domain must be a Domain, got {type(domain).__name__}")
    _check_length("cell_size", cell_size)
    _check_int("order", order)
    refined_order = order if refined_order is None else refined_order
    _check_int("refined_order", refined_order)
    x0, y0, x1, y1 = domain.bbox
    nx = max(1, math.ceil((x1 - x0) / cell_size - 1e-9))
    ny = max(1, math.ceil((y1 - y0) / cell_size - 1e-9))
    cells = np.column_stack(np.divmod(np.arange(nx * ny), nx)[::-1])  # (i, j), row by row
    origin = np.array([x0, y0])
    centre = origin + cell_size * (cells + 0.5)
    level = np.zeros(len(cells), np.int64)  # 0: coarse; k: split into k x k
    for z in zones:
        inz = np.sum((centre - np.asarray(z.centre)) ** 2, axis=1) <= z.radius**2
        level[inz] = np.maximum(level[inz], math.ceil(cell_size / z.spacing - 1e-9))
    seg = outline = domain.boundary_segments()
    if cracks:  # each crack segment as a slit: travelled both ways
        cs = np.concatenate([c.segments for c in cracks])
        seg = np.concatenate([seg, cs, cs[:, ::-1]])
    tips = [t for c in cracks for t in c.tip_list]
    parts, offset = [], 0
    for k in np.unique(level):
        sel = cells[level == k]
        if k > 0:  # the k x k sub-cells of each cell
            sub = np.column_stack(np.divmod(np.arange(k * k), k))
            sel = (sel[:, None, :] * k + sub).reshape(-1, 2)
        size = cell_size / max(k, 1)
        if tips:
            sel, fans = tip_cells(sel, origin, size, tips, cracks, tip_rays,
                                   tip_order or refined_order, outline)
            for x, w in fans:
                parts.append((x, w, np.full(len(x), offset)))
                offset += 1
        x, w, owner = _grid_rule(domain, seg, origin, size, sel,
                                 refined_order if k > 0 else order)
        parts.append((x, w, owner + offset))
        offset += len(sel)
    x, w, owner = (np.concatenate(v) for v in zip(*parts, strict=True))
    used = np.zeros(offset, bool)
    used[owner] = True
    return Points(x, w, (np.cumsum(used) - 1)[owner])


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
    >>> from efgkit.geometry import Domain
    >>> g = np.linspace(0, 1, 5)
    >>> nodes = np.column_stack([a.ravel() for a in np.meshgrid(g, g)])
    >>> round(float(triangle_points(Domain.rectangle(0, 0, 1, 1), nodes, 2).w.sum()), 12)
    1.0
    """
    _check_int("order", order)
    nodes = np.asarray(nodes, dtype=float)
    if nodes.ndim != 2 or nodes.shape[1] != 2 or len(nodes) < 3 or not np.isfinite(nodes).all():
        raise ValueError(f"nodes must be a finite array of shape (n >= 3, 2), got {nodes.shape}")
    v = nodes[Delaunay(nodes).simplices]
    keep = np.flatnonzero(triangle_areas(v) > 1e-12 * domain.size**2)
    keep = keep[domain.contains(v[keep].mean(axis=1))]
    return Points(*_on_triangles(v[keep], 2 * order - 1, np.arange(len(keep))))
