"""Incremental update of the EFG system after a crack-growth step.

The stiffness is a sum over quadrature points (seed 003 Eq. 22a),
``K = sum_q w_q B_q^T D B_q``, and a point's row ``B_q`` depends only on the node
cloud, the point, and the crack geometry its neighbours' supports see. When a crack
gains a segment (seed 002 Sect. 3.1: only the nodes a new segment influences change)

    K_new = K_old - sum_{q in R_old} w_q B_q^T D B_q + sum_{q in R_new} w_q B_q^T D B_q,

where ``R`` holds every point whose row can change:

* points that are new or gone: the domain points are regenerated and matched bitwise
  (x, y, w) to the old ones (tip cells with fan rules, refined tip zones and cut cells
  move with the tip);
* points with a neighbour node in the affected set ``A``: the nodes whose support comes
  within ``rho`` of a changed segment (a new segment, or an old or new tip; ``rho =
  kappa h`` for transparency, whose opacity depends on the arc from the tip, else 0:
  a crack rule changes a pair (x, x_I) only when the new segment cuts it or the tip it
  is diffracted around moved, both inside the support; an end that stopped on the
  boundary or on another crack's face, a mouth or a junction, is prolonged by
  ``MOUTH_REACH d_mI``, so the reach is ``d_mI (1 + MOUTH_REACH) + rho``), and every
  enriched node (PU
  nodes, nodes with a non-zero ramped extrinsic field) of the old or new enrichment;
* points inside an enrichment disc of an old or new tip (intrinsic ramp, ramped
  extrinsic fields): r < r2 of the tip, and with a kinked crack within L + r2 of the
  kink (the kink map keeps the distance to the kink, so r >= |r_kink - L|);
* points with an enrichment entry in the old shape.

All enrichment lives in ``R``, so the kept part of K is its nodal block; the enrichment
unknowns may appear, vanish or be renumbered. The load vector is rebuilt from the
composed shape rows (tractions: a few boundary points; a body force: a sparse product).

The update is exact (to rounding) only with an unchanged node cloud: automatic tip
zones (``zones=None``) and rosettes follow the tip and move nodes, and global
(unramped) extrinsic Williams fields change everywhere when the tip moves. In those
cases, and for the modified-MLS interpolation, :func:`update` rebuilds everything
and says why (``Assembled.reason``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_array

from ..approx.crack_rules import MOUTH_REACH
from ..approx.shape import Extra, Shape
from ..methods.boundary import loads
from ..methods.discretize import Discretization, approximation, discretize, shadow_rays
from ..methods.efg import EFG
from ..nodes import NodeCloud, generate_nodes
from ..problem.scene import Scene
from ..quadrature.cells import cell_rule, triangle_points
from ..quadrature.rules import Points
from ..search import BoxGrid, Neighbours, find_neighbours
from ..system.assemble import stiffness

__all__ = ["Assembled", "assemble", "update"]

_OPS = ("ux", "uy", "gxx", "gxy", "gyx", "gyy")


@dataclass(frozen=True, eq=False)
class Assembled:
    """A discretisation with its stiffness and load vector (before the constraints).

    Attributes
    ----------
    disc : Discretization
    K : csr_array (n_dofs, n_dofs)
    f : ndarray (n_dofs,)
    recomputed : int
        Quadrature points whose shape rows were evaluated (all of them in a full build).
    reason : str or None
        Why the last call rebuilt everything; None after an incremental update.
    seconds : float
        Wall time of the build or update.
    """

    disc: Discretization
    K: csr_array
    f: np.ndarray
    recomputed: int
    reason: str | None
    seconds: float = 0.0


def assemble(scene: Scene, method: EFG, reason: str = "first step") -> Assembled:
    """Full build: :func:`~efgkit.methods.discretize.discretize`, K and f of ``scene``."""
    t0 = time.perf_counter()
    disc = discretize(scene, method)
    K = stiffness(disc.shape, disc.points.w, scene.material.D)
    f = loads(disc)
    return Assembled(disc, K, f, len(disc.points.w), reason, time.perf_counter() - t0)


def _why_not(prev: Assembled, scene: Scene, m: EFG) -> str | None:
    pm = prev.disc.method
    if prev.disc.scene.domain is not scene.domain:
        return "the domain changed"
    if prev.disc.scene.material is not scene.material:
        return "the material changed"
    if m.zones != pm.zones:
        return ("the node zones changed (automatic tip zones follow the tip: give fixed zones, "
                "or zones=(), for the incremental path)")
    if m.rosette is not None:
        return "a tip rosette moves with the tip (nodes change)"
    if m.bc == "modified_mls":
        return "bc='modified_mls' (interpolating supports) is rebuilt in full"
    if m.enrichment == "extrinsic_mls" and m.enrich_radius is None:
        return ("unramped (global) extrinsic Williams fields change everywhere when a tip moves: "
                "give enrich_radius")
    changed = [k for k, v in vars(m).items() if k != "coordinates" and v != getattr(pm, k)]
    if changed:
        why = "; ".join(f"{k}: {getattr(pm, k)!r} -> {getattr(m, k)!r}" for k in changed)
        if "enrichment" in changed:  # EFG.for_scene: PU for several tips, extrinsic for one
            why += (" (the automatic enrichment follows the number of tips: give enrichment "
                    "explicitly for the incremental path)")
        return f"the method changed ({why})"
    return None


def _segment_distance(x: np.ndarray, seg: np.ndarray) -> np.ndarray:
    """Distance of points ``x (n, 2)`` to the nearest of ``seg (s, 2, 2)``, shape (n,)."""
    best = np.full(len(x), np.inf)
    for a, b in seg:  # a handful of segments
        ab = b - a
        den = float(ab @ ab)
        t = np.zeros(len(x)) if den == 0 else np.clip((x - a) @ ab / den, 0.0, 1.0)
        best = np.minimum(best, np.hypot(*(x - a - t[:, None] * ab).T))
    return best


def _changed_segments(old: Scene, new: Scene) -> np.ndarray:
    """Segments in one scene and not the other, and every old and new tip as a segment of
    length 0, shape (s, 2, 2)."""
    def segs(sc):
        return np.concatenate([c.segments for c in sc.cracks]).reshape(-1, 2, 2) if sc.cracks \
            else np.zeros((0, 2, 2))

    so, sn = segs(old), segs(new)
    key = [s.reshape(len(s), -1) for s in (so, sn)]
    out = [s[~(k[:, None, :] == kk[None, :, :]).all(axis=2).any(axis=1)]
           for s, k, kk in ((so, key[0], key[1]), (sn, key[1], key[0]))]
    tips = [t.x for sc in (old, new) for t in sc.tips]
    out += [np.array([[x, x]]) for x in tips]
    return np.concatenate(out).reshape(-1, 2, 2)


def _enrichment_discs(enrichments) -> list[tuple[np.ndarray, float]]:
    """Discs (centre, radius) holding every point whose ramped enrichment (intrinsic, or
    extrinsic with enrich_radius) can be non-zero: r < r2 of a tip, and with a kink map
    (:func:`~efgkit.approx.tip_functions.tip_coordinates`, which keeps the distance rb to
    the kink, so r >= |rb - L|) the points within L + r2 of the kink."""
    out = []
    for enr in enrichments:
        if enr is None or enr.kind == "pu" or not np.isfinite(enr.r2):
            continue
        for g in enr.tips:
            out.append((np.asarray(g.tip.x, float), enr.r2))
            if g.kink is not None:
                out.append((g.kink, float(np.hypot(*(g.tip.x - g.kink))) + enr.r2))
    return out


def _in_box(x: np.ndarray, lo, hi) -> np.ndarray:
    """Points ``x (n, 2)`` strictly inside the box [lo, hi], (n,) bool."""
    x0, x1 = x[:, 0], x[:, 1]
    return (x0 > lo[0]) & (x0 < hi[0]) & (x1 > lo[1]) & (x1 < hi[1])


def _in_discs(x: np.ndarray, discs) -> np.ndarray:
    """Points ``x (n, 2)`` inside any of ``discs``, (n,) bool."""
    out = np.zeros(len(x), bool)
    for c, r in discs:  # a few discs
        box = np.flatnonzero(_in_box(x, c - r, c + r))
        out[box[np.hypot(*(x[box] - c).T) < r]] = True
    return out


def _points(scene: Scene, m: EFG, nodes: NodeCloud, boxes: BoxGrid):
    """The domain points of :func:`~efgkit.methods.discretize.discretize`, in its order (by
    search box, stably), and their box indices (n_points,)."""
    if m.quadrature == "cells":
        pts = cell_rule(scene.domain, m.cell_size or m.spacing, m.order,
                        zones=m.zones + m.tip_cell_zones(scene), refined_order=m.refined_order,
                        cracks=scene.cracks, tip_rays=shadow_rays(scene, nodes),
                        tip_order=m.tip_order)
    else:
        pts = triangle_points(scene.domain, nodes.x, m.order)
    pts = pts.sorted_by(boxes.box_of)  # as discretize sorts them
    return pts, boxes.box_of(pts.x)


def _match(a: Points, box_a: np.ndarray, b: Points, box_b: np.ndarray):
    """Indices (ia, ib) of the points of ``a`` and ``b`` with bitwise equal (x, y, w).

    Both are sorted by search box, and within a box in generation order: the boxes that
    hold as many points in both are compared position by position (O(n), no sort); points
    of other boxes, or that differ, stay unmatched (and are recomputed)."""
    nbox = int(max(box_a.max(initial=-1), box_b.max(initial=-1))) + 2
    ca = np.bincount(box_a + 1, minlength=nbox)
    cb = np.bincount(box_b + 1, minlength=nbox)
    start_a = np.concatenate([[0], np.cumsum(ca)[:-1]])
    start_b = np.concatenate([[0], np.cumsum(cb)[:-1]])
    ib = np.flatnonzero((ca == cb)[box_b + 1])
    bx = box_b[ib] + 1
    ia = start_a[bx] + (ib - start_b[bx])
    xa, xb = a.x[ia], b.x[ib]
    same = (xa[:, 0] == xb[:, 0]) & (xa[:, 1] == xb[:, 1]) & (a.w[ia] == b.w[ib])
    return ia[same], ib[same]


def _near(x: np.ndarray, seg: np.ndarray, reach) -> np.ndarray:
    """Points ``x (n, 2)`` closer than ``reach`` (scalar or (n,)) to a segment, (n,) bool:
    distances only inside the segments' box grown by the largest reach."""
    out = np.zeros(len(x), bool)
    if len(seg) == 0:
        return out
    r = np.broadcast_to(reach, (len(x),))
    top = float(r.max(initial=0.0))
    lo, hi = seg.reshape(-1, 2).min(axis=0) - top, seg.reshape(-1, 2).max(axis=0) + top
    c = np.flatnonzero(_in_box(x, lo, hi))
    out[c] = _segment_distance(x[c], seg) < r[c]
    return out


