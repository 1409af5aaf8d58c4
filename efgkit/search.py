"""Neighbour search: which nodes' supports cover each point.

The result is padded: ``idx (n_points, k)`` node indices and ``mask (n_points, k)``,
with the valid entries of each row first. Padded arrays are what the
vectorised MLS kernel consumes.

The search is a uniform box (cell-list) search: every node is registered in
the boxes its support disc overlaps, so the candidates of a point are the
nodes of its box, and all points of one box share them. Everything is array
work; no loop visits a node or a point.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from .nodes import NodeCloud

__all__ = ["Neighbours", "BoxGrid", "find_neighbours"]


@dataclass(frozen=True, eq=False)
class Neighbours:
    """Padded neighbour lists.

    Attributes
    ----------
    idx : ndarray, shape (n_points, k), int
        Node indices; entries where ``mask`` is False are 0 (a valid index, unused).
    mask : ndarray, shape (n_points, k), bool
        True for nodes whose support contains the point (strictly: d < d_mI).
        The search puts the valid entries first in each row; a crack rule
        may clear entries anywhere.
    """

    idx: np.ndarray
    mask: np.ndarray

    @property
    def counts(self) -> np.ndarray:
        """Number of neighbours of each point, shape (n_points,)."""
        return self.mask.sum(axis=1)

    def subset(self, rows) -> Neighbours:
        return Neighbours(self.idx[rows], self.mask[rows])


@dataclass(frozen=True, eq=False)
class BoxGrid:
    """Nodes registered in the boxes their supports overlap.

    Attributes
    ----------
    origin : ndarray (2,); size : float; shape : (nx, ny)
    table : ndarray, shape (n_boxes, k_box), int
        Candidate nodes of each box, padded with ``-1``.
    """

    origin: np.ndarray
    size: float
    shape: tuple[int, int]
    table: np.ndarray

    @classmethod
    def build(cls, nodes: NodeCloud, size: float | None = None) -> BoxGrid:
        x, r = nodes.x, nodes.radius
        size = float(np.median(r)) if size is None else float(size)
        origin = (x - r[:, None]).min(axis=0)
        top = (x + r[:, None]).max(axis=0)
        nx, ny = (np.floor((top - origin) / size).astype(int) + 1).tolist()
        lo = np.floor((x - r[:, None] - origin) / size).astype(np.int64)
        hi = np.floor((x + r[:, None] - origin) / size).astype(np.int64)
        span = hi - lo + 1  # boxes per direction for each node
        count = span[:, 0] * span[:, 1]
        node = np.repeat(np.arange(len(x)), count)
        k = np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        bx = lo[node, 0] + k % span[node, 0]
        by = lo[node, 1] + k // span[node, 0]
        # Keep only boxes the disc really touches (closest box point within r).
        cx = np.clip(x[node, 0], origin[0] + bx * size, origin[0] + (bx + 1) * size)
        cy = np.clip(x[node, 1], origin[1] + by * size, origin[1] + (by + 1) * size)
        touch = (cx - x[node, 0]) ** 2 + (cy - x[node, 1]) ** 2 < r[node] ** 2
        box, node = (by * nx + bx)[touch], node[touch]
        order = np.argsort(box, kind="stable")
        box, node = box[order], node[order]
        per_box = np.bincount(box, minlength=nx * ny)
        start = np.cumsum(per_box) - per_box
        col = np.arange(len(box)) - start[box]
        table = np.full((nx * ny, max(1, int(per_box.max()))), -1, dtype=np.int64)
        table[box, col] = node
        return cls(origin, size, (nx, ny), table)

    def box_of(self, x: np.ndarray) -> np.ndarray:
        """Box index of points ``x (n, 2)``, shape (n,); -1 outside the grid."""
        ij = np.floor((x - self.origin) / self.size).astype(np.int64)
        nx, ny = self.shape
        ok = (ij[:, 0] >= 0) & (ij[:, 0] < nx) & (ij[:, 1] >= 0) & (ij[:, 1] < ny)
        return np.where(ok, ij[:, 1] * nx + ij[:, 0], -1)


@njit(cache=True, parallel=True)
def _filter_candidates(x, box, table, nx, radius):
    """Compiled twin of the numpy path: padded valid neighbours (n, k_box) and counts."""
    n, kb = len(x), table.shape[1]
    idx = np.zeros((n, kb), np.int64)
    count = np.zeros(n, np.int64)
    for q in prange(n):
        b = box[q]
        if b < 0:
            continue
        c = 0
        for a in range(kb):
            I = table[b, a]
            if I < 0:
                break
            dx = nx[I, 0] - x[q, 0]
            dy = nx[I, 1] - x[q, 1]
            if dx * dx + dy * dy < radius[I] * radius[I]:
                idx[q, c] = I
                c += 1
        count[q] = c
    return idx, count


def find_neighbours(x: np.ndarray, nodes: NodeCloud, boxes: BoxGrid | None = None,
                    chunk: int = 131072, backend: str = "numba") -> Neighbours:
    """Nodes I with |x - x_I| < d_mI for every point of ``x (n_points, 2)``.

    Examples
    --------
    >>> from efgkit.nodes import NodeCloud
    >>> cloud = NodeCloud(np.array([[0., 0.], [1., 0.], [3., 0.]]), np.full(3, 1.5), np.ones(3, bool))
    >>> nb = find_neighbours(np.array([[0.5, 0.0]]), cloud)
    >>> sorted(nb.idx[0][nb.mask[0]].tolist())
    [0, 1]
    """
    x = np.asarray(x, dtype=float)
    boxes = BoxGrid.build(nodes) if boxes is None else boxes
    box = boxes.box_of(x)
    if backend == "numba":
        idx, count = _filter_candidates(x, box, boxes.table, nodes.x, nodes.radius)
        kmax = int(count.max()) if len(x) else 0
        idx = np.ascontiguousarray(idx[:, :kmax])
        return Neighbours(idx, np.arange(kmax)[None, :] < count[:, None])
    if backend != "numpy":
        raise ValueError(f"backend must be 'numba' or 'numpy', got {backend!r}")
    parts = []
    for s in range(0, len(x), chunk):
        xs, bs = x[s:s + chunk], box[s:s + chunk]
        cand = np.where(bs[:, None] >= 0, boxes.table[np.maximum(bs, 0)], -1)
        safe = np.maximum(cand, 0)
        d2 = ((nodes.x[safe] - xs[:, None, :]) ** 2).sum(axis=-1)
        valid = (cand >= 0) & (d2 < nodes.radius[safe] ** 2)
        parts.append((safe, valid))
    kmax = max([int(v.sum(axis=1).max()) for _, v in parts if len(v)] + [0])
    idx = np.zeros((len(x), kmax), dtype=np.int64)
    mask = np.zeros((len(x), kmax), dtype=bool)
    row0 = 0
    for safe, valid in parts:
        rows, cols = np.nonzero(valid)  # row-major: valid entries keep their order
        pos = np.cumsum(valid, axis=1)[rows, cols] - 1
        idx[row0 + rows, pos] = safe[rows, cols]
        mask[row0 + rows, pos] = True
        row0 += len(valid)
    return Neighbours(idx, mask)
