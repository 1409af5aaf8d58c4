"""The neighbour graph by scipy's cKDTree, for comparison and for small clouds.

The relation is the box search's, |x_q - x_I| < d_mI with the node's own radius: the
tree is built on the points and each node asks for the points within its radius
(``query_ball_point`` with one radius per node), then the (point, node) pairs are sorted
by point. The tree's test is ``<=`` with its own arithmetic, so its answer (asked with a
radius one part in 1e9 larger) is filtered with the box kernels' exact test.
"""

from __future__ import annotations

from itertools import chain

import numpy as np
from scipy.spatial import cKDTree

from ..nodes import NodeCloud

__all__ = ["kdtree_lists"]

# Fewer query discs than this are searched by one thread: starting the pool's threads costs
# more than the query of a small cloud (~0.5 ms a call, two calls a solve; docs/performance.md,
# work_interleaved).
THREADED = 20_000
# Up to this many (point, node) pairs every pair is tested, without a tree: at a few hundred
# points the tree's per-node Python lists cost more than the test of all pairs (the singular
# patch's 480 points x 10 nodes: 0.06 against 0.3 ms; docs/performance.md, work_interleaved).
ALL_PAIRS = 50_000


def kdtree_lists(x: np.ndarray, nodes: NodeCloud, chunk: int = 65536):
    """CSR neighbour graph ``(indptr (n_points + 1,), indices)`` by cKDTree, rows ascending
    (up to :data:`ALL_PAIRS` (point, node) pairs by testing them all: the same graph).

    Examples
    --------
    >>> from efgkit.nodes import NodeCloud
    >>> cloud = NodeCloud(np.array([[0., 0.], [1., 0.]]), np.full(2, 1.5), np.ones(2, bool))
    >>> indptr, indices = kdtree_lists(np.array([[0.5, 0.0], [2.0, 0.0]]), cloud)
    >>> indptr.tolist(), indices.tolist()
    ([0, 2, 3], [0, 1, 1])
    """
    x = np.ascontiguousarray(x, dtype=float)
    xn, r = nodes.x, nodes.radius
    if len(x) * len(xn) <= ALL_PAIRS:  # the same test of every pair, in (point, node) order
        dx = xn[None, :, 0] - x[:, None, 0]
        dy = xn[None, :, 1] - x[:, None, 1]
        near = dx * dx + dy * dy < r * r
        indptr = np.zeros(len(x) + 1, np.int64)
        np.cumsum(near.sum(axis=1), out=indptr[1:])
        return indptr, np.nonzero(near)[1].astype(np.int64)
    tree = cKDTree(x)
    pts, nds = [], []
    for s in range(0, len(xn), chunk):  # bounded memory: the lists of one chunk of nodes
        found = tree.query_ball_point(xn[s:s + chunk], r[s:s + chunk] * (1 + 1e-9),
                                      return_sorted=False,
                                      workers=-1 if len(xn) >= THREADED else 1)
        lengths = np.fromiter(map(len, found), np.int64, len(found))
        q = np.fromiter(chain.from_iterable(found), np.int64, int(lengths.sum()))
        I = np.repeat(np.arange(s, s + len(found)), lengths)
        dx = xn[I, 0] - x[q, 0]
        dy = xn[I, 1] - x[q, 1]
        keep = dx * dx + dy * dy < r[I] * r[I]
        pts.append(q[keep])
        nds.append(I[keep])
    q = np.concatenate(pts) if pts else np.zeros(0, np.int64)
    I = np.concatenate(nds) if nds else np.zeros(0, np.int64)
    order = np.argsort(q, kind="stable")  # nodes ascending within a point (already by node)
    indptr = np.concatenate([[0], np.cumsum(np.bincount(q, minlength=len(x)))]).astype(np.int64)
    return indptr, I[order]
