"""The symmetry line of a nodal release (:mod:`efgkit.growth.release`): its nodes and
segments, the Lagrange rows of the bonded segments (piecewise-linear multiplier hats,
per-segment rows computed once), the forces of the support on a segment, the maximum
principal stress at the nodes and the release of the nodes where it reaches ``sigma_c``
(seed 000 Sect. 5.2.1, Fig. 15)."""

from __future__ import annotations

import numpy as np
from scipy.sparse import csr_array

from ..problem.material import strain_from_gradient
from .dynamic import principal_stress
from .release_rules import release_segments

__all__ = ["ReleaseLine"]


class ReleaseLine:
    """The nodes of the symmetry line of a :class:`~efgkit.growth.release.LineRelease`, their
    segments (open: crack face; bonded: ligament) and the support of the bonded ones.

    Parameters
    ----------
    disc : Discretization
        Of the scene (its nodes, shape functions at points, material, grading).
    rule : LineRelease
        The line ``y = y0``, the initial cracks, ``sigma_c`` and ``fracture_energy``.

    Raises
    ------
    ValueError
        Fewer than 3 nodes on the line, an initial crack spanning no segment, or a
        ``sigma_c`` / ``fracture_energy`` not finite and positive at a node of the line.
    """

    def __init__(self, disc, rule):
        x = disc.nodes.x
        on = np.abs(x[:, 1] - rule.y0) <= rule.tol * max(disc.scene.domain.size, 1.0)
        xs = np.unique(np.round(x[on, 0], 12))
        if len(xs) < 3:
            raise ValueError(f"the line y = {rule.y0!r} holds {len(xs)} nodes; it needs at least 3 "
                             "(put a row of nodes on the symmetry line)")
        self.x = xs
        self.open = np.zeros(len(xs) - 1, bool)
        k = int(np.argmin(np.abs(xs - (xs[0] + rule.a0))))
        if k == 0:
            raise ValueError(f"a0 = {rule.a0!r} is shorter than half the first node interval "
                             f"({xs[1] - xs[0]:.6g}): the initial crack needs at least one segment")
        self.open[:k] = True
        for x0, x1 in rule.cracks:
            i, j = (int(np.argmin(np.abs(xs - v))) for v in (x0, x1))
            if j <= i:
                raise ValueError(f"crack ({x0!r}, {x1!r}) spans no segment of the line's nodes")
            self.open[i:j] = True
        # a point inside each initial crack, to follow its tips
        self.seeds = [0.5 * (xs[0] + xs[k])] + [0.5 * (a + b) for a, b in rule.cracks]
        self.y0 = rule.y0
        self.shape = disc.shape_at(np.column_stack([xs, np.full(len(xs), rule.y0)]), derivatives=True)
        self.D = disc.scene.material.D
        g = disc.scene.grading  # graded: D(x) = modulus(x) D
        on_line = np.column_stack([xs, np.full(len(xs), rule.y0)])
        self.fE = np.ones(len(xs)) if g is None else g.factors(on_line)[0]
        sc = rule.sigma_c
        self.sigma_c = np.broadcast_to(np.asarray(sc(on_line) if callable(sc) else sc, float), (len(xs),))
        gc = rule.fracture_energy
        gc = np.broadcast_to(np.asarray(gc(on_line) if callable(gc) else gc, float), (len(xs),))
        if not np.all(np.isfinite(gc) & (gc >= 0)):
            k = int(np.flatnonzero(~(np.isfinite(gc) & (gc >= 0)))[0])
            raise ValueError(f"fracture_energy is {float(gc[k])!r} at the line's node "
                             f"x = {float(xs[k])!r}: it must be finite and >= 0 at every node")
        self.gc = 0.5 * (gc[:-1] + gc[1:])  # per segment
        if not np.all(np.isfinite(self.sigma_c) & (self.sigma_c > 0)):
            k = int(np.flatnonzero(~(np.isfinite(self.sigma_c) & (self.sigma_c > 0)))[0])
            raise ValueError(f"sigma_c is {float(self.sigma_c[k])!r} at the line's node "
                             f"x = {float(xs[k])!r}: the critical stress must be finite and > 0 "
                             "at every node")
        # per segment j: rows 2j, 2j + 1 = int_seg (1 - s) u_y, int_seg s u_y (3-point Gauss)
        g, gw = np.polynomial.legendre.leggauss(3)
        g, gw = 0.5 * (g + 1), 0.5 * gw
        L = np.diff(xs)
        px = (xs[:-1, None] + L[:, None] * g[None, :]).ravel()
        pts = np.column_stack([px, np.full(len(px), rule.y0)])
        uy = disc.shape_at(pts, derivatives=False).u_operators()[1]
        w = (L[:, None] * gw[None, :]).ravel()
        sg = np.tile(g, len(L))
        rows = np.repeat(np.arange(len(L)), len(g))
        W = csr_array((np.concatenate([w * (1 - sg), w * sg]),
                       (np.concatenate([2 * rows, 2 * rows + 1]), np.tile(np.arange(len(px)), 2))),
                      shape=(2 * len(L), len(px)))
        self.B = csr_array(W @ uy)

    def length(self) -> float:
        closed = np.flatnonzero(~self.open)
        return float(self.x[closed[0]] - self.x[0]) if len(closed) else float(self.x[-1] - self.x[0])

    def tips(self) -> np.ndarray:
        """The ends ``(x_left, x_right)`` of the open stretch holding each initial crack,
        shape (n_cracks, 2)."""
        j = np.clip(np.searchsorted(self.x, self.seeds, side="right") - 1, 0, len(self.open) - 1)
        closed = np.flatnonzero(~self.open)
        out = np.empty((len(j), 2))
        for i, k in enumerate(j):  # a few cracks
            left = closed[closed < k]
            right = closed[closed > k]
            out[i] = (self.x[left[-1] + 1] if len(left) else self.x[0],
                      self.x[right[0]] if len(right) else self.x[-1])
        return out

    def rows(self) -> csr_array:
        """The Lagrange rows ``int_bonded N_k u_y dx = 0`` of the bonded segments, one per
        hat ``N_k`` (piecewise linear on the line's nodes, as
        :func:`~efgkit.methods.boundary.essential_conditions`), shape (r, n_dofs)."""
        bonded = (~self.open).astype(float)
        m = len(self.x)
        # hat k gets the right-end part of segment k - 1 and the left-end part of segment k
        hat = np.concatenate([np.arange(m - 1), np.arange(1, m)])
        seg = np.concatenate([np.arange(m - 1), np.arange(m - 1)])
        S = csr_array((np.concatenate([bonded, bonded]), (hat, seg * 2 + np.r_[np.zeros(m - 1, int),
                                                                                np.ones(m - 1, int)])),
                      shape=(m, 2 * (m - 1)))
        G = csr_array(S @ self.B)
        used = np.flatnonzero(np.diff(G.indptr) > 0)
        self.used = used  # the hats of the rows returned
        return csr_array(G[used])

    def segment_forces(self, lam: np.ndarray, segments: np.ndarray) -> np.ndarray:
        """The force the support exerted on each of ``segments`` (indices into the
        segments), ``-int_seg lambda(x) u_y dx`` with ``lambda = sum_k lam_k N_k`` (``lam``:
        one multiplier per row of the last :meth:`rows`), shape (n_dofs, len(segments))."""
        node = np.zeros(len(self.x))
        node[self.used] = lam
        j = np.asarray(segments, int)
        return -(self.B[2 * j].toarray() * node[j, None] + self.B[2 * j + 1].toarray() * node[j + 1, None]).T

    def sigma1(self, u) -> np.ndarray:
        s = strain_from_gradient(self.shape.gradient(u)) @ self.D.T
        return principal_stress(self.fE[:, None] * s)

    def release(self, s1: np.ndarray, sigma_c) -> list[tuple[float, bool]]:
        """Open the segments of the nodes where ``s1 >= sigma_c``: ``[(x, new_crack)]``."""
        return [(float(self.x[k]), new) for k, new in release_segments(self.open, s1, sigma_c)]
