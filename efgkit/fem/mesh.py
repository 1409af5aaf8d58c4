"""Triangle meshes of a scene for the finite-element reference model (:mod:`efgkit.fem`).

The mesher is Shewchuk's Triangle through the ``triangle`` package of PyPI
(``pip install triangle``: a ~2 MB binary wheel, no system libraries). It
meshes planar straight-line graphs with constrained internal segments (the
cracks), holes, segment markers (the edge names) and per-triangle area limits
(the grading): all this module needs. gmsh, the alternative, ships wheels of
tens of MB that need system OpenGL libraries on Linux, and its scripting API
is far larger than the problem. Licence note: Triangle is free for research
and non-commercial use; commercial use of this (optional, reference) model
needs a licence from its author.

Pipeline of :func:`mesh_scene` (steps 1-2 in :mod:`efgkit.fem.pslg`):

1. planar straight-line graph: every loop as a polyline (straight edges split
   at spacing ``h``, arcs at spacing ``h`` and at most pi/8 of sweep), crack
   mouths inserted into the boundary, crack polylines as internal segments;
   segment marker ``2 + k`` for edge ``k`` of ``domain.edges()`` and
   ``2 + n_edges + c`` for crack ``c`` (Triangle reserves 0 and 1);
2. a quality mesh (minimum angle ``min_angle``) with area limit of size ``h``,
   then refinement passes with per-triangle area limits until every triangle
   is no larger than the size field at its vertex nearest a tip,
   ``s(x) = min(h, tip_h + (grading - 1) |x - tip|)`` (sizes of neighbouring
   elements then grow by about the factor ``grading``);
3. vertices of arc facets moved onto their circle;
4. cracks opened: every node of a crack facet except the tips (a mouth
   included) is duplicated; the copy goes to the elements on the *right* face
   of the crack (``cross(b - a, x - a) < 0`` for a crack segment ``a -> b``),
   the original stays with the left face, as in :mod:`efgkit.problem.crack`.

The element *size* is the edge of the equilateral triangle of the same area,
``sqrt(4 area / sqrt(3))``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_array
from scipy.sparse.csgraph import connected_components

from .pslg import (
    EQUILATERAL_AREA,
    FIRST_MARK,
    refinement_points,
    scene_pslg,
    tip_fans,
    triangle_areas,
    triangulate,
)

__all__ = ["TriMesh", "mesh_scene", "size_field"]

_MAX_ELEMENTS = 4_000_000


@dataclass(frozen=True, eq=False)
class TriMesh:
    """A linear triangle mesh of a scene with named boundary facets and open cracks.

    Attributes
    ----------
    x : ndarray, shape (n_nodes, 2)
        Node coordinates; the copies of crack nodes come last.
    t : ndarray, shape (n_elements, 3), int
        Counter-clockwise vertex indices.
    facets : ndarray, shape (n_facets, 2), int
        Boundary facets (domain edges and crack faces), ordered so that the
        material is on their left: the outward normal is ``(t_y, -t_x)``.
    facet_owner : ndarray, shape (n_facets,), int
        Index ``k >= 0`` into ``domain.edges()``, or ``-1 - c`` for a face of
        crack ``c``.
    origin : ndarray, shape (n_nodes,), int
        The node each node was copied from (itself for all but crack copies).
    crack_nodes : tuple of (ndarray, ndarray)
        Per crack: ``(left (k,), right (k,))`` node indices of its opened
        nodes ordered from the crack's first vertex to its last.
    tip_nodes : tuple of int
        Node of each tip, in the order of ``Scene.tips``.
    domain : Domain
    cracks : tuple of Crack
    """

    x: np.ndarray
    t: np.ndarray
    facets: np.ndarray
    facet_owner: np.ndarray
    origin: np.ndarray
    crack_nodes: tuple
    tip_nodes: tuple
    domain: object
    cracks: tuple

    @property
    def n_nodes(self) -> int:
        return len(self.x)

    @property
    def n_elements(self) -> int:
        return len(self.t)

    @property
    def area(self) -> np.ndarray:
        """Element areas, shape (n_elements,)."""
        return triangle_areas(self.x, self.t)

    @property
    def size(self) -> np.ndarray:
        """Element sizes ``sqrt(4 area / sqrt(3))``, shape (n_elements,)."""
        return np.sqrt(self.area / EQUILATERAL_AREA)

    def boundary(self, name: str) -> np.ndarray:
        """Indices of the boundary facets of the edges called ``name``, shape (k,).

        KeyError naming the valid edges for an unknown ``name``.
        """
        edges = self.domain.edges()
        self.domain.edges(name)  # KeyError with the valid names
        owners = [k for k, e in enumerate(edges) if e.name == name]
        return np.flatnonzero(np.isin(self.facet_owner, owners))


def size_field(x, h: float, tips=(), tip_h: float | None = None, grading: float = 1.25):
    """Target element size ``s(x) = min(h, min_tips(tip_h + (grading - 1) |x - tip|))``.

    Parameters
    ----------
    x : array_like, shape (n, 2)
    h : float
        Global size.
    tips : sequence of Tip or points (2,)
    tip_h : float, optional
        Size at the tips (default ``h``: uniform).
    grading : float
        Ratio of neighbouring element sizes, > 1.

    Returns
    -------
    ndarray, shape (n,)

    Examples
    --------
    >>> size_field([[0.0, 0.0], [1.0, 0.0], [9.0, 0.0]], 1.0, [(0.0, 0.0)], 0.1, 1.5).tolist()
    [0.1, 0.6, 1.0]
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    s = np.full(len(x), float(h))
    if tip_h is None or tip_h >= h:
        return s
    for tip in tips:
        p = np.asarray(getattr(tip, "x", tip), dtype=float)
        s = np.minimum(s, tip_h + (grading - 1.0) * np.linalg.norm(x - p, axis=1))
    return s


