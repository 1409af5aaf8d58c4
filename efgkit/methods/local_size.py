"""How big an MLPG1 discretisation and its solve will be, estimated before allocating.

MLPG evaluates the MLS at the points of every node's test disc (seed 002 Eq. 39: radial x
angular per full disc; discs cut by the boundary or a crack get Gauss rules on their
angular pieces), at the boundary pieces inside the discs, and on the background cells of
the field quadrature (energies, J integrals). :func:`local_size_estimate` counts them from
the node estimate of :func:`efgkit.nodes.estimate_nodes` and the cell count of
:func:`efgkit.methods.size.size_estimate`, and converts them to bytes with the calibration
below; :func:`efgkit.methods.local.discretize_local` refuses what would not fit.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..problem.scene import Scene
from ..system.krylov import AUTO_KRYLOV_THRESHOLD
from .mlpg import MLPG
from .size import SLOT_BYTES, SizeEstimate, size_estimate

__all__ = ["local_size_estimate", "CUT_ROWS", "CUT_PIECES", "TIP_DISC_POINTS"]

# Calibration (unit plate, left edge clamped, quadratic basis, d_max 2.5, 5 x 8 / 16 Gauss,
# regular grid; peak RSS above the interpreter of solve(), which holds the disc, boundary
# and cell shape functions at once): 2,601 nodes: 151,720 disc points, 6,400 boundary
# points, 40,000 cells, width 21, 272 MB (SuperLU); 10,201 nodes: 503,720 disc points,
# 12,800 boundary points, 160,000 cells, 783 MB. Fit: SLOT_BYTES per padded neighbour slot
# as for EFG, plus 35 kB per node (K, SuperLU's factors; times (nodes / 2e4)^0.25 above 2e4
# as EFG's) -> 276 and 954 MB (1.0 and 1.2 times the measured peaks).
# Cut discs: about CUT_ROWS rows of nodes along every boundary and crack-face line lie
# within r_s of it, with CUT_PIECES angular pieces each (measured: 400 cut discs, 2 pieces).
CUT_ROWS = 2.0
CUT_PIECES = 2.0
# Discs near a crack tip (methods.local_tips), counted on the SENT of seed 001 at 20, 40 and 80
# across (the same at every spacing: a fixed number per tip), per unit of their rule: with an
# enrichment 23 discs x 1.7 angular pieces of tip_radial x tip_angular points (49,920 points at
# 20 x 64); without, 27 discs split into 24.6 pieces (angular x radial) of split_radial x
# split_angular points (95,600 at 3 x 48). Scaled by the disc count's area ((r_s + reach)^2).
TIP_DISC_POINTS = {"refined": 23 * 1.7, "split": 27 * 24.6}
NODE_BYTES_DIRECT = 35e3  # per node beyond the shape functions: K, its LU (SuperLU), f
# per node with GMRES: K (147 non-zeros per node, 1.8 kB) and its ILU factors (drop 1e-5,
# fill 20: nnz(L + U) 2,290 per node at 100k nodes, 27 kB; efgkit.system.krylov), the GMRES(50)
# basis 0.8 kB; counted from the measured non-zeros, not a measured peak
NODE_BYTES_KRYLOV = 30e3


def local_size_estimate(scene: Scene, method: MLPG) -> SizeEstimate:
    """Estimate the size of ``discretize_local(scene, method)`` and its solve, allocating nothing.

    ``points`` counts the disc points, the boundary pieces and the background cells;
    ``point_parts`` names them. Calibration in the module comment.

    Examples
    --------
    >>> from efgkit import Domain, Elastic, MLPG, Scene
    >>> est = local_size_estimate(Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3)),
    ...                           MLPG(spacing=0.02))
    >>> round(est.nodes, -2), round(est.points, -4), est.width, round(est.bytes / 1e6, -1)
    (2700.0, 220000.0, 21, 280.0)
    >>> # measured: 2,601 nodes, 198,120 points, width 21, peak 272 MB (module comment)
    """
    if not isinstance(method, MLPG):
        raise TypeError(f"method must be an MLPG description, got {type(method).__name__}")
    method = method.for_scene(scene)
    cells = size_estimate(scene, method)
    dom = scene.domain
    segs = np.concatenate([dom.boundary_segments()]  # crack segments twice: two faces
                          + [cr.segments for cr in scene.cracks for _ in (0, 1)])
    length = float(np.hypot(*(segs[:, 1] - segs[:, 0]).T).sum())
    h = min([method.spacing] + [z.spacing for z in method.zones])
    cut = min(cells.nodes, CUT_ROWS * length / h)  # graded zones: an upper bound
    full = max(cells.nodes - cut, 0.0) * method.radial * method.angular
    pieces = cut * method.radial * method.cut_angular * CUT_PIECES
    boundary = cut * 2 * method.boundary_order
    parts = {f"spacing = {method.spacing!r}: test discs, radial = {method.radial}, angular = "
             f"{method.angular}": full,
             **_tip_parts(scene, method),
             f"discs cut by the boundary or a crack, cut_angular = {method.cut_angular}": pieces,
             f"boundary pieces, boundary_order = {method.boundary_order}": boundary,
             **{f"field quadrature: {k}": v for k, v in cells.point_parts.items()}}
    points = sum(parts.values())
    direct = method.solver == "direct" or (method.solver == "auto"
                                           and 2 * cells.nodes <= AUTO_KRYLOV_THRESHOLD)
    per_node = NODE_BYTES_DIRECT * max(1.0, cells.nodes / 2e4) ** 0.25 if direct else NODE_BYTES_KRYLOV
    return replace(cells, points=points, point_parts=parts,
                   shape_bytes=SLOT_BYTES * points * cells.width,
                   solve_bytes=per_node * (method.d_max / 2.5) ** 2 * cells.nodes)


def _tip_parts(scene: Scene, method: MLPG) -> dict:
    """The points of the discs near the crack tips (module comment), {name: count}."""
    n = len(scene.tips)
    if not n:
        return {}
    if method.enrichment != "none":
        count = (n * TIP_DISC_POINTS["refined"] * ((method.test_radius + 1.0) / 2.5) ** 2
                 * method.tip_radial * method.tip_angular)
        return {f"discs near {n} tip(s), tip_radial x tip_angular = {method.tip_radial} x "
                f"{method.tip_angular}": count}
    if method.quadrature != "gauss":
        return {}
    count = (n * TIP_DISC_POINTS["split"] * ((method.test_radius + method.d_max - 1.0) / 3.0) ** 2
             * (method.d_max / 2.5) ** 2 * method.split_radial * method.split_angular)
    return {f"discs near {n} tip(s) split at shadow rays and support circles, split_radial x "
            f"split_angular = {method.split_radial} x {method.split_angular}": count}
