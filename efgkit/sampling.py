"""The sample grid: a triangulation of the material that leaves holes, notches and cracks
open, on which fields are written and plotted (:mod:`efgkit.io`, :mod:`efgkit.plot`), so
that ``warp by vector`` in ParaView shows the deformed body with its crack faces apart."""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from .problem.geometry import Domain, segments_intersect

__all__ = ["sample_grid"]

_ARC_MIN = 48  # boundary points per full turn of an arc, whatever the grid spacing
_CLEAR = 0.35  # grid points closer than this many spacings to the boundary are dropped
_OFFSET = 0.02  # crack-face sample points sit this many spacings off the crack line


def _boundary_samples(domain: Domain, h: float) -> np.ndarray:
    """Points along every edge at spacing <= h, end vertices once, shape (m, 2)."""
    pts = []
    for e in domain.edges():
        n = max(1, math.ceil(e.length / h - 1e-9))
        if e.is_arc:
            n = max(n, math.ceil(_ARC_MIN * abs(e.sweep) / (2 * math.pi)))
        x, _ = e.at(np.arange(n) / n)
        pts.append(x)
    return np.concatenate(pts)


def _crack_samples(cracks, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Points along the crack lines at spacing <= h: ``on (m, 2)`` and ``off (2 m, 2)``.

    ``off`` are the same points moved ``_OFFSET h`` to either side (the two faces).
    """
    on, off = [], []
    for crack in cracks:
        for a, b in crack.segments:
            ln = float(np.linalg.norm(b - a))
            n = max(1, math.ceil(ln / h - 1e-9))
            s = np.linspace(0.0, 1.0, n + 1)
            x = a + s[:, None] * (b - a)
            nrm = np.array([a[1] - b[1], b[0] - a[0]]) / ln
            on.append(x)
            off += [x + _OFFSET * h * nrm, x - _OFFSET * h * nrm]
    if not on:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.concatenate(on), np.concatenate(off)


def sample_grid(domain: Domain, n_target: int = 20000, cracks=()) -> tuple[np.ndarray, np.ndarray]:
    """Triangulated sample points covering the material.

    A regular grid (cell-centred in the bounding box, spacing
    ``h = sqrt(area / n_target)``) is kept where it lies inside the material and
    at least ``0.35 h`` from the boundary; points along every edge (and both
    faces of every crack) are added; the union is Delaunay-triangulated (Shewchuk's
    Triangle) and triangles whose centroid lies outside the material, or which cross a
    crack segment, are removed.

    Parameters
    ----------
    domain : Domain
    n_target : int
        Approximate number of grid points.
    cracks : sequence of Crack
        Cracks to keep open.

    Returns
    -------
    x : ndarray, shape (n, 2)
        Sample points.
    triangles : ndarray, shape (m, 3), int
        Counter-clockwise vertex indices into ``x``.

    Examples
    --------
    >>> from efgkit import Loop
    >>> dom = Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1, 0.5], 0.25)])
    >>> x, tri = sample_grid(dom, n_target=500)
    >>> bool(dom.contains(x[tri].mean(axis=1)).all())
    True
    """
    if isinstance(n_target, bool) or not isinstance(n_target, (int, np.integer)) or n_target < 4:
        raise ValueError(f"n_target must be an integer >= 4, got {n_target!r}")
    h = math.sqrt(domain.area / n_target)
    x0, y0, x1, y1 = domain.bbox
    gx = np.arange(x0 + h / 2, x1, h)
    gy = np.arange(y0 + h / 2, y1, h)
    grid = np.stack(np.meshgrid(gx, gy, indexing="xy"), axis=-1).reshape(-1, 2)
    grid = grid[domain.contains(grid)]
    edge = _boundary_samples(domain, h)
    _, faces = _crack_samples(cracks, h)
    # distance to the boundary and cracks (to within h / 8) from finely sampled lines
    fine = np.concatenate([_boundary_samples(domain, h / 4), _crack_samples(cracks, h / 4)[0]])
    d, _ = cKDTree(fine).query(grid)
    grid = grid[d > _CLEAR * h]
    if len(faces):
        faces = faces[domain.contains(faces)]
    x = np.concatenate([grid, edge, faces])
    if len(x) < 3:
        raise ValueError(f"n_target={n_target} gives too few sample points ({len(x)}); raise it")
    import triangle  # 20-30x faster than qhull on these partly regular clouds

    tri = triangle.triangulate({"vertices": x}, "Q")["triangles"].astype(np.intp)
    p = x[tri]  # (m, 3, 2)
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    area2 = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    keep = (np.abs(area2) > 1e-10 * h * h) & domain.contains(p.mean(axis=1))
    for crack in cracks:
        for a, b in crack.segments:
            for i, j in ((0, 1), (1, 2), (2, 0)):
                m = len(p)
                keep &= ~segments_intersect(p[:, i], p[:, j], np.broadcast_to(a, (m, 2)),
                                            np.broadcast_to(b, (m, 2)))
    tri, area2 = tri[keep], area2[keep]
    flip = area2 < 0
    tri[flip] = tri[flip][:, [0, 2, 1]]
    return x, tri