def _touched(x: np.ndarray, nodes: NodeCloud, affected: np.ndarray, discs) -> np.ndarray:
    """Points ``x`` in an enrichment disc or with an affected neighbour node, (n,) bool."""
    out = _in_discs(x, discs)
    a = np.flatnonzero(affected)
    if len(a) == 0:
        return out
    lo = (nodes.x[a] - nodes.radius[a, None]).min(axis=0)
    hi = (nodes.x[a] + nodes.radius[a, None]).max(axis=0)
    cand = np.flatnonzero(_in_box(x, lo, hi) & ~out)
    sub = NodeCloud(nodes.x[a], nodes.radius[a], nodes.boundary[a])
    nb = find_neighbours(x[cand], sub, BoxGrid.build(sub))
    out[cand[nb.mask.any(axis=1)]] = True
    return out


def _rows(sh: Shape, rows: np.ndarray) -> Shape:
    """Shape ``sh`` at the points ``rows``."""
    extra = None
    if sh.extra is not None:
        extra = Extra(*(None if getattr(sh.extra, k) is None else
                        csr_array(getattr(sh.extra, k)[rows, :]) for k in _OPS))
    return Shape(sh.neighbours.subset(rows), sh.values[rows], sh.ddx[rows], sh.ddy[rows],
                 sh.n_functions, extra)


