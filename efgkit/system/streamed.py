"""The stiffness assembled from chunks of quadrature points, their shape functions dropped as
it goes.

K = sum_q w_q B(x_q)^T D B(x_q) (seed 003 Eq. 22a) is a sum over the points, so it is the sum
of the stiffnesses of any partition of the points into chunks. :func:`streamed_stiffness`
forms the shape functions of one chunk of points
(:meth:`efgkit.approx.point_shapes.PointShapes.chunk`), assembles that chunk's K_c with
:func:`efgkit.system.assemble.stiffness` (the same kernel, the same backend as for all points
at once) on the DOFs the chunk touches, and drops the chunk's shape functions. The K_c are
held (the points are sorted by box, so a chunk's K_c touches a compact set of nodes and all
K_c together hold about nnz(K) (1 + the chunks' overlap) entries) and summed at the end by
:func:`chunk_sum` into one CSR allocated once, in one pass over their entries.

What is held is K, the chunks' K_c and one chunk's shape functions, never the shape
functions at all points (29 bytes per padded (point, neighbour) slot plus the enrichment
operators: 3.1 GB at 1e5 nodes of the cracked plate, docs/performance.md).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array

from ..approx.point_shapes import PointShapes
from ..approx.shape import Shape
from ..jit import resolve_backend
from ..memory import fresh_array, small_pages
from .assemble import stiffness

__all__ = ["streamed_stiffness", "chunk_sum", "chunk_stiffness"]


def chunk_stiffness(sh: Shape, w: np.ndarray, D: np.ndarray,
                    backend: str) -> tuple[np.ndarray, csr_array]:
    """K_c of the points of ``sh`` (a chunk) on the DOFs they touch: ``(dof (m,), K_c (m, m))``,
    ``dof`` int64 ascending, K_c's row and column k being the global DOF ``dof[k]``.

    Assembled over the nodes the points hold (:meth:`~efgkit.search.Neighbours.compact`), so
    that a chunk's work and its K_c are of the chunk's size: over all n_functions, the
    assembly's arrays per row and per thread, its row order and lower part, and the rows
    :func:`chunk_sum` walks would cost n_chunks x n_nodes in all (the superlinear part of the
    stiffness from 1e5 to 1e6 nodes before). The renumbering keeps the nodes' order, and every
    entry is the same sum in the same order as over all nodes: the same K_c to the bit."""
    n, N = sh.n_functions, sh.n_dofs
    local, nodes = sh.neighbours.compact(n)
    small = Shape(local, sh.values, sh.ddx, sh.ddy, len(nodes), sh.extra)
    dof = np.concatenate([(2 * nodes[:, None] + np.arange(2)).ravel(), np.arange(2 * n, N)])
    K_c = csr_array(stiffness(small, w, D, backend=backend))
    K_c.sort_indices()  # chunk_sum merges sorted rows (a check only: the kernels sort them)
    return dof, K_c


def chunk_sum(parts: list[tuple[np.ndarray, csr_array]], n_dofs: int) -> csr_array:
    """K (n_dofs, n_dofs) = the sum of the chunks ``parts`` [(dof, K_c)] of
    :func:`chunk_stiffness` (the list is emptied as they are added), columns sorted, entries
    that sum to exactly zero left out. The output is allocated once
    (:func:`~efgkit.memory.fresh_array`), with room in each row for the sum of its lengths
    over the chunks, and the chunks are merged into it in their order
    (:mod:`efgkit.system.chunk_sum_kernels`): O(sum of the chunks' nnz). The room left over,
    the entries two or more chunks share (6 % at 1e5 nodes of the cracked plate), stays
    allocated behind K's arrays.

    Examples
    --------
    >>> parts = [(np.array([0, 2]), csr_array(np.array([[1.0, 2.0], [2.0, 1.0]]))),
    ...          (np.array([1, 2]), csr_array(np.array([[3.0, 0.0], [0.0, 4.0]])))]
    >>> chunk_sum(parts, 3).toarray().tolist()
    [[1.0, 0.0, 2.0], [0.0, 3.0, 0.0], [2.0, 0.0, 5.0]]
    """
    from .chunk_sum_kernels import add_chunk, close_gaps

    start = np.zeros(n_dofs + 1, np.int64)  # room of each row: its lengths summed over chunks
    for dof, K_c in parts:
        start[dof + 1] += np.diff(K_c.indptr)
    np.cumsum(start, out=start)
    index = np.int32 if max(n_dofs, start[-1]) < 2**31 else np.int64
    out_idx, out_val = fresh_array(start[-1], index), fresh_array(start[-1], np.float64)
    first, fill = np.zeros(n_dofs, np.int64), np.zeros(n_dofs, np.int64)
    for k in range(len(parts)):  # in chunk order, each dropped once added
        dof, K_c = parts[k]
        parts[k] = None
        add_chunk(start, first, fill, out_idx, out_val, dof, K_c.indptr, K_c.indices, K_c.data)
        del dof, K_c
    parts.clear()
    indptr = close_gaps(start.astype(index), first, fill, out_idx, out_val)
    return csr_array((out_val[: indptr[-1]], out_idx[: indptr[-1]], indptr),
                     shape=(n_dofs, n_dofs))


def streamed_stiffness(shapes: PointShapes, w: np.ndarray, D: np.ndarray, clock=None) -> csr_array:
    """K (n_dofs, n_dofs) of the points of ``shapes`` with weights ``w (n_points,)``
    (modulus-weighted when graded) and the elasticity matrix ``D (3, 3)``, assembled a chunk
    of points at a time (module docstring); Bubnov-Galerkin (test = trial), enrichment
    included. The backend of the assembly is chosen from the number of all points, as
    :func:`~efgkit.system.assemble.stiffness` would for them at once.

    ``clock`` (a :class:`~efgkit.timing.Stopwatch`) gets the laps "search", "shape" (the
    chunks' shape functions) and "stiffness" (their K_c and the sums).

    Examples
    --------
    >>> from efgkit import Domain, EFG, Elastic
    >>> from efgkit.approx.approximation import Approximation
    >>> from efgkit.nodes import generate_nodes
    >>> from efgkit.search import BoxGrid
    >>> nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25))
    >>> approx = Approximation(nodes, BoxGrid.build(nodes))
    >>> x = np.random.default_rng(0).random((400, 2))
    >>> w, D = np.full(400, 1 / 400), Elastic(1.0, 0.3).D
    >>> K = streamed_stiffness(PointShapes(approx, x, chunk_points=100), w, D)
    >>> K_all = stiffness(approx.shape(x), w, D)
    >>> bool(abs(K - K_all).max() <= 1e-14 * abs(K_all).max())
    True
    """
    w = np.asarray(w, dtype=float)
    if w.shape != (shapes.n_points,):
        raise ValueError(f"w must have shape ({shapes.n_points},) like the points, got {w.shape}")
    D = np.asarray(D, dtype=float)
    if D.shape != (3, 3):
        raise ValueError(f"D must have shape (3, 3), got {D.shape}")
    backend = resolve_backend("auto", shapes.n_points)

    parts = []
    with small_pages():  # the chunks' K_c and their sum: fresh memory written once
        for s, e in shapes.bounds():
            sh = shapes.chunk(s, e, derivatives=True, clock=clock)
            parts.append(chunk_stiffness(sh, w[s:e], D, backend))
            del sh  # the chunk's shape functions go before the next chunk's
            if clock is not None:
                clock.lap("stiffness")
        K = chunk_sum(parts, shapes.n_dofs)
    if clock is not None:
        clock.lap("stiffness")
    return K
