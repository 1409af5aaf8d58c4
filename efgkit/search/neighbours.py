"""Neighbour search: which nodes' supports cover each point.

The result is padded: ``idx (n_points, k)`` node indices and ``mask (n_points, k)``,
with the valid entries of each row first and ascending; :func:`neighbour_lists` gives
the same graph as CSR. Three methods give the identical graph |x_q - x_I| < d_mI:

- ``"uniform"``: a box grid with one box side (seed 000's uniform box search);
- ``"nonuniform"``: boxes sized by the supports that reach them (seed 000 Sect. 4.1);
- ``"kdtree"``: scipy's cKDTree ``query_ball_point`` (:mod:`efgkit.search.kdtree`);

and ``"auto"`` picks one by the size of the problem and the spread of the radii. The box
queries count first and then fill, so no array wider than the largest neighbour count is
ever allocated.
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from ..jit import resolve_backend
from ..nodes import NodeCloud
from .boxes import SPREAD, BoxGrid
from .kdtree import kdtree_lists

__all__ = ["Neighbours", "BoxGrid", "METHODS", "choose_method", "find_neighbours",
           "neighbour_lists"]

METHODS = ("auto", "uniform", "nonuniform", "kdtree")
# Fewer points than this are searched by one thread: below it the parallel region's
# start and barrier cost more than they save, the more so on a machine shared by many jobs.
PARALLEL = 100_000
# The CSR lists (neighbour_lists) come from the parallel count and fill passes with more numba
# threads than this, from the fused one-thread pass (kernels.csr_serial) otherwise. The two
# passes read every candidate twice, the fused one once, yet on two threads they were not
# slower at N = 145,281 (seed 000's layout, four runs of 41 rounds in turns: fused / count +
# fill medians 1.05, 1.34, 1.77, 1.01; docs/performance.md, search_against_2t), so threads keep them.
FUSED_THREADS = 1


@dataclass(frozen=True, eq=False)
class Neighbours:
    """Padded neighbour lists.

    Attributes
    ----------
    idx : ndarray, shape (n_points, k), int32
        Node indices; entries where ``mask`` is False are 0 (a valid index, unused).
        int32 halves the largest integer array of a solve (node counts stay far below
        2**31); flat positions ``q * k + a`` are formed in int64 where they could exceed it.
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

    def compact(self, n_nodes: int) -> tuple[Neighbours, np.ndarray]:
        """The lists renumbered over the nodes they hold: (neighbours with indices into
        ``nodes``, ``nodes (m,)`` int64 ascending), ``nodes[local.idx] == idx`` where valid
        (masked entries 0). The numbering keeps the order of the nodes, so ascending lists
        stay ascending. For the work of a chunk of points that would otherwise run over
        all ``n_nodes`` nodes (:func:`efgkit.system.streamed.streamed_stiffness`).

        Examples
        --------
        >>> nb = Neighbours(np.array([[7, 2], [2, 0]], np.int32), np.array([[True, True], [True, False]]))
        >>> local, nodes = nb.compact(10)
        >>> nodes.tolist(), local.idx.tolist()
        ([2, 7], [[1, 0], [0, 0]])
        """
        from .kernels import compact_numbering

        idx, nodes = compact_numbering(self.idx, self.mask, n_nodes)
        return Neighbours(idx, self.mask), nodes


def choose_method(n_points: int, nodes: NodeCloud) -> str:
    """The ``"auto"`` method: ``"kdtree"`` below :data:`efgkit.jit.COMPILED_MIN` points
    (no kernel to compile), ``"uniform"`` boxes when the largest support radius is at most
    SPREAD times the median, ``"nonuniform"`` boxes for graded clouds."""
    if resolve_backend("auto", n_points) == "numpy":
        return "kdtree"
    r = nodes.radius
    return "uniform" if r.max() <= SPREAD * np.median(r) else "nonuniform"


def _check(x, nodes, method):
    x = np.ascontiguousarray(x, dtype=float)
    if x.ndim != 2 or x.shape[1] != 2:
        raise ValueError(f"x must have shape (n_points, 2), got {x.shape}")
    if not np.all(np.isfinite(x)):
        bad = int(np.flatnonzero(~np.isfinite(x).all(axis=1))[0])
        raise ValueError(f"x must be finite, but point {bad} is {x[bad].tolist()}: "
                         "remove or fix the non-finite points before the search")
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    return x


