"""Node clouds: coordinates, characteristic spacings and support radii.

Generators place boundary nodes along every edge at the local spacing, a
regular grid inside, finer grids in refinement zones, and optionally a seeded
random perturbation of the interior nodes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.spatial import cKDTree

from .memory import ALWAYS_ALLOWED, FALLBACK_MEMORY, available_memory, check_memory  # noqa: F401 (re-exported)
from .methods.efg import EFG
from .problem.geometry import Domain

__all__ = ["NodeCloud", "generate_nodes", "support_radii", "NodeEstimate", "estimate_nodes",
           "area_in_disc", "available_memory", "check_memory"]  # the last two from efgkit.memory

# Size guard. Node generation holds about 300 bytes per point of its grids at its peak (the
# bounding-box grid, the local-spacing and boundary-distance arrays, the k-d tree of the
# support radii). Calibration: tracemalloc peak of generate_nodes on unit plates, 289 B per
# node at 19,881 and at 320,356 nodes (301 B perturbed, 295 B with a zone), plus up to
# 0.15 GB of chunked boundary distances on curved boundaries, which the floor covers.
GRID_POINT_BYTES = 300.0


@dataclass(frozen=True, eq=False)
class NodeCloud:
    """Nodes and their circular supports.

    Attributes
    ----------
    x : ndarray, shape (n_nodes, 2)
        Coordinates.
    radius : ndarray, shape (n_nodes,)
        Support radii d_mI = d_max c_I (seed 003 Eq. 2).
    boundary : ndarray, shape (n_nodes,), bool
        Nodes generated on the boundary.
    face : ndarray, shape (n_nodes,), int8, or None
        For nodes split on a crack (seed 003 Sect. 2.2: one node per face):
        +1 on the left face of the crack segment they lie on, -1 on the right
        face, 0 for all other nodes. None when the scene has no cracks.
    face_segment : ndarray, shape (n_nodes,), int, or None
        The crack segment (global index over the scene's cracks, in order) a
        split node lies on, -1 for all other nodes.
    """

    x: np.ndarray
    radius: np.ndarray
    boundary: np.ndarray
    face: np.ndarray | None = None
    face_segment: np.ndarray | None = None

    @property
    def n(self) -> int:
        return len(self.x)

    def face_positions(self, lines, fraction: float) -> np.ndarray:
        """Coordinates with every split node moved off the crack onto its face by
        ``fraction`` of its support radius, shape (n_nodes, 2): where the two copies of a
        split node differ (e.g. to evaluate each one's own side). ``lines`` is the
        scene's :class:`~efgkit.approx.crack_rules.CrackLines` (None: no cracks)."""
        if lines is None or self.face is None or not np.any(self.face):
            return self.x
        k = np.flatnonzero(self.face != 0)
        e = lines.b[self.face_segment[k]] - lines.a[self.face_segment[k]]
        left = np.column_stack([-e[:, 1], e[:, 0]]) / np.hypot(*e.T)[:, None]
        x = self.x.copy()
        x[k] += (fraction * self.radius[k] * self.face[k])[:, None] * left
        return x


def support_radii(x: np.ndarray, d_max: float, regular: bool) -> np.ndarray:
    """Support radii d_mI = d_max c_I, shape (n,).

    c_I is the distance to the 2nd nearest neighbour for regularly spaced
    nodes and to the 3rd for irregular ones (seed 003, text after Eq. 3).
    """
    k = 2 if regular else 3
    if len(x) <= k:
        raise ValueError(f"a cloud needs more than {k} nodes to define supports, got {len(x)}")
    d, _ = cKDTree(x).query(x, k=k + 1)  # column 0 is the node itself
    c = d[:, k]
    if np.any(c <= 0):
        i = int(np.argmin(c))
        raise ValueError(f"duplicate nodes near {x[i].tolist()}: remove coincident nodes")
    return d_max * c


@dataclass(frozen=True)
class NodeEstimate:
    """Size of :func:`generate_nodes`, estimated before anything is allocated: ``nodes`` in
    the body (area / spacing^2 and perimeter / spacing of the background and of every zone,
    nested zones counted twice; rosettes, split crack nodes), ``grid`` points allocated on
    the way (bounding boxes of the domain and zones), and ``parts``, the nodes by source
    (``{"spacing = 0.1": n, "zones[0] (...)": n, ...}``)."""

    nodes: float
    grid: float
    parts: dict


def estimate_nodes(domain: Domain, method: EFG, cracks=()) -> NodeEstimate:
    """Estimate the size of :func:`generate_nodes` ``(domain, method, cracks)`` from areas.

    Examples
    --------
    >>> est = estimate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.01))
    >>> round(est.nodes), round(est.grid)   # 101 x 101 = 10,201 nodes are generated
    (10400, 10201)
    """
    method = _without_auto_zones(method)
    perimeter = sum(e.length for e in domain.edges())
    if method.coordinates is not None:
        n = float(len(method.coordinates))
        parts, grid = {f"coordinates ({len(method.coordinates)} nodes)": n}, n
    else:
        h = method.spacing
        x0, y0, x1, y1 = domain.bbox
        parts = {f"spacing = {h!r}": domain.area / h**2 + perimeter / h}
        grid = (math.floor((x1 - x0) / h) + 1.0) * (math.floor((y1 - y0) / h) + 1.0)
        for i, z in enumerate(method.zones):
            parts[f"zones[{i}] (radius {z.radius!r}, spacing {z.spacing!r})"] = (
                area_in_disc(domain, z.centre, z.radius) / z.spacing**2
                + min(2 * math.pi * z.radius, perimeter) / z.spacing)
            grid += (2 * z.radius / z.spacing + 2.0) ** 2
    if cracks:
        h_min = min([method.spacing] + [z.spacing for z in method.zones])
        n_split = sum(c.length for c in cracks) / h_min + 1.0
        tips = sum(len(c.tip_list) for c in cracks)
        if method.rosette is not None:
            r = method.rosette
            parts["rosette"] = tips * (r.rings * (r.per_ring - 1) + 1.0)
            n_split += tips * r.rings
        parts["cracks (split nodes)"] = n_split
    return NodeEstimate(sum(parts.values()), grid, parts)


def area_in_disc(domain: Domain, centre, radius: float) -> float:
    """Area of the material within ``radius`` of ``centre``, from 64 x 64 samples (~2 %)."""
    u = (np.arange(64) + 0.5) / 32 - 1
    d = np.column_stack([a.ravel() for a in np.meshgrid(u, u)])
    d = d[np.hypot(*d.T) <= 1]
    return math.pi * radius**2 * float(domain.contains(np.asarray(centre) + radius * d).mean())


def _without_auto_zones(method: EFG) -> EFG:
    """``method`` with ``zones=None`` (tip zones chosen for a scene, :meth:`EFG.for_scene`,
    as :func:`~efgkit.methods.discretize.discretize` does first) read as no zones."""
    return replace(method, zones=()) if method.zones is None else method


def _grid(x0, y0, x1, y1, h, origin=(0.0, 0.0)):
    """Grid points of spacing h aligned to ``origin`` covering the box, shape (m, 2)."""
    i0, i1 = math.floor((x0 - origin[0]) / h - 1e-9), math.ceil((x1 - origin[0]) / h + 1e-9)
    j0, j1 = math.floor((y0 - origin[1]) / h - 1e-9), math.ceil((y1 - origin[1]) / h + 1e-9)
    gx = origin[0] + h * np.arange(i0, i1 + 1)
    gy = origin[1] + h * np.arange(j0, j1 + 1)
    X, Y = np.meshgrid(gx, gy, indexing="xy")
    return np.column_stack([X.ravel(), Y.ravel()])


def _edge_nodes(domain: Domain, h: float) -> np.ndarray:
    """Nodes along every edge at spacing <= h (vertices included, each once), shape (m, 2)."""
    pts = []
    for e in domain.edges():
        n = max(1, math.ceil(e.length / h - 1e-9))
        x, _ = e.at(np.arange(n) / n)  # the end vertex is the next edge's start
        pts.append(x)
    return np.concatenate(pts)


def _local_spacing(x: np.ndarray, method: EFG) -> np.ndarray:
    """Target spacing at points ``x (n, 2)``: the finest zone containing them, else h."""
    h = np.full(len(x), float(method.spacing))
    for z in method.zones:
        inside = np.hypot(*(x - z.centre).T) <= z.radius
        h[inside] = np.minimum(h[inside], z.spacing)
    return h


def generate_nodes(domain: Domain, method: EFG, cracks=()) -> NodeCloud:
    """The node cloud of ``method`` on ``domain``.

    Boundary nodes are placed on every edge at the local spacing; grid nodes
    closer than a quarter spacing to the boundary are dropped so that no two
    nodes nearly coincide. Perturbation (``method.perturb``) moves interior
    nodes by a uniform random fraction of the local spacing in each direction
    and never moves a node out of the material.

    With ``cracks``: a star-shaped rosette of nodes is placed around every tip
    when ``method.rosette`` is set (background nodes inside it switched off,
    seed 003 Sect. 2.2 and Fig. 29), and every node lying on a crack
    (within 1e-6 of the local spacing, tips excepted) is split into two nodes,
    one per face (:attr:`NodeCloud.face`). Support radii are those of the
    unsplit cloud: both copies of a split node share one. ``zones=None`` (chosen per
    scene, :meth:`EFG.for_scene`) counts as no zones here.

    Raises
    ------
    ValueError
        When the estimated peak memory (:func:`estimate_nodes`) exceeds what the machine
        has available (:func:`check_memory`).

    Examples
    --------
    >>> from efgkit import Crack, Domain, EFG
    >>> cloud = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25))
    >>> cloud.n, float(cloud.radius.min())
    (25, 0.5)
    >>> cracked = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25),
    ...                          [Crack([[0.0, 0.5], [0.5, 0.5]], (False, True))])
    >>> cracked.n, sorted(cracked.face.tolist()).count(1)   # 2 nodes on the crack split
    (27, 2)
    """
    method = _without_auto_zones(method)
    est = estimate_nodes(domain, method, cracks)
    check_memory(GRID_POINT_BYTES * max(est.grid, est.nodes),
                 f"{max(est.parts, key=est.parts.get)} would give about {est.nodes:.2g} nodes on grids of "
                 f"{est.grid:.2g} points", "Remedy: a spacing about {factor:.2g} times coarser "
                 "would fit; refine only where needed (zones near tips, holes and corners).")
    x, is_bnd = _positions(domain, method)
    regular = method.regular
    if cracks and method.rosette is not None:
        x, is_bnd = _with_rosettes(x, is_bnd, domain, method, cracks)
        regular = False
    radius = support_radii(x, method.d_max, regular)
    if not cracks:
        return NodeCloud(x, radius, is_bnd)
    return _split_on_cracks(NodeCloud(x, radius, is_bnd), cracks, _local_spacing(x, method),
                            keep_single=method.crack_rule == "see_through")


def _positions(domain: Domain, method: EFG) -> tuple[np.ndarray, np.ndarray]:
    """Node coordinates (n, 2) and the boundary flags (n,) of the uncracked cloud."""
    if method.coordinates is not None:
        x = np.asarray(method.coordinates, dtype=float)
        tol = 1e-9 * domain.size
        outside = ~domain.contains(x, tol=tol)
        if np.any(outside):
            raise ValueError(
                f"{int(outside.sum())} given node(s) lie outside the domain, e.g. "
                f"{x[outside][0].tolist()}; remove them or enlarge the domain"
            )
        return x, domain.distance_to_boundary(x) <= tol

    h = method.spacing
    # Boundary nodes: coarse ones outside zones, fine ones inside each zone.
    bnd = _edge_nodes(domain, h)
    keep = _local_spacing(bnd, method) >= h
    parts = [bnd[keep]]
    for z in method.zones:
        fine = _edge_nodes(domain, z.spacing)
        hz = _local_spacing(fine, method)
        parts.append(fine[(np.hypot(*(fine - z.centre).T) <= z.radius) & (hz >= z.spacing)])
    bnd = np.concatenate(parts)
    # Interior grids, each restricted to where it is the finest spacing.
    x0, y0, x1, y1 = domain.bbox
    grids = []
    g = _grid(x0, y0, x1, y1, h, origin=(x0, y0))
    grids.append(g[_local_spacing(g, method) >= h])
    for z in method.zones:
        zc = np.asarray(z.centre)
        g = _grid(*(zc - z.radius), *(zc + z.radius), z.spacing, origin=tuple(zc))
        hz = _local_spacing(g, method)
        grids.append(g[(np.hypot(*(g - zc).T) <= z.radius) & (hz >= z.spacing)])
    interior = np.concatenate(grids)
    hloc = _local_spacing(interior, method)
    inside = domain.contains(interior)
    interior, hloc = interior[inside], hloc[inside]
    far = domain.distance_to_boundary(interior) >= 0.25 * hloc
    interior, hloc = interior[far], hloc[far]
    if method.perturb > 0:
        rng = np.random.default_rng(method.seed)
        trial = interior + method.perturb * hloc[:, None] * rng.uniform(-1, 1, interior.shape)
        ok = domain.contains(trial) & (domain.distance_to_boundary(trial) >= 0.25 * hloc)
        interior = np.where(ok[:, None], trial, interior)
    x = np.concatenate([bnd, interior])
    is_bnd = np.zeros(len(x), bool)
    is_bnd[: len(bnd)] = True
    # Drop near-duplicates (zone borders, shared vertices): keep the first.
    pairs = cKDTree(x).query_pairs(1e-6 * min([h] + [z.spacing for z in method.zones]),
                                   output_type="ndarray")
    if len(pairs):
        drop = np.zeros(len(x), bool)
        drop[pairs.max(axis=1)] = True
        x, is_bnd = x[~drop], is_bnd[~drop]
    return x, is_bnd


def _with_rosettes(x, is_bnd, domain: Domain, method: EFG, cracks):
    """Add the rosette of ``method.rosette`` around every tip (seed 003 Fig. 29).

    A rosette has ``rings`` rings of radii ``radius k / rings`` with
    ``per_ring - 1`` nodes each at angles ``-pi + 2 pi j / (per_ring - 1)``
    from the tip direction (the node at the crack faces, theta = +-pi, is
    split later, so a ring counts ``per_ring`` nodes as in the seed), plus a
    node at the tip. Background nodes closer to the tip than the outer ring
    plus half a ring gap are switched off; rosette nodes outside the body
    are dropped.
    """
    ros = method.rosette
    keep = np.ones(len(x), bool)
    added = []
    off = ros.radius * (1 + 0.5 / ros.rings)  # outer ring plus half a ring gap
    for c in cracks:
        for tip in c.tip_list:
            keep &= np.hypot(*(x - tip.x).T) > off
            r = ros.radius * np.arange(1, ros.rings + 1) / ros.rings
            th = tip.angle - np.pi + 2 * np.pi * np.arange(ros.per_ring - 1) / (ros.per_ring - 1)
            R, T = np.meshgrid(r, th, indexing="ij")
            ring = tip.x + np.column_stack([(R * np.cos(T)).ravel(), (R * np.sin(T)).ravel()])
            added.append(np.vstack([tip.x, ring]))
    new = np.concatenate(added)
    new = new[domain.contains(new) & (domain.distance_to_boundary(new) > 1e-9 * domain.size)]
    return np.concatenate([x[keep], new]), np.concatenate([is_bnd[keep], np.zeros(len(new), bool)])


def _split_on_cracks(cloud: NodeCloud, cracks, spacing: np.ndarray, keep_single: bool = False
                     ) -> NodeCloud:
    """Split nodes lying on a crack (not at a tip) into a left-face and a right-face copy.

    ``keep_single`` (the see-through rule): a node whose support holds a tip of
    its crack sees both faces anyway, so its two copies would be the same
    function; it stays one node.
    """
    x = cloud.x
    seg_of = np.full(len(x), -1)
    crack_of = np.full(len(x), -1)
    s0 = 0
    for i, c in enumerate(cracks):
        for k, (a, b) in enumerate(c.segments):
            ab = b - a
            t = np.clip((x - a) @ ab / (ab @ ab), 0.0, 1.0)
            on = np.hypot(*(x - a - t[:, None] * ab).T) <= 1e-6 * spacing
            new = on & (seg_of < 0)
            seg_of, crack_of = np.where(new, s0 + k, seg_of), np.where(new, i, crack_of)
        s0 += len(c.segments)
    at_tip = np.zeros(len(x), bool)
    for i, c in enumerate(cracks):
        for tip in c.tip_list:
            d = np.hypot(*(x - tip.x).T)
            at_tip |= (d <= 1e-6 * spacing) | (keep_single & (crack_of == i) & (d < cloud.radius))
    seg_of[at_tip] = -1
    split = np.flatnonzero(seg_of >= 0)
    # put the split nodes exactly on their segment (they were within 1e-6 h of it): a node a
    # hair off the line would see across it by rounding and give slivers in the tip fans
    # (moved along the segment's normal only: a node already on it keeps its coordinates, so a
    # mirror-symmetric cloud stays symmetric to the bit, efgkit.system.images)
    segs = np.concatenate([c.segments for c in cracks])[seg_of[split]]
    ab = segs[:, 1] - segs[:, 0]
    nrm = np.column_stack([-ab[:, 1], ab[:, 0]]) / np.hypot(*ab.T)[:, None]
    x = x.copy()
    x[split] -= np.einsum("nd,nd->n", x[split] - segs[:, 0], nrm)[:, None] * nrm
    order = np.concatenate([np.arange(len(x)), split])
    face = np.zeros(len(order), np.int8)
    face[split] = 1
    face[len(x):] = -1
    return NodeCloud(x[order], cloud.radius[order], cloud.boundary[order], face, seg_of[order])