def check_sizes(h, tip_h, grading, min_angle, tip_fan=0):
    for name, v in (("h", h), ("grading", grading), ("min_angle", min_angle)) + (
            (("tip_h", tip_h),) if tip_h is not None else ()):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise TypeError(f"{name} must be a real number, got {v!r}")
        if not math.isfinite(v) or v <= 0:
            raise ValueError(f"{name} must be finite and > 0, got {v!r}")
    if tip_h is not None and tip_h > h:
        raise ValueError(f"tip_h = {tip_h!r} exceeds h = {h!r}: the tip size must be <= the "
                         "global size (or None for a uniform mesh)")
    if not 1.0 < grading <= 4.0:
        raise ValueError(f"grading must lie in (1, 4] (ratio of neighbouring element sizes), "
                         f"got {grading!r}")
    if not 0 < min_angle <= 33:
        raise ValueError(f"min_angle must lie in (0, 33] degrees (Triangle may not terminate "
                         f"above), got {min_angle!r}")
    if isinstance(tip_fan, bool) or not isinstance(tip_fan, (int, np.integer)) or not (
            tip_fan == 0 or 5 <= tip_fan <= 360 / min_angle):
        raise ValueError(f"tip_fan must be 0 (no fan) or an integer n with 5 <= n <= 360 / "
                         f"min_angle = {360 / min_angle:.4g} (the fan's angles 360 / n must not "
                         f"be below min_angle), got {tip_fan!r}")


def edge_keys(a, b, n):
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    return lo * n + hi


def open_cracks(x, t, crack_facets, keep):
    """Duplicate the nodes of crack facets (but not ``keep``) for the right-face elements.

    ``crack_facets (k, 2)`` are node pairs oriented along their crack. Returns the new
    ``x``, ``t`` and ``origin``.
    """
    n = len(x)
    split = np.setdiff1d(np.unique(crack_facets), keep)
    if len(split) == 0:
        return x, t, np.arange(n)
    is_split = np.zeros(n, bool)
    is_split[split] = True
    # incidences (element, local vertex) of split nodes
    ie, il = np.nonzero(is_split[t])
    inc_id = np.full(t.shape, -1)
    inc_id[ie, il] = np.arange(len(ie))
    # mesh edges with their elements: element e, local edge j = (j, j+1)
    e3 = np.repeat(np.arange(len(t)), 3)
    a, b = t[:, [0, 1, 2]].ravel(), t[:, [1, 2, 0]].ravel()
    la, lb = np.tile([0, 1, 2], len(t)), np.tile([1, 2, 0], len(t))
    key = edge_keys(a, b, n)
    ckey = np.unique(edge_keys(crack_facets[:, 0], crack_facets[:, 1], n))
    order = np.argsort(key, kind="stable")
    ks = key[order]
    pair = np.flatnonzero(ks[1:] == ks[:-1])  # interior edges: two consecutive equal keys
    i1, i2 = order[pair], order[pair + 1]
    ok = ~np.isin(key[i1], ckey)
    i1, i2 = i1[ok], i2[ok]
    rows, cols = [], []
    for end1, end2_a, end2_b in ((la, la, lb), (lb, la, lb)):  # each endpoint of the edge
        node = t[e3[i1], end1[i1]]
        loc2 = np.where(t[e3[i2], end2_a[i2]] == node, end2_a[i2], end2_b[i2])
        s = is_split[node]
        rows.append(inc_id[e3[i1][s], end1[i1][s]])
        cols.append(inc_id[e3[i2][s], loc2[s]])
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    graph = coo_array((np.ones(len(rows)), (rows, cols)), shape=(len(ie), len(ie)))
    _, comp = connected_components(graph, directed=False)
    # side of the elements next to each crack facet: left if the third vertex is left of a -> b
    fa, fb = crack_facets[:, 0], crack_facets[:, 1]
    fkey = edge_keys(fa, fb, n)
    pos = np.searchsorted(ks, fkey)
    side = np.zeros(comp.max() + 1)
    for off in (0, 1):
        idx = order[np.minimum(pos + off, len(ks) - 1)]
        e = e3[idx]
        third = t[e, 3 - la[idx] - lb[idx]]
        d = x[fb] - x[fa]
        cr = d[:, 0] * (x[third, 1] - x[fa, 1]) - d[:, 1] * (x[third, 0] - x[fa, 0])
        sgn = np.where(cr > 0, 1.0, -1.0)
        for node in (fa, fb):
            loc = np.argmax(t[e] == node[:, None], axis=1)
            inc = inc_id[e, loc]
            good = inc >= 0
            np.add.at(side, comp[inc[good]], sgn[good])
    if np.any(side == 0) or np.any(np.bincount(comp) == 0):  # pragma: no cover - defensive
        raise RuntimeError("opening a crack failed: a face of its node fans touches no crack facet")
    right = side[comp] < 0
    new_node = np.unique(t[ie[right], il[right]], return_inverse=True)
    copies, inv = new_node
    t = t.copy()
    t[ie[right], il[right]] = n + inv
    origin = np.concatenate([np.arange(n), copies])
    return np.vstack([x, x[copies]]), t, origin