@contextmanager
def _threads(one):
    """One numba thread inside when ``one``, the configured number otherwise."""
    import numba  # here, not at the top: runs without compiled kernels never import it

    before = numba.get_num_threads()
    if one:
        numba.set_num_threads(1)
    try:
        yield
    finally:
        numba.set_num_threads(before)


def _grid(x, nodes, boxes, method):
    """The box grid to search ``x`` in, or None for the k-d tree. A grid built before is used
    under "auto" when the points or the nodes are many enough for the compiled kernels: a
    few boundary points of a large cloud are searched in it (O(points)) rather than in a k-d
    tree built over all nodes (O(n_nodes log n_nodes): 0.08 s at 97k nodes)."""
    if boxes is not None and (method == boxes.kind or (
            method == "auto" and resolve_backend("auto", max(len(x), nodes.n)) == "numba")):
        return boxes
    if method == "auto":
        method = choose_method(len(x), nodes)
    return None if method == "kdtree" else BoxGrid.build(nodes, kind=method)


def neighbour_lists(x: np.ndarray, nodes: NodeCloud, boxes: BoxGrid | None = None,
                    method: str = "auto"):
    """The neighbour graph as CSR: ``indptr (n_points + 1,)``, ``indices`` (rows ascending).

    Examples
    --------
    >>> from efgkit.nodes import NodeCloud
    >>> cloud = NodeCloud(np.array([[0., 0.], [1., 0.], [3., 0.]]), np.full(3, 1.5), np.ones(3, bool))
    >>> indptr, indices = neighbour_lists(np.array([[0.5, 0.0]]), cloud, method="uniform")
    >>> indptr.tolist(), indices.tolist()
    ([0, 2], [0, 1])
    """
    x = _check(x, nodes, method)
    grid = _grid(x, nodes, boxes, method)
    if grid is None:
        return kdtree_lists(x, nodes)
    import numba

    from .kernels import box_index, count_neighbours, csr_serial, fill_csr

    with _threads(len(x) < PARALLEL or numba.get_num_threads() <= FUSED_THREADS):
        box = box_index(x, grid.axis, grid.edges, grid.side, grid.offset, grid.lo)
        if numba.get_num_threads() == 1:  # one pass: count and fill together
            return csr_serial(x, box, grid.start, grid.members, grid.packed)
        count = count_neighbours(x, box, grid.start, grid.packed)
        indptr = np.zeros(len(x) + 1, np.int64)
        np.cumsum(count, out=indptr[1:])
        return indptr, fill_csr(x, box, grid.start, grid.members, grid.packed, indptr)


def find_neighbours(x: np.ndarray, nodes: NodeCloud, boxes: BoxGrid | None = None,
                    method: str = "auto") -> Neighbours:
    """Nodes I with |x - x_I| < d_mI for every point of ``x (n_points, 2)``, padded.

    Parameters
    ----------
    x : ndarray, shape (n_points, 2)
    nodes : NodeCloud
    boxes : BoxGrid, optional
        A grid of ``nodes`` built before (used unless ``method`` names another kind).
    method : {"auto", "uniform", "nonuniform", "kdtree"}

    Returns
    -------
    Neighbours
        ``idx, mask (n_points, k)`` with k the largest neighbour count.

    Examples
    --------
    >>> from efgkit.nodes import NodeCloud
    >>> cloud = NodeCloud(np.array([[0., 0.], [1., 0.], [3., 0.]]), np.full(3, 1.5), np.ones(3, bool))
    >>> nb = find_neighbours(np.array([[0.5, 0.0]]), cloud)
    >>> sorted(nb.idx[0][nb.mask[0]].tolist())
    [0, 1]
    """
    x = _check(x, nodes, method)
    grid = _grid(x, nodes, boxes, method)
    if grid is None:
        indptr, indices = kdtree_lists(x, nodes)
        count = np.diff(indptr)
        kmax = int(count.max()) if len(x) else 0
        mask = np.arange(kmax)[None, :] < count[:, None]
        idx = np.zeros((len(x), kmax), np.int32)
        idx[mask] = indices
        return Neighbours(idx, mask)
    from .kernels import box_index, count_neighbours, fill_padded

    with _threads(len(x) < PARALLEL):
        box = box_index(x, grid.axis, grid.edges, grid.side, grid.offset, grid.lo)
        count = count_neighbours(x, box, grid.start, grid.packed)
        kmax = int(count.max()) if len(x) else 0
        idx = fill_padded(x, box, grid.start, grid.members, grid.packed, kmax)
    return Neighbours(idx, np.arange(kmax)[None, :] < count[:, None])
