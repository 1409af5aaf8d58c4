"""Scene + EFG -> nodes, quadrature points and shape functions.

Only what the scene needs is built: derivatives at domain points (the
stiffness needs them), values alone at traction points, and the modified-MLS
interpolation only for nodes on essential edges when ``bc="modified_mls"``.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from .approx.mls import Shape, mls_shape
from .geometry import Domain, Edge
from .methods import EFG
from .nodes import NodeCloud, generate_nodes
from .quadrature import Points, cell_points, gauss_legendre, triangle_points
from .scene import Scene
from .search import BoxGrid, find_neighbours

__all__ = ["Discretization", "discretize", "support_edges", "edge_rule"]


@dataclass(frozen=True, eq=False)
class Discretization:
    """Everything the solvers need from the discretisation of a scene.

    Attributes
    ----------
    scene : Scene; method : EFG
    nodes : NodeCloud
    points : Points
        Domain quadrature points ``x (n_points, 2)`` and weights.
    shape : Shape
        Shape functions with derivatives at ``points``.
    interpolate : (n_nodes,) bool or None
        Nodes with the Kronecker-delta property (modified MLS only).
    boxes : BoxGrid
        The neighbour-search structure (reused for every later evaluation).
    timings : dict
        Seconds per stage.
    """

    scene: Scene
    method: EFG
    nodes: NodeCloud
    points: Points
    shape: Shape
    interpolate: np.ndarray | None
    boxes: BoxGrid
    timings: dict = field(default_factory=dict)

    def shape_at(self, x: np.ndarray, derivatives: bool = True) -> Shape:
        """Shape functions of this discretisation at points ``x (n, 2)``."""
        m = self.method
        x = np.atleast_2d(np.asarray(x, dtype=float))
        nb = find_neighbours(x, self.nodes, self.boxes)
        return mls_shape(x, self.nodes, m.weight, m.basis, d_max=m.d_max, alpha=m.alpha,
                         derivatives=derivatives, neighbours=nb, interpolate=self.interpolate)


def support_edges(domain: Domain, where) -> list[Edge]:
    """Edges selected by a support/traction ``where`` (a name, or all edges for a callable)."""
    return domain.edges(where) if isinstance(where, str) else domain.edges()


def edge_rule(edge: Edge, n_segments: int, order: int):
    """Gauss rule on ``n_segments`` equal-parameter pieces of ``edge``.

    Returns x (m, 2), w (m,), normal (m, 2), segment (m,) and local t (m,) in [0, 1].
    """
    xi, gw = gauss_legendre(order)
    seg = np.repeat(np.arange(n_segments), order)
    t = np.tile((xi + 1) / 2, n_segments)
    s = (seg + t) / n_segments
    x, tangent = edge.at(s)
    w = np.tile(gw / 2, n_segments) * edge.length / n_segments
    normal = np.column_stack([tangent[:, 1], -tangent[:, 0]])
    return x, w, normal, seg, t


def _nodes_on(edge: Edge, x: np.ndarray, tol: float) -> np.ndarray:
    """Mask of points ``x (n, 2)`` within ``tol`` of ``edge``."""
    p = edge.polyline()
    a, b = p[:-1], p[1:]
    best = np.full(len(x), np.inf)
    for k in range(0, len(a), 256):
        aa, ab = a[None, k:k + 256], (b - a)[None, k:k + 256]
        t = np.clip(np.sum((x[:, None] - aa) * ab, -1) / np.sum(ab * ab, -1), 0, 1)
        d = np.linalg.norm(x[:, None] - aa - t[..., None] * ab, axis=-1).min(axis=1)
        best = np.minimum(best, d)
    return best <= tol


def essential_nodes(scene: Scene, nodes: NodeCloud, spacing: float) -> np.ndarray:
    """Nodes lying on an edge that carries a support, shape (n_nodes,) bool."""
    on = np.zeros(nodes.n, bool)
    tol = 1e-6 * spacing
    for sup in scene.supports:
        for e in support_edges(scene.domain, sup.edge):
            hit = _nodes_on(e, nodes.x, tol)
            if callable(sup.edge):
                hit &= np.asarray(sup.edge(nodes.x), bool)
            on |= hit
    return on


def discretize(scene: Scene, method: EFG) -> Discretization:
    """Nodes, domain quadrature and shape functions of ``scene`` under ``method``.

    Examples
    --------
    >>> from efgkit import Domain, EFG, Elastic, Scene, Support
    >>> scene = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3),
    ...               supports=(Support("left", ux=0.0, uy=0.0),))
    >>> d = discretize(scene, EFG(spacing=0.25))
    >>> d.nodes.n, round(float(d.points.w.sum()), 12)
    (25, 1.0)
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    if not isinstance(method, EFG):
        raise TypeError(f"method must be an EFG description, got {type(method).__name__}")
    timings = {}
    t0 = time.perf_counter()
    nodes = generate_nodes(scene.domain, method)
    interpolate = None
    if method.bc == "modified_mls":
        warnings.warn(
            "bc='modified_mls' (seed 002): the interpolation constraints switch on where a point "
            "enters an essential-boundary node's support, so the shape functions are "
            "discontinuous there and the EFG weak form is not consistent (patch-test error "
            "~1e-1, docs/theory.md). Prefer 'lagrange' or 'variational' for EFG.",
            UserWarning, stacklevel=2)
        interpolate = essential_nodes(scene, nodes, method.spacing)
        nodes = _interpolating_supports(nodes, interpolate)
    timings["nodes"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    if method.quadrature == "cells":
        points = cell_points(scene.domain, method.cell_size or method.spacing, method.order,
                             zones=method.zones, refined_order=method.refined_order)
    else:
        points = triangle_points(scene.domain, nodes.x, method.order)
    timings["quadrature"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    boxes = BoxGrid.build(nodes)
    order = np.argsort(boxes.box_of(points.x), kind="stable")  # locality for the kernels
    points = Points(points.x[order], points.w[order],
                    None if points.owner is None else points.owner[order])
    nb = find_neighbours(points.x, nodes, boxes)
    timings["search"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    shape = mls_shape(points.x, nodes, method.weight, method.basis, d_max=method.d_max,
                      alpha=method.alpha, neighbours=nb, interpolate=interpolate)
    timings["shape"] = time.perf_counter() - t0
    return Discretization(scene, method, nodes, points, shape, interpolate, boxes, timings)


def _interpolating_supports(nodes: NodeCloud, interp: np.ndarray) -> NodeCloud:
    """Shrink supports of interpolating nodes to their nearest interpolating neighbour.

    Seed 002 (text after Eq. 18) needs no more interpolation nodes in a support
    than the basis can interpolate; a support reaching only the adjacent
    boundary nodes gives at most two per straight edge, and u^h along the
    edge is then the linear interpolant of the prescribed values.
    """
    from scipy.spatial import cKDTree

    r = nodes.radius.copy()
    xb = nodes.x[interp]
    if len(xb) >= 2:
        d, _ = cKDTree(xb).query(xb, k=2)
        r[interp] = np.minimum(r[interp], d[:, 1] * (1 - 1e-9))  # neighbour itself excluded
    return NodeCloud(nodes.x, r, nodes.boundary)


def boundary_segments_for(edge: Edge, nodes: NodeCloud, spacing: float) -> int:
    """Number of rule pieces on ``edge``: at least one per node interval on it."""
    on = _nodes_on(edge, nodes.x, 1e-6 * spacing).sum()
    return max(1, math.ceil(edge.length / spacing - 1e-9), int(on) - 1)