def mesh_scene(scene, h: float, tip_h: float | None = None, grading: float = 1.25,
               min_angle: float = 28.0, tip_fan: int = 0, refine=()) -> TriMesh:
    """Quality triangle mesh of a scene, graded toward its crack tips, cracks opened.

    Parameters
    ----------
    scene : Scene
        Its domain and cracks are meshed.
    h : float
        Global element size (> 0).
    tip_h : float, optional
        Element size at every crack tip (``<= h``); default ``h`` (no grading).
    grading : float
        Growth ratio of neighbouring element sizes away from a tip, in (1, 4].
    min_angle : float
        Smallest triangle angle in degrees (Triangle's ``q``), in (0, 33].
    tip_fan : int
        0, or the number ``n >= 5`` of elements around every tip: ``n - 1``
        vertices at angles ``pi (2 k / n - 1)``, ``k = 1..n-1``, from the
        crack's direction, at about the distance ``tip_h`` (``h`` without
        grading) from the tip (less for small ``n``, so that the fan triangles
        are not refined further, and at most 0.45 of the free radius around
        the tip), so the tip's fan holds ``n`` elements of angle ``2 pi / n``
        (quarter-point elements want ``n >= 8``; Triangle alone leaves 4-6).
    refine : array_like, shape (k, 2)
        Further points toward which the mesh is graded as toward the tips (a
        re-entrant corner, the tip of a crack modelled by a symmetry support);
        each becomes a mesh vertex.

    Returns
    -------
    TriMesh

    Examples
    --------
    >>> from efgkit import Crack, Domain, Elastic, Scene
    >>> scene = Scene(Domain.rectangle(-1, -1, 1, 1), Elastic(1.0, 0.3),
    ...               cracks=(Crack([[-1.0, 0.0], [0.0, 0.0]], tips=(False, True)),))
    >>> m = mesh_scene(scene, h=0.5, tip_h=0.05)
    >>> round(float(m.area.sum()), 12)
    4.0
    >>> left, right = m.crack_nodes[0]
    >>> bool(np.allclose(m.x[left], m.x[right])), bool(m.size.min() < 0.06)
    (True, True)
    """
    from ..problem.scene import Scene

    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a Scene, got {type(scene).__name__}")
    check_sizes(h, tip_h, grading, min_angle, tip_fan)
    refine = refinement_points(refine, scene.domain)
    tips = scene.tips
    est = scene.domain.area / (EQUILATERAL_AREA * h * h)
    if tip_h is not None and tip_h < h and (tips or len(refine)):  # 1/(EQ s^2) over graded discs
        est += ((len(tips) + len(refine)) * 2 * math.pi / (EQUILATERAL_AREA * (grading - 1) ** 2)
                * math.log(h / tip_h))
    if est > _MAX_ELEMENTS:
        raise ValueError(f"h = {h!r}, tip_h = {tip_h!r} would give about {est:.2g} elements "
                         f"(limit {_MAX_ELEMENTS:.0e}); raise h or tip_h")
    domain, cracks = scene.domain, scene.cracks
    x0, segs, marks, holes, crack_ids, n_edges = scene_pslg(domain, cracks, h)
    if tip_fan and tips:
        x0 = np.vstack([x0, tip_fans(scene, tips, tip_h if tip_h is not None else h, tip_fan)])
    if len(refine):  # as vertices (those on the boundary polylines are there already)
        d = np.linalg.norm(refine[:, None] - x0[None], axis=-1).min(axis=1)
        x0 = np.vstack([x0, refine[d > 1e-12 * domain.size]])
    x, t, fseg, fmark = triangulate(x0, segs, marks, holes, h, lambda p: size_field(
        p, h, tuple(tips) + tuple(refine), tip_h, grading), min_angle)
    edges = domain.edges()
    owner = fmark - FIRST_MARK
    for k, e in enumerate(edges):  # vertices of arc facets onto their circle
        if e.is_arc:
            v = np.unique(fseg[owner == k])
            d = x[v] - e.centre
            r = np.linalg.norm(e.start - e.centre)
            x[v] = e.centre + r * d / np.linalg.norm(d, axis=1)[:, None]
    is_crack = owner >= n_edges
    cf = fseg[is_crack]
    cidx = owner[is_crack] - n_edges
    dirs = np.zeros((len(cf), 2))
    for ci, c in enumerate(cracks):  # orient crack facets along their crack segment
        sel = cidx == ci
        k = c.project(0.5 * (x[cf[sel, 0]] + x[cf[sel, 1]]))[0]
        dirs[sel] = c.segments[k, 1] - c.segments[k, 0]
    flip = np.einsum("nd,nd->n", x[cf[:, 1]] - x[cf[:, 0]], dirs) < 0
    cf[flip] = cf[flip][:, ::-1]
    tip_nodes = tuple(int(crack_ids[[c.name for c in cracks].index(tp.crack)][0 if tp.end == 0 else -1])
                      for tp in tips)
    n_orig = len(x)
    x, t, origin = open_cracks(x, t, cf, np.array(tip_nodes, dtype=np.int64))
    fac, own = _boundary_facets(t, origin, fseg, owner, n_edges)
    crack_nodes = crack_node_pairs(cracks, x, origin, n_orig, cf, cidx, tip_nodes)
    return TriMesh(x, t, fac, own, origin, crack_nodes, tip_nodes, domain, tuple(cracks))