def _extra_rows(sh: Shape) -> np.ndarray:
    """Points with any stored enrichment entry, (n_points,) bool."""
    out = np.zeros(len(sh.values), bool)
    if sh.extra is not None:
        for k in _OPS:
            op = getattr(sh.extra, k)
            if op is not None:
                out |= np.diff(op.indptr) > 0
    return out


def _scatter(op: csr_array, rows: np.ndarray, n: int) -> csr_array:
    """csr (len(rows), m) -> (n, m) with its rows at ``rows`` (sorted), zero elsewhere."""
    counts = np.zeros(n, np.int64)
    counts[rows] = np.diff(op.indptr)
    indptr = np.concatenate([[0], np.cumsum(counts)])
    return csr_array((op.data, op.indices, indptr), shape=(n, op.shape[1]))


def _compose(n: int, keep_new, keep_old, old: Shape, rec: np.ndarray, new: Shape,
             n_functions: int) -> Shape:
    """The shape at all n new points: rows ``keep_new`` from ``old[keep_old]``, rows
    ``rec`` from ``new`` (whose enrichment block is the only one)."""
    k_old, k_new = old.neighbours.idx.shape[1], new.neighbours.idx.shape[1]
    src = np.zeros(n, np.int64)  # one gather of the old rows (rec rows overwritten below)
    src[keep_new] = keep_old
    arrays = [np.take(a, src, axis=0) for a in (old.neighbours.idx, old.neighbours.mask,
                                                 old.values, old.ddx, old.ddy)]
    arrays[1][rec] = False
    if k_new > k_old:
        arrays = [np.pad(a, ((0, 0), (0, k_new - k_old))) for a in arrays]
    for a, b in zip(arrays, (new.neighbours.idx, new.neighbours.mask, new.values, new.ddx,
                             new.ddy), strict=True):
        a[rec, :k_new] = b
        if k_new < a.shape[1]:
            a[rec, k_new:] = 0
    extra = None
    if new.extra is not None:
        extra = Extra(*(_scatter(getattr(new.extra, key), rec, n) for key in _OPS))
    return Shape(Neighbours(arrays[0], arrays[1]), arrays[2], arrays[3], arrays[4], n_functions,
                 extra)


