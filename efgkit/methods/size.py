"""How big a discretisation and its static solve will be, estimated before allocating.

:func:`size_estimate` counts nodes, quadrature points and neighbour-list widths from areas
(the domain, zones, tip cells and cut cells), and converts them to bytes with the
calibration below; :func:`efgkit.methods.discretize.discretize` refuses a problem that would
not fit in the available memory.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..nodes import area_in_disc, estimate_nodes
from ..problem.scene import Scene
from ..quadrature.rules import triangle_rule
from ..system.linalg import AUTO_AMG_THRESHOLD
from .efg import EFG

__all__ = ["SizeEstimate", "size_estimate", "RELEASE_POINTS", "STREAM_POINTS"]

# Size guard: the peak memory of discretize and a static solve, estimated before allocating.
# Calibration (the larger of the tracemalloc peak and the peak RSS above the interpreter; unit
# plate, bc="lagrange", order 4, d_max 2, regular grid unless stated): 19,881 nodes, 313,600
# points (width 13): discretize 152 MB, solve (AMG) 516 MB; order 6 (705,600 points) 720 MB;
# d_max 3 (width 30) 1184 MB; perturb 0.3 (width 22) 692 MB; solver="direct" 967 MB (SuperLU's
# factors, RSS). 40,401 nodes, 640,000 points: 1052 MB; 5,041 nodes (SuperLU) 176 MB.
# Fit: 40 B per padded neighbour slot (points x widest neighbour list: phi, d/dx, d/dy, the
# index and the mask, and the search) plus, per node, 18 kB (CG with AMG) or 49 kB
# (nodes / 2e4)^0.25 (SuperLU), times (d_max / 2)^2 (node pairs of the stiffness).
# Check: the four examples refined to 4,600-20,000 nodes (solve, sifs) peak at 1/1.1-1/2.1 of it.
SLOT_BYTES = 40.0
NODE_BYTES_AMG = 18e3
NODE_BYTES_DIRECT = 49e3
# From RELEASE_POINTS domain points on, efgkit.static.solve drops the padded values before the
# stiffness and keeps compact CSR derivatives (Shape.gradients_only) through the linear solve;
# the peak is then the larger of the discretisation's (SLOT_BYTES per slot) and the solve's
# (HELD_SLOT_BYTES per slot held plus the per-node bytes) instead of their sum. Calibration
# (peak RSS above the interpreter, sampled every 5 ms; the slots and nodes of this estimate,
# which counts ~20 % more nodes and points than generated here): edge-cracked plate of
# benchmarks/scaling.py, bc="lagrange", CG: 19,564 nodes, 590,440 points: discretisation
# 0.73 GB (43 B per estimated slot), solve 0.51 GB; 96,980 nodes, 2.92M points: 3.60 GB
# (45 B per slot) and 2.77 GB; 289,950 nodes, 8.74M points: 11.39 GB (48 B per slot) and
# 8.2 GB; the unit plate above: 411 MB (516 MB with the arrays held). With the enrichment's
# temporaries formed in chunks (enrichment.EXTRA_CHUNK) the 1e5 peak fell to 3.33 GB above the
# interpreter (3.62 GB in all); the constants below keep the earlier, larger calibration.
# HELD_SLOT_BYTES: the CSR d/dx, d/dy (8 B each and a shared 4 B index per pair, ~0.57
# pairs per padded slot) and the enrichment's gradient operators. The cracked plate's 43-48 B
# per slot (extrinsic enrichment at every point) are SLOT_BYTES plus ENRICHED_POINT_BYTES per
# point; estimated / measured peak above the interpreter: 0.82 / 0.69, 3.93 / 3.60 and
# 11.62 / 11.39 GB at 2e4, 1e5 and 3e5 nodes; 1e6 nodes: 38.4 GB (refused on 24 GB).
RELEASE_POINTS = 200_000
HELD_SLOT_BYTES = 12.0
# Extrinsic MLS enrichment without enrich_radius is non-zero at every point: its operators and
# temporaries add to the discretisation. Measured beyond SLOT_BYTES on the cracked plate: 69,
# 115 and 175 B per estimated point at 2e4, 1e5 and 3e5 nodes (peaks 0.98, 3.89, 11.68 GB; the
# discretisation sets the peak from 1e5 nodes on).
ENRICHED_POINT_BYTES = 200.0
# From STREAM_POINTS domain points on, efgkit.static.solve (scenes without body force and
# symmetry) never forms the shape functions at all points: discretize(..., chunked="auto")
# leaves them to efgkit.system.streamed.streamed_stiffness, a chunk of CHUNK_POINTS at a time.
# The peak is then the largest of: the quadrature (QUADRATURE_POINT_BYTES per point: the cells'
# points and the box sort), the assembly (the points' x and w held, STREAM_POINT_BYTES per point,
# plus one chunk's shape functions, the chunks' K_c and their sum, STREAM_ASSEMBLY_BYTES per weighted
# node) and the solve (the points held plus STREAM_NODE_BYTES per weighted node: K, the
# constrained matrix, A_rho of the Uzawa steps and the auxiliary preconditioner; the Lagrange
# saddle point's matrix, a copy of K, is no longer formed for CG (system.linear_system), so the
# constant, calibrated with it, lies ~1.4 kB per weighted node above that solve: 1.25 instead
# of 1.46-1.49 GB peak at 96,980 nodes, 10.9 instead of 12.6 GB at 965,572), the weighted
# nodes being nodes (d_max / 2)^2 sqrt(irregular) as for NODE_BYTES_AMG. Calibration (peak RSS
# above the interpreter, 5 ms samples, the estimated counts; cracked plate of
# benchmarks/scaling.py, bc="lagrange", CG): 19,564 nodes (590,440 points, 3 chunks): quadrature
# 0.02 GB, assembly 0.35 GB (chunk-bound), solve 0.24 GB (6.9 kB per weighted node); 96,980 nodes
# (2.92M points, 12 chunks): quadrature 0.30 GB (85 B per estimated point), assembly 0.68 GB (the
# partial sums 1.9 kB per weighted node; K alone ~1.4 kB), solve 1.31 GB (7.9 kB per weighted
# node); the unit plate above (19,881 nodes, 313,600 points, 2 chunks): 255 MB in all (12.6 kB per
# weighted node: a regular cloud, narrower neighbour lists, the same solver's parts). The solve is
# STREAM_FIXED_BYTES (the multigrid's modules and work arrays) plus STREAM_NODE_BYTES per weighted
# node: estimated / measured 0.29 / 0.26 GB (plate), 0.41 / 0.24 and 1.59 / 1.31 GB (cracked).
STREAM_POINTS = 200_000
CHUNK_POINTS = 2**18  # efgkit.approx.point_shapes.CHUNK_POINTS
QUADRATURE_POINT_BYTES = 110.0
STREAM_POINT_BYTES = 24.0
STREAM_ASSEMBLY_BYTES = 3e3
STREAM_NODE_BYTES = 9e3
STREAM_FIXED_BYTES = 1e8


@dataclass(frozen=True)
class SizeEstimate:
    """What :func:`discretize` and a static solve would allocate, estimated from areas:
    ``nodes``, ``points`` (domain quadrature), ``width`` (padded width of the neighbour
    lists: pi d_max^2, more on irregular clouds), ``shape_bytes`` (shape functions at the
    points), ``solve_bytes`` (stiffness, constraints, linear solve) and the nodes and points
    by source (``node_parts``, ``point_parts``: "arguments = values" -> count), and
    ``held_bytes``: what the solve keeps of the shape functions when it releases their padded
    arrays (None: it keeps them all, and the two parts add up)."""

    nodes: float
    points: float
    width: int
    shape_bytes: float
    solve_bytes: float
    node_parts: dict
    point_parts: dict
    held_bytes: float | None = None
    streamed: bool = False

    @property
    def bytes(self) -> float:
        """The estimated peak: the discretisation's, then the solve's on top of what it holds."""
        if self.held_bytes is None:
            return self.shape_bytes + self.solve_bytes
        return max(self.shape_bytes, self.held_bytes + self.solve_bytes)

    def describe(self) -> str:
        """What the parts of :attr:`bytes` are, for the size guard's message."""
        gb = 1e9
        if self.streamed:
            return (f"discretising it and assembling the stiffness a chunk of points at a time needs "
                    f"{self.shape_bytes / gb:.3g} GB and the solve {self.solve_bytes / gb:.3g} GB on top "
                    f"of the {self.held_bytes / gb:.3g} GB of the points' arrays kept through it (the "
                    "shape functions at all points are never held)")
        return (f"discretising and solving it needs {self.shape_bytes / gb:.3g} GB for the shape "
                f"functions and {self.solve_bytes / gb:.3g} GB for the stiffness and the solve"
                + ("" if self.held_bytes is None else
                   f" (on top of the {self.held_bytes / gb:.3g} GB of compact derivatives kept "
                   "through it; the padded shape arrays are released)"))