def _boundary_facets(t, origin, fseg, owner, n_edges):
    """Boundary facets ``(f, 2)`` of the opened mesh and their ``facet_owner (f,)``, via ``fseg (s, 2)``."""
    n0 = len(origin)
    key = edge_keys(t[:, [0, 1, 2]].ravel(), t[:, [1, 2, 0]].ravel(), n0)
    uniq, cnt = np.unique(key, return_counts=True)
    bnd = np.isin(key, uniq[cnt == 1])
    fac = np.column_stack([t[:, [0, 1, 2]].ravel()[bnd], t[:, [1, 2, 0]].ravel()[bnd]])
    okey = edge_keys(origin[fac[:, 0]], origin[fac[:, 1]], n0)
    skey = edge_keys(fseg[:, 0], fseg[:, 1], n0)
    srt = np.argsort(skey)
    pos = np.searchsorted(skey[srt], okey)
    if np.any(skey[srt][np.minimum(pos, len(skey) - 1)] != okey):  # pragma: no cover
        raise RuntimeError("a boundary facet of the mesh lies on no input segment")
    own = owner[srt][pos]
    return fac, np.where(own >= n_edges, -1 - (own - n_edges), own)


def crack_node_pairs(cracks, x, origin, n_orig, cf, cidx, tip_nodes):
    """Per crack, ``(left (k,), right (k,))`` indices of its opened nodes ordered by arc length."""
    crack_nodes = []
    copy = np.full(n_orig, -1)
    copy[origin[n_orig:]] = np.arange(n_orig, len(origin))
    for ci, c in enumerate(cracks):
        ids = np.unique(cf[cidx == ci])
        ids = ids[~np.isin(ids, tip_nodes)]
        right = np.where(copy[ids] >= 0, copy[ids], ids)
        o = np.argsort(arclength(c, x[ids]))
        crack_nodes.append((ids[o], right[o]))
    return tuple(crack_nodes)


def arclength(crack, p):
    """Arc-length parameter along the crack polyline of points ``p (n, 2)`` on it."""
    k, t, _ = crack.project(p)
    ln = np.linalg.norm(crack.segments[:, 1] - crack.segments[:, 0], axis=1)
    return np.concatenate([[0.0], np.cumsum(ln)])[k] + t * ln[k]

