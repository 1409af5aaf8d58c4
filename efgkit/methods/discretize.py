"""Scene + EFG -> nodes, quadrature points and shape functions.

Only what the scene needs is built: derivatives at domain points (the
stiffness needs them), values alone at traction points, and the modified-MLS
interpolation only for nodes on essential edges when ``bc="modified_mls"``.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ..approx.approximation import Approximation
from ..approx.crack_rules import CrackLines, CrackRule
from ..approx.enrichment import Enrichment
from ..approx.hole_rules import Holes
from ..approx.point_shapes import PointShapes
from ..approx.shape import Shape
from ..approx.tip_functions import TipGeometry
from ..nodes import NodeCloud, check_memory, generate_nodes, support_radii
from ..problem.geometry import Domain, Edge
from ..problem.scene import Scene
from ..quadrature.cell_rule import CellRule
from ..quadrature.cells import cell_points, cell_rule, triangle_points
from ..quadrature.rules import Points
from ..search import BoxGrid, find_neighbours
from ..system.images import image_group, image_positions, part_weights, tie
from ..timing import Stopwatch
from .crack_choices import check_crack_choices
from .efg import EFG, Zone
from .size import STREAM_POINTS, size_estimate

__all__ = ["Discretization", "discretize", "support_edges", "crack_mouths", "essential_nodes",
           "interpolating_supports", "shadow_rays"]



@dataclass(frozen=True, eq=False)
class Discretization:
    """Everything the solvers need from the discretisation of a scene.

    Attributes
    ----------
    scene : Scene; method : EFG
    nodes : NodeCloud
    points : Points
        Domain quadrature points ``x (n_points, 2)`` and weights.
    shape : Shape or PointShapes
        Shape functions with derivatives at ``points`` (a :class:`PointShapes`, formed a
        chunk of points at a time on demand, when discretised with ``chunked``).
    approx : Approximation
        The trial functions (nodes, search structure, crack rule,
        enrichment): evaluates shape functions at any points.
    timings : dict
        Seconds per stage.
    test : Shape, optional
        Test functions at ``points`` (MLPG: the disc spline of each point's owner node);
        None: Bubnov-Galerkin (test = trial).
    field_points : Points, optional
        An area quadrature of the body for energies, errors and J integrals when
        ``points`` is none (MLPG's discs overlap); None: ``points`` is one.
    local : object, optional
        MLPG: the boundary pieces of the sub-domains (:class:`efgkit.methods.local.LocalBoundary`).
    images : ImageTie, optional
        A half or quarter model (``scene.symmetry``): ``nodes``, ``approx`` and ``shape`` are
        those of the mirrored cloud (the part's nodes and their images), ``points`` the
        part's, and the coefficients are tied by :class:`efgkit.system.images.ImageTie`.
    """

    scene: Scene
    method: EFG
    nodes: NodeCloud
    points: Points
    shape: Shape
    approx: Approximation
    timings: dict = field(default_factory=dict)
    test: Shape | None = None
    field_points: Points | None = None
    local: object = None
    images: object = None

    @property
    def post_points(self) -> Points:
        """The area quadrature of post-processing (energies, errors, J integrals)."""
        return self.points if self.field_points is None else self.field_points

    @cached_property
    def post_shape(self) -> Shape:
        """Shape functions with derivatives at :attr:`post_points` (computed once)."""
        return self.shape if self.field_points is None else self.shape_at(self.field_points.x)

    @property
    def interpolate(self) -> np.ndarray | None:
        """Nodes with the Kronecker-delta property (modified MLS only)."""
        return self.approx.interpolate

    @property
    def boxes(self) -> BoxGrid:
        return self.approx.boxes

    @property
    def n_dofs(self) -> int:
        """Unknowns of the trial space: 2 per node plus the enrichment unknowns."""
        return self.approx.n_dofs

    def shape_at(self, x: np.ndarray, derivatives: bool = True) -> Shape:
        """Shape functions of this discretisation at points ``x (n, 2)``."""
        return self.approx.shape(x, derivatives=derivatives)


def support_edges(domain: Domain, where) -> list[Edge]:
    """Edges selected by a support/traction ``where`` (a name, or all edges for a callable)."""
    return domain.edges(where) if isinstance(where, str) else domain.edges()


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


def crack_mouths(scene: Scene) -> np.ndarray:
    """The crack ends on the boundary (not tips), shape (b, 2): boundary rules break there."""
    pts = [c.vertices[-1 if e else 0] for c in scene.cracks for e in (0, 1) if not c.tips[e]]
    return np.array(pts).reshape(-1, 2)


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


def discretize(scene: Scene, method: EFG, chunked: bool | str = False) -> Discretization:
    """Nodes, domain quadrature and shape functions of ``scene`` under ``method``.

    The automatic choices of ``method`` are made first (:meth:`EFG.for_scene`).

    ``chunked``: True leaves the shape functions at the domain points unformed (``shape`` a
    :class:`~efgkit.approx.point_shapes.PointShapes`: formed a chunk of points at a time by
    whoever needs them, :func:`efgkit.system.streamed.streamed_stiffness`); "auto" does so from
    :data:`~efgkit.methods.size.STREAM_POINTS` domain points on for scenes without a body
    force and without symmetry (what :func:`efgkit.static.solve` asks for).

    Raises
    ------
    ValueError
        Before allocating anything, when discretising and solving would need more memory
        than the machine has available (:func:`efgkit.methods.size.size_estimate`,
        :func:`efgkit.nodes.check_memory`);
        and for the combinations of options that are not supported.

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
    if chunked not in (False, True, "auto"):
        raise ValueError(f"chunked must be False, True or 'auto', got {chunked!r}")
    streamable = scene.body_force is None and scene.symmetry is None
    if chunked is True and not streamable:
        raise ValueError(f"chunked=True needs a scene without body force and symmetry (scene "
                         f"{scene.name!r} has one): use chunked=False or 'auto'")
    sw = Stopwatch()  # laps: stages that add up to the wall time, compilation apart
    method = method.for_scene(scene)  # the automatic choices (tip zones, enrichment, bc)
    est = size_estimate(scene, method, chunked=chunked if streamable else False)
    source = max(est.point_parts, key=est.point_parts.get)  # arguments giving the most points
    check_memory(est.bytes, f"{source} would give about {est.nodes:.2g} nodes and "
                 f"{est.points:.2g} quadrature points with up to {est.width} neighbours each; "
                 + est.describe(),
                 "Remedy: a discretisation about {factor:.2g} times coarser (spacing, cell_size, "
                 "zone spacings) would fit; refine only where needed (zones near tips, holes and "
                 "corners), or lower d_max or order.")
    sw.lap("setup")
    if scene.symmetry is not None:
        return _mirrored(scene, method, sw)
    nodes = generate_nodes(scene.domain, method, scene.cracks)
    interpolate = None
    if method.bc == "modified_mls":
        warnings.warn(
            "bc='modified_mls' (seed 002): the interpolation constraints switch on where a point "
            "enters an essential-boundary node's support, so the shape functions are "
            "discontinuous there and the EFG weak form is not consistent (patch-test error "
            "~1e-1, docs/theory.md). Prefer 'lagrange' or 'variational' for EFG.",
            UserWarning, stacklevel=2)
        interpolate = essential_nodes(scene, nodes, method.spacing)
        nodes = interpolating_supports(nodes, interpolate)
    sw.lap("nodes")
    if method.quadrature == "cells":
        points = cell_rule(scene.domain, method.cell_size or method.spacing, method.order,
                           zones=method.zones + method.tip_cell_zones(scene),
                           refined_order=method.refined_order, cracks=scene.cracks,
                           tip_rays=shadow_rays(scene, nodes), tip_order=method.tip_order)
    else:
        points = triangle_points(scene.domain, nodes.x, method.order)
    sw.lap("quadrature")
    approx = approximation(scene, method, nodes, interpolate)
    sw.lap("approximation")  # crack lines, enrichment, the box grid of the nodes
    later = chunked is True or (chunked == "auto" and streamable and points.n >= STREAM_POINTS)
    points, shape = _shape_functions(points, approx, sw, later)
    return Discretization(scene, method, nodes, points, shape, approx, sw.timings)


def _shape_functions(points: Points | CellRule, approx: Approximation, sw: Stopwatch,
                     later: bool = False) -> tuple[Points, Shape | PointShapes]:
    """The points sorted by box (locality for the kernels; a cell rule's points are written
    in that order once), then their neighbours and shape functions (stages "search" and
    "shape"), or with ``later`` a :class:`PointShapes` that forms them a chunk at a time
    when asked."""
    points = points.sorted_by(approx.boxes.box_of)
    if later:
        return points, PointShapes(approx, points.x)
    nb = find_neighbours(points.x, approx.nodes, approx.boxes)
    sw.lap("search")
    shape = approx.shape(points.x, neighbours=nb)
    sw.lap("shape")
    return points, shape


def _mirrored(scene: Scene, method: EFG, sw: Stopwatch) -> Discretization:
    """A half or quarter model on the mirrored cloud, its coefficients tied to the part's
    (:mod:`efgkit.system.images`): the full model's MLS functions and quadrature (restricted to
    the part) on the part's nodes and their images."""
    sym, full = scene.symmetry, scene.full()
    why = ("cracks off the symmetry lines (their images are not built)" if scene.cracks else
           f"bc={method.bc!r} (it eliminates coefficients; use 'lagrange', 'penalty' or "
           "'variational')" if method.bc in ("modified_mls", "collocation") else
           "rosette (use zones)" if method.rosette is not None else None)
    if why:
        raise ValueError(f"scene {scene.name!r}: EFG half and quarter models (symmetry) take no {why}")
    part = generate_nodes(scene.domain, method)
    tol = 1e-9 * scene.domain.size
    y, U = image_positions(part.x, sym.lines, tol)
    cloud = generate_nodes(full.domain, replace(method, coordinates=y, zones=(), perturb=0.0),
                           full.cracks)
    origin, side = np.arange(cloud.n), np.zeros((cloud.n, 2))
    if cloud.face is not None:  # nodes on the crack: one per face
        origin[len(y):] = np.flatnonzero(cloud.face[: len(y)] == 1)
        k = np.flatnonzero(cloud.face != 0)
        seg = np.concatenate([c.segments for c in full.cracks])[cloud.face_segment[k]]
        e = seg[:, 1] - seg[:, 0]
        side[k] = cloud.face[k, None] * np.column_stack([-e[:, 1], e[:, 0]])
    # the exact mirror positions (splitting put the face nodes on the crack with rounding that
    # differs between a node and its image, which tips rules decided at ties, e.g. PU's radius)
    nodes = NodeCloud(y[origin], support_radii(y, method.d_max, method.regular)[origin],
                      cloud.boundary, cloud.face, cloud.face_segment)
    sides = np.array([np.sign(((part.x - p) @ n).sum()) for p, n in sym.lines])
    sw.lap("nodes")
    if method.quadrature == "cells":
        R, c = image_group(sym.lines)
        zones = {(tuple(np.round(R[s] @ z.centre + c[s], 12)), z.radius, z.spacing): None
                 for z in method.zones for s in range(len(R))}
        pts = cell_points(full.domain, method.cell_size or method.spacing, method.order,
                          zones=tuple(Zone(*z) for z in zones) + method.tip_cell_zones(full),
                          refined_order=method.refined_order, cracks=full.cracks,
                          tip_rays=shadow_rays(full, nodes), tip_order=method.tip_order)
        f = part_weights(pts.x, sym.lines, sides, tol)
        points = Points(pts.x[f > 0], pts.w[f > 0] * f[f > 0], pts.owner[f > 0])
    else:
        points = triangle_points(scene.domain, part.x, method.order)
    sw.lap("quadrature")
    approx = approximation(full, method, nodes)
    images = tie(sym.lines, U, origin, side, sides, approx.enrichment, tol)
    sw.lap("approximation")
    points, shape = _shape_functions(points, approx, sw)
    return Discretization(scene, method, nodes, points, shape, approx, sw.timings, images=images)


def shadow_rays(scene: Scene, nodes: NodeCloud) -> list[np.ndarray]:
    """For every tip, the directions ``tip - x_I (k, 2)`` of the nodes whose support holds
    it: the rays through the tip where the crack rules put kinks in the weights."""
    rays = []
    for tip in scene.tips:
        d = tip.x - nodes.x
        r = np.hypot(*d.T)
        rays.append(d[(r < nodes.radius) & (r > 1e-9 * nodes.radius)])
    return rays


def approximation(scene: Scene, method: EFG, nodes: NodeCloud,
                  interpolate: np.ndarray | None = None) -> Approximation:
    """The trial functions of ``method`` on ``nodes`` for ``scene`` (crack rule, enrichment).

    An automatic enrichment not yet made for the scene (:meth:`EFG.for_scene`, which
    :func:`discretize` applies) counts as none here, as automatic zones do in
    :func:`~efgkit.nodes.generate_nodes`: the stage functions build what they are told."""
    if method.enrichment == "auto":
        method = replace(method, enrichment="none")
    lines = rule = enrichment = None
    if scene.cracks:
        lines = CrackLines.from_cracks(scene.cracks)
        rule = CrackRule(method.crack_rule, method.rule_power, method.kappa, method.spacing)
        check_crack_choices(scene, method, nodes, lines)
        if method.enrichment != "none":
            tips = [TipGeometry.of(c, e) for c in scene.cracks for e in (0, 1) if c.tips[e]]
            r2 = method.ramp_outer
            if method.enrichment == "extrinsic_mls":
                r2 = method.enrich_radius if method.enrich_radius is not None else np.inf
            enrichment = Enrichment.build(method.enrichment, tips, nodes, scene.material,
                                          method.ramp_inner, r2, method.ramp, method.pu_radius)
    elif method.enrichment != "none":
        raise ValueError(f"enrichment={method.enrichment!r} needs a crack tip, but scene "
                         f"{scene.name!r} has no cracks; use enrichment='none'")
    holes = Holes.of(scene.domain) if method.hole_rule != "see_through" and scene.domain.holes \
        else None
    if holes is not None and rule is None:
        rule = CrackRule("diffraction", method.rule_power, method.kappa, method.spacing)
    return Approximation(nodes, BoxGrid.build(nodes), method.weight, method.basis, method.d_max,
                         method.alpha, method.spacing, interpolate, lines, rule, enrichment,
                         holes, method.hole_rule, getattr(method, "weight_k", 1))


def interpolating_supports(nodes: NodeCloud, interp: np.ndarray) -> NodeCloud:
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
    return NodeCloud(nodes.x, r, nodes.boundary, nodes.face, nodes.face_segment)  # crack faces kept


def boundary_segments_for(edge: Edge, nodes: NodeCloud, spacing: float) -> int:
    """Number of equal-parameter pieces of the boundary rules (and Lagrange-multiplier hats)
    on ``edge``: at least one per node interval on it."""
    on = _nodes_on(edge, nodes.x, 1e-6 * spacing)
    positions = len(np.unique(np.round(nodes.x[on] / spacing, 6), axis=0))  # split copies once
    return max(1, math.ceil(edge.length / spacing - 1e-9), positions - 1)
