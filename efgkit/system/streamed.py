"""The stiffness assembled from chunks of quadrature points, their shape functions dropped as
it goes.

K = sum_q w_q B(x_q)^T D B(x_q) (seed 003 Eq. 22a) is a sum over the points, so it is the sum
of the stiffnesses of any partition of the points into chunks. :func:`streamed_stiffness`
forms the shape functions of one chunk of points
(:meth:`efgkit.approx.point_shapes.PointShapes.chunk`), assembles that chunk's K_c with
:func:`efgkit.system.assemble.stiffness` (the same kernel, the same backend as for all points
at once), drops the chunk's shape functions, and adds the K_c pairwise: partial sums of equal
numbers of chunks are added (a binary counter), so every stored entry is added
O(log n_chunks) times instead of O(n_chunks) for a running sum, and at most one partial sum
per level is held. The points are sorted by box, so a chunk's K_c touches a compact set of
nodes and the partial sums hold about nnz(K) (1 + the chunks' overlap) entries.

What is held is K, its partial sums and one chunk's shape functions, never the shape
functions at all points (29 bytes per padded (point, neighbour) slot plus the enrichment
operators: 3.1 GB at 1e5 nodes of the cracked plate, docs/performance.md).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array

from ..approx.point_shapes import PointShapes
from ..approx.shape import Shape
from ..jit import resolve_backend
from .assemble import stiffness

__all__ = ["streamed_stiffness", "pairwise_sum", "chunk_stiffness"]


def _add(a: csr_array, b: csr_array) -> csr_array:
    out = csr_array(a + b)
    return _narrow(out)


def _narrow(K: csr_array) -> csr_array:
    """``K`` with int32 index arrays when its size allows (scipy's sum may widen them)."""
    if K.nnz < 2**31 and max(K.shape) < 2**31 and K.indices.dtype != np.int32:
        return csr_array((K.data, K.indices.astype(np.int32), K.indptr.astype(np.int32)),
                         shape=K.shape)
    return K


def pairwise_sum(parts):
    """The sum of the sparse matrices of the iterable ``parts``, added pairwise: a partial
    sum of 2**j parts meets the next one of 2**j parts (a binary counter), so each stored
    entry is added about log2(len(parts)) times. Returns None for no parts.

    Examples
    --------
    >>> from scipy.sparse import eye_array
    >>> S = pairwise_sum(csr_array(k * eye_array(3)) for k in range(1, 6))
    >>> S.toarray().diagonal().tolist()
    [15.0, 15.0, 15.0]
    """
    stack: list[tuple[int, csr_array]] = []  # (level, partial sum of 2**level parts)
    for p in parts:
        level, acc = 0, _narrow(csr_array(p))
        while stack and stack[-1][0] == level:
            _, prev = stack.pop()
            acc, level = _add(prev, acc), level + 1
            del prev
        stack.append((level, acc))
        del acc, p
    if not stack:
        return None
    total = stack.pop()[1]
    while stack:  # the smaller partial sums first
        total = _add(stack.pop()[1], total)
    return total


def chunk_stiffness(sh: Shape, w: np.ndarray, D: np.ndarray, backend: str) -> csr_array:
    """K (n_dofs, n_dofs) of the points of ``sh`` (a chunk). With more nodes than half the
    chunk's points, assembled over the nodes the points hold
    (:meth:`~efgkit.search.Neighbours.compact`) and placed at those nodes' DOFs: the
    assembly's arrays per row and per thread, its row order and lower part run over all
    n_functions otherwise, for every chunk (n_chunks x n_nodes work in all: the superlinear
    part of the stiffness from 1e5 to 1e6 nodes). CPU per chunk of 2**18 points of the
    cracked plate at 1e5 nodes, the functions padded to 1, 2, 3 and 10 times its 96,980
    nodes: 162 / 172, 172 / 143, 218 / 148, 407 / 148 ms all nodes / nodes held (medians,
    one process, load 3.5). The renumbering keeps the nodes' order, and every entry is the
    same sum in the same order: the same K_c to the bit."""
    if 2 * sh.n_functions <= sh.shape[0]:
        return stiffness(sh, w, D, backend=backend)
    local, nodes = sh.neighbours.compact(sh.n_functions)
    small = Shape(local, sh.values, sh.ddx, sh.ddy, len(nodes), sh.extra)
    K = csr_array(stiffness(small, w, D, backend=backend))
    n, N = sh.n_functions, sh.n_dofs
    dof = np.concatenate([(2 * nodes[:, None] + np.arange(2)).ravel(),
                          np.arange(2 * n, N)])  # local DOF -> global, ascending
    index = np.int32 if max(N, K.nnz) < 2**31 else np.int64
    indptr = np.zeros(N + 1, np.int64)
    indptr[dof + 1] = np.diff(K.indptr)
    np.cumsum(indptr, out=indptr)
    return csr_array((K.data, dof.astype(index)[K.indices], indptr.astype(index)), shape=(N, N))


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

    def parts():
        for s, e in shapes.bounds():
            sh = shapes.chunk(s, e, derivatives=True, clock=clock)
            K_c = chunk_stiffness(sh, w[s:e], D, backend)
            del sh  # the chunk's shape functions go before the sums
            if clock is not None:
                clock.lap("stiffness")
            yield K_c
            del K_c  # summed: not held through the next chunk
            if clock is not None:  # the sums of the pairs (not the next chunk's search)
                clock.lap("stiffness")

    K = pairwise_sum(parts())
    if K is None:  # no points
        K = csr_array((shapes.n_dofs, shapes.n_dofs))
    K.sort_indices()
    if clock is not None:
        clock.lap("stiffness")
    return K