def size_estimate(scene: Scene, method: EFG, chunked: bool | str = "auto") -> SizeEstimate:
    """Estimate the size of ``discretize(scene, method, chunked)`` and a static solve,
    allocating nothing. ``chunked`` as in :func:`~efgkit.methods.discretize.discretize`
    ("auto": as :func:`efgkit.static.solve` discretises).

    Examples
    --------
    >>> from efgkit import Domain, EFG, Elastic, Scene
    >>> plate = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3))
    >>> est = size_estimate(plate, EFG(spacing=1 / 140, bc="lagrange"), chunked=False)
    >>> round(est.nodes, -2), round(est.points, -4), est.width, round(est.bytes / 1e6, -1)
    (20200.0, 350000.0, 14, 420.0)
    >>> # measured: 19,881 nodes, 313,600 points, width 13, peak 411 MB (module comment)
    >>> round(size_estimate(plate, EFG(spacing=1 / 140, bc="lagrange")).bytes / 1e6, -1)
    290.0
    >>> # streamed (the static solve's default at this size): measured 255 MB (module comment)
    """
    method = method.for_scene(scene)
    dom, cracks = scene.domain, scene.cracks
    nodes = estimate_nodes(dom, method, cracks)
    h, o, ro = method.spacing, method.order, method.refined_order
    c = method.cell_size or h
    segs = np.concatenate([dom.boundary_segments()]  # crack segments twice: two faces
                          + [cr.segments for cr in cracks for _ in (0, 1)])

    def cut(size, order, centre=(0.0, 0.0), radius=np.inf):
        # cells cut by the boundary: ~4 triangles each, plus 2 per polyline segment in them
        near = np.hypot(*(segs.mean(axis=1) - centre).T) <= radius
        length = np.hypot(*(segs[near, 1] - segs[near, 0]).T).sum()
        return float(2 * near.sum() + 4 * length / size) * len(triangle_rule(2 * order - 1)[1])

    base = f"spacing = {h!r}" + (f", cell_size = {c!r}" if method.cell_size else "")
    if method.quadrature == "triangles":
        parts = {f"{base}, quadrature='triangles', order = {o}":
                 2 * nodes.nodes * len(triangle_rule(2 * o - 1)[1])}
    else:  # full cells of the grid and of the split cells in zones, and the cut cells
        parts = {f"{base}, order = {o}": dom.area / c**2 * o**2 + cut(c, o)}
        for i, z in enumerate(method.zones + method.tip_cell_zones(scene)):
            name = (f"zones[{i}] (radius {z.radius!r}, spacing {z.spacing!r})"
                    if i < len(method.zones) else f"the cells near the tips (radius {z.radius:g})")
            name += f" with refined_order = {ro}"
            k = math.ceil(c / z.spacing - 1e-9)
            parts[name] = (parts.get(name, 0.0) + cut(c / k, ro, z.centre, z.radius)
                           + area_in_disc(dom, z.centre, z.radius) * (k * ro / c) ** 2)
    irregular = 1.0 if method.regular and method.rosette is None else 1.75
    width = math.ceil(math.pi * method.d_max**2 * irregular) + 1
    if method.rosette is not None and scene.tips:  # near the tip a point may see all of it
        width += method.rosette.rings * (method.rosette.per_ring - 1) + 1
    if scene.tips and method.quadrature == "cells":  # fans of ~width + 4 triangles in 4 cells
        parts[f"tip_order = {method.tip_order}"] = 4 * len(scene.tips) * (width + 4) * method.tip_order**2
    points = sum(parts.values())
    direct = method.solver == "direct" or (method.solver == "auto" and 2 * nodes.nodes <= AUTO_AMG_THRESHOLD)
    per_node = NODE_BYTES_DIRECT * max(1.0, nodes.nodes / 2e4) ** 0.25 if direct else NODE_BYTES_AMG
    released = isinstance(method, EFG) and points >= RELEASE_POINTS  # efgkit.static.solve
    everywhere = getattr(method, "enrichment", "none") == "extrinsic_mls" and \
        getattr(method, "enrich_radius", None) is None and bool(scene.tips)
    per_point = SLOT_BYTES * width + (ENRICHED_POINT_BYTES if everywhere else 0.0)
    weighted = (method.d_max / 2) ** 2 * irregular**0.5 * nodes.nodes
    streamed = isinstance(method, EFG) and (chunked is True or (
        chunked == "auto" and points >= STREAM_POINTS and scene.body_force is None
        and scene.symmetry is None))
    if streamed:  # one chunk's shape functions at a time, the points' arrays held throughout
        held = STREAM_POINT_BYTES * points
        assembly = held + per_point * min(points, CHUNK_POINTS) + STREAM_ASSEMBLY_BYTES * weighted
        return SizeEstimate(nodes.nodes, points, width, max(QUADRATURE_POINT_BYTES * points, assembly),
                            STREAM_FIXED_BYTES + STREAM_NODE_BYTES * weighted, nodes.parts, parts, held,
                            streamed=True)
    return SizeEstimate(nodes.nodes, points, width, per_point * points, per_node * weighted,
                        nodes.parts, parts, HELD_SLOT_BYTES * points * width if released else None)
