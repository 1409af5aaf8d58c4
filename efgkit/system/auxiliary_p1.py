"""The P1 finite-element stiffness of the auxiliary space (:mod:`efgkit.system.auxiliary`):
linear triangles on a Delaunay triangulation of the nodes.

The triangulation is Shewchuk's Triangle (the ``triangle`` package) on a copy of the nodes
jittered by 1e-3 of the mean spacing: the jitter makes the Delaunay triangulation unique
(exact grids are degenerate), so Triangle gives the triangles that Qhull
(``scipy.spatial.Delaunay``) gave before, in 0.075 against 0.63 s at 97k nodes. The element
matrices are assembled as 2 x 2 node blocks (one sort of the node pairs, then sums per
block) and stored without explicit zeros (on grids some couplings cancel exactly; stored
zeros would count as connections in the aggregation of the multigrid hierarchy): set-up
0.3-0.5 against 1.1-1.9 s at 97k nodes (docs/performance.md, solve_stage_notes). Large
solves assemble the blocks in one compiled pass (:mod:`efgkit.system.p1_kernels`): the
whole P1 stiffness of 97k random points in 0.32 against 1.12 s, the same pattern, the
entries to 3e-16.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import bsr_array, csr_array

from .compiled_operators import use_compiled

__all__ = ["ROUNDOFF", "delaunay_triangles", "p1_stiffness"]

ROUNDOFF = 1e-12  # entries below ROUNDOFF sqrt(P_ii P_jj) are round-off of a cancelled coupling


def delaunay_triangles(x: np.ndarray) -> np.ndarray:
    """Delaunay triangles (t, 3) int of the points ``x`` (n, 2) jittered by 1e-3 of the mean
    spacing (deterministic seed), by Triangle; (0, 3) for fewer than three points. Nodes on a
    line come out as slivers (the jitter moves them off it), which :func:`p1_stiffness` drops
    by their quality.

    Examples
    --------
    >>> delaunay_triangles(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])).shape
    (2, 3)
    """
    import triangle

    x = np.asarray(x, dtype=float)
    n = len(x)
    if n < 3:
        return np.zeros((0, 3), dtype=np.int64)
    s = np.sqrt(max(np.prod(np.ptp(x, axis=0)), 1e-300) / n)
    jitter = 1e-3 * s * np.random.default_rng(0).uniform(-1.0, 1.0, x.shape)
    out = triangle.triangulate({"vertices": x + jitter}, "Q")  # Q: quiet
    return np.asarray(out.get("triangles", np.zeros((0, 3))), dtype=np.int64).reshape(-1, 3)


def _cut(x: np.ndarray, tri: np.ndarray, cuts: np.ndarray) -> np.ndarray:
    """Triangles (t,) bool with an edge crossing one of the segments ``cuts (m, 2, 2)``."""
    from ..problem.geometry import segments_intersect

    p = x[tri]
    lo, hi = p.min(axis=1), p.max(axis=1)
    hit = np.zeros(len(tri), bool)
    for a, b in cuts:
        near = np.flatnonzero(np.all(lo <= np.maximum(a, b), axis=1)
                              & np.all(hi >= np.minimum(a, b), axis=1))
        for i, j in ((0, 1), (1, 2), (2, 0)):
            aa, bb = np.broadcast_to(a, (len(near), 2)), np.broadcast_to(b, (len(near), 2))
            hit[near] |= segments_intersect(p[near, i], p[near, j], aa, bb)
    return hit


def _coupling(D: np.ndarray) -> np.ndarray:
    """``C`` (4, 4) of the element blocks: ``B_a^T D B_b [c, d] = sum_kl g_ak g_bl C[k * 2 + l, c
    * 2 + d]``, ``g`` the gradients of the barycentric coordinates. With Voigt rows (xx, yy, xy),
    ``B_a = [[g_ax, 0], [0, g_ay], [g_ay, g_ax]]`` = ``S[p, c, k] g_ak``, so ``C[k, l, c, d] =
    sum_pq S[p, c, k] D[p, q] S[q, d, l]``."""
    S = np.zeros((3, 2, 2))
    S[0, 0, 0] = S[1, 1, 1] = S[2, 0, 1] = S[2, 1, 0] = 1.0
    return np.einsum("pck,pq,qdl->klcd", S, np.asarray(D, dtype=float), S).reshape(4, 4)


def _node_blocks(tri: np.ndarray, g: np.ndarray, area: np.ndarray, C: np.ndarray, n: int):
    """Node-block CSR (indptr (n + 1,), columns (m,), blocks (m, 4)) of ``sum_e area_e B^T D
    B`` in numpy: the element blocks (t, 3, 3, 4), one stable sort of the node pairs, sums per
    pair in the order of the triangles."""
    gg = g[:, :, None, :, None] * g[:, None, :, None, :]  # (t, a, b, k, l)
    blocks = (gg.reshape(-1, 4) * np.repeat(area, 9)[:, None]) @ C
    key = (tri[:, :, None] * n + tri[:, None, :]).ravel()  # node pair (a, b) -> a n + b
    order = np.argsort(key, kind="stable")
    key = key[order]
    first = np.ones(len(key), bool)
    first[1:] = key[1:] != key[:-1]
    starts = np.flatnonzero(first)  # each node pair's run of element entries
    data = np.add.reduceat(blocks[order], starts, axis=0) if len(starts) else np.zeros((0, 4))
    key = key[starts]
    return np.searchsorted(key // n, np.arange(n + 1)), key % n, data


def p1_stiffness(x: np.ndarray, D: np.ndarray, domain=None, cuts=None,
                 min_quality: float = 1e-2) -> csr_array:
    """P1 elasticity stiffness on a Delaunay triangulation of the nodes, (2 n, 2 n).

    DOFs are ``2 i + c`` like the EFG coefficients. Triangles
    (:func:`delaunay_triangles`) whose centroid lies outside ``domain`` (holes, concave
    parts), that cross a segment of ``cuts (m, 2, 2)`` (cracks) or whose quality ``4 sqrt(3)
    area / sum(l^2)`` is below ``min_quality`` (collinear boundary nodes) are dropped.
    Element stiffness ``area B^T D B``; canonical CSR without explicit zeros.

    Examples
    --------
    >>> P = p1_stiffness(np.array([[0., 0.], [1., 0.], [0., 1.]]), np.eye(3))
    >>> P.shape, bool(np.allclose(P @ np.tile([1.0, 0.0], 3), 0))
    ((6, 6), True)
    """
    x = np.asarray(x, dtype=float)
    n = len(x)
    tri = delaunay_triangles(x)
    p = x[tri]  # (t, 3, 2)
    e = p[:, [2, 0, 1]] - p[:, [1, 2, 0]]  # edge opposite vertex i, (t, 3, 2)
    area = 0.5 * (e[:, 2, 0] * e[:, 0, 1] - e[:, 2, 1] * e[:, 0, 0])
    keep = 4 * np.sqrt(3) * np.abs(area) > min_quality * np.sum(e**2, axis=(1, 2))
    if domain is not None and len(tri):
        keep &= domain.contains(p.mean(axis=1))
    if cuts is not None and len(cuts) and len(tri):
        keep &= ~_cut(x, tri, np.asarray(cuts, dtype=float).reshape(-1, 2, 2))
    tri, e, area = tri[keep], e[keep], area[keep]
    g = np.stack([-e[..., 1], e[..., 0]], axis=-1) / (2 * area[:, None, None])  # grad lambda_i
    args = (tri.astype(np.int64), np.ascontiguousarray(g), np.abs(area), _coupling(D), n)
    if use_compiled(2 * n):  # large solves: one compiled pass (p1_kernels)
        from .p1_kernels import p1_node_blocks

        indptr, cols, data = p1_node_blocks(*args)
    else:
        indptr, cols, data = _node_blocks(*args)
    # Couplings that cancel in exact arithmetic (on grids) come out as round-off of either
    # sign or as exact zeros, depending on the order of the sums: drop them all (below
    # ROUNDOFF sqrt(P_ii P_jj); the diagonal from the diagonal blocks).
    rows = np.repeat(np.arange(n), np.diff(indptr))
    on = rows == cols
    d = np.zeros((n, 2))
    d[rows[on]] = np.sqrt(np.abs(data[on][:, [0, 3]]))
    data = data.reshape(-1, 2, 2)
    data[np.abs(data) <= ROUNDOFF * d[rows][:, :, None] * d[cols][:, None, :]] = 0.0
    P = csr_array(bsr_array((data, cols, indptr), shape=(2 * n, 2 * n)).tocsr())
    P.eliminate_zeros()
    return P
