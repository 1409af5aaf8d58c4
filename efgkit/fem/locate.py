"""Point location in a finite-element mesh: the element holding each point and its
reference coordinates, for evaluating fields of :class:`efgkit.fem.solution.FEMSolution`
anywhere in the body.

A trapezoid-map finder (matplotlib) on the straight triangles gives a first element;
Newton's method on the element's (possibly isoparametric, quarter-point) map gives the
reference coordinates; points it leaves outside their triangle (curved elements) try
the elements with the nearest centroids. A point on a crack line (within 1e-12 of the
domain size) is moved 1e-10 of the domain size onto the crack's *left* face, the
:mod:`efgkit.problem.crack` convention (left of a segment ``a -> b``).
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

__all__ = ["PointLocator"]


def _solve2(J, r):
    """Solve the 2x2 systems ``J[:, :, n] dX[:, n] = r[:, n]``; 0 where J is singular."""
    det = J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
    ok = det != 0
    d = np.where(ok, det, 1.0)
    out = np.array([(J[1, 1] * r[0] - J[0, 1] * r[1]) / d, (J[0, 0] * r[1] - J[1, 0] * r[0]) / d])
    return np.where(ok, out, 0.0)


def outside(X: np.ndarray) -> np.ndarray:
    """How far reference points ``X (2, ...)`` lie outside the reference triangle (0 inside)."""
    return np.maximum.reduce([-X[0], -X[1], X[0] + X[1] - 1, np.zeros(X.shape[1:])])


class PointLocator:
    """``locator(x) -> (elements (n,), reference coordinates (2, n))`` for points ``x (n, 2)``.

    Parameters
    ----------
    scene : Scene
        For the body (points outside it are refused) and the cracks.
    mesh : TriMesh
        The linear triangle mesh (cracks opened; ``origin`` maps nodes to geometric points).
    skmesh : skfem.Mesh
        The scikit-fem mesh with the geometric map (``doflocs``, ``elem``).
    """

    def __init__(self, scene, mesh, skmesh):
        self.scene, self.mesh, self.skmesh = scene, mesh, skmesh

    @cached_property
    def _finder(self):
        from matplotlib.tri import Triangulation

        n0 = int(self.mesh.origin.max()) + 1
        x = self.mesh.x[:n0]
        return Triangulation(x[:, 0], x[:, 1], self.mesh.origin[self.mesh.t]).get_trifinder()

    @cached_property
    def geometry(self) -> np.ndarray:
        """Element node coordinates of the geometric map, shape (2, n_geometric_nodes, n_elements)."""
        return self.skmesh.doflocs[:, self.skmesh.dofs.element_dofs]

    def _map(self, G: np.ndarray, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Mapped points (2, n) and Jacobians ``J[d, e, n] = dx_d / dX_e`` (2, 2, n) of
        reference points ``X (2, n)`` in elements with node coordinates ``G (2, g, n)``."""
        gel = self.skmesh.elem()
        ev = [gel.lbasis(X, i) for i in range(G.shape[1])]
        return (np.einsum("dgn,gn->dn", G, np.array([e[0] for e in ev])),
                np.einsum("dgn,gen->den", G, np.array([e[1] for e in ev])))

    def jacobian(self, elems: np.ndarray, X: np.ndarray) -> np.ndarray:
        """Jacobians (2, 2, n) of the element maps at reference points ``X (2, n)``."""
        return self._map(self.geometry[:, :, elems], X)[1]

    def inverse(self, elems: np.ndarray, x: np.ndarray) -> np.ndarray:
        """Reference coordinates (2, n) of points ``x (n, 2)`` in elements ``elems (n,)``."""
        G = self.geometry[:, :, elems]
        J0 = np.stack([G[:, 1] - G[:, 0], G[:, 2] - G[:, 0]], axis=1)
        X = _solve2(J0, x.T - G[:, 0])
        for _ in range(30):
            F, J = self._map(G, X)
            dX = _solve2(J, x.T - F)
            X = X + dX
            if np.abs(dX).max(initial=0.0) < 1e-14:
                break
        return X

    def __call__(self, x) -> tuple[np.ndarray, np.ndarray]:
        from scipy.spatial import cKDTree

        dom = self.scene.domain
        x = dom.field_points(x).copy()
        for c in self.scene.cracks:  # points on a crack line go to its left face
            k, _, d = c.project(x)
            on = d <= 1e-12 * dom.size
            if on.any():
                t = c.segments[k[on], 1] - c.segments[k[on], 0]
                t /= np.linalg.norm(t, axis=1)[:, None]
                x[on] += 1e-10 * dom.size * np.column_stack([-t[:, 1], t[:, 0]])
        e = np.asarray(self._finder(x[:, 0], x[:, 1]))
        X = np.zeros((2, len(x)))
        found = e >= 0
        X[:, found] = self.inverse(e[found], x[found])
        bad = ~found | (outside(X) > 1e-9)
        if bad.any():  # curved elements: try the elements with the nearest centroids
            G = self.geometry
            k = min(16, G.shape[2])
            _, cand = cKDTree(G[:, :3].mean(axis=1).T).query(x[bad], k=k)
            cand = cand.reshape(-1, k)
            Xc = self.inverse(cand.ravel(), np.repeat(x[bad], k, axis=0)).reshape(2, -1, k)
            best = np.argmin(outside(Xc), axis=1)
            rows = np.arange(len(cand))
            e[bad], X[:, bad] = cand[rows, best], Xc[:, rows, best]
        return e, X