def _resize(K: csr_array, n: int) -> csr_array:
    """The leading (n, n) block of a csr K with sorted indices, or K padded with zeros.

    Truncation keeps the leading rows (a view of ``indptr``) and drops the few entries in
    columns >= n (the enrichment block) with one mask: no general submatrix copy."""
    K = csr_array(K)
    if not K.has_sorted_indices:
        K.sort_indices()
    m = min(n, K.shape[0])
    indptr, end = K.indptr[: m + 1], int(K.indptr[m])
    indices, data = K.indices[:end], K.data[:end]
    drop = np.flatnonzero(indices >= n)
    if len(drop):
        keep = np.ones(end, bool)
        keep[drop] = False
        indices, data = indices[keep], data[keep]
        removed = np.bincount(np.searchsorted(indptr, drop, side="right") - 1, minlength=m)
        indptr = indptr - np.concatenate([[0], np.cumsum(removed)])
    if m < n:
        indptr = np.concatenate([indptr, np.full(n - m, indptr[-1])])
    return csr_array((data, indices, indptr), shape=(n, n))


def update(previous: Assembled | None, scene: Scene, method: EFG) -> Assembled:
    """K and f of ``scene`` from those of the previous growth step.

    Parameters
    ----------
    previous : Assembled or None
        The last step's system (None: full build).
    scene : Scene
        The scene after the crack increment (same domain, material, loads).
    method : EFG

    Returns
    -------
    Assembled
        With ``reason`` None when the update was incremental; otherwise a full build and
        the reason (node cloud changed, unramped extrinsic fields, ...).
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    if not isinstance(method, EFG):
        raise TypeError(f"method must be an EFG description, got {type(method).__name__}")
    m = method.for_scene(scene)
    if previous is None:
        return assemble(scene, m)
    if not isinstance(previous, Assembled):
        raise TypeError(f"previous must be an Assembled (or None), got {type(previous).__name__}")
    reason = _why_not(previous, scene, m)
    if reason is not None:
        return assemble(scene, m, reason)
    t0 = time.perf_counter()
    old = previous.disc
    nodes = generate_nodes(scene.domain, m, scene.cracks)
    if nodes.n != old.nodes.n or not np.array_equal(nodes.x, old.nodes.x) or \
            not np.array_equal(nodes.radius, old.nodes.radius):
        return assemble(scene, m, "the node cloud changed (a node on the new segment is split)")
    approx = approximation(scene, m, nodes)
    pts, box = _points(scene, m, nodes, approx.boxes)
    io, inew = _match(old.points, approx.boxes.box_of(old.points.x), pts, box)
    seg = _changed_segments(old.scene, scene)
    rho = m.kappa * m.spacing if m.crack_rule == "transparency" else 0.0  # s_c < kappa h
    discs = _enrichment_discs((old.approx.enrichment, approx.enrichment))
    # a crack end that is not a tip (a mouth, a junction) reaches MOUTH_REACH d_mI further
    affected = _near(nodes.x, seg, nodes.radius * (1 + MOUTH_REACH) + rho) | \
        _in_discs(nodes.x, discs)
    for enr in (old.approx.enrichment, approx.enrichment):
        if enr is not None and enr.pu_nodes is not None:
            affected[enr.pu_nodes] = True
        if enr is not None and enr.node_q is not None:
            affected |= (enr.node_q != 0).any(axis=(0, 2, 3))
    flag_new = np.ones(len(pts.w), bool)
    flag_old = np.ones(len(old.points.w), bool)
    both = _touched(pts.x[inew], nodes, affected, discs) | _extra_rows(old.shape)[io]
    flag_new[inew], flag_old[io] = both, both
    rec, gone = np.flatnonzero(flag_new), np.flatnonzero(flag_old)
    new_rows = approx.shape(pts.x[rec])
    D = scene.material.D
    n_dofs = approx.n_dofs
    delta = csr_array((n_dofs, n_dofs))  # K(R_new) - K(R_old), small: one pass over K
    if len(gone):
        delta = delta - _resize(_resize(stiffness(_rows(old.shape, gone), old.points.w[gone], D),
                                        2 * nodes.n), n_dofs)
    if len(rec):
        delta = delta + stiffness(new_rows, pts.w[rec], D)
    K = _resize(_resize(previous.K, 2 * nodes.n), n_dofs) + delta
    keep_new, keep_old = inew[~both], io[~both]
    shape = _compose(len(pts.w), keep_new, keep_old, old.shape, rec, new_rows, nodes.n)
    disc = Discretization(scene, m, nodes, pts, shape, approx,
                          {"incremental": time.perf_counter() - t0})
    f = loads(disc)  # boundary rows are few; a body force uses the composed rows
    return Assembled(disc, csr_array(K), f, len(rec), None, time.perf_counter() - t0)
